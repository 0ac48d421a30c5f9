#include "studies/sweep.h"

#include "runtime/exit_status.h"

#include <fcntl.h>
#include <fmt/core.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "io/trajectory.h"
#include "runtime/json_text.h"

extern char** environ;

namespace splam::studies {

using runtime::JsonText;
using runtime::ReadJson;
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A value label as a file name: a path becomes its file name without extension; characters other
// than letters, digits, '.', '+' and '-' become '-'.
std::string NamePart(std::string label) {
  if (label.find('/') != std::string::npos) label = std::filesystem::path(label).stem().string();
  for (char& c : label)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '+' && c != '-') c = '-';
  return label.empty() ? "-" : label;
}

// "set.exploration.alpha" -> "alpha".
std::string AxisShortName(const std::string& axis) {
  const std::size_t dot = axis.rfind('.');
  return NamePart(dot == std::string::npos ? axis : axis.substr(dot + 1));
}

// The options in order, a later one replacing an earlier of the same name (a --set value of the
// same key, or a plain option: the command line takes each only once).
void AddOption(const io::GridOption& option, std::vector<io::GridOption>* options) {
  std::erase_if(*options, [&](const io::GridOption& o) {
    return o.name == option.name && o.set == option.set;
  });
  options->push_back(option);
}

std::vector<std::string> CommandLine(const io::Grid& grid,
                                     const std::vector<io::GridOption>& options) {
  std::vector<std::string> args = grid.command;
  for (const io::GridOption& o : options) {
    if (o.set) {
      args.insert(args.end(), {"--set", o.name + "=" + o.value});
    } else if (o.value == "true") {
      args.push_back("--" + o.name);
    } else if (o.value != "false") {
      args.insert(args.end(), {"--" + o.name, o.value});
    }
  }
  return args;
}

std::string Host() {
  char name[256] = {};
  return gethostname(name, sizeof(name) - 1) == 0 ? name : "unknown";
}

// The last non-empty line of a file (at most its last 64 KiB are read).
std::string LastLine(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return "";
  const std::streamoff size = in.tellg();
  const std::streamoff from = std::max<std::streamoff>(0, size - 65536);
  in.seekg(from);
  std::string text(static_cast<std::size_t>(size - from), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  const std::size_t newline = text.rfind('\n');
  return newline == std::string::npos ? text : text.substr(newline + 1);
}

// Starts a cell's command with its output in cell.log, in a process group of its own (a Ctrl-C
// at the terminal reaches the pool only, which passes one SIGINT on). Returns its pid, or -1 with
// the reason in cell.log.
pid_t SpawnCell(const std::string& dir, const SweepCell& cell, const std::string& binary) {
  const std::string cell_dir = CellDir(dir, cell);
  std::error_code ec;
  std::filesystem::create_directories(cell_dir, ec);
  std::filesystem::remove(cell_dir + "/cell.json", ec);
  std::vector<std::string> args = cell.args;
  args.insert(args.begin(), binary);
  args.insert(args.end(), {"--out", cell_dir});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string log = cell_dir + "/cell.log";
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&files, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&files, 1, 2);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attributes, 0);
  pid_t pid = -1;
  const int error = posix_spawn(&pid, binary.c_str(), &files, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  posix_spawnattr_destroy(&attributes);
  if (error != 0) {
    std::ofstream(log) << "cannot start " << binary << ": " << std::strerror(error) << "\n";
    return -1;
  }
  // A record for `sweep status`; the run goes on without it (it only says where the cell runs).
  static_cast<void>(io::WriteTextFile(
      cell_dir + "/cell.started",
      JsonText(nlohmann::json{{"host", Host()}, {"pid", pid}, {"args", args}}) + "\n"));
  return pid;
}

int ExitStatusOf(int wait_status) {
  if (WIFEXITED(wait_status)) return WEXITSTATUS(wait_status);
  if (WIFSIGNALED(wait_status)) return 128 + WTERMSIG(wait_status);
  return 255;
}

CellRecord FinishCell(const std::string& cell_dir, int exit_status, double wall_s) {
  CellRecord record;
  record.exit_status = exit_status;
  record.wall_s = wall_s;
  record.host = Host();
  record.message = LastLine(cell_dir + "/cell.log");
  if (exit_status > 128 && record.message.empty())
    record.message = "killed by signal " + std::to_string(exit_status - 128);
  // Unwritten, the cell counts as not finished and runs again on resume: say why.
  if (kernel::Status error = io::WriteTextFile(
          cell_dir + "/cell.json", JsonText(nlohmann::json{{"exit_status", record.exit_status},
                                                           {"wall_s", record.wall_s},
                                                           {"message", record.message},
                                                           {"host", record.host}},
                                            2) +
                                       "\n");
      !error.ok())
    record.message = error.message() + "; " + record.message;
  return record;
}

std::string Describe(const SweepCell& cell, const CellRecord& r) {
  std::ostringstream text;
  text.precision(1);
  text << std::fixed << cell.name << ": "
       << (r.exit_status == 0 ? "ok"
           : r.ok()           ? "ok, stopped early (exit 3)"
                              : "FAILED (exit " + std::to_string(r.exit_status) + "): " + r.message)
       << " (" << r.wall_s << " s)";
  return text.str();
}

std::string Duration(double s) {
  if (s < 0) return "?";
  const long total = std::lround(s);
  return total >= 3600 ? fmt::format("{}h{:02}m", total / 3600, total / 60 % 60)
                       : fmt::format("{}m{:02}s", total / 60, total % 60);
}

}  // namespace

std::function<void(const SweepProgress&)> PrintSweepProgress() {
  const bool terminal = isatty(fileno(stdout)) != 0;
  return [terminal](const SweepProgress& p) {
    const std::string status =
        fmt::format("[{}/{} done, {} failed, {} running, {} skipped; {} left]", p.done + p.skipped,
                    p.total, p.failed, p.running, p.skipped, Duration(p.eta_s));
    if (terminal) {
      if (!p.event.empty()) fmt::print("\r\033[K{}\n", p.event);
      fmt::print("\r\033[K{}", status);
    } else if (!p.event.empty()) {
      fmt::print("{} {}\n", status, p.event);
    }
    std::fflush(stdout);
  };
}

std::vector<SweepCell> GridCells(const io::Grid& grid) {
  std::vector<SweepCell> cells;
  std::vector<std::size_t> at(grid.axes.size(), 0);
  std::set<std::string> names;
  while (true) {
    SweepCell cell;
    std::vector<io::GridOption> options;
    for (const io::GridOption& o : grid.options) AddOption(o, &options);
    for (std::size_t a = 0; a < grid.axes.size(); ++a) {
      const io::GridValue& value = grid.axes[a].values[at[a]];
      cell.values.emplace_back(grid.axes[a].name, value.label);
      cell.name += (a ? "_" : "") + AxisShortName(grid.axes[a].name) + "-" + NamePart(value.label);
      for (const io::GridOption& o : value.options) AddOption(o, &options);
    }
    if (cell.name.empty()) cell.name = "single";
    if (!names.insert(cell.name).second) cell.name += "_" + std::to_string(cells.size());
    cell.args = CommandLine(grid, options);
    cells.push_back(std::move(cell));
    std::size_t a = grid.axes.size();
    while (a > 0 && ++at[a - 1] == grid.axes[a - 1].values.size()) at[--a] = 0;
    if (a == 0) break;
  }
  return cells;
}

std::string CellDir(const std::string& dir, const SweepCell& cell) {
  return dir + "/cells/" + cell.name;
}

kernel::Status WriteSweepPlan(const std::string& dir, const io::Grid& grid, bool* write_failed) {
  std::error_code ec;
  std::filesystem::create_directories(dir + "/cells", ec);
  if (ec) return kernel::Status::Error("cannot create " + dir + ": " + ec.message());
  const std::string grid_path = dir + "/grid.yaml";
  if (std::filesystem::exists(grid_path)) {
    io::Result<io::Grid> existing = io::ReadGrid(grid_path);
    if (!existing.ok()) return existing.status();
    if (*existing.value != grid)
      return kernel::Status::Error(dir + " holds the cells of another grid (" + grid_path +
                                   "): give another --out, or remove it");
  }
  std::ostringstream tsv;
  tsv << "# index\tname\tsplam command line (arguments separated by tabs; --out <dir>/cells/<name>"
         " follows)\n";
  const std::vector<SweepCell> cells = GridCells(grid);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    tsv << i << "\t" << cells[i].name;
    for (const std::string& a : cells[i].args) tsv << "\t" << a;
    tsv << "\n";
  }
  const kernel::Status written =
      kernel::FirstError(io::WriteTextFile(grid_path, io::GridToYaml(grid)),
                         io::WriteTextFile(dir + "/cells.tsv", tsv.str()));
  if (!written.ok() && write_failed != nullptr) *write_failed = true;
  return written;
}

kernel::Result<SweepPlan> ReadSweepPlan(const std::string& dir) {
  using R = kernel::Result<SweepPlan>;
  io::Result<io::Grid> grid = io::ReadGrid(dir + "/grid.yaml");
  if (!grid.ok()) return R::Fail(grid.error + " (is " + dir + " a sweep directory?)");
  SweepPlan plan{std::move(*grid.value), {}};
  // The cells and their command lines come from grid.yaml; cells.tsv, the record of what the
  // sweep runs, must say the same (a truncated or edited one ran other command lines than
  // grid.yaml, and filed their figures under other cells).
  std::vector<SweepCell> cells = GridCells(plan.grid);
  std::string text;
  const std::string path = dir + "/cells.tsv";
  if (kernel::Status error = io::ReadTextFile(path, &text); !error.ok()) return R::Fail(error);
  std::istringstream lines(text);
  int number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    const std::size_t i = plan.cells.size();
    std::vector<std::string> expected{std::to_string(i)};
    if (i < cells.size()) {
      expected.push_back(cells[i].name);
      expected.insert(expected.end(), cells[i].args.begin(), cells[i].args.end());
    }
    std::vector<std::string> fields;
    std::istringstream split(line);
    for (std::string f; std::getline(split, f, '\t');) fields.push_back(f);
    if (i >= cells.size() || fields != expected)
      return R::Fail(path + ":" + std::to_string(number) + ": not cell " + std::to_string(i) +
                     " of " + dir + "/grid.yaml");
    plan.cells.push_back(std::move(cells[i]));
  }
  if (plan.cells.size() != cells.size())
    return R::Fail(fmt::format("{} lists {} cells, {}/grid.yaml makes {}", path, plan.cells.size(),
                               dir, cells.size()));
  return R::Ok(std::move(plan));
}

std::optional<CellRecord> ReadCellRecord(const std::string& cell_dir) {
  std::ifstream in(cell_dir + "/cell.json");
  if (!in) return std::nullopt;
  // A record of other types than splam writes (a hand-edited or damaged file) is no record: the
  // cell runs again. `message` a number or `wall_s` a string aborted status, resume and merge.
  const nlohmann::json j = ReadJson(in);
  const auto is = [&](const char* key, bool (nlohmann::json::*type)() const noexcept) {
    return j.contains(key) && (j[key].*type)();
  };
  if (!j.is_object() || !is("exit_status", &nlohmann::json::is_number_integer) ||
      !is("wall_s", &nlohmann::json::is_number) || !is("message", &nlohmann::json::is_string) ||
      !is("host", &nlohmann::json::is_string))
    return std::nullopt;
  const auto status = j["exit_status"].get<long long>();
  if (status < 0 || status > 255) return std::nullopt;
  CellRecord r;
  r.exit_status = static_cast<int>(status);
  r.wall_s = j["wall_s"].get<double>();
  r.message = j["message"].get<std::string>();
  r.host = j["host"].get<std::string>();
  return r;
}

std::vector<int> CellsToRun(const std::string& dir, const SweepPlan& plan) {
  std::vector<int> cells;
  for (std::size_t i = 0; i < plan.cells.size(); ++i) {
    const std::optional<CellRecord> r = ReadCellRecord(CellDir(dir, plan.cells[i]));
    if (!r || !r->ok()) cells.push_back(static_cast<int>(i));
  }
  return cells;
}

CellRecord RunCell(const std::string& dir, const SweepCell& cell, const std::string& splam_binary) {
  const Clock::time_point start = Clock::now();
  const pid_t pid = SpawnCell(dir, cell, splam_binary);
  int status = 0;
  const int exit_status = pid < 0 || waitpid(pid, &status, 0) != pid ? 127 : ExitStatusOf(status);
  return FinishCell(CellDir(dir, cell), exit_status, SecondsSince(start));
}

kernel::Result<SweepRunSummary> RunSweepLocally(const std::string& dir,
                                                const SweepRunOptions& options) {
  const Clock::time_point start = Clock::now();
  SweepRunSummary summary;
  kernel::Result<SweepPlan> plan = ReadSweepPlan(dir);
  if (!plan.ok()) return kernel::Result<SweepRunSummary>::Fail(plan.error);
  const std::vector<SweepCell>& cells = plan.value->cells;
  summary.cells = static_cast<int>(cells.size());
  std::vector<std::size_t> pending;
  for (const int i : CellsToRun(dir, *plan.value)) pending.push_back(static_cast<std::size_t>(i));
  summary.skipped = summary.cells - static_cast<int>(pending.size());
  std::reverse(pending.begin(), pending.end());  // pop_back runs them in grid order
  const int jobs = options.jobs > 0
                       ? options.jobs
                       : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  struct Running {
    std::size_t cell;
    Clock::time_point start;
  };
  std::map<pid_t, Running> running;
  SweepProgress progress;
  progress.total = summary.cells;
  progress.skipped = summary.skipped;
  const auto report = [&](const std::string& event) {
    progress.running = static_cast<int>(running.size());
    progress.event = event;
    const int ended = summary.done + summary.failed;
    const double left =
        static_cast<double>(pending.size()) + 0.5 * static_cast<double>(running.size());
    progress.eta_s = ended > 0 ? summary.cells_wall_s / ended * left / jobs : -1.0;
    if (options.progress) options.progress(progress);
  };
  bool stopping = false;
  while ((!pending.empty() && !stopping) || !running.empty()) {
    if (!stopping && options.stop && options.stop()) {
      stopping = summary.interrupted = true;
      for (const auto& [pid, r] : running) kill(pid, SIGINT);
    }
    while (!stopping && !pending.empty() && static_cast<int>(running.size()) < jobs) {
      const std::size_t i = pending.back();
      pending.pop_back();
      const Clock::time_point cell_start = Clock::now();
      const pid_t pid = SpawnCell(dir, cells[i], options.splam_binary);
      if (pid < 0) {
        const CellRecord r = FinishCell(CellDir(dir, cells[i]), 127, 0.0);
        ++summary.failed;
        progress.failed = summary.failed;
        report(Describe(cells[i], r));
        continue;
      }
      running[pid] = {i, cell_start};
      report("");
    }
    bool ended = false;
    for (auto it = running.begin(); it != running.end();) {
      int status = 0;
      if (waitpid(it->first, &status, WNOHANG) != it->first) {
        ++it;
        continue;
      }
      ended = true;
      const Running r = it->second;
      it = running.erase(it);
      if (stopping) {  // interrupted: no record, it runs again next time
        std::error_code ec;
        std::filesystem::remove(CellDir(dir, cells[r.cell]) + "/cell.started", ec);
        continue;
      }
      const double wall = SecondsSince(r.start);
      const CellRecord record = FinishCell(CellDir(dir, cells[r.cell]), ExitStatusOf(status), wall);
      summary.cells_wall_s += wall;
      (record.ok() ? summary.done : summary.failed)++;
      if (record.exit_status == runtime::kExitWriteFailed) ++summary.write_failed;
      progress.done = summary.done;
      progress.failed = summary.failed;
      report(Describe(cells[r.cell], record));
    }
    if (!ended) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  summary.left = summary.cells - summary.skipped - summary.done - summary.failed;
  summary.wall_s = SecondsSince(start);
  return kernel::Result<SweepRunSummary>::Ok(summary);
}

kernel::Result<SweepStatus> ReadSweepStatus(const std::string& dir) {
  kernel::Result<SweepPlan> plan = ReadSweepPlan(dir);
  if (!plan.ok()) return kernel::Result<SweepStatus>::Fail(plan.error);
  SweepStatus status;
  for (const SweepCell& cell : plan.value->cells) {
    ++status.total;
    const std::string cell_dir = CellDir(dir, cell);
    if (const std::optional<CellRecord> r = ReadCellRecord(cell_dir)) {
      if (r->ok()) {
        ++status.done;
      } else {
        ++status.failed;
        status.failures.emplace_back(cell.name, *r);
      }
    } else if (std::filesystem::exists(cell_dir + "/cell.started")) {
      ++status.running;
    } else {
      ++status.pending;
    }
  }
  return kernel::Result<SweepStatus>::Ok(std::move(status));
}

}  // namespace splam::studies
