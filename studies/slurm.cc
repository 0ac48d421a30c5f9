#include "studies/slurm.h"

#include <fmt/core.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "io/text.h"
#include "io/trajectory.h"

namespace splam::studies {
namespace {

// `text` in single quotes for the shell.
std::string ShellQuoted(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// Runs a shell command, returning its standard output and error and its exit status.
std::pair<int, std::string> Capture(const std::string& command) {
  std::string output;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return {-1, "cannot run " + command};
  std::array<char, 4096> buffer{};
  while (const std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe))
    output.append(buffer.data(), n);
  const int status = pclose(pipe);
  while (!output.empty() && (output.back() == '\n' || output.back() == '\r')) output.pop_back();
  return {status == -1 ? -1 : WEXITSTATUS(status), output};
}

}  // namespace

kernel::Status CheckScriptPath(const std::string& what, const std::string& path) {
  for (const char c : path) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f || c == '"')
      return kernel::Status::Error(fmt::format(
          "{} {} holds a control character or a double quote, which a Slurm job script cannot "
          "carry: choose another path",
          what, io::Quoted(path)));
  }
  return kernel::Status::Ok();
}

kernel::Status CheckSlurmPaths(const std::string& dir, const std::string& splam_binary) {
  return kernel::FirstError(
      CheckScriptPath("the sweep directory",
                      std::filesystem::absolute(dir).lexically_normal().string()),
      CheckScriptPath("the working directory", std::filesystem::current_path().string()),
      CheckScriptPath("the splam binary", std::filesystem::absolute(splam_binary).string()));
}

kernel::Status SlurmOptions::Validate() const {
  if (cpus_per_task < 1) return kernel::Status::Error("cpus_per_task must be at least 1");
  if (array_chunk < 1) return kernel::Status::Error("array_chunk must be at least 1");
  for (const std::string* s : {&partition, &time})
    if (s->find_first_of(" \t\n'\"") != std::string::npos)
      return kernel::Status::Error("a partition or time with spaces or quotes: '" + *s + "'");
  return kernel::Status::Ok();
}

std::string SlurmScript(const std::string& dir, const std::string& splam_binary, int cells,
                        const std::string& workdir, const SlurmOptions& options) {
  const int tasks = (cells + options.array_chunk - 1) / options.array_chunk;
  std::string script = "#!/bin/bash\n";
  script += "# A splam sweep as a Slurm job array, written by `splam sweep --slurm`.\n";
  // sbatch splits an #SBATCH line at whitespace outside double quotes; the paths hold neither
  // double quotes nor control characters (CheckScriptPath).
  script += fmt::format("#SBATCH --job-name=\"splam-sweep-{}\"\n",
                        std::filesystem::path(dir).filename().string());
  script += fmt::format("#SBATCH --array=0-{}\n", tasks - 1);
  script += fmt::format("#SBATCH --cpus-per-task={}\n", options.cpus_per_task);
  script += fmt::format("#SBATCH --output=\"{}/slurm/task-%A_%a.out\"\n", dir);
  script += fmt::format("#SBATCH --chdir=\"{}\"\n", workdir);
  if (!options.partition.empty()) script += "#SBATCH --partition=" + options.partition + "\n";
  if (!options.time.empty()) script += "#SBATCH --time=" + options.time + "\n";
  script += fmt::format(
      "# Task i runs lines i*{0}+1 .. i*{0}+{0} of slurm-cells.txt, each an index into cells.tsv.\n"
      "first=$((SLURM_ARRAY_TASK_ID * {0} + 1))\n"
      "for line in $(seq \"$first\" $((first + {0} - 1))); do\n"
      "  cell=$(sed -n \"${{line}}p\" {1}/slurm-cells.txt)\n"
      "  [[ -n $cell ]] || break\n"
      "  {2} sweep cell {1} \"$cell\" || echo \"cell $cell failed: exit $?\"\n"
      "done\n",
      options.array_chunk, ShellQuoted(dir), ShellQuoted(splam_binary));
  return script;
}

kernel::Result<std::string> SubmitSweepToSlurm(const std::string& dir,
                                               const std::string& splam_binary,
                                               const std::vector<int>& cells,
                                               const SlurmOptions& options) {
  using R = kernel::Result<std::string>;
  if (kernel::Status s = options.Validate(); !s.ok()) return R::Fail(s.message());
  if (cells.empty()) return R::Fail("every cell has already run: nothing to submit");
  if (kernel::Status s = CheckSlurmPaths(dir, splam_binary); !s.ok()) return R::Fail(s.message());
  const std::string abs_dir = std::filesystem::absolute(dir).lexically_normal().string();
  const std::string workdir = std::filesystem::current_path().string();
  const std::string binary = std::filesystem::absolute(splam_binary).string();
  std::error_code ec;
  std::filesystem::create_directories(abs_dir + "/slurm", ec);
  if (ec) return R::Fail("cannot create " + abs_dir + "/slurm: " + ec.message());
  std::string list;
  for (const int c : cells) list += std::to_string(c) + "\n";
  if (kernel::Status error = io::WriteTextFile(abs_dir + "/slurm-cells.txt", list); !error.ok())
    return R::Fail(error);
  const std::string script_path = abs_dir + "/sweep.sbatch";
  if (kernel::Status error = io::WriteTextFile(
          script_path,
          SlurmScript(abs_dir, binary, static_cast<int>(cells.size()), workdir, options));
      !error.ok())
    return R::Fail(error);
  const auto [status, output] = Capture(options.sbatch + " --parsable " + ShellQuoted(script_path));
  if (status != 0)
    return R::Fail(fmt::format("{} failed (exit {}): {}", options.sbatch, status, output));
  // --parsable prints "jobid" or "jobid;cluster".
  const std::string id =
      output.substr(output.rfind('\n') == std::string::npos ? 0 : output.rfind('\n') + 1);
  return R::Ok(id.substr(0, id.find(';')));
}

}  // namespace splam::studies
