#include "runtime/exploration_report.h"

#include "runtime/run_html.h"

#include <fmt/core.h>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "estimation/evaluation/metrics.h"
#include "exploration/coverage.h"
#include "exploration/perception.h"
#include "io/plot.h"
#include "io/render.h"
#include "io/run_picture.h"
#include "io/trajectory.h"
#include "runtime/json_text.h"
#include "runtime/slam_report.h"
#include "runtime/step_trace.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"

namespace splam::runtime {
namespace {

// An options struct's fields as a JSON object (the report's copy of the run's options).
class JsonWriter : public kernel::FieldVisitor {
 public:
  explicit JsonWriter(nlohmann::json* out) : out_(out) {}
  void Field(std::string_view key, double* v, std::string_view) override { Set(key, *v); }
  void Field(std::string_view key, int* v, std::string_view) override { Set(key, *v); }
  void Field(std::string_view key, std::uint64_t* v, std::string_view) override { Set(key, *v); }
  void Field(std::string_view key, bool* v, std::string_view) override { Set(key, *v); }
  void Field(std::string_view key, std::string* v, std::string_view) override { Set(key, *v); }
  void Field(std::string_view key, std::vector<double>* v, std::string_view) override {
    Set(key, *v);
  }
  void Field(std::string_view key, kernel::Pose2* v, std::string_view) override {
    Set(key, std::vector<double>{v->x(), v->y(), v->theta()});
  }
  void Choice(std::string_view key, int* index, std::initializer_list<std::string_view> choices,
              std::string_view) override {
    Set(key, std::string(*(choices.begin() + *index)));
  }
  void Group(std::string_view key, std::string_view,
             const std::function<void(FieldVisitor&)>& fields) override {
    nlohmann::json group = nlohmann::json::object();
    JsonWriter writer(&group);
    fields(writer);
    (*out_)[std::string(key)] = std::move(group);
  }

 private:
  template <class T>
  void Set(std::string_view key, const T& value) {
    (*out_)[std::string(key)] = value;
  }
  nlohmann::json* out_;
};

}  // namespace

nlohmann::json ExplorationReport(const sim::World& world, const ExploreSetup& setup,
                                 const ExploreOutcome& outcome) {
  const exploration::ExplorationRun& run = outcome.run;
  const int nodes = static_cast<int>(run.graph.num_nodes());
  nlohmann::json report;
  report["world"] = world.name;
  report["explorer"] = setup.explorer;
  report["localization"] = setup.localization;
  report["seed"] = setup.seed;
  report["nodes"] = nodes;
  report["edges"] = run.graph.num_edges();
  report["distance_m"] = run.distance_m;
  report["time_s"] = run.time_s;
  report["coverage_fraction"] = outcome.coverage();
  report["reachable_free_area_m2"] = outcome.reachable_area_m2;
  report["termination"] = exploration::TerminationName(run.termination);
  report["termination_message"] = run.message;
  report["moves"] = run.moves;
  report["failed_moves"] = run.failed_moves;
  report["blocked_steps"] = run.blocked_steps;
  report["replanned_moves"] = run.replanned_moves;
  report["unreachable_frontiers"] = run.unreachable_frontiers;
  // The frontiers given up, as the explorer's own map shows them at the end; open ones make
  // the run `incomplete`.
  nlohmann::json given_up = nlohmann::json::array();
  for (const exploration::GivenUpFrontier& f : run.given_up)
    given_up.push_back({{"node", f.node},
                        {"kind", !f.unseen.empty()    ? "unseen"
                                 : f.shadow_edge >= 0 ? "shadow"
                                                      : "arc"},
                        {"x", f.midpoint.x()},
                        {"y", f.midpoint.y()},
                        {"start_angle_rad", f.arc.start_angle_rad},
                        {"end_angle_rad", f.arc.end_angle_rad},
                        {"reason", f.reason},
                        {"open", f.open}});
  report["given_up_frontiers"] = given_up;
  // Active loop closing's revisits (ExplorerOptions::active_loop_closing).
  report["revisits"] = run.revisits.size();
  nlohmann::json revisits = nlohmann::json::array();
  double revisit_m = 0.0;
  for (const exploration::RevisitRecord& r : run.revisits) {
    revisits.push_back({{"from", r.from},
                        {"to", r.to},
                        {"time_s", r.time_s},
                        {"path_m", r.path_m},
                        {"information_nats", r.information_nats},
                        {"position_sigma_m", r.position_sigma_m},
                        {"position_sigma_after_m", std::isnan(r.position_sigma_after_m)
                                                       ? nlohmann::json(nullptr)
                                                       : nlohmann::json(r.position_sigma_after_m)},
                        {"reached", r.reached}});
    revisit_m += r.path_m;
  }
  report["revisit_records"] = revisits;
  nlohmann::json sigma = nlohmann::json::array();
  for (const auto& [time_s, sigma_m] : run.position_sigma) sigma.push_back({time_s, sigma_m});
  report["position_sigma"] = sigma;  // [simulated s, m] at each decision
  report["revisit_distance_m"] = revisit_m;
  report["planning_wall_s"] = run.planning_wall_s;
  report["planning_ms_per_node"] = nodes > 0 ? 1e3 * run.planning_wall_s / nodes : 0.0;
  report["wall_s"] = outcome.wall_s;
  const Trajectories t = TrajectoriesOf(run);
  report["trajectory_error"] = {
      {"estimate", ErrorJson(evaluation::CompareToTruth(t.truth, t.estimate))},
      {"odometry", ErrorJson(evaluation::CompareToTruth(t.truth, t.odometry))}};
  if (const estimation::SlamMethod* slam = outcome.slam_method()) {
    const SlamDriver& driver = *outcome.slam->driver();
    const std::vector<double>& ms = driver.update_ms();
    const std::vector<estimation::MapSpline> splines = slam->Map().splines;
    std::size_t control_points = 0;
    for (const estimation::MapSpline& s : splines)
      control_points += s.spline.control_points().size();
    // size: control points of spline maps, landmarks of line maps (SlamMethod::MapSize).
    nlohmann::json map = {{"description", slam->MapDescription()}, {"size", slam->MapSize()}};
    if (!splines.empty()) {
      map["curves"] = splines.size();
      map["control_points"] = control_points;
      const sim::RayCaster caster(world);
      map["mean_distance_to_obstacles_m"] = MeanDistanceToObstacles(caster, splines);
      map["curves_per_obstacle"] = CurvesPerObstacle(caster, splines);
    }
    const nlohmann::json statistics =
        nlohmann::json::parse(JsonText(StatisticsJson(slam->Statistics())));
    report["slam"] = {
        {"method", setup.localization},
        {"healthy", slam->healthy()},
        {"health", slam->health().message()},
        {"map", map},
        {"associations", statistics["associations"]},
        {"localization_steps", ms.size()},
        {"ms_per_step", {{"median", Percentile(ms, 0.5)}, {"p95", Percentile(ms, 0.95)}}},
        {"ms_per_step_by_map_curves",
         nlohmann::json::parse(JsonText(TimeBinsJson(TimeByMapSize(ms, driver.map_curves()))))}};
    if (statistics.contains("least_squares"))
      report["slam"]["least_squares"] = statistics["least_squares"];
  }
  // Every option of the explorer (the shared ones, its own under its name), the region and
  // the simulated sensors' switches.
  nlohmann::json options = {{"lsr_radius_m", setup.region.radius_m},
                            {"alpha", setup.region.alpha},
                            {"sonar", setup.sonar},
                            {"odometry_noise_scale", setup.odometry_noise_scale}};
  JsonWriter writer(&options);
  exploration::ExplorerOptions shared = setup.options;
  shared.seed = setup.seed;  // as RunExploration runs it
  shared.VisitFields(writer);
  std::unique_ptr<kernel::AnyOptions> own =
      setup.explorer_options ? setup.explorer_options->Clone() : nullptr;
  if (const exploration::ExplorerInfo* info =
          exploration::ExplorerRegistry::Global().Find(setup.explorer);
      !own && info != nullptr)
    own = info->default_options();
  if (own) {
    writer.Group(setup.explorer, "", [&](kernel::FieldVisitor& v) { own->VisitFields(v); });
  }
  report["options"] = std::move(options);
  return report;
}

std::string RunTitle(const sim::World& world, const ExploreSetup& setup,
                     const ExploreOutcome& outcome) {
  return fmt::format(
      "{} | {} | {} | seed {} | {} nodes, {:.0f} m, {:.0f} s, {:.1f} % explored, ended: {}",
      world.name, setup.explorer, setup.localization, setup.seed, outcome.run.graph.num_nodes(),
      outcome.run.distance_m, outcome.run.time_s, 100.0 * outcome.coverage(),
      exploration::TerminationName(outcome.run.termination));
}

kernel::Status WriteExplorationRun(const sim::World& world, const ExploreSetup& setup,
                                   const ExploreOutcome& outcome, const nlohmann::json& report,
                                   const std::string& dir, std::vector<std::string>* written) {
  const std::string title = RunTitle(world, setup, outcome);
  const Trajectories t = TrajectoriesOf(outcome.run);
  const auto save = [&](const std::string& name, kernel::Status status) {
    if (status.ok()) written->push_back(name);
    return status;
  };
  std::vector<kernel::Status> errors = {
      save("report.json", io::WriteTextFile(dir + "/report.json", JsonText(report, 2) + "\n")),
      save("graph.svg/png",
           SaveExplorationPicture(world, outcome, title, {dir + "/graph.svg", dir + "/graph.png"})),
      save("explored.svg/png",
           SaveCoveragePlot(outcome, title, {dir + "/explored.svg", dir + "/explored.png"})),
      save("errors.svg/png",
           SaveTrajectoryErrorPlot(outcome, title + ": error against ground truth",
                                   {dir + "/errors.svg", dir + "/errors.png"})),
      save("truth.txt", io::WriteTrajectory(dir + "/truth.txt", t.truth, "ground truth")),
      save("odometry.txt", io::WriteTrajectory(dir + "/odometry.txt", t.odometry, "odometry")),
      save("estimate.txt", io::WriteTrajectory(dir + "/estimate.txt", t.estimate,
                                               setup.localization + " estimate"))};
  if (const estimation::SlamMethod* slam = outcome.slam_method()) {
    errors.push_back(save("map.svg/png", SaveSlamMapPicture(world, outcome, title,
                                                            {dir + "/map.svg", dir + "/map.png"})));
    const kernel::Status map = io::WriteMap(slam->Map(), dir);
    errors.push_back(map);
    if (map.ok()) written->insert(written->end(), {"map.txt", "map.dxf"});
    if (setup.trace_steps)
      errors.push_back(
          save("steps.csv", WriteStepTrace(dir + "/steps.csv", outcome.slam->driver()->steps(),
                                           outcome.slam->step_times(), t.truth)));
  }
  // How the run ended first: a reader must not take an incomplete exploration for a finished one.
  std::vector<std::string> headline = {
      fmt::format("ended: {}{}", exploration::TerminationName(outcome.run.termination),
                  outcome.run.message.empty() ? "" : " (" + outcome.run.message + ")"),
      fmt::format("{:.1f} % of the reachable free space explored, {:.0f} m driven in {:.0f} s",
                  100.0 * outcome.coverage(), outcome.run.distance_m, outcome.run.time_s)};
  if (!t.truth.empty() && !t.estimate.empty()) {
    const evaluation::TrajectoryError e = evaluation::CompareToTruth(t.truth, t.estimate);
    const evaluation::TrajectoryError o = evaluation::CompareToTruth(t.truth, t.odometry);
    headline.push_back(fmt::format("{} position RMSE {:.3f} m (odometry {:.3f} m)",
                                   setup.localization, e.rmse_position_m, o.rmse_position_m));
  }
  errors.push_back(save("report.html", WriteRunHtml(dir, "splam explore: " + title, headline)));
  return kernel::FirstError(errors);
}

kernel::Status SaveExplorationPicture(const sim::World& world, const ExploreOutcome& outcome,
                                      const std::string& title,
                                      const std::vector<std::string>& paths) {
  const exploration::ExplorationRun& run = outcome.run;
  const graph::ExplorationGraph& g = run.graph;
  kernel::Box2 area = world.Bounds();
  io::FigureOptions figure_options;
  figure_options.title = title;
  io::Figure figure(area, figure_options);
  constexpr io::Rgb kRegion{0.20, 0.65, 0.30};
  constexpr io::Rgb kEdge{0.90, 0.45, 0.05};
  constexpr io::Rgb kShortcut{0.55, 0.25, 0.70};
  constexpr io::Rgb kFrontier{0.0, 0.75, 0.0};
  for (graph::Vertex v = 0; v < g.num_nodes(); ++v)
    figure.DrawPolygon(g[v].lsr.boundary(), kRegion, 0.06, 0.3, "local safe regions");
  figure.DrawWorld(world);
  std::vector<kernel::Pose2> truth;
  for (const exploration::TraceSample& s : run.trace) truth.push_back(s.truth);
  figure.DrawPath(truth, io::palette::kTrue, 1.0, "true path");
  for (const auto& [a, b, edge] : g.Edges()) {
    const bool driven = run.nodes[b].parent == static_cast<int>(a);
    std::vector<Eigen::Vector2d> path = edge->path;
    if (path.size() < 2)
      path = {g[a].configuration.translation(), g[b].configuration.translation()};
    if (driven) {
      figure.DrawPolyline(path, kEdge, 2.0, run.explorer == "srt" ? "tree edges" : "driven edges");
    } else {
      figure.DrawPolyline(path, kShortcut, 1.5, "edges through overlaps", true);
    }
  }
  std::vector<Eigen::Vector2d> nodes;
  for (graph::Vertex v = 0; v < g.num_nodes(); ++v)
    nodes.push_back(g[v].configuration.translation());
  figure.DrawMarkers(nodes, io::Figure::Marker::kCircle, kEdge, 3.0, "nodes");
  if (!nodes.empty())
    figure.DrawMarkers({nodes.front()}, io::Figure::Marker::kDiamond, io::palette::kEstimate, 7.0,
                       "start");
  // SRT keeps no frontier bookkeeping: its free arcs never shrink, so only REG's are drawn.
  for (graph::Vertex v = 0; run.explorer == "reg" && v < g.num_nodes(); ++v) {
    for (const kernel::FrontierArc& arc : g[v].frontiers) {
      std::vector<Eigen::Vector2d> points;
      const int n = std::max(2, static_cast<int>(std::ceil(arc.AngularWidth() / 0.02)));
      for (int k = 0; k <= n; ++k)
        points.push_back(g[v].lsr.ArcPoint(arc.start_angle_rad + arc.AngularWidth() * k / n));
      figure.DrawPolyline(points, kFrontier, 3.0, "open frontiers");
    }
  }
  // Given-up frontiers still open at the end (the reason an `incomplete` run stopped short).
  constexpr io::Rgb kGivenUp{0.85, 0.0, 0.0};
  for (const exploration::GivenUpFrontier& f : run.given_up) {
    if (!f.open) continue;
    const kernel::LocalSafeRegion& lsr = g[static_cast<graph::Vertex>(f.node)].lsr;
    std::vector<Eigen::Vector2d> points = f.unseen;
    if (f.shadow_edge >= 0) {  // the occlusion edge
      const auto edge = static_cast<std::size_t>(f.shadow_edge);
      points = {lsr.boundary()[edge], lsr.boundary()[(edge + 1) % lsr.boundary().size()]};
    }
    const int n = std::max(2, static_cast<int>(std::ceil(f.arc.AngularWidth() / 0.02)));
    for (int k = 0; f.shadow_edge < 0 && f.unseen.empty() && k <= n; ++k)
      points.push_back(lsr.ArcPoint(f.arc.start_angle_rad + f.arc.AngularWidth() * k / n));
    figure.DrawPolyline(points, kGivenUp, 4.0, "given-up frontiers, open");
  }
  // Where the robot chose to close a loop (active loop closing): each revisit's drive, and the
  // node it revisited.
  constexpr io::Rgb kRevisit{0.95, 0.0, 0.75};
  for (const exploration::RevisitRecord& r : run.revisits) {
    std::vector<kernel::Pose2> drive;
    for (std::size_t k = r.trace_begin; k < r.trace_end && k < run.trace.size(); ++k)
      drive.push_back(run.trace[k].truth);
    figure.DrawPath(drive, kRevisit, 3.0, "revisits (active loop closing)");
    figure.DrawMarkers({g[static_cast<graph::Vertex>(r.to)].configuration.translation()},
                       io::Figure::Marker::kDiamond, kRevisit, 8.0, "revisited nodes");
  }
  if (!run.trace.empty())
    figure.DrawRobot(run.trace.back().truth, outcome.robot_radius_m, io::palette::kTrue);
  for (const std::string& path : paths) {
    if (kernel::Status error = figure.Save(path); !error.ok()) return error;
  }
  return {};
}

kernel::Status SaveSlamMapPicture(const sim::World& world, const ExploreOutcome& outcome,
                                  const std::string& title, const std::vector<std::string>& paths) {
  const estimation::SlamMethod* slam = outcome.slam_method();
  if (slam == nullptr) return kernel::Status::Error("no SLAM map to draw");
  const Trajectories t = TrajectoriesOf(outcome.run);
  io::RunPicture picture;
  picture.title = title + " | " + slam->MapDescription();
  picture.world = &world;
  picture.world_color = io::Rgb{0.75, 0.75, 0.75};
  picture.truth = t.truth;
  picture.odometry = t.odometry;
  picture.estimates = {{outcome.slam->name() + " estimate", t.estimate}};
  io::DrawMap(slam->Map(), &picture);
  picture.pixels_per_meter = 40.0;
  return io::SaveRunPicture(picture, paths);
}

kernel::Status SaveTrajectoryErrorPlot(const ExploreOutcome& outcome, const std::string& title,
                                       const std::vector<std::string>& paths) {
  const Trajectories t = TrajectoriesOf(outcome.run);
  return io::SaveErrorPlot(title, t.truth,
                           {{"odometry", io::palette::kOdometry, t.odometry},
                            {outcome.run.localization, io::palette::kEstimate, t.estimate}},
                           paths);
}

kernel::Status SaveCoveragePlot(const ExploreOutcome& outcome, const std::string& title,
                                const std::vector<std::string>& paths) {
  io::PlotSeries coverage{"explored", io::palette::kTrue, outcome.coverage_time_s, {}};
  for (double f : outcome.coverage_fraction) coverage.y.push_back(100.0 * f);
  io::PlotSeries nodes{"nodes", io::palette::kEstimate, outcome.coverage_time_s, {}};
  for (std::size_t k = 0; k < outcome.coverage_time_s.size(); ++k)
    nodes.y.push_back(static_cast<double>(std::min(k + 1, outcome.run.nodes.size())));
  io::PlotOptions options;
  options.title = title;
  options.x_label = "simulated time (s)";
  return io::SavePlot({{"explored free space (%)", {coverage}}, {"nodes", {nodes}}}, options,
                      paths);
}

}  // namespace splam::runtime
