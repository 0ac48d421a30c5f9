#include "io/slam_state_file.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "io/internal/plausible.h"
#include "io/map_export.h"
#include "io/text.h"
#include "io/trajectory.h"

namespace splam::io {
namespace {

std::string Numbers(std::initializer_list<double> values) {
  std::string out;
  for (double v : values) out += " " + FormatDouble(v);
  return out;
}

kernel::Pose2 PoseAt(const std::vector<double>& v, std::size_t i) {
  return kernel::Pose2(v[i], v[i + 1], v[i + 2]);
}

// The values after a line's keyword as numbers, finite unless `infinite_from` (ranges may be
// "inf": no return), at least `count`.
kernel::Status LineNumbers(const std::vector<std::string_view>& tokens, std::size_t count,
                           std::size_t infinite_from, std::vector<double>* values) {
  values->clear();
  for (std::size_t i = 1; i < tokens.size(); ++i) {
    const std::optional<double> v = ParseDouble(tokens[i]);
    const bool may_be_infinite = i - 1 >= infinite_from && v && *v > 0 && std::isinf(*v);
    if (!v || (!std::isfinite(*v) && !may_be_infinite))
      return kernel::Status::Error(Quoted(tokens[i]) + " is not a finite number");
    values->push_back(*v);
  }
  if (values->size() < count)
    return kernel::Status::Error(
        fmt::format("{}: expected {} values, found {}", tokens[0], count, values->size()));
  return kernel::Status::Ok();
}

}  // namespace

std::string FormatSlamState(const estimation::SlamState& state) {
  std::string text =
      "# splam state: a SLAM method's map and its keyframes' readings (splam slam --save-state)\n"
      "# keyframe x y theta | loop_edge a b | spline (as map.txt) | scan x y theta lx ly ltheta "
      "time start step min_range max_range n r_0 ... r_n-1\n"
      "splam_state 1\nmethod " +
      state.method + "\n";
  for (const kernel::Pose2& k : state.map.keyframes)
    text += "keyframe" + Numbers({k.x(), k.y(), k.theta()}) + "\n";
  for (const auto& [a, b] : state.map.loop_edges) text += fmt::format("loop_edge {} {}\n", a, b);
  const std::string splines = FormatSplineMapText(state.map.splines);
  for (std::size_t at = 0; at < splines.size();) {  // without its comment lines
    const std::size_t end = splines.find('\n', at);
    if (splines[at] != '#') text += splines.substr(at, end - at + 1);
    at = end + 1;
  }
  for (const estimation::MapScan& m : state.scans) {
    const kernel::Scan& s = m.scan;
    text += "scan" +
            Numbers({m.pose.x(), m.pose.y(), m.pose.theta(), m.robot_T_laser.x(),
                     m.robot_T_laser.y(), m.robot_T_laser.theta(), s.timestamp_s, s.start_angle_rad,
                     s.angular_step_rad, s.min_range_m, s.max_range_m}) +
            " " + std::to_string(s.ranges_m.size());
    for (double r : s.ranges_m) text += " " + FormatDouble(r);
    text += "\n";
  }
  return text;
}

kernel::Status WriteSlamState(const std::string& path, const estimation::SlamState& state) {
  return WriteTextFile(path, FormatSlamState(state));
}

Result<estimation::SlamState> ReadSlamState(const std::string& path) {
  std::string text;
  if (kernel::Status read = ReadTextFile(path, &text); !read.ok())
    return Result<estimation::SlamState>::Fail(read);
  return ParseSlamState(text, path);
}

Result<estimation::SlamState> ParseSlamState(const std::string& text, const std::string& path) {
  using R = Result<estimation::SlamState>;
  estimation::SlamState state;
  bool header = false;
  std::vector<double> v;
  const kernel::Status parsed = ForEachDataLine(
      text, [&](int line, const std::vector<std::string_view>& t) -> kernel::Status {
        const auto fail = [&](const std::string& message) {
          return FileError(path, line, message);
        };
        if (!header) {
          if (t.size() != 2 || t[0] != "splam_state")
            return fail("not a splam state file (its first line must be 'splam_state 1')");
          if (t[1] != "1") return fail("state format " + Quoted(t[1]) + " is not known (1 is)");
          header = true;
          return kernel::Status::Ok();
        }
        if (t[0] == "method") {
          const auto is_name_byte = [](char c) {
            return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_';
          };
          if (t.size() != 2 || !std::all_of(t[1].begin(), t[1].end(), is_name_byte))
            return fail("method: expected one name of letters, digits, '-' and '_'" +
                        (t.size() == 2 ? ", not " + Quoted(t[1]) : std::string()));
          state.method = std::string(t[1]);
        } else if (t[0] == "keyframe") {
          if (kernel::Status e = LineNumbers(t, 3, 3, &v); !e.ok()) return fail(e.message());
          if (kernel::Status e = internal::PoseProblem(PoseAt(v, 0), "keyframe"); !e.ok())
            return fail(e.message());
          state.map.keyframes.push_back(PoseAt(v, 0));
        } else if (t[0] == "loop_edge") {
          const long n = static_cast<long>(state.map.keyframes.size());
          const auto index = [&](std::size_t i) {
            const std::optional<long> k = i < t.size() ? ParseInteger(t[i]) : std::nullopt;
            return k && *k >= 0 && *k < n ? static_cast<int>(*k) : -1;
          };
          const int a = index(1), b = index(2);
          if (t.size() != 3 || a < 0 || b < 0)
            return fail("loop_edge: expected two indices of keyframes above it");
          state.map.loop_edges.emplace_back(a, b);
        } else if (t[0] == "spline") {
          // -1: not an integer.
          const long id = t.size() > 2 ? ParseInteger(t[1]).value_or(-1) : -1;
          const long n = t.size() > 2 ? ParseInteger(t[2]).value_or(-1) : -1;
          if (id < 0 || id > std::numeric_limits<int>::max() || n < 4 || n > 1000000 ||
              t.size() != 3 + 3 * static_cast<std::size_t>(n) + 4)
            return fail("spline: expected id, n >= 4, n control points and n + 4 knots");
          std::vector<std::string_view> numbers(t.begin() + 2, t.end());
          if (kernel::Status e = LineNumbers(numbers, numbers.size() - 1, numbers.size(), &v);
              !e.ok())
            return fail(e.message());
          std::vector<Eigen::Vector2d> control;
          for (long i = 0; i < n; ++i) {
            control.emplace_back(v[static_cast<std::size_t>(2 * i)],
                                 v[static_cast<std::size_t>(2 * i + 1)]);
            // As every pose of the file: a curve at 1e300 m loaded, ran, and failed the export.
            if (!(control.back().cwiseAbs().maxCoeff() <= internal::kMaxCoordinateM))
              return fail(fmt::format(
                  "spline {}: control point {} ({}, {}) is not finite or beyond +-1e+06 m", id, i,
                  FormatDouble(control.back().x()), FormatDouble(control.back().y())));
          }
          std::vector<double> knots(v.begin() + 2 * n, v.end());
          kernel::Result<kernel::CubicBSpline> spline =
              kernel::CubicBSpline::Create(std::move(control), std::move(knots));
          if (!spline) return fail("spline: " + spline.error);
          state.map.splines.push_back({static_cast<int>(id), std::move(*spline), 0});
        } else if (t[0] == "scan") {
          if (kernel::Status e = LineNumbers(t, 12, 12, &v); !e.ok()) return fail(e.message());
          const double n = v[11];
          // The count compared as a double first: a huge one does not fit a size_t.
          if (!(n >= 0 && n == std::floor(n) && n == static_cast<double>(v.size() - 12)))
            return fail(fmt::format("scan: {} ranges announced, {} given", n, v.size() - 12));
          estimation::MapScan m;
          m.pose = PoseAt(v, 0);
          m.robot_T_laser = PoseAt(v, 3);
          m.scan.timestamp_s = v[6];
          m.scan.start_angle_rad = v[7];
          m.scan.angular_step_rad = v[8];
          m.scan.min_range_m = v[9];
          m.scan.max_range_m = v[10];
          m.scan.ranges_m.assign(v.begin() + 12, v.end());
          for (const auto& [pose, what] : {std::pair{m.pose, "scan: pose"},
                                           std::pair{m.robot_T_laser, "scan: laser mounting"}})
            if (kernel::Status e = internal::PoseProblem(pose, what); !e.ok())
              return fail(e.message());
          if (kernel::Status e = internal::ScanGeometryProblem(m.scan); !e.ok())
            return fail("scan: " + e.message());
          state.scans.push_back(std::move(m));
        } else {
          return fail("unknown line " + Quoted(t[0]) +
                      " (known: method, keyframe, loop_edge, spline, scan)");
        }
        return kernel::Status::Ok();
      });
  if (!parsed.ok()) return R::Fail(parsed);
  if (!header) return R::Fail(FileError(path, 0, "empty: not a splam state file"));
  if (state.method.empty()) return R::Fail(FileError(path, 0, "no 'method' line"));
  return R::Ok(std::move(state));
}

}  // namespace splam::io
