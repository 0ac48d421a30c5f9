// splam convert: a CARMEN log to a ROS 1 bag, or a bag to a CARMEN log.
#include <fmt/core.h>

#include "apps/commands.h"
#include "apps/log_input.h"

namespace splam::apps {
namespace {

struct ConvertArgs {
  std::string in, out;
  LogInput input;
};

int RunConvert(const ConvertArgs& args) {
  const io::CarmenReadResult read = ReadLogInput(args.in, args.input);
  if (!read.log.ok()) {
    fmt::print(stderr, "splam convert: {}\n", read.log.error);
    return kExitBadInput;
  }
  const io::CarmenLog& log = *read.log.value;
  if (log.Lasers().empty()) {
    fmt::print(stderr, "splam convert: {}: no laser scan to convert\n", args.in);
    return kExitBadInput;
  }
  if (io::IsRosBagPath(args.out)) {
    io::RosBagWriteStats stats;
    if (kernel::Status error = io::WriteRosBag(log, args.out, args.input.bag, &stats);
        !error.ok()) {
      fmt::print(stderr, "splam convert: {}\n", error.message());
      return stats.write_failed ? kExitWriteFailed : kExitBadInput;
    }
    fmt::print("wrote {}: {} scans, {} odometry poses, {} true poses", args.out, stats.scans,
               stats.odometry, stats.true_poses);
    if (stats.sonar_skipped > 0)
      fmt::print(" ({} sonar messages have no ROS counterpart here: not written)",
                 stats.sonar_skipped);
    fmt::print("\n");
  } else {
    if (kernel::Status error = io::WriteCarmenLog(args.out, log); !error.ok()) {
      fmt::print(stderr, "splam convert: {}\n", error.message());
      return kExitWriteFailed;
    }
    fmt::print("wrote {}: {} scans, {} odometry poses, {} true poses\n", args.out,
               log.Lasers().size(), log.Odometry().size(), log.TruePoses().size());
  }
  return kExitOk;
}

}  // namespace

void AddConvertCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<ConvertArgs>();
  CLI::App* cmd = app->add_subcommand(
      "convert",
      "Convert a CARMEN log to a ROS 1 bag (OUT ends in .bag) or a bag to a CARMEN log: scans "
      "(sensor_msgs/LaserScan), odometry (nav_msgs/Odometry), the laser mounting (/tf_static) "
      "and ground truth (--truth-topic)");
  cmd->add_option("in", args->in, "Input: a CARMEN log or a .bag")->required();
  cmd->add_option("out", args->out, "Output: a .bag or a CARMEN log")->required();
  AddLogInputOptions(cmd, &args->input);
  cmd->callback([args, exit_code] { *exit_code = RunConvert(*args); });
}

}  // namespace splam::apps
