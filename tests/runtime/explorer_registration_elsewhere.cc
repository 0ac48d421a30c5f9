// An explorer registered by a namespace-scope object of a translation unit that nothing else
// refers to (exploration::ExplorerRegistration), as a user's variant in a file of its own would
// be; RunExploration.RunsAnExplorerRegisteredInAnotherUnit checks it arrived and runs with
// its own options.
#include <algorithm>
#include <memory>

#include "exploration/explorer.h"
#include "exploration/reg.h"

namespace splam::runtime {
namespace {

// Its own options: a node cap of its own.
struct RegAgainOptions {
  int node_cap = 1000;
  void VisitFields(kernel::FieldVisitor& v) { v.Field("node_cap", &node_cap, "nodes at most"); }
  kernel::Status Validate() const {
    return node_cap >= 1 ? kernel::Status::Ok() : kernel::Status::Error("node_cap must be >= 1");
  }
};

exploration::ExplorerOptions Capped(exploration::ExplorerOptions options,
                                    const RegAgainOptions& own) {
  options.max_nodes = std::min(options.max_nodes, own.node_cap);
  return options;
}

// REG under another name.
class RegAgain : public exploration::Explorer {
 public:
  RegAgain(const exploration::ExplorerOptions& options, const RegAgainOptions& own)
      : reg_(Capped(options, own)) {}
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

const exploration::ExplorerRegistration<RegAgainOptions> kRegistered(
    "reg-again", "REG under another name, registered in another translation unit",
    [](const exploration::ExplorerOptions& o, const RegAgainOptions& own) {
      return std::make_unique<RegAgain>(o, own);
    });

}  // namespace
}  // namespace splam::runtime
