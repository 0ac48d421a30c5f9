// A SLAM method registered by a namespace-scope object of a translation unit that nothing else
// refers to (SlamMethodRegistration), as a user's variant in a file of its own would be;
// SlamRegistry.AMethodRegisteredInAnotherUnitIsThere checks it arrived.
#include <memory>

#include "estimation/slam_method.h"
#include "tests/estimation/echo_slam_method.h"

namespace splam::estimation::test_methods {
namespace {

const SlamMethodRegistration<EchoOptions> kRegistered(
    "echo-elsewhere", "registered by a static object in another translation unit",
    [](const EchoOptions& o, const SlamContext& c) { return std::make_unique<Echo>(o, c); });

}  // namespace
}  // namespace splam::estimation::test_methods
