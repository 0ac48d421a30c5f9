#include "io/trajectory.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>

#include "io/text.h"

namespace splam::io {

kernel::Status ReadTextFile(const std::string& path, std::string* text, std::size_t max_bytes) {
  // A directory opens as an empty stream: it read as an empty file.
  if (std::filesystem::is_directory(path)) return FileError(path, 0, "is a directory, not a file");
  // /dev/zero or /dev/full (a result file linked to it and read back) would never end.
  if (std::filesystem::is_character_file(path) || std::filesystem::is_block_file(path))
    return FileError(path, 0, "is a device, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) return FileError(path, 0, "cannot open for reading");
  // In pieces, counting: a pipe or a device has no size to check first.
  text->clear();
  std::string piece(std::size_t{1} << 20, '\0');
  while (in) {
    in.read(piece.data(), static_cast<std::streamsize>(piece.size()));
    const auto got = static_cast<std::size_t>(in.gcount());
    if (text->size() + got > max_bytes) {
      text->clear();
      text->shrink_to_fit();
      return FileError(
          path, 0,
          "holds more than " + std::to_string(max_bytes) + " bytes, the most a text file may hold");
    }
    text->append(piece, 0, got);
  }
  if (in.bad()) return FileError(path, 0, "read failed");
  return {};
}

kernel::Status WriteTextFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return FileError(path, 0, "cannot open for writing");
  out << text;
  // The buffer reaches the disk at close: a full disk fails there, not at the write.
  out.close();
  return out ? kernel::Status::Ok() : FileError(path, 0, "write failed (disk full?)");
}

namespace {

// The planar pose of a line of `format`'s values (`v` holds them all, finite), or why not.
kernel::Result<StampedPose> PoseOfValues(TrajectoryFormat format, const std::vector<double>& v,
                                         double index) {
  using R = kernel::Result<StampedPose>;
  switch (format) {
    case TrajectoryFormat::kSplam:
      return R::Ok({v[0], kernel::Pose2(v[1], v[2], v[3])});
    case TrajectoryFormat::kTum: {
      // Yaw of the rotation (the z-y-x Euler angle about z). The scale of q cancels: divided by
      // its largest component first, so that no square overflows (1e300 gave a NaN heading).
      const double scale =
          std::max({std::abs(v[4]), std::abs(v[5]), std::abs(v[6]), std::abs(v[7])});
      if (scale == 0.0) return R::Fail("the quaternion (qx qy qz qw) is zero");
      const double qx = v[4] / scale, qy = v[5] / scale, qz = v[6] / scale, qw = v[7] / scale;
      const double yaw =
          std::atan2(2.0 * (qw * qz + qx * qy), qw * qw + qx * qx - qy * qy - qz * qz);
      return R::Ok({v[0], kernel::Pose2(v[1], v[2], yaw)});
    }
    case TrajectoryFormat::kKitti:
      // The heading is the direction of the rotation's first column in the plane.
      if (v[0] == 0.0 && v[4] == 0.0)
        return R::Fail("the rotation's first column (r00, r10) is zero: no heading in the plane");
      return R::Ok({index, kernel::Pose2(v[3], v[7], std::atan2(v[4], v[0]))});
  }
  return R::Fail("unknown format");
}

std::size_t ValueCount(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kSplam:
      return 4;
    case TrajectoryFormat::kTum:
      return 8;
    case TrajectoryFormat::kKitti:
      return 12;
  }
  return 0;
}

}  // namespace

TrajectoryFormat TrajectoryFormatOf(const std::string& path) {
  if (path.ends_with(".tum")) return TrajectoryFormat::kTum;
  if (path.ends_with(".kitti")) return TrajectoryFormat::kKitti;
  return TrajectoryFormat::kSplam;
}

const char* TrajectoryFormatName(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kSplam:
      return "splam 'time x y theta'";
    case TrajectoryFormat::kTum:
      return "TUM 'time x y z qx qy qz qw'";
    case TrajectoryFormat::kKitti:
      return "KITTI (12 values of a 3x4 pose matrix)";
  }
  return "unknown";
}

Result<Trajectory> ParseTrajectory(const std::string& text, const std::string& name) {
  Trajectory trajectory;
  std::optional<TrajectoryFormat> format;
  std::vector<double> v;
  const kernel::Status error =
      ForEachDataLine(text, [&](int line, const std::vector<std::string_view>& tokens) {
        if (!format) {
          for (const TrajectoryFormat f :
               {TrajectoryFormat::kSplam, TrajectoryFormat::kTum, TrajectoryFormat::kKitti})
            if (tokens.size() == ValueCount(f)) format = f;
          if (!format)
            return FileError(name, line,
                             "expected 4 values 'time x y theta' (or 8 of TUM, 12 of KITTI), "
                             "found " +
                                 std::to_string(tokens.size()));
        } else if (tokens.size() != ValueCount(*format)) {
          return FileError(name, line,
                           "expected " + std::to_string(ValueCount(*format)) + " values (" +
                               TrajectoryFormatName(*format) + ", as the first pose), found " +
                               std::to_string(tokens.size()));
        }
        if (kernel::Status bad = ParseFiniteNumbers(tokens, &v); !bad.ok())
          return FileError(name, line, bad.message());
        const kernel::Result<StampedPose> pose =
            PoseOfValues(*format, v, static_cast<double>(trajectory.size()));
        if (!pose) return FileError(name, line, pose.error);
        trajectory.push_back(*pose);
        return kernel::Status::Ok();
      });
  if (!error.ok()) return Result<Trajectory>::Fail(error);
  if (trajectory.empty()) return Result<Trajectory>::Fail(FileError(name, 0, "no poses"));
  return Result<Trajectory>::Ok(std::move(trajectory));
}

Result<Trajectory> ReadTrajectory(const std::string& path) {
  std::string text;
  if (kernel::Status error = ReadTextFile(path, &text); !error.ok()) {
    return Result<Trajectory>::Fail(error);
  }
  return ParseTrajectory(text, path);
}

std::string FormatTrajectory(const Trajectory& trajectory, const std::string& comment,
                             TrajectoryFormat format) {
  std::string out;
  if (!comment.empty() && format != TrajectoryFormat::kKitti) out += "# " + OneLine(comment) + "\n";
  if (format == TrajectoryFormat::kSplam) out += "# time_s x_m y_m theta_rad\n";
  if (format == TrajectoryFormat::kTum) out += "# timestamp x y z qx qy qz qw\n";
  for (const StampedPose& p : trajectory) {
    const std::string x = FormatDouble(p.pose.x()), y = FormatDouble(p.pose.y());
    const double theta = p.pose.theta();
    switch (format) {
      case TrajectoryFormat::kSplam:
        out += FormatDouble(p.time_s) + " " + x + " " + y + " " + FormatDouble(theta) + "\n";
        break;
      case TrajectoryFormat::kTum:  // rotation by theta about z: q = (0, 0, sin, cos)(theta / 2)
        out += FormatDouble(p.time_s) + " " + x + " " + y + " 0 0 0 " +
               FormatDouble(std::sin(0.5 * theta)) + " " + FormatDouble(std::cos(0.5 * theta)) +
               "\n";
        break;
      case TrajectoryFormat::kKitti: {
        const double sine = std::sin(theta);
        const std::string c = FormatDouble(std::cos(theta)), s = FormatDouble(sine);
        // 0.0 - sine: +0 rather than -0 for a zero heading.
        out += c + " " + FormatDouble(0.0 - sine) + " 0 " + x + " " + s + " " + c + " 0 " + y +
               " 0 0 1 0\n";
        break;
      }
    }
  }
  return out;
}

kernel::Status WriteTrajectory(const std::string& path, const Trajectory& trajectory,
                               const std::string& comment) {
  return WriteTextFile(path, FormatTrajectory(trajectory, comment, TrajectoryFormatOf(path)));
}

}  // namespace splam::io
