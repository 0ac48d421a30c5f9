// libFuzzer harness: a sweep directory's state, which a user, a crashed cell or a full disk may
// have changed, through what `sweep status`, resume and `sweep merge`
// read: grid.yaml, cells.tsv and, for the first two cells, cell.json, summary.json and
// report.json. The input is those five files separated by NUL bytes. The cells' files are also
// read in a fixed directory without a plan (ReadCellRecord, RunFigures), so that the JSON
// readers are reached when the grid and cells.tsv do not agree.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "runtime/run_html.h"
#include "studies/sweep.h"
#include "studies/sweep_merge.h"

namespace {

void Write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

// A directory of this process's own, removed at exit (the path outlives the static destructors).
const std::string& Scratch() {
  static const std::string* const dir = [] {
    // In memory where there is a writable tmpfs: creating files on a disk took half the time.
    for (const std::filesystem::path& base :
         {std::filesystem::path("/dev/shm"), std::filesystem::temp_directory_path()}) {
      std::string pattern = base / "splam-fuzz-sweep-XXXXXX";
      if (!mkdtemp(pattern.data())) continue;
      std::atexit([] { std::filesystem::remove_all(Scratch()); });
      return new std::string(pattern);
    }
    std::abort();
  }();
  return *dir;
}

void WriteCellFiles(const std::string& cell_dir, const std::vector<std::string>& parts) {
  std::error_code ec;  // a cell name longer than a file name may be: the files are not there
  std::filesystem::create_directories(cell_dir, ec);
  Write(cell_dir + "/cell.json", parts[2]);
  Write(cell_dir + "/summary.json", parts[3]);
  Write(cell_dir + "/report.json", parts[4]);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace runtime = splam::runtime;
  namespace studies = splam::studies;
  std::vector<std::string> parts(1);
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] == 0 && parts.size() < 5) {
      parts.emplace_back();
    } else {
      parts.back().push_back(static_cast<char>(data[i]));
    }
  }
  parts.resize(5);
  const std::string dir = Scratch() + "/sweep";
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  std::filesystem::create_directories(dir, ec);
  Write(dir + "/grid.yaml", parts[0]);
  Write(dir + "/cells.tsv", parts[1]);

  const std::string loose = dir + "/loose";
  WriteCellFiles(loose, parts);
  static_cast<void>(studies::ReadCellRecord(loose));
  static_cast<void>(runtime::RunFigures(loose));

  const auto plan = studies::ReadSweepPlan(dir);
  if (!plan.ok()) return 0;
  for (std::size_t c = 0; c < plan.value->cells.size() && c < 2; ++c)
    WriteCellFiles(studies::CellDir(dir, plan.value->cells[c]), parts);
  static_cast<void>(studies::CellsToRun(dir, *plan.value));
  static_cast<void>(studies::ReadSweepStatus(dir));
  const auto merged = studies::MergeSweep(dir);
  if (merged.ok()) static_cast<void>(studies::WriteMergedSweep(*merged.value));
  return 0;
}
