#ifndef SPLAM_TESTS_ESTIMATION_ECHO_SLAM_METHOD_H_
#define SPLAM_TESTS_ESTIMATION_ECHO_SLAM_METHOD_H_

#include <string>

#include "estimation/slam_method.h"

namespace splam::estimation::test_methods {

// A method of one's own: it reports what it was given.
struct EchoOptions {
  double gain = 1.0;
  void VisitFields(kernel::FieldVisitor& v) { v.Field("gain", &gain, "a gain"); }
  kernel::Status Validate() const {
    return gain > 0 ? kernel::Status::Ok() : kernel::Status::Error("gain must be positive");
  }
};
class Echo : public SlamMethod {
 public:
  Echo(const EchoOptions& o, const SlamContext& c) : gain_(o.gain), pose_(c.start) {}
  void Predict(const kernel::Pose2& u) override { pose_ = pose_ * u; }
  void Update(const kernel::Scan&, const kernel::Pose2&) override { ++updates_; }
  kernel::Pose2 pose() const override { return pose_; }
  kernel::Status health() const override { return kernel::Status::Ok(); }
  std::size_t MapSize() const override { return static_cast<std::size_t>(updates_); }
  std::string MapDescription() const override { return "echo"; }
  SlamMap Map() const override { return {}; }
  SlamStatistics Statistics() const override {
    SlamStatistics s;
    s.map = {{"gain", long(gain_)}};
    return s;
  }

 private:
  double gain_;
  kernel::Pose2 pose_;
  int updates_ = 0;
};

}  // namespace splam::estimation::test_methods

#endif  // SPLAM_TESTS_ESTIMATION_ECHO_SLAM_METHOD_H_
