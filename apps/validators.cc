#include <cmath>
#include <string>

#include "apps/commands.h"
#include "io/floor_plan.h"

namespace splam::apps {
namespace {

// A validator of one number in [lo, hi] (lo excluded when lo_open); `need` says what was needed.
CLI::Validator NumberCheck(const std::string& need, double lo, double hi, bool lo_open) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value) || value > hi ||
            (lo_open ? value <= lo : value < lo))
          return "must be " + need + ", not '" + text + "'";
        return "";
      },
      need);
}

}  // namespace

CLI::Validator FinitePositive() {
  return NumberCheck("a finite number above 0", 0.0, HUGE_VAL, true);
}

CLI::Validator FiniteNonNegative() {
  return NumberCheck("a finite number at least 0", 0.0, HUGE_VAL, false);
}

CLI::Validator FiniteRange(double lo, double hi) {
  return NumberCheck(
      "a finite number in [" + CLI::detail::to_string(lo) + ", " + CLI::detail::to_string(hi) + "]",
      lo, hi, false);
}

CLI::Validator OdometryNoiseScale() { return FiniteRange(0.0, 100.0); }

CLI::Validator FloorPlanResolution() {
  return FiniteRange(io::FloorPlanOptions::kMinResolutionM, io::FloorPlanOptions::kMaxResolutionM);
}

CLI::Validator Seed() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const bool digits =
            !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        if (!digits) return "must be an integer from 0 to 18446744073709551615, not '" + text + "'";
        return "";
      },
      "SEED");
}

CLI::Validator PicturePath() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (text.ends_with(".svg") || text.ends_with(".png")) return "";
        return "must name a .svg or .png picture, not '" + text + "'";
      },
      "PICTURE");
}

CLI::Option* AddPoseOption(CLI::App* cmd, const std::string& name, std::vector<double>* pose,
                           const std::string& help) {
  return cmd->add_option(name, *pose, help)
      ->delimiter(',')
      ->expected(3)
      ->check(FiniteRange(-1e6, 1e6));
}

CLI::Option* AddSetOption(CLI::App* cmd, std::vector<std::string>* sets,
                          const std::string& example) {
  return cmd
      ->add_option("--set", *sets,
                   "Override one option, KEY=VALUE with the keys of the configuration file, e.g. " +
                       example + " (repeatable: one --set per option)")
      ->allow_extra_args(false);
}

}  // namespace splam::apps
