// Every splam command in the README, docs/ and the examples' READMEs, as written there: each
// parses (its options exist and take the values given), and the quick ones run. A command is a
// line of an indented code block that starts with `splam` or `build/apps/splam`; a trailing
// `# comment` and a `> file` redirection are not part of it.
#include <gtest/gtest.h>

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
  std::string args;  // after `splam`
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
        for (const char* cut : {" #", " >"})
          if (const std::size_t at = args.find(cut); at != std::string::npos) args.resize(at);
        commands.push_back({fs::relative(f, root).string(), number, args});
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

}  // namespace
}  // namespace splam
