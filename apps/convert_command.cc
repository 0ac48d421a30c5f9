// splam convert: a CARMEN log to a ROS 1 bag, or a bag to a CARMEN log; a trajectory between
// splam's, TUM's and KITTI's formats.
#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <string_view>

#include "apps/commands.h"
#include "apps/log_input.h"
#include "apps/output_paths.h"
#include "io/trajectory.h"

namespace splam::apps {
namespace {

struct ConvertArgs {
  std::string in, out;
  LogInput input;
};

constexpr std::array<std::string_view, 5> kLogOutputs = {".bag", ".mcap", ".db3", ".clf", ".log"};

// A path that names a TUM or KITTI trajectory by its extension.
bool IsTrajectoryPath(const std::string& path) {
  return io::TrajectoryFormatOf(path) != io::TrajectoryFormat::kSplam;
}

// A trajectory in any format to the format of OUT's extension.
int ConvertTrajectory(const ConvertArgs& args) {
  const io::Result<io::Trajectory> trajectory = io::ReadTrajectory(args.in);
  if (!trajectory) {
    fmt::print(stderr, "splam convert: {}\n", trajectory.error);
    return kExitBadInput;
  }
  if (kernel::Status error =
          io::WriteTrajectory(args.out, *trajectory, "converted from " + args.in);
      !error.ok()) {
    fmt::print(stderr, "splam convert: {}\n", error.message());
    return kExitWriteFailed;
  }
  fmt::print("wrote {}: {} poses, {}\n", args.out, trajectory->size(),
             io::TrajectoryFormatName(io::TrajectoryFormatOf(args.out)));
  return kExitOk;
}

int RunConvert(const ConvertArgs& args) {
  CommandFiles files;
  files.inputs = {{"the input", args.in}};
  files.outputs = {args.out};
  if (const kernel::Status s = OutputOverwritesInput(files); !s.ok()) {
    fmt::print(stderr, "splam convert: {}\n", s.message());
    return kExitBadInput;
  }
  if (IsTrajectoryPath(args.out) || IsTrajectoryPath(args.in)) return ConvertTrajectory(args);
  if (std::none_of(kLogOutputs.begin(), kLogOutputs.end(),
                   [&](std::string_view e) { return args.out.ends_with(e); })) {
    fmt::print(stderr,
               "splam convert: {}: unknown output format; known: .bag (ROS 1 bag), .mcap or .db3 "
               "(ROS 2 bag: MCAP or SQLite3), .clf or .log (CARMEN log), .tum or .kitti (a "
               "trajectory, from a trajectory file)\n",
               args.out);
    return kExitBadInput;
  }
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
      "Convert a CARMEN log to a ROS 1 bag (OUT ends in .bag) or a ROS 2 bag (.mcap, .db3), or a "
      "bag to a CARMEN log (.clf, .log): scans (LaserScan), odometry (Odometry), the laser "
      "mounting "
      "(/tf_static) and ground truth (--truth-topic); or a trajectory to TUM (.tum) or KITTI "
      "(.kitti), as evo reads them, and back (.txt)");
  cmd->add_option("in", args->in, "Input: a CARMEN log, a ROS 1 or ROS 2 bag, or a trajectory")
      ->required();
  cmd->add_option("out", args->out,
                  "Output: .bag, .mcap, .db3, .clf, .log; .tum, .kitti, .txt (trajectories)")
      ->required();
  AddLogInputOptions(cmd, &args->input);
  cmd->callback([args, exit_code] { *exit_code = RunConvert(*args); });
}

}  // namespace splam::apps
