#include "estimation/ekf/ekf_methods.h"
#include "estimation/pose_graph/graph_method.h"
#include "estimation/slam_method.h"
#include "estimation/topological/topological_methods.h"

namespace splam::estimation {
namespace {

// The built-in methods, in the order the command line lists them; each family registers its
// own beside its code.
void AddBuiltinSlamMethods(kernel::Registry<SlamMethodInfo>* registry) {
  AddEkfMethods(registry);
  AddTopologicalMethod(registry);
  AddGraphSlamMethod(registry);
  AddTopologicalGraphMethod(registry);
}

}  // namespace

SlamRegistry& SlamRegistry::Global() {
  static SlamRegistry registry(AddBuiltinSlamMethods);
  return registry;
}

kernel::Result<std::unique_ptr<SlamMethod>> SlamRegistry::Make(const std::string& name,
                                                               const SlamOptions* options,
                                                               const SlamContext& context) const {
  using R = kernel::Result<std::unique_ptr<SlamMethod>>;
  const SlamMethodInfo* info = Find(name);
  if (info == nullptr) {
    return R::Fail("unknown SLAM method '" + name + "' (" + NameList() + ")");
  }
  std::unique_ptr<SlamOptions> defaults;
  if (options == nullptr) {
    defaults = info->default_options(SensorNoise());
    options = defaults.get();
  }
  if (kernel::Status s = options->Validate(); !s.ok())
    return R::Fail(s.Prefixed(name + " options"));
  std::unique_ptr<SlamMethod> method = info->make(*options, context);
  if (!method) return R::Fail("the options given are not " + name + "'s");
  return R::Ok(std::move(method));
}

}  // namespace splam::estimation
