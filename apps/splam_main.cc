// splam: 2-D laser SLAM and exploration in complex environments. One binary, one subcommand
// per job; `splam <command> --help` documents each.
#include <CLI/CLI.hpp>

#include "apps/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"splam: B-spline SLAM and exploration for 2-D laser robots"};
  app.require_subcommand(1);
  int exit_code = splam::apps::kExitOk;
  splam::apps::AddSimulateCommand(&app, &exit_code);
  splam::apps::AddRenderCommand(&app, &exit_code);
  splam::apps::AddSlamCommand(&app, &exit_code);
  splam::apps::AddEvalCommand(&app, &exit_code);
  splam::apps::AddExperimentCommand(&app, &exit_code);
  splam::apps::AddExploreCommand(&app, &exit_code);
  splam::apps::AddConfigCommand(&app, &exit_code);
  splam::apps::AddConvertCommand(&app, &exit_code);
  splam::apps::AddSweepCommand(&app, &exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status = app.exit(e);
    return status == 0 ? 0 : splam::apps::kExitBadInput;
  }
  return exit_code;
}
