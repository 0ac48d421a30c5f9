// splam config print: every option of a run with its default, unit and comment, as YAML that
// --config reads back.
#include <fmt/core.h>

#include "apps/commands.h"
#include "apps/run_config.h"
#include "exploration/explorer.h"

namespace splam::apps {
namespace {

struct ConfigArgs {
  std::string method;    // a SLAM method: the `splam slam` document
  std::string explorer;  // an explorer: the `splam explore` document
};

int PrintConfig(const ConfigArgs& args) {
  if (!args.explorer.empty() || args.method.empty()) {
    ExploreConfig config;
    if (!args.explorer.empty()) config.setup.explorer = args.explorer;
    if (!args.method.empty()) config.setup.localization = args.method;
    ResetExploreDefaults(&config);
    fmt::print("{}",
               io::ConfigToYaml(ExploreConfigRoot(&config),
                                "splam explore --config FILE: every option with its default"));
    return kExitOk;
  }
  SlamConfig config;
  config.method = args.method;
  // The defaults for a simulated URG-04LX log; `splam slam` adapts the noise to the log's laser
  // before it reads the file.
  config.options = estimation::SlamRegistry::Global().Find(args.method)->default_options({});
  fmt::print("{}", io::ConfigToYaml(SlamConfigRoot(&config),
                                    "splam slam --config FILE LOG: every option with its default"));
  return kExitOk;
}

}  // namespace

void AddConfigCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<ConfigArgs>();
  CLI::App* cmd = app->add_subcommand("config", "Configuration files.");
  cmd->require_subcommand(1);
  CLI::App* print = cmd->add_subcommand(
      "print",
      "Print every option with its default, unit and comment as YAML for --config: with --method "
      "alone the `splam slam` document, with --explorer (or nothing) the `splam explore` one.");
  print
      ->add_option("--method", args->method,
                   "SLAM method (or, with --explorer, the localisation):\n" +
                       estimation::SlamRegistry::Global().Describe())
      ->check(CLI::IsMember(runtime::LocalizationChoices()));
  print
      ->add_option("--explorer", args->explorer,
                   "Exploration strategy:\n" + exploration::ExplorerRegistry::Global().Describe())
      ->check(CLI::IsMember(exploration::ExplorerRegistry::Global().Names()));
  print->callback([args, exit_code] { *exit_code = PrintConfig(*args); });
}

}  // namespace splam::apps
