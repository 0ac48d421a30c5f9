// splam eval: score trajectories against ground truth and with the relations metric.
#include <fmt/core.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "apps/output_paths.h"
#include "estimation/evaluation/metrics.h"
#include "io/relations.h"
#include "io/run_picture.h"
#include "io/trajectory.h"
#include "kernel/angle.h"
#include "runtime/json_text.h"
#include "runtime/slam_report.h"

namespace splam::apps {
namespace {

struct EvalArgs {
  std::string run;
  std::string estimate, truth, odometry, relations, out;
  std::string label = "estimate";
};

// Why a trajectory could not be scored: "" when `used` items (poses matched, relations with both
// times) are more than 0 and every figure is finite. A metric over nothing is no zero, and a
// figure that overflowed is no number (it was written as null).
std::string NotScored(std::size_t used, const std::string& item, const std::string& against,
                      const std::string& label, std::initializer_list<double> figures) {
  if (used == 0)
    return label + ": no " + item + " of " + against + " matches a time of the trajectory";
  for (const double f : figures)
    if (!std::isfinite(f)) return label + ": the error against " + against + " is not finite";
  return "";
}

// Reports a trajectory that could not be scored (NotScored); returns the exit status after it: the
// input scored nothing.
int ReportNotScored(int status, const std::string& problem) {
  fmt::print(stderr, "splam eval: {}\n", problem);
  return std::max(status, kExitBadInput);
}

// The absolute trajectory error after SE(2) alignment of every run that matched the truth.
void ReportAlignedErrors(const kernel::Trajectory& truth,
                         const std::vector<std::pair<std::string, kernel::Trajectory>>& runs,
                         nlohmann::ordered_json* report) {
  fmt::print(
      "absolute trajectory error after SE(2) alignment:\n  {:<10} {:>12} {:>12} {:>12} {:>12} "
      "{:>15} {:>18}\n",
      "", "RMSE (m)", "mean (m)", "median (m)", "max (m)", "RMSE head (deg)", "alignment");
  for (const auto& [label, trajectory] : runs) {
    const evaluation::AlignedError e = evaluation::AbsoluteTrajectoryError(truth, trajectory);
    if (e.matched == 0 || !std::isfinite(e.rmse_m)) continue;  // said by the table above
    const kernel::Pose2& a = e.truth_T_estimate;
    (*report)["ate"][label] = {{"matched_poses", e.matched},
                               {"rmse_m", e.rmse_m},
                               {"mean_m", e.mean_m},
                               {"median_m", e.median_m},
                               {"std_m", e.std_m},
                               {"max_m", e.max_m},
                               {"rmse_heading_deg", kernel::RadToDeg(e.rmse_heading_rad)},
                               {"alignment", {a.x(), a.y(), a.theta()}}};
    fmt::print("  {:<10} {:>12.4f} {:>12.4f} {:>12.4f} {:>12.4f} {:>15.2f} {:>18}\n", label,
               e.rmse_m, e.mean_m, e.median_m, e.max_m, kernel::RadToDeg(e.rmse_heading_rad),
               fmt::format("{:.2f} {:.2f} {:.1f}deg", a.x(), a.y(), kernel::RadToDeg(a.theta())));
  }
}

int RunEval(EvalArgs args) {
  // A trajectory file given where the run directory goes is the estimate.
  if (!args.run.empty() && std::filesystem::is_regular_file(args.run) && args.estimate.empty()) {
    args.estimate = args.run;
    args.run.clear();
  }
  if (!args.run.empty()) {
    const std::filesystem::path dir(args.run);
    if (args.estimate.empty()) args.estimate = (dir / "trajectory.txt").string();
    if (args.odometry.empty() && std::filesystem::exists(dir / "odometry.txt"))
      args.odometry = (dir / "odometry.txt").string();
    if (args.truth.empty() && std::filesystem::exists(dir / "truth.txt"))
      args.truth = (dir / "truth.txt").string();
    if (args.out.empty()) args.out = args.run;
  }
  if (args.estimate.empty()) {
    fmt::print(stderr, "splam eval: give a run directory or --estimate\n");
    return kExitBadInput;
  }
  if (args.truth.empty() && args.relations.empty()) {
    fmt::print(stderr,
               "splam eval: nothing to compare with: give --truth or --relations (or a run with "
               "truth.txt)\n");
    return kExitBadInput;
  }
  if (!args.out.empty()) {
    CommandFiles files;
    files.inputs = {{"--estimate", args.estimate},
                    {"--odometry", args.odometry},
                    {"--truth", args.truth},
                    {"--relations", args.relations}};
    files.AddOutputs(args.out, {"eval.json", "eval_errors.svg", "eval_errors.png"});
    if (const kernel::Status s = OutputOverwritesInput(files); !s.ok()) {
      fmt::print(stderr, "splam eval: {}\n", s.message());
      return kExitBadInput;
    }
  }
  // Trajectories to score: the estimate and, as the baseline, raw odometry.
  std::vector<std::pair<std::string, kernel::Trajectory>> runs;
  for (const auto& [label, path] :
       {std::pair{args.label, args.estimate}, std::pair{std::string("odometry"), args.odometry}}) {
    if (path.empty()) continue;
    io::Result<kernel::Trajectory> t = io::ReadTrajectory(path);
    if (!t.ok()) {
      fmt::print(stderr, "splam eval: {}\n", t.error);
      return kExitBadInput;
    }
    runs.emplace_back(label, std::move(*t.value));
  }
  nlohmann::ordered_json report;
  int status = kExitOk;
  if (!args.truth.empty()) {
    io::Result<kernel::Trajectory> truth = io::ReadTrajectory(args.truth);
    if (!truth.ok()) {
      fmt::print(stderr, "splam eval: {}\n", truth.error);
      return kExitBadInput;
    }
    fmt::print("against ground truth ({}):\n  {:<10} {:>12} {:>12} {:>14} {:>14} {:>8}\n",
               args.truth, "", "RMSE pos (m)", "max pos (m)", "RMSE head (deg)", "max head (deg)",
               "poses");
    std::vector<std::tuple<std::string, io::Rgb, kernel::Trajectory>> plotted;
    for (const auto& [label, trajectory] : runs) {
      const evaluation::TrajectoryError e = evaluation::CompareToTruth(*truth.value, trajectory);
      if (const std::string problem = NotScored(e.matched, "pose", args.truth, label,
                                                {e.rmse_position_m, e.rmse_heading_rad});
          !problem.empty()) {
        report["truth"][label] = {{"error", problem}};
        status = ReportNotScored(status, problem);
        continue;
      }
      report["truth"][label] = {{"matched_poses", e.matched},
                                {"rmse_position_m", e.rmse_position_m},
                                {"max_position_m", e.max_position_m},
                                {"rmse_heading_deg", kernel::RadToDeg(e.rmse_heading_rad)},
                                {"max_heading_deg", kernel::RadToDeg(e.max_heading_rad)}};
      fmt::print("  {:<10} {:>12.3f} {:>12.3f} {:>14.2f} {:>14.2f} {:>8}\n", label,
                 e.rmse_position_m, e.max_position_m, kernel::RadToDeg(e.rmse_heading_rad),
                 kernel::RadToDeg(e.max_heading_rad), e.matched);
      plotted.emplace_back(
          label, label == "odometry" ? io::palette::kOdometry : io::palette::kEstimate, trajectory);
    }
    ReportAlignedErrors(*truth.value, runs, &report);
    if (!args.out.empty()) {
      kernel::Status e = CreateOutputDirectory(args.out);
      if (e.ok())
        e = io::SaveErrorPlot("error against ground truth", *truth.value, plotted,
                              {args.out + "/eval_errors.svg", args.out + "/eval_errors.png"});
      if (!e.ok()) {
        fmt::print(stderr, "splam eval: {}\n", e.message());
        return kExitWriteFailed;
      }
    }
  }
  if (!args.relations.empty()) {
    io::Result<std::vector<evaluation::Relation>> relations = io::ReadRelations(args.relations);
    if (!relations.ok()) {
      fmt::print(stderr, "splam eval: {}\n", relations.error);
      return kExitBadInput;
    }
    fmt::print("relations metric ({}, {} relations):\n  {:<10} {:>22} {:>22} {:>6}\n",
               args.relations, relations.value->size(), "", "translation (m)", "rotation (deg)",
               "used");
    for (const auto& [label, trajectory] : runs) {
      const evaluation::RelationsError r =
          evaluation::EvaluateRelations(*relations.value, trajectory);
      if (const std::string problem =
              NotScored(r.used, "relation", args.relations, label,
                        {r.translation_mean, r.translation_std, r.rotation_mean, r.rotation_std});
          !problem.empty()) {
        report["relations"][label] = {{"error", problem}};
        status = ReportNotScored(status, problem);
        continue;
      }
      report["relations"][label] = runtime::RelationsJson(r);
      fmt::print("  {:<10} {:>10.4f} +- {:<9.4f} {:>10.3f} +- {:<9.3f} {:>6}\n", label,
                 r.translation_mean, r.translation_std, kernel::RadToDeg(r.rotation_mean),
                 kernel::RadToDeg(r.rotation_std), r.used);
    }
  }
  if (!args.out.empty()) {
    kernel::Status e = CreateOutputDirectory(args.out);
    if (e.ok()) e = io::WriteTextFile(args.out + "/eval.json", runtime::JsonText(report, 2) + "\n");
    if (!e.ok()) {
      fmt::print(stderr, "splam eval: {}\n", e.message());
      return kExitWriteFailed;
    }
    fmt::print("wrote {}/eval.json{}\n", args.out,
               args.truth.empty() ? "" : " and eval_errors.{svg,png}");
  }
  return status;
}

}  // namespace

void AddEvalCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* cmd = app->add_subcommand("eval",
                                      "Score a trajectory against ground truth (RMSE, max, error "
                                      "plots, and the absolute trajectory error after SE(2) "
                                      "alignment) and/or with the relations metric; raw "
                                      "odometry is scored too as the baseline.");
  cmd->add_option("run", args->run,
                  "A run directory of `splam slam` (trajectory.txt, odometry.txt, truth.txt), or "
                  "a trajectory file (the estimate)");
  cmd->add_option("--estimate", args->estimate,
                  "Estimated trajectory: splam 'time x y theta', TUM or KITTI (told by the values "
                  "per line)");
  cmd->add_option("--truth", args->truth, "Ground-truth trajectory");
  cmd->add_option("--odometry", args->odometry, "Odometry trajectory (the baseline)");
  cmd->add_option("--relations", args->relations,
                  "Relations file of the SLAM benchmark (t1 t2 x y z roll pitch yaw)");
  cmd->add_option("--label", args->label, "Name of the estimate in tables")->capture_default_str();
  cmd->add_option("--out", args->out,
                  "Where eval.json and the error plots go (default: the run directory)");
  cmd->callback([args, exit_code] { *exit_code = RunEval(*args); });
}

}  // namespace splam::apps
