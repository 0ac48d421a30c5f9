#include "apps/cli.h"

#include <CLI/CLI.hpp>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <new>
#include <string_view>
#include <system_error>

#include "apps/commands.h"

namespace splam::apps {
namespace {

// Standard output or error that cannot be written (a full disk) is a failed write like any
// file's: said on standard error (if it can be), exit status 4 (kExitWriteFailed).
int StreamFailed(const char* why) {
  std::fprintf(stderr, "splam: writing to standard output or error failed: %s\n", why);
  return splam::apps::kExitWriteFailed;
}

}  // namespace

int Main(int argc, char** argv) {
  // A file-size limit (ulimit -f) makes a write fail (EFBIG) like a full disk: the command then
  // exits 4 naming the file, instead of being killed by SIGXFSZ with its files cut short.
  std::signal(SIGXFSZ, SIG_IGN);
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
  splam::apps::AddSplitCommand(&app, &exit_code);
  splam::apps::AddSweepCommand(&app, &exit_code);
  // SPLAM_PARSE_ONLY=1: check the command line and stop before the command runs (the test of
  // the documentation's commands, tests/apps/docs_commands_test.cc).
  if (const char* parse_only = std::getenv("SPLAM_PARSE_ONLY");
      parse_only != nullptr && std::string_view(parse_only) == "1")
    app.parse_complete_callback([] { throw CLI::Success(); });  // after the checks, before any
                                                                // command's callback
  int status = exit_code;
  try {
    app.parse(argc, argv);
    status = exit_code;
  } catch (const CLI::ParseError& e) {
    status = app.exit(e) == 0 ? 0 : splam::apps::kExitBadInput;
  } catch (const std::filesystem::filesystem_error& e) {  // what no command caught: a path
    std::fprintf(stderr, "splam: %s\n", e.what());
    return splam::apps::kExitWriteFailed;
  } catch (const std::system_error& e) {  // fmt::print to a stream that refused the bytes
    return StreamFailed(e.code().message().c_str());
  } catch (const std::bad_alloc&) {  // what no bound caught: said, not a signal
    std::fprintf(stderr, "splam: out of memory: the input asks for more than this machine has\n");
    return splam::apps::kExitBadInput;
  }
  errno = 0;
  if (std::fflush(stdout) != 0 || std::ferror(stdout))
    return status != 0 ? status : StreamFailed(errno != 0 ? std::strerror(errno) : "stream error");
  return status;
}

}  // namespace splam::apps
