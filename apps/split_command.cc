// splam split: one log cut into sessions with no shared frame (io::SplitLog), to test how maps
// join on a real log whose relations score the joined trajectory.
#include <fmt/core.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "apps/log_input.h"
#include "apps/output_paths.h"
#include "io/log_split.h"
#include "io/render.h"
#include "io/trajectory.h"
#include "runtime/json_text.h"

namespace splam::apps {
namespace {

struct SplitArgs {
  std::string log, out;
  io::LogSplitOptions split;
  LogInput input;
};

// Distinct colours for the sessions, in order (cycled beyond eight).
io::Rgb SessionColor(int k) {
  static constexpr io::Rgb kColors[] = {{0.10, 0.35, 0.85}, {0.85, 0.10, 0.65}, {0.10, 0.60, 0.25},
                                        {0.95, 0.45, 0.05}, {0.45, 0.20, 0.70}, {0.75, 0.10, 0.10},
                                        {0.20, 0.75, 0.75}, {0.40, 0.40, 0.40}};
  return kColors[k % 8];
}

// Each session's odometry in the frame it was moved to, in its own colour.
kernel::Status SaveSessionsPicture(const std::vector<io::LogSession>& sessions,
                                   const std::string& title, const std::string& path) {
  kernel::Box2 area;
  std::vector<std::vector<kernel::Pose2>> paths;
  for (const io::LogSession& s : sessions) {
    paths.emplace_back();
    for (const io::LaserMessage* laser : s.log.Lasers()) {
      paths.back().push_back(laser->robot_pose);
      area.Extend(laser->robot_pose.translation());
    }
  }
  io::FigureOptions options;
  options.pixels_per_meter = 10.0;
  options.margin_m = 5.0;
  options.title = title;
  io::Figure figure(area, options);
  for (std::size_t k = 0; k < sessions.size(); ++k) {
    figure.DrawPath(paths[k], SessionColor(static_cast<int>(k)), 1.5,
                    fmt::format("{}: {} scans, odometry", sessions[k].name, sessions[k].scans));
    figure.DrawRobot(paths[k].front(), 1.0, SessionColor(static_cast<int>(k)));
  }
  return figure.Save(path);
}

int RunSplit(const SplitArgs& args) {
  if (kernel::Status s = args.split.Validate(); !s.ok()) {
    fmt::print(stderr, "splam split: {}\n", s.message());
    return kExitBadInput;
  }
  CommandFiles files;
  files.inputs = {{"the log", args.log}};
  std::vector<std::string> names = {"split.json", "sessions.svg", "sessions.png"};
  for (int k = 1; k <= args.split.sessions; ++k) names.push_back(fmt::format("session{}.clf", k));
  files.AddOutputs(args.out, names);
  if (const kernel::Status s = OutputOverwritesInput(files); !s.ok()) {
    fmt::print(stderr, "splam split: {}\n", s.message());
    return kExitBadInput;
  }
  const io::CarmenReadResult read = ReadLogInput(args.log, args.input);
  if (!read.log.ok()) {
    fmt::print(stderr, "splam split: {}\n", read.log.error);
    return kExitBadInput;
  }
  const io::Result<std::vector<io::LogSession>> sessions = io::SplitLog(*read.log, args.split);
  if (!sessions.ok()) {
    fmt::print(stderr, "splam split: {}: {}\n", args.log, sessions.error);
    return kExitBadInput;
  }
  if (kernel::Status e = CreateOutputDirectory(args.out); !e.ok()) {
    fmt::print(stderr, "splam split: {}\n", e.message());
    return kExitWriteFailed;
  }
  nlohmann::ordered_json manifest = {{"log", args.log},
                                     {"seed", args.split.seed},
                                     {"min_offset_m", args.split.min_offset_m},
                                     {"max_offset_m", args.split.max_offset_m},
                                     {"sessions", nlohmann::ordered_json::array()}};
  for (const io::LogSession& s : *sessions) {
    const std::string file = s.name + ".clf";
    if (kernel::Status e = io::WriteCarmenLog(args.out + "/" + file, s.log); !e.ok()) {
      fmt::print(stderr, "splam split: {}\n", e.message());
      return kExitWriteFailed;
    }
    const kernel::Pose2& t = s.log_T_session;
    manifest["sessions"].push_back({{"name", s.name},
                                    {"file", file},
                                    {"scans", s.scans},
                                    {"first_time_s", s.first_time_s},
                                    {"last_time_s", s.last_time_s},
                                    {"log_T_session", {t.x(), t.y(), t.theta()}}});
  }
  if (kernel::Status e =
          io::WriteTextFile(args.out + "/split.json", runtime::JsonText(manifest, 2) + "\n");
      !e.ok()) {
    fmt::print(stderr, "splam split: {}\n", e.message());
    return kExitWriteFailed;
  }
  const std::string title =
      fmt::format("{} in {} sessions (seed {})", args.log, args.split.sessions, args.split.seed);
  for (const char* picture : {"/sessions.svg", "/sessions.png"})
    if (kernel::Status e = SaveSessionsPicture(*sessions, title, args.out + picture); !e.ok()) {
      fmt::print(stderr, "splam split: {}\n", e.message());
      return kExitWriteFailed;
    }
  for (const io::LogSession& s : *sessions)
    fmt::print("{}: {} scans, {:.1f} s to {:.1f} s\n", s.name, s.scans, s.first_time_s,
               s.last_time_s);
  fmt::print("wrote {}/{{split.json, sessions.svg, sessions.png, session1..{}.clf}}\n", args.out,
             sessions->size());
  return kExitOk;
}

}  // namespace

void AddSplitCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<SplitArgs>();
  CLI::App* cmd = app->add_subcommand(
      "split",
      "Cut a log into sessions with equally many scans, each session's odometry moved by a "
      "rigid motion it does not tell (its first pose 50-150 m away, any heading; time stamps "
      "kept): sessions that share no frame, to map together and score with the log's relations");
  cmd->add_option("log", args->log, "A CARMEN log or a ROS 1 or ROS 2 bag")->required();
  cmd->add_option("--out", args->out, "Output directory")->required();
  cmd->add_option("--sessions", args->split.sessions, "Number of sessions, 2-10")
      ->capture_default_str();
  cmd->add_option("--seed", args->split.seed, "Seed of the rigid motions")
      ->check(Seed())
      ->capture_default_str();
  cmd->add_option("--min-offset", args->split.min_offset_m,
                  "Each session's first pose moved at least this far, m")
      ->check(FiniteNonNegative())
      ->capture_default_str();
  cmd->add_option("--max-offset", args->split.max_offset_m, "... and at most this far, m")
      ->check(FiniteNonNegative())
      ->capture_default_str();
  AddLogInputOptions(cmd, &args->input);
  cmd->callback([args, exit_code] { *exit_code = RunSplit(*args); });
}

}  // namespace splam::apps
