#include <algorithm>

#include "estimation/slam_method.h"

namespace splam::estimation {

void AddBuiltinSlamMethods(SlamRegistry* registry);  // builtin_slam_methods.cc

SlamRegistry& SlamRegistry::Global() {
  static SlamRegistry* const registry = [] {
    auto* r = new SlamRegistry;
    AddBuiltinSlamMethods(r);
    return r;
  }();
  return *registry;
}

void SlamRegistry::Add(SlamMethodInfo info) {
  const auto same = std::find_if(methods_.begin(), methods_.end(),
                                 [&](const SlamMethodInfo& m) { return m.name == info.name; });
  if (same != methods_.end()) {
    *same = std::move(info);
  } else {
    methods_.push_back(std::move(info));
  }
}

const SlamMethodInfo* SlamRegistry::Find(const std::string& name) const {
  for (const SlamMethodInfo& m : methods_)
    if (m.name == name) return &m;
  return nullptr;
}

std::vector<std::string> SlamRegistry::Names() const {
  std::vector<std::string> names;
  for (const SlamMethodInfo& m : methods_) names.push_back(m.name);
  return names;
}

std::string SlamRegistry::NameList() const {
  std::string list;
  for (const SlamMethodInfo& m : methods_) list += (list.empty() ? "" : ", ") + m.name;
  return list;
}

std::string SlamRegistry::Describe() const {
  std::string text;
  for (const SlamMethodInfo& m : methods_)
    text += (text.empty() ? "" : "\n") + m.name + ": " + m.description;
  return text;
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
