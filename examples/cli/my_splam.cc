// Tutorial: a splam program of your own. Its variants are registered in one line each and then
// offered by every subcommand of `splam`, beside the built-in ones:
//   example_my_splam slam --method scan-matcher LOG --out DIR
//   example_my_splam explore --explorer reg-again --localization scan-matcher
//   example_my_splam config print --method scan-matcher
// The rest of the program is the command line itself, splam::cli (apps/cli.h).
#include <memory>

#include "apps/cli.h"
#include "estimation/slam_method.h"
#include "examples/estimation/scan_matcher.h"
#include "exploration/explorer.h"
#include "exploration/reg.h"

namespace {

// An explorer variant: REG, under a name of its own. A variant that changes the strategy
// implements exploration::Explorer::Run the same way (see exploration/reg.h).
class RegUnderAnotherName : public splam::exploration::Explorer {
 public:
  explicit RegUnderAnotherName(const splam::exploration::ExplorerOptions& options)
      : reg_(options) {}
  std::string name() const override { return "reg-again"; }
  splam::exploration::ExplorationRun Run(splam::exploration::RobotInterface* robot,
                                         splam::exploration::Localization* localization) override {
    splam::exploration::ExplorationRun run = reg_.Run(robot, localization);
    run.explorer = name();
    return run;
  }

 private:
  splam::exploration::RegExplorer reg_;
};

}  // namespace

int main(int argc, char** argv) {
  namespace estimation = splam::estimation;
  namespace exploration = splam::exploration;
  // 1. The SLAM variant of examples/estimation/, in one line.
  estimation::RegisterSlamMethod<my_lab::ScanMatcherOptions>(
      "scan-matcher", "odometry corrected by scan-to-previous-scan ICP (tutorial)",
      [](const my_lab::ScanMatcherOptions& o, const estimation::SlamContext& c) {
        return std::make_unique<my_lab::ScanMatcher>(o, c);
      });
  // 2. The explorer variant, in one line.
  exploration::RegisterExplorer("reg-again", "REG under another name (tutorial)",
                                [](const exploration::ExplorerOptions& o) {
                                  return std::make_unique<RegUnderAnotherName>(o);
                                });
  // 3. The command line, with both among its choices.
  return splam::apps::Main(argc, argv);
}
