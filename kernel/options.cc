#include "kernel/options.h"

#include <cmath>

namespace splam::kernel {
namespace {

// Keeps the key of the first field holding a number that is not finite, or an integer beyond
// kMaxCount.
class FiniteChecker : public FieldVisitor {
 public:
  explicit FiniteChecker(std::string prefix = "") : prefix_(std::move(prefix)) {}
  const std::string& first() const { return first_; }

  void Field(std::string_view key, double* v, std::string_view) override { Check(key, {*v}); }
  void Field(std::string_view key, int* v, std::string_view) override {
    if (first_.empty() && std::abs(*v) > kMaxCount) first_ = prefix_ + std::string(key);
  }
  void Field(std::string_view, std::uint64_t*, std::string_view) override {}
  void Field(std::string_view, bool*, std::string_view) override {}
  void Field(std::string_view, std::string*, std::string_view) override {}
  void Field(std::string_view key, std::vector<double>* v, std::string_view) override {
    Check(key, *v);
  }
  void Choice(std::string_view, int*, std::initializer_list<std::string_view>,
              std::string_view) override {}
  void Field(std::string_view key, Pose2* v, std::string_view) override {
    Check(key, {v->x(), v->y(), v->theta()});
  }
  void Group(std::string_view key, std::string_view,
             const std::function<void(FieldVisitor&)>& fields) override {
    if (!first_.empty()) return;
    FiniteChecker nested(prefix_ + std::string(key) + ".");
    fields(nested);
    first_ = nested.first_;
  }

 private:
  void Check(std::string_view key, const std::vector<double>& values) {
    if (!first_.empty()) return;
    for (const double x : values)
      if (!std::isfinite(x)) {
        first_ = prefix_ + std::string(key);
        return;
      }
  }
  std::string prefix_, first_;
};

}  // namespace

Status CheckFinite(const std::function<void(FieldVisitor&)>& visit) {
  FiniteChecker checker;
  visit(checker);
  return checker.first().empty()
             ? Status::Ok()
             : Status::Error(checker.first() + " must be a finite number (an integer at most " +
                             std::to_string(kMaxCount) + " in magnitude)");
}

}  // namespace splam::kernel
