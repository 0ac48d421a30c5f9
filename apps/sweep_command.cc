// splam sweep: experiment grids on all cores or on a Slurm cluster, merged into one report.
//   splam sweep GRID.yaml [--jobs N] [--out DIR] [--slurm ...]
//   splam sweep status DIR | splam sweep merge DIR | splam sweep cell DIR INDEX
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <cstdio>
#include <filesystem>

#include "apps/commands.h"
#include "apps/interrupt.h"
#include "io/sweep_grid.h"
#include "studies/slurm.h"
#include "studies/sweep.h"
#include "studies/sweep_merge.h"

namespace splam::apps {
namespace {

struct SweepArgs {
  std::string grid, out, dir;
  int jobs = 0;
  bool slurm = false, merge = true;
  studies::SlurmOptions slurm_options;
  std::vector<int> cells;  // sweep cell
};

int Merge(const std::string& dir) {
  kernel::Result<studies::MergedSweep> merged = studies::MergeSweep(dir);
  if (!merged.ok()) {
    fmt::print(stderr, "splam sweep merge: {}\n", merged.error);
    return kExitBadInput;
  }
  kernel::Result<std::vector<std::string>> written = studies::WriteMergedSweep(*merged.value);
  if (!written.ok()) {
    fmt::print(stderr, "splam sweep merge: {}\n", written.error);
    return kExitWriteFailed;
  }
  int missing = 0;
  for (const studies::MergedCell& c : merged.value->cells) missing += !c.record || !c.record->ok();
  fmt::print("merged {} cells ({} without results) into {}/{{table.csv, table.md, report.html}}\n",
             merged.value->cells.size(), missing, dir);
  return missing ? kExitIncomplete : kExitOk;
}

int Status(const std::string& dir) {
  kernel::Result<studies::SweepStatus> status = studies::ReadSweepStatus(dir);
  if (!status.ok()) {
    fmt::print(stderr, "splam sweep status: {}\n", status.error);
    return kExitBadInput;
  }
  const studies::SweepStatus& s = *status.value;
  fmt::print("{}: {} cells: {} done, {} failed, {} running, {} not started\n", dir, s.total, s.done,
             s.failed, s.running, s.pending);
  for (const auto& [name, record] : s.failures)
    fmt::print("  {}: exit {} on {}: {}\n", name, record.exit_status, record.host, record.message);
  return s.done == s.total ? kExitOk : kExitIncomplete;
}

int RunCells(const SweepArgs& args) {
  kernel::Result<studies::SweepPlan> plan = studies::ReadSweepPlan(args.dir);
  if (!plan.ok()) {
    fmt::print(stderr, "splam sweep cell: {}\n", plan.error);
    return kExitBadInput;
  }
  int worst = kExitOk;
  for (const int index : args.cells) {
    if (index < 0 || index >= static_cast<int>(plan.value->cells.size())) {
      fmt::print(stderr, "splam sweep cell: {} has no cell {} (0 to {})\n", args.dir, index,
                 plan.value->cells.size() - 1);
      return kExitBadInput;
    }
    const studies::SweepCell& cell = plan.value->cells[static_cast<std::size_t>(index)];
    const studies::CellRecord r = studies::RunCell(args.dir, cell, SplamBinary());
    fmt::print("{}: exit {} in {:.1f} s{}\n", cell.name, r.exit_status, r.wall_s,
               r.ok() ? "" : ": " + r.message);
    if (!r.ok()) worst = r.exit_status;
  }
  return worst;
}

// Every option a cell would give (fixed ones and every axis value's, --set keys aside) is an
// option of the grid's command: a misspelt axis is refused before any cell runs.
kernel::Status CheckGridOptions(const CLI::App& root, const io::Grid& grid,
                                const std::string& path) {
  const CLI::App* command = &root;
  std::string name = "splam";
  for (const std::string& word : grid.command) {
    const std::vector<const CLI::App*> named =
        command->get_subcommands([&](const CLI::App* c) { return c->get_name() == word; });
    name += " " + word;
    if (named.empty()) return kernel::Status::Error(path + ": command: no `" + name + "`");
    command = named.front();
  }
  std::vector<std::pair<std::string, const io::GridOption*>> given;  // (where, option)
  for (const io::GridOption& o : grid.options) given.emplace_back("options", &o);
  for (const io::GridAxis& a : grid.axes)
    for (const io::GridValue& v : a.values)
      for (const io::GridOption& o : v.options) given.emplace_back("axis " + a.name, &o);
  for (const auto& [where, option] : given) {
    if (option->set || command->get_option_no_throw("--" + option->name) != nullptr) continue;
    std::vector<std::string> known;
    for (const CLI::Option* o : command->get_options())
      if (o->get_lnames().size() == 1 && o->get_group() != "" && o->get_lnames()[0] != "help")
        known.push_back(o->get_lnames()[0]);
    return kernel::Status::Error(
        fmt::format("{}: {}: --{} is not an option of `{}`; its options: {}", path, where,
                    option->name, name, fmt::join(known, ", ")));
  }
  return kernel::Status::Ok();
}

int RunGrid(const CLI::App& root, const SweepArgs& args) {
  io::Result<io::Grid> grid = io::ReadGrid(args.grid);
  if (!grid.ok()) {
    fmt::print(stderr, "splam sweep: {}\n", grid.error);
    return kExitBadInput;
  }
  if (kernel::Status s = CheckGridOptions(root, *grid.value, args.grid); !s.ok()) {
    fmt::print(stderr, "splam sweep: {}\n", s.message());
    return kExitBadInput;
  }
  const std::string dir = args.out.empty()
                              ? "runs/sweep-" + std::filesystem::path(args.grid).stem().string()
                              : args.out;
  if (args.slurm) {  // before the plan is written: a path a job script cannot carry
    if (kernel::Status s = studies::CheckSlurmPaths(dir, SplamBinary()); !s.ok()) {
      fmt::print(stderr, "splam sweep: {}\n", s.message());
      return kExitBadInput;
    }
  }
  bool write_failed = false;
  if (kernel::Status s = studies::WriteSweepPlan(dir, *grid.value, &write_failed); !s.ok()) {
    fmt::print(stderr, "splam sweep: {}\n", s.message());
    return write_failed ? kExitWriteFailed : kExitBadInput;
  }
  if (args.slurm) {
    kernel::Result<studies::SweepPlan> plan = studies::ReadSweepPlan(dir);
    if (!plan.ok()) {
      fmt::print(stderr, "splam sweep: {}\n", plan.error);
      return kExitBadInput;
    }
    const std::vector<int> pending = studies::CellsToRun(dir, *plan.value);
    kernel::Result<std::string> job =
        studies::SubmitSweepToSlurm(dir, SplamBinary(), pending, args.slurm_options);
    if (!job.ok()) {
      fmt::print(stderr, "splam sweep: {}\n", job.error);
      return kExitBadInput;
    }
    fmt::print(
        "submitted job {} ({} cells); follow it with `splam sweep status {}`, then run "
        "`splam sweep merge {}`\n",
        *job.value, pending.size(), dir, dir);
    return kExitOk;
  }
  CatchInterrupts();
  studies::SweepRunOptions options;
  options.splam_binary = SplamBinary();
  options.jobs = args.jobs;
  options.stop = [] { return Interrupted(); };
  options.progress = studies::PrintSweepProgress();
  kernel::Result<studies::SweepRunSummary> run = studies::RunSweepLocally(dir, options);
  if (!run.ok()) {
    fmt::print(stderr, "splam sweep: {}\n", run.error);
    return kExitBadInput;
  }
  const studies::SweepRunSummary& s = *run.value;
  fmt::print(
      "\n{}: {} cells: {} run now ({} failed), {} skipped (done before), {} left; {:.1f} s "
      "wall for {:.1f} s of cells ({:.2f})\n",
      dir, s.cells, s.done + s.failed, s.failed, s.skipped, s.left, s.wall_s, s.cells_wall_s,
      s.cells_wall_s > 0 ? s.wall_s / s.cells_wall_s : 0.0);
  if (s.interrupted) {
    fmt::print("interrupted: the {} cells left run when the same command is given again\n", s.left);
    return kExitIncomplete;
  }
  const int merged = args.merge ? Merge(dir) : kExitOk;
  // A cell that could not write its results (a full disk) makes the sweep's a failed write.
  if (s.write_failed > 0 || merged == kExitWriteFailed) {
    if (s.write_failed > 0)
      fmt::print(stderr, "splam sweep: {} cells could not write their results (exit 4)\n",
                 s.write_failed);
    return kExitWriteFailed;
  }
  return s.failed > 0 || merged != kExitOk ? kExitIncomplete : kExitOk;
}

}  // namespace

std::string SplamBinary() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? "splam" : self.string();
}

void AddSweepCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<SweepArgs>();
  CLI::App* cmd = app->add_subcommand(
      "sweep",
      "Run a grid of splam runs (a YAML file: command, options, axes) on all cores or as a Slurm "
      "job array, then merge their figures into table.csv, table.md and report.html "
      "(docs/sweeps.md)");
  cmd->add_option("grid", args->grid, "Grid file (see experiments/*.yaml)");
  cmd->add_option("--out", args->out, "Sweep directory (default runs/sweep-<grid name>)");
  cmd->add_option("--jobs", args->jobs, "Cells run at once (default: one per core)")
      ->check(FinitePositive());
  cmd->add_flag("!--no-merge", args->merge, "Do not merge the cells when the sweep ends");
  cmd->add_flag("--slurm", args->slurm,
                "Submit the cells as a Slurm job array instead of running them here");
  cmd->add_option("--partition", args->slurm_options.partition, "Slurm partition");
  cmd->add_option("--time", args->slurm_options.time, "Slurm time limit per array task");
  cmd->add_option("--cpus-per-task", args->slurm_options.cpus_per_task, "Slurm CPUs per task")
      ->check(FinitePositive())
      ->capture_default_str();
  cmd->add_option("--array-chunk", args->slurm_options.array_chunk, "Cells per Slurm array task")
      ->check(FinitePositive())
      ->capture_default_str();
  cmd->require_subcommand(0, 1);

  CLI::App* status = cmd->add_subcommand("status", "Cells done, failed, running and not started");
  status->add_option("dir", args->dir, "Sweep directory")->required();
  CLI::App* merge =
      cmd->add_subcommand("merge", "Write table.csv, table.md and report.html of a sweep");
  merge->add_option("dir", args->dir, "Sweep directory")->required();
  CLI::App* cell = cmd->add_subcommand(
      "cell", "Run cells of a sweep by index (what each Slurm array task does)");
  cell->add_option("dir", args->dir, "Sweep directory")->required();
  cell->add_option("index", args->cells, "Cell indices (cells.tsv)")->required();

  status->callback([args, exit_code] { *exit_code = Status(args->dir); });
  merge->callback([args, exit_code] { *exit_code = Merge(args->dir); });
  cell->callback([args, exit_code] { *exit_code = RunCells(*args); });
  cmd->callback([app, cmd, args, exit_code] {
    if (!cmd->get_subcommands().empty()) return;
    if (args->grid.empty()) {
      fmt::print(stderr, "splam sweep: give a grid file, or status/merge DIR\n");
      *exit_code = kExitBadInput;
      return;
    }
    *exit_code = RunGrid(*app, *args);
  });
}

}  // namespace splam::apps
