// libFuzzer harness: option values, in and out of range, through short runs
// (tests/fuzz/README.md). The bytes pick a SLAM method or an explorer, then up to eight of its
// options (every field its VisitFields lists, nested groups included; an explorer's shared options
// and its own) and a value for each: zero, negative, tiny, huge, NaN, infinite, the default scaled,
// or any double. Options that pass Validate run: the method over the first scans of a simulated lap
// of `complex`, the explorer (with the simulator and ground truth) for up to two nodes. A crash, a
// hang or an allocation past the limit is a defect: Validate must cover every option's whole
// domain.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "estimation/slam_method.h"
#include "exploration/explorer.h"
#include "kernel/options.h"
#include "runtime/exploration_run.h"
#include "sim/builtin_worlds.h"
#include "sim/ray_caster.h"
#include "sim/simulator.h"
#include "tests/fuzz/fuzzed_scan.h"

namespace splam::fuzz {
namespace {

double FuzzedDouble(Bytes* in, double current) {
  static constexpr double kValues[] = {0.0,  -0.0,  1e-300, 1e-12, 1e-6, 1e-3,  0.01,  0.1,
                                       0.5,  1.0,   2.0,    3.0,   10.0, 100,   1e3,   1e6,
                                       1e12, 1e308, -1e-6,  -1.0,  -1e6, 0.999, 1.001, 4.0};
  const std::uint8_t pick = in->Byte();
  if (pick < 96) return kValues[pick % std::size(kValues)];
  if (pick < 160) return current * std::pow(10.0, (pick % 13) - 6.0);  // the default scaled
  if (pick < 176) return std::numeric_limits<double>::quiet_NaN();
  if (pick < 184)
    return pick % 2 ? std::numeric_limits<double>::infinity()
                    : -std::numeric_limits<double>::infinity();
  std::uint64_t bits = 0;  // any double
  for (int i = 0; i < 8; ++i) bits = bits << 8 | in->Byte();
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

int FuzzedInt(Bytes* in, int current) {
  static constexpr int kValues[] = {0,
                                    -1,
                                    1,
                                    2,
                                    3,
                                    4,
                                    5,
                                    10,
                                    100,
                                    1000,
                                    100000,
                                    1 << 30,
                                    std::numeric_limits<int>::max(),
                                    std::numeric_limits<int>::min()};
  const std::uint8_t pick = in->Byte();
  if (pick < 128) return kValues[pick % std::size(kValues)];
  if (pick < 192)
    return static_cast<int>(std::clamp<long>(static_cast<long>(current) + in->Byte() - 128L,
                                             std::numeric_limits<int>::min(),
                                             std::numeric_limits<int>::max()));
  return static_cast<int>(static_cast<std::uint32_t>(in->U16()) << 16 | in->U16());
}

// Visits an options struct and gives the fields whose running index (nested groups flattened)
// is in `chosen` a fuzzed value, while the visitor holds them: some options visit an enum
// through a local index, so a pointer kept past the visit would dangle.
class Assigner : public kernel::FieldVisitor {
 public:
  Assigner(std::vector<int> chosen, Bytes* in) : chosen_(std::move(chosen)), in_(in) {}
  int count() const { return next_; }
  void Field(std::string_view key, double* v, std::string_view) override {
    for (int k = Take(); k > 0; --k) {
      *v = FuzzedDouble(in_, *v);
      Show(key, std::to_string(*v));
    }
  }
  void Field(std::string_view key, int* v, std::string_view) override {
    for (int k = Take(); k > 0; --k) {
      *v = FuzzedInt(in_, *v);
      Show(key, std::to_string(*v));
    }
  }
  void Field(std::string_view, std::uint64_t* v, std::string_view) override {
    for (int k = Take(); k > 0; --k) *v = static_cast<std::uint64_t>(in_->U16()) << 48 | in_->U16();
  }
  void Field(std::string_view, bool* v, std::string_view) override {
    for (int k = Take(); k > 0; --k) *v = in_->Byte() % 2;
  }
  void Field(std::string_view, std::string* v, std::string_view) override {
    for (int k = Take(); k > 0; --k) v->assign(in_->Byte() % 8, static_cast<char>(in_->Byte()));
  }
  void Field(std::string_view, std::vector<double>* v, std::string_view) override {
    for (int k = Take(); k > 0; --k) {
      v->resize(in_->Byte() % 5);
      for (double& x : *v) x = FuzzedDouble(in_, 1.0);
    }
  }
  // The names a file can give.
  void Choice(std::string_view, int* index, std::initializer_list<std::string_view> choices,
              std::string_view) override {
    for (int k = Take(); k > 0; --k) *index = in_->Byte() % static_cast<int>(choices.size());
  }
  void Field(std::string_view, kernel::Pose2* v, std::string_view) override {
    for (int k = Take(); k > 0; --k)
      *v = kernel::Pose2(FuzzedDouble(in_, v->x()), FuzzedDouble(in_, v->y()),
                         FuzzedDouble(in_, v->theta()));
  }
  void Group(std::string_view, std::string_view,
             const std::function<void(FieldVisitor&)>& nested) override {
    nested(*this);
  }

 private:
  // Reproducing an input (FUZZ_VERBOSE set): which option got which value.
  static void Show(std::string_view key, const std::string& value) {
    if (std::getenv("FUZZ_VERBOSE"))
      std::fprintf(stderr, "%.*s = %s\n", static_cast<int>(key.size()), key.data(), value.c_str());
  }
  // How many times the next field was chosen.
  int Take() {
    const int index = next_++;
    return static_cast<int>(std::count(chosen_.begin(), chosen_.end(), index));
  }
  std::vector<int> chosen_;
  Bytes* in_;
  int next_ = 0;
};

// Sets up to eight fields of `visit`'s options from the bytes.
void Fuzz(const std::function<void(kernel::FieldVisitor&)>& visit, Bytes* in) {
  Assigner counter({}, in);
  visit(counter);
  if (counter.count() == 0) return;
  std::vector<int> chosen(1 + in->Byte() % 8);
  for (int& c : chosen) c = in->U16() % counter.count();
  Assigner assigner(std::move(chosen), in);
  visit(assigner);
}

// The first scans of a lap of `complex` (URG-04LX), simulated once.
const std::vector<sim::SensorFrame>& Frames() {
  static const std::vector<sim::SensorFrame> frames = [] {
    const sim::World world = *sim::BuiltinWorld("complex");
    const sim::RayCaster caster(world);
    sim::Simulator simulator(caster, {}, *world.start, 1);
    sim::RouteRun run = sim::FollowRoute(&simulator, {world.route.front()}, {});
    run.frames.resize(std::min<std::size_t>(run.frames.size(), 6));
    return run.frames;
  }();
  return frames;
}

void RunSlam(const std::string& name, Bytes* in) {
  const auto& registry = estimation::SlamRegistry::Global();
  auto options = registry.Find(name)->default_options({});
  estimation::SlamContext context{Frames().front().odometry_pose, {}};
  Fuzz([&](kernel::FieldVisitor& v) { options->VisitFields(v); }, in);
  Fuzz([&](kernel::FieldVisitor& v) { context.region.VisitFields(v); }, in);
  if (!options->Validate().ok() || !context.region.Validate().ok()) return;
  auto method = registry.Make(name, options.get(), context);
  if (!method.ok()) return;
  const kernel::Pose2 robot_T_laser = sim::LaserOptions().robot_T_laser;
  for (std::size_t i = 0; i < Frames().size(); ++i) {
    if (i > 0)
      (*method.value)->Predict(Frames()[i - 1].odometry_pose.Between(Frames()[i].odometry_pose));
    (*method.value)->Update(Frames()[i].scan, robot_T_laser);
  }
  (*method.value)->Finish();
}

void RunExplorer(Bytes* in) {
  static const sim::World world = *sim::BuiltinWorld("complex");
  runtime::ExploreSetup setup;
  const auto& explorers = exploration::ExplorerRegistry::Global();
  const std::vector<std::string> names = explorers.Names();
  setup.explorer = names[in->Byte() % names.size()];
  setup.localization = "ground-truth";
  Fuzz([&](kernel::FieldVisitor& v) { setup.options.VisitFields(v); }, in);
  // The explorer's own options (SrtOptions, RegOptions) through their YAML form too.
  std::unique_ptr<kernel::AnyOptions> own = explorers.Find(setup.explorer)->default_options();
  Fuzz([&](kernel::FieldVisitor& v) { own->VisitFields(v); }, in);
  setup.explorer_options = std::move(own);
  Fuzz([&](kernel::FieldVisitor& v) { setup.region.VisitFields(v); }, in);
  // The caps' own domains are part of Validate; the run itself is kept short.
  setup.options.max_nodes = std::min(setup.options.max_nodes, 2);
  setup.options.max_time_s = std::min(setup.options.max_time_s, 60.0);
  static_cast<void>(runtime::RunExploration(world, setup));
}

}  // namespace
}  // namespace splam::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  splam::fuzz::Bytes in(data, size);
  const auto names = splam::estimation::SlamRegistry::Global().Names();
  const std::size_t pick = in.Byte() % (names.size() + 1);
  if (std::getenv("FUZZ_VERBOSE"))
    std::fprintf(stderr, "%s\n", pick == names.size() ? "explorer" : names[pick].c_str());
  if (pick == names.size())
    splam::fuzz::RunExplorer(&in);
  else
    splam::fuzz::RunSlam(names[pick], &in);
  return 0;
}
