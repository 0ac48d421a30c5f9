#include "io/trajectory.h"

#include <cmath>
#include <filesystem>
#include <fstream>

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

Result<Trajectory> ParseTrajectory(const std::string& text, const std::string& name) {
  Trajectory trajectory;
  std::vector<double> v;
  const kernel::Status error =
      ForEachDataLine(text, [&](int line, const std::vector<std::string_view>& tokens) {
        if (tokens.size() != 4) {
          return FileError(
              name, line,
              "expected 4 values 'time x y theta', found " + std::to_string(tokens.size()));
        }
        if (kernel::Status bad = ParseFiniteNumbers(tokens, &v); !bad.ok()) {
          return FileError(name, line, bad.message());
        }
        trajectory.push_back({v[0], kernel::Pose2(v[1], v[2], v[3])});
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

std::string FormatTrajectory(const Trajectory& trajectory, const std::string& comment) {
  std::string out;
  if (!comment.empty()) out += "# " + comment + "\n";
  out += "# time_s x_m y_m theta_rad\n";
  for (const StampedPose& p : trajectory) {
    out += FormatDouble(p.time_s) + " " + FormatDouble(p.pose.x()) + " " +
           FormatDouble(p.pose.y()) + " " + FormatDouble(p.pose.theta()) + "\n";
  }
  return out;
}

kernel::Status WriteTrajectory(const std::string& path, const Trajectory& trajectory,
                               const std::string& comment) {
  return WriteTextFile(path, FormatTrajectory(trajectory, comment));
}

}  // namespace splam::io
