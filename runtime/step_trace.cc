#include "runtime/step_trace.h"

#include <fmt/format.h>

#include <sstream>

#include "io/trajectory.h"
#include "kernel/angle.h"

namespace splam::runtime {

kernel::Status WriteStepTrace(const std::string& path, const std::vector<StepRecord>& steps,
                              const std::vector<double>& times, const kernel::Trajectory& truth) {
  std::ostringstream out;
  std::vector<std::string> names;
  for (const StepRecord& s : steps) {
    if (s.values.empty()) continue;
    for (const auto& [name, value] : s.values) names.push_back(name);
    break;
  }
  out << "step,time_s,predicted_x_m,predicted_y_m,predicted_theta_rad,x_m,y_m,theta_rad";
  if (!truth.empty())
    out << ",truth_x_m,truth_y_m,truth_theta_rad,predicted_position_error_m,position_error_m,"
           "predicted_heading_error_deg,heading_error_deg";
  for (const std::string& n : names) out << ',' << n;
  out << '\n';
  for (std::size_t i = 0; i < steps.size() && i < times.size(); ++i) {
    const StepRecord& s = steps[i];
    out << fmt::format("{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}", i, times[i],
                       s.predicted.x(), s.predicted.y(), s.predicted.theta(), s.corrected.x(),
                       s.corrected.y(), s.corrected.theta());
    if (!truth.empty()) {
      if (const auto t = kernel::PoseAt(truth, times[i], 0.0, 1e-3)) {
        const auto heading = [&](const kernel::Pose2& p) {
          return kernel::RadToDeg(kernel::WrapAngle(p.theta() - t->theta()));
        };
        out << fmt::format(",{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.4f},{:.4f}", t->x(), t->y(),
                           t->theta(), (s.predicted.translation() - t->translation()).norm(),
                           (s.corrected.translation() - t->translation()).norm(),
                           heading(s.predicted), heading(s.corrected));
      } else {
        out << ",,,,,,,";
      }
    }
    for (std::size_t k = 0; k < names.size(); ++k) {
      out << ',';
      if (k < s.values.size() && s.values[k].first == names[k]) out << s.values[k].second;
    }
    out << '\n';
  }
  return io::WriteTextFile(path, out.str());
}

}  // namespace splam::runtime
