#ifndef SPLAM_ESTIMATION_SLAM_METHOD_H_
#define SPLAM_ESTIMATION_SLAM_METHOD_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "estimation/slam_map.h"
#include "kernel/local_safe_region.h"
#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/registry.h"
#include "kernel/scan.h"
#include "kernel/spline_extraction.h"
#include "kernel/status.h"

// The SLAM interface every method implements, and the registry that maps a method's name to its
// factory, its options and a one-line description. The command line, the experiments and the
// explorer's localisation all read the registry: adding a method is one header, one source file
// and one RegisterSlamMethod call (see examples/estimation/).
namespace splam::estimation {

// Predict, Update and pose are all a method must implement; the rest have defaults.
class SlamMethod {
 public:
  virtual ~SlamMethod() = default;
  // Motion between the previous and this reading, in the robot frame (x_k-1 (+) u = x_k).
  virtual void Predict(const kernel::Pose2& odometry_increment) = 0;
  // A laser sweep taken at the predicted pose by a laser mounted at robot_T_laser.
  virtual void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) = 0;
  virtual kernel::Pose2 pose() const = 0;
  // The data has ended (a log, an exploration): methods that work in batches finish theirs.
  virtual void Finish() {}
  // The pose of every Update so far as the method now estimates it, for methods that revise the
  // past (a pose graph moves earlier poses when a loop closes); empty for filters, whose
  // trajectory is the sequence of pose() after each update.
  virtual std::vector<kernel::Pose2> Trajectory() const { return {}; }
  // The covariance of the current pose (x, y, theta; world frame), nullopt for a method that
  // keeps none. A filter's is part of its state; a pose graph's marginal costs a factorisation of
  // the graph (PoseCovarianceEveryScan false): the explorer asks it at its decisions, and the log
  // replay's per-scan consistency (NEES) only of methods whose covariance is cheap.
  virtual std::optional<Eigen::Matrix3d> PoseCovariance() const { return std::nullopt; }
  virtual bool PoseCovarianceEveryScan() const { return true; }
  // Ok while the method runs; otherwise why it stopped (it then ignores input).
  virtual kernel::Status health() const { return kernel::Status::Ok(); }
  bool healthy() const { return health().ok(); }
  // Number of 2-vectors in the state besides the pose: landmarks, or control points.
  virtual std::size_t MapSize() const { return 0; }
  // Map curves (0 for maps that are not curves).
  virtual std::size_t MapCurves() const { return 0; }
  // "12 lines, 3 corners"; empty for a method without a map.
  virtual std::string MapDescription() const { return {}; }
  virtual SlamMap Map() const { return {}; }
  // Named counters for summary.json (associations, map size, solver runs, times).
  virtual SlamStatistics Statistics() const { return {}; }
  // What the last Update did, as named numbers (associations, corrections, map changes): the
  // per-step trace of `splam slam --trace`. Empty for methods that keep none.
  virtual std::vector<std::pair<std::string, double>> LastUpdate() const { return {}; }
};

// What the sensors are believed to be, for the methods' noise models. Defaults: a Hokuyo
// URG-04LX and the simulator's odometry; `splam slam` picks them from the log's laser type.
struct SensorNoise {
  double odometry_noise_scale = 1.0;  // times the default odometry noise model
  double range_sigma_m = 0.003;       // line fitting: sigma = this + fraction * range, m
  double range_sigma_fraction = 0.01;
  double beam_sigma_floor_m = 0.0;  // beam model (ekf-bspline): floor + fraction * range, m
};

// Everything a factory needs besides the method's options.
struct SlamContext {
  kernel::Pose2 start;                // the first pose (known, as the papers assume)
  kernel::LocalRegionOptions region;  // the explorer's LSR radius and step (topological)
};

// A method's options, type-erased so that the registry and the configuration files can hold
// any method's options struct.
using SlamOptions = kernel::AnyOptions;
// `Options` (a struct with VisitFields and Validate) as SlamOptions.
template <class Options>
using SlamOptionsOf = kernel::OptionsOf<Options>;

struct SlamMethodInfo {
  std::string name;         // "ekf-lines"
  std::string description;  // one line for --help
  // The method's default options, adapted to the sensors' noise.
  std::function<std::unique_ptr<SlamOptions>(const SensorNoise&)> default_options;
  // Sets the fields of `options` that describe the sensors' noise (after a configuration file,
  // when the command line names the noise).
  std::function<void(const SensorNoise&, SlamOptions*)> adapt_to_sensors;
  // A method with valid `options` (as returned by default_options, possibly edited).
  std::function<std::unique_ptr<SlamMethod>(const SlamOptions&, const SlamContext&)> make;
};

// name -> method. The built-in methods (ekf-lines, ekf-bspline, topological, graph,
// topological-graph) are there from the start; others join with RegisterSlamMethod or a
// SlamMethodRegistration, from anywhere (kernel::Registry).
class SlamRegistry : public kernel::Registry<SlamMethodInfo> {
 public:
  explicit SlamRegistry(std::function<void(kernel::Registry<SlamMethodInfo>*)> builtins)
      : kernel::Registry<SlamMethodInfo>(std::move(builtins)) {}
  // The registry of the command line, the experiments and the explorer's localisation.
  static SlamRegistry& Global();
  // The method `name` with `options` (its defaults when null); an error names the unknown method
  // with the known ones, or the invalid option.
  kernel::Result<std::unique_ptr<SlamMethod>> Make(const std::string& name,
                                                   const SlamOptions* options,
                                                   const SlamContext& context) const;
};

// The registry entry of a method whose options struct is `Options` (with VisitFields and
// Validate): `make` builds it from valid options, `adapt` (may be empty) writes the sensors'
// noise into the options.
template <class Options>
SlamMethodInfo MakeSlamMethodInfo(
    std::string name, std::string description,
    std::function<std::unique_ptr<SlamMethod>(const Options&, const SlamContext&)> make,
    std::function<void(const SensorNoise&, Options*)> adapt = {}) {
  using Typed = SlamOptionsOf<Options>;
  SlamMethodInfo info;
  info.name = std::move(name);
  info.description = std::move(description);
  info.adapt_to_sensors = [adapt](const SensorNoise& noise, SlamOptions* options) {
    if (auto* typed = dynamic_cast<Typed*>(options); typed != nullptr && adapt)
      adapt(noise, &typed->options());
  };
  info.default_options = [adapt](const SensorNoise& noise) -> std::unique_ptr<SlamOptions> {
    auto options = std::make_unique<Typed>();
    if (adapt) adapt(noise, &options->options());
    return options;
  };
  info.make = [make](const SlamOptions& options,
                     const SlamContext& context) -> std::unique_ptr<SlamMethod> {
    const auto* typed = dynamic_cast<const Typed*>(&options);
    return typed != nullptr ? make(typed->options(), context) : nullptr;
  };
  return info;
}

// Adds a method to the global registry: the one line that makes a new method known to the
// command line, the experiments and the explorer's localisation. From a function (main, a test)
// or, as a SlamMethodRegistration, from a namespace-scope object of any translation unit. (The
// built-in families add theirs with MakeSlamMethodInfo, e.g. estimation/ekf/ekf_methods.cc.)
template <class Options>
void RegisterSlamMethod(
    std::string name, std::string description,
    std::function<std::unique_ptr<SlamMethod>(const Options&, const SlamContext&)> make,
    std::function<void(const SensorNoise&, Options*)> adapt = {}) {
  SlamRegistry::Global().Add(MakeSlamMethodInfo<Options>(std::move(name), std::move(description),
                                                         std::move(make), std::move(adapt)));
}

// RegisterSlamMethod as an object, for a translation unit of its own:
//   static const SlamMethodRegistration<MyOptions> kMine("mine", "...", MakeMine);
// It registers when the program starts (static initialisation; the registry is built on first
// use, whichever unit gets there first). A unit in a static library is linked only when the
// program uses a symbol of it: register from a function the program calls, or link that
// library whole (an OBJECT library, or --whole-archive).
template <class Options>
struct SlamMethodRegistration {
  SlamMethodRegistration(
      std::string name, std::string description,
      std::function<std::unique_ptr<SlamMethod>(const Options&, const SlamContext&)> make,
      std::function<void(const SensorNoise&, Options*)> adapt = {}) {
    RegisterSlamMethod<Options>(std::move(name), std::move(description), std::move(make),
                                std::move(adapt));
  }
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_SLAM_METHOD_H_
