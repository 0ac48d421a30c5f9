// Every splam command in the README, docs/ and the examples' READMEs, as written there: each
// parses (its options exist and take the values given), and the quick ones run. A command is a
// line of an indented code block that starts with `splam` or `build/apps/splam`; a trailing
// `# comment` and a `> file` redirection are not part of it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/apps/cli_util.h"

namespace splam {
namespace {

using namespace cli_test;  // NOLINT

struct DocCommand {
  std::string file;
  int line = 0;
  std::string args;      // after `splam`
  std::string redirect;  // "> file" when the line writes splam's output to a file
};

std::vector<DocCommand> DocumentedCommands() {
  const fs::path root = SPLAM_SOURCE_DIR;
  std::vector<fs::path> files = {root / "README.md"};
  for (const fs::path& dir : {root / "docs", root / "examples"})
    for (const auto& e : fs::recursive_directory_iterator(dir))
      if (e.path().extension() == ".md") files.push_back(e.path());
  std::vector<DocCommand> commands;
  for (const fs::path& f : files) {
    std::ifstream in(f);
    int number = 0;
    for (std::string line; std::getline(in, line);) {
      ++number;
      for (const std::string prefix : {"    build/apps/splam ", "    splam "}) {
        if (!line.starts_with(prefix)) continue;
        std::string args = line.substr(prefix.size());
        if (const std::size_t at = args.find(" #"); at != std::string::npos) args.resize(at);
        std::string redirect;
        if (const std::size_t at = args.find(" >"); at != std::string::npos) {
          redirect = args.substr(at + 1);
          args.resize(at);
        }
        commands.push_back({fs::relative(f, root).string(), number, args, redirect});
      }
    }
  }
  return commands;
}

TEST(DocumentedCommands, EveryOneParsesAsWritten) {
  const std::vector<DocCommand> commands = DocumentedCommands();
  EXPECT_GT(commands.size(), 40u);
  setenv("SPLAM_PARSE_ONLY", "1", 1);
  for (const DocCommand& c : commands) {
    const Output r = Splam(c.args);
    EXPECT_EQ(r.status, 0) << c.file << ":" << c.line << ": splam " << c.args << "\n" << r.text;
  }
  unsetenv("SPLAM_PARSE_ONLY");
}

// Names the docs use for the reader's own files: a command that holds one is parsed, not run.
bool HasPlaceholder(const DocCommand& c) {
  for (const char* name : {" LOG", "my_", "plan.png", "r.txt", "study.yaml", "experiments/"})
    if (c.args.find(name) != std::string::npos) return true;
  return false;
}

// Too long for the test suite: experiments, sweeps and explorations (minutes; their quick
// versions run in their own tests), and SLAM on a real log outside the README (the README's own
// runs, 10 s on intel).
bool IsLong(const DocCommand& c) {
  for (const char* command : {"experiment ", "sweep ", "explore "})
    if (c.args.starts_with(command)) return true;
  return c.args.starts_with("slam ") && c.file != "README.md" &&
         (c.args.find("intel") != std::string::npos || c.args.find("mit-") != std::string::npos);
}

// The documented commands that are quick run as written, one after the other (README first, so
// the runs/ directories later pages use exist), in a scratch copy of the tree's layout: the
// repository with runs/, and ../shared/datasets (the real logs, when this machine has them).
TEST(DocumentedCommands, TheQuickOnesRunAsWritten) {
  const fs::path root = Temp("documented");
  fs::remove_all(root);
  const fs::path repo = root / "repo";
  fs::create_directories(repo);
  const char* data = std::getenv("SPLAM_DATA");
  const fs::path datasets = data != nullptr ? fs::path(data) : fs::path(SPLAM_DEFAULT_DATA_DIR);
  const bool have_data = fs::exists(datasets / "intel.clf");
  if (have_data) {
    fs::create_directories(root / "shared");
    fs::create_directory_symlink(fs::absolute(datasets), root / "shared" / "datasets");
  }
  std::vector<DocCommand> commands = DocumentedCommands();
  std::stable_partition(commands.begin(), commands.end(),
                        [](const DocCommand& c) { return c.file == "README.md"; });
  int run = 0;
  std::vector<std::string> not_made;  // the --out of commands not run: later uses are not run
  for (const DocCommand& c : commands) {
    const bool uses_not_made = std::any_of(not_made.begin(), not_made.end(), [&](const auto& o) {
      return c.args.find(" " + o) != std::string::npos;
    });
    if (HasPlaceholder(c) || IsLong(c) || uses_not_made ||
        (!have_data && c.args.find("../shared/") != std::string::npos)) {
      if (const std::size_t at = c.args.find("--out "); at != std::string::npos) {
        const std::string out = c.args.substr(at + 6);
        not_made.push_back(out.substr(0, out.find(' ')));
      }
      continue;
    }
    const Output r = Splam(c.args + (c.redirect.empty() ? "" : " " + c.redirect), repo);
    ++run;
    EXPECT_EQ(r.status, 0) << c.file << ":" << c.line << ": splam " << c.args << "\n" << r.text;
  }
  EXPECT_GE(run, have_data ? 25 : 15) << run << " commands ran";
  if (!have_data)
    GTEST_SKIP() << "ran " << run << " commands; those on real logs need " << datasets
                 << " (or $SPLAM_DATA)";
}

}  // namespace
}  // namespace splam
