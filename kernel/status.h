#ifndef SPLAM_KERNEL_STATUS_H_
#define SPLAM_KERNEL_STATUS_H_

#include <optional>
#include <string>
#include <utility>
#include <vector>

// The one error convention of splam: an expected failure (bad input, invalid options, a solver
// that did not converge) comes back as a value with a message; bugs are assertions.
namespace splam::kernel {

// Success, or the message saying what is wrong. Messages about files start with "path:line: ".
class [[nodiscard]] Status {
 public:
  Status() = default;  // success
  static Status Ok() { return {}; }
  static Status Error(std::string message) {
    Status s;
    s.message_ = message.empty() ? "error" : std::move(message);
    return s;
  }
  bool ok() const { return message_.empty(); }
  // Empty for success.
  const std::string& message() const { return message_; }
  // The same failure with "prefix: " in front of its message (success stays success).
  Status Prefixed(const std::string& prefix) const {
    return ok() ? *this : Error(prefix + ": " + message_);
  }

 private:
  std::string message_;
};

// The first failure of a list of checks, or success.
template <class... S>
Status FirstError(const S&... statuses) {
  Status first;
  ((first = first.ok() ? statuses : first), ...);
  return first;
}

// The first failure of a list, or success (for writing several files, each tried).
inline Status FirstError(const std::vector<Status>& statuses) {
  for (const Status& s : statuses)
    if (!s.ok()) return s;
  return {};
}

// The value of an operation that can fail, or the message saying why.
template <class T>
struct Result {
  std::optional<T> value;
  std::string error;

  static Result Ok(T v) { return {std::move(v), {}}; }
  static Result Fail(std::string message) { return {std::nullopt, std::move(message)}; }
  static Result Fail(const Status& status) { return Fail(status.message()); }
  bool ok() const { return value.has_value(); }
  Status status() const { return ok() ? Status::Ok() : Status::Error(error); }
  // The value, as std::optional gives it (ok() first).
  explicit operator bool() const { return ok(); }
  T& operator*() { return *value; }
  const T& operator*() const { return *value; }
  T* operator->() { return &*value; }
  const T* operator->() const { return &*value; }
};

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_STATUS_H_
