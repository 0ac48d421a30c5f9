#ifndef SPLAM_IO_RESULT_H_
#define SPLAM_IO_RESULT_H_

#include <optional>
#include <string>
#include <utility>

namespace splam::io {

// The value of an operation that can fail on bad input, or the message saying why; messages
// about files start with "path:line: ".
template <class T>
struct Result {
  std::optional<T> value;
  std::string error;

  static Result Ok(T v) { return {std::move(v), {}}; }
  static Result Fail(std::string message) { return {std::nullopt, std::move(message)}; }
  bool ok() const { return value.has_value(); }
};

// "path:line: message" (line omitted when 0).
std::string FileError(const std::string& path, int line, const std::string& message);

}  // namespace splam::io

#endif  // SPLAM_IO_RESULT_H_
