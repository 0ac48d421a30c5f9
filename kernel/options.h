#ifndef SPLAM_KERNEL_OPTIONS_H_
#define SPLAM_KERNEL_OPTIONS_H_

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "kernel/pose2.h"
#include "kernel/status.h"

// Options structs describe their fields to a visitor, once, next to their definition: the key
// (the field's name), a pointer to the value and a one-line comment with the unit. io/ turns the
// visitor into YAML reading and writing, the command line into `--set key=value`; nothing in
// kernel knows about files.
namespace splam::kernel {

class FieldVisitor {
 public:
  virtual ~FieldVisitor() = default;
  virtual void Field(std::string_view key, double* value, std::string_view doc) = 0;
  virtual void Field(std::string_view key, int* value, std::string_view doc) = 0;
  virtual void Field(std::string_view key, std::uint64_t* value, std::string_view doc) = 0;
  virtual void Field(std::string_view key, bool* value, std::string_view doc) = 0;
  virtual void Field(std::string_view key, std::string* value, std::string_view doc) = 0;
  virtual void Field(std::string_view key, std::vector<double>* value, std::string_view doc) = 0;
  // One of `choices` (an enum's names), stored as its index.
  virtual void Choice(std::string_view key, int* index,
                      std::initializer_list<std::string_view> choices, std::string_view doc) = 0;
  // A pose as [x (m), y (m), theta (rad)].
  virtual void Field(std::string_view key, Pose2* value, std::string_view doc) = 0;
  // A nested options struct: `fields` visits its fields, under `key`.
  virtual void Group(std::string_view key, std::string_view doc,
                     const std::function<void(FieldVisitor&)>& fields) = 0;

  // A key that this struct no longer has, now at `new_key` (relative to the struct's own
  // section): a reader refuses a value under `old_key` with a message naming the new key. Writers
  // and checks ignore it.
  virtual void Moved(std::string_view /*old_key*/, std::string_view /*new_key*/) {}

  // Visits a nested options struct that has a VisitFields(FieldVisitor&) member.
  template <class Options>
  void Nested(std::string_view key, std::string_view doc, Options* options) {
    Group(key, doc, [options](FieldVisitor& v) { options->VisitFields(v); });
  }
};

// No integer option counts beyond this (keyframes, beams, iterations): the sum of a few stays
// an int (a loop target's window of INT_MAX keyframes overflowed one).
constexpr int kMaxCount = 100000000;

// The first field that `visit` shows holding a number that is not finite (a NaN, an infinity:
// no option means anything by one) or an integer beyond kMaxCount in magnitude, as an error
// naming its key (nested keys joined by dots); success when there is none. Options read from
// files and `--set` are finite already (io's reader refuses the others); this covers options set
// in code, where an infinity passes a range check written as `x >= 0`.
Status CheckFinite(const std::function<void(FieldVisitor&)>& visit);

// CheckFinite of an options struct with a VisitFields(FieldVisitor&) member (visited on a copy).
template <class Options>
Status FiniteFields(Options options) {
  return CheckFinite([&options](FieldVisitor& v) { options.VisitFields(v); });
}

// An options struct whose type is chosen at run time (a SLAM method's, an explorer's own): the
// registries, the configuration documents and the runs hold any variant's options through it.
class AnyOptions {
 public:
  virtual ~AnyOptions() = default;
  virtual void VisitFields(FieldVisitor& v) = 0;
  virtual Status Validate() const = 0;
  virtual std::unique_ptr<AnyOptions> Clone() const = 0;
};

// `Options` (a struct with VisitFields and Validate) as AnyOptions.
template <class Options>
class OptionsOf : public AnyOptions {
 public:
  explicit OptionsOf(Options options = {}) : options_(std::move(options)) {}
  void VisitFields(FieldVisitor& v) override { options_.VisitFields(v); }
  // Every number finite (FiniteFields), then the struct's own checks.
  Status Validate() const override {
    if (Status s = FiniteFields(options_); !s.ok()) return s;
    return options_.Validate();
  }
  std::unique_ptr<AnyOptions> Clone() const override {
    return std::make_unique<OptionsOf>(options_);
  }
  Options& options() { return options_; }
  const Options& options() const { return options_; }

 private:
  Options options_;
};

// The options of a variant that has none of its own.
struct NoOptions {
  void VisitFields(FieldVisitor&) {}
  Status Validate() const { return Status::Ok(); }
};

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_OPTIONS_H_
