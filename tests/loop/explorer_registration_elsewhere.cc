// An explorer registered by a namespace-scope object of a translation unit that nothing else
// refers to (exploration::ExplorerRegistration), as a user's variant in a file of its own would
// be; RunExploration.RunsAnExplorerRegisteredInAnotherUnit checks it arrived and runs.
#include <memory>

#include "exploration/explorer.h"
#include "exploration/reg.h"

namespace splam::loop {
namespace {

// REG under another name.
class RegAgain : public exploration::Explorer {
 public:
  explicit RegAgain(const exploration::ExplorerOptions& options) : reg_(options) {}
  std::string name() const override { return "reg-again"; }
  exploration::ExplorationRun Run(exploration::RobotInterface* robot,
                                  exploration::Localization* localization) override {
    exploration::ExplorationRun run = reg_.Run(robot, localization);
    run.explorer = name();
    return run;
  }

 private:
  exploration::RegExplorer reg_;
};

const exploration::ExplorerRegistration kRegistered(
    "reg-again", "REG under another name, registered in another translation unit",
    [](const exploration::ExplorerOptions& o) { return std::make_unique<RegAgain>(o); });

}  // namespace
}  // namespace splam::loop
