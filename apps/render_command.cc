// splam render: draw a world, a log, trajectories, or any of them over each other.
#include <fmt/core.h>

#include "apps/commands.h"
#include "apps/log_input.h"
#include "apps/output_paths.h"
#include "io/carmen.h"
#include "io/run_picture.h"
#include "io/simulation_log.h"
#include "io/world_file.h"
#include "kernel/angle.h"
#include "runtime/log_replay.h"
#include "runtime/slam_report.h"

namespace splam::apps {
namespace {

struct RenderArgs {
  std::string world;
  std::string log;
  std::vector<std::string> trajectories;
  std::vector<std::string> out = {"render.svg", "render.png"};
  std::string title;
  int scan_every = 10;
  double resolution_m_per_px = 0.05;
  double pixels_per_meter = 40.0;
  std::string grid;  // map.yaml of the occupancy grid of --log at the first --trajectory
  estimation::OccupancyGridOptions grid_options;
  LogInput input;
};

int RunRender(const RenderArgs& args) {
  if (args.world.empty() && args.log.empty() && args.trajectories.empty()) {
    fmt::print(stderr, "splam render: give at least one of --world, --log, --trajectory\n");
    return kExitBadInput;
  }
  if (!args.grid.empty() && (args.log.empty() || args.trajectories.empty())) {
    fmt::print(stderr,
               "splam render: --grid needs --log (the scans) and --trajectory (their poses)\n");
    return kExitBadInput;
  }
  // Output directories that do not exist yet are made, as slam's --out is.
  std::vector<std::string> outputs = args.out;
  if (!args.grid.empty()) {
    outputs.push_back(args.grid);
    for (const char* extension : {".pgm", ".png"})
      outputs.push_back(std::filesystem::path(args.grid).replace_extension(extension).string());
  }
  CommandFiles files;
  files.inputs = {{"the world", args.world}, {"the log", args.log}};
  for (const std::string& t : args.trajectories) files.inputs.emplace_back("--trajectory", t);
  files.outputs = outputs;
  if (const kernel::Status s = OutputOverwritesInput(files); !s.ok()) {
    fmt::print(stderr, "splam render: {}\n", s.message());
    return kExitBadInput;
  }
  for (const std::string& o : outputs) {
    const std::filesystem::path parent = std::filesystem::path(o).parent_path();
    std::error_code ec;
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  }
  io::RunPicture picture;
  io::CarmenReadResult read_log;
  picture.title = args.title;
  picture.pixels_per_meter = args.pixels_per_meter;
  std::optional<sim::World> world;
  if (!args.world.empty()) {
    io::FloorPlanOptions floor_plan;
    floor_plan.resolution_m_per_px = args.resolution_m_per_px;
    io::Result<sim::World> read = io::LoadWorld(args.world, floor_plan);
    if (!read.ok()) {
      fmt::print(stderr, "splam render: {}\n", read.error);
      return kExitBadInput;
    }
    world = std::move(read.value);
    picture.world = &*world;
    if (picture.title.empty()) picture.title = world->name;
  }
  if (!args.log.empty()) {
    read_log = ReadLogInput(args.log, args.input);
    if (!read_log.log.ok()) {
      fmt::print(stderr, "splam render: {}\n", read_log.log.error);
      return kExitBadInput;
    }
    const io::CarmenLog& log = *read_log.log.value;
    if (log.messages.empty()) {
      fmt::print(stderr, "splam render: {}: no laser, odometry or true pose message to draw\n",
                 args.log);
      return kExitBadInput;
    }
    picture.truth = io::TrueTrajectory(log);
    picture.odometry = io::OdometryTrajectory(log);
    picture.scan_points = io::ScanPointsInWorld(log, args.scan_every);
    if (picture.title.empty()) picture.title = args.log;
    fmt::print("{}: {} scans, {} odometry poses, {} true poses\n", args.log, log.Lasers().size(),
               picture.odometry.size(), picture.truth.size());
  }
  for (const std::string& path : args.trajectories) {
    io::Result<io::Trajectory> read = io::ReadTrajectory(path);
    if (!read.ok()) {
      fmt::print(stderr, "splam render: {}\n", read.error);
      return kExitBadInput;
    }
    picture.estimates.emplace_back(std::filesystem::path(path).stem().string(),
                                   std::move(*read.value));
  }
  std::vector<kernel::Status> errors = {io::SaveRunPicture(picture, args.out)};
  std::vector<std::string> written = args.out;
  if (!args.grid.empty()) {
    const kernel::Trajectory& poses = picture.estimates.front().second;
    const std::vector<evaluation::PlacedScan> placed =
        runtime::PlacedScansAt(*read_log.log.value, poses);
    if (placed.empty()) {
      fmt::print(stderr, "splam render: no scan of {} lies within the time of {}\n", args.log,
                 args.trajectories.front());
      return kExitBadInput;
    }
    const std::string picture_path =
        std::filesystem::path(args.grid).replace_extension(".png").string();
    const nlohmann::ordered_json grid = runtime::WriteGridFiles(
        placed, args.grid_options, args.grid, {picture_path},
        fmt::format("occupancy grid of {} at {}",
                    std::filesystem::path(args.log).filename().string(),
                    std::filesystem::path(args.trajectories.front()).filename().string()),
        poses, &errors);
    if (grid.contains("error")) {
      fmt::print(stderr, "splam render: {}\n", grid["error"].get<std::string>());
      return kExitBadInput;
    }
    fmt::print("occupancy grid of {} scans: {} x {} cells of {} m\n", placed.size(),
               grid["cells"][0].get<int>(), grid["cells"][1].get<int>(),
               grid["resolution_m"].get<double>());
    for (const char* extension : {".yaml", ".pgm"})
      written.push_back(std::filesystem::path(args.grid).replace_extension(extension).string());
    written.push_back(picture_path);
  }
  if (const kernel::Status error = kernel::FirstError(errors); !error.ok()) {
    fmt::print(stderr, "splam render: {}\n", error.message());
    return kExitWriteFailed;
  }
  for (const std::string& path : written) fmt::print("wrote {}\n", path);
  return kExitOk;
}

}  // namespace

void AddRenderCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = app->add_subcommand(
      "render", "Draw a world, a CARMEN log and trajectories to SVG and/or PNG.");
  cmd->add_option("--world", args->world,
                  "Built-in world name, YAML world file or floor-plan image");
  cmd->add_option("--log", args->log,
                  "CARMEN log or ROS bag: ground truth, odometry and scan points");
  cmd->add_option("--trajectory", args->trajectories,
                  "Trajectory file(s) 'time x y theta' to draw as estimates");
  cmd->add_option("--out", args->out, "Output picture(s), .svg or .png")
      ->check(PicturePath())
      ->capture_default_str();
  cmd->add_option("--title", args->title, "Title above the picture");
  cmd->add_option("--grid", args->grid,
                  "Write the occupancy grid of --log's scans at the first --trajectory's poses: "
                  "FILE.yaml and FILE.pgm (ROS map_server) and FILE.png");
  cmd->add_option("--grid-resolution", args->grid_options.resolution_m,
                  "Cell side of the occupancy grid, m")
      ->check(FinitePositive())
      ->capture_default_str();
  cmd->add_option("--scan-every", args->scan_every, "Draw the points of every N-th scan")
      ->check(FinitePositive())
      ->capture_default_str();
  cmd->add_option("--resolution", args->resolution_m_per_px,
                  "Metres per pixel of a floor-plan image world")
      ->check(FloorPlanResolution())
      ->capture_default_str();
  cmd->add_option("--pixels-per-meter", args->pixels_per_meter, "Picture scale")
      ->check(FinitePositive())
      ->capture_default_str();
  AddLogInputOptions(cmd, &args->input);
  cmd->callback([args, exit_code] { *exit_code = RunRender(*args); });
}

}  // namespace splam::apps
