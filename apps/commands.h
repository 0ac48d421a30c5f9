#ifndef SPLAM_APPS_COMMANDS_H_
#define SPLAM_APPS_COMMANDS_H_

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "runtime/exit_status.h"

namespace splam::apps {

// Each Add*Command registers a subcommand whose callback stores its exit status in *exit_code.
void AddSimulateCommand(CLI::App* app, int* exit_code);
void AddRenderCommand(CLI::App* app, int* exit_code);
void AddSlamCommand(CLI::App* app, int* exit_code);
void AddEvalCommand(CLI::App* app, int* exit_code);
void AddExperimentCommand(CLI::App* app, int* exit_code);
void AddExploreCommand(CLI::App* app, int* exit_code);
void AddConfigCommand(CLI::App* app, int* exit_code);
void AddConvertCommand(CLI::App* app, int* exit_code);
void AddSplitCommand(CLI::App* app, int* exit_code);
void AddSweepCommand(CLI::App* app, int* exit_code);

// The path of this splam binary (sweeps and experiments run their cells with it).
std::string SplamBinary();

// Exit statuses of every command: 0 done, 2 bad input, 3 stopped early (results written).
using runtime::kExitBadInput;
using runtime::kExitIncomplete;
using runtime::kExitOk;
using runtime::kExitWriteFailed;

// Number checks for options. CLI::PositiveNumber, NonNegativeNumber and Range let NaN through
// (every comparison with it is false), and CLI11 reads "-1" as 2^64 - 1 for an unsigned option.
// A finite number above 0.
CLI::Validator FinitePositive();
// A finite number at least 0.
CLI::Validator FiniteNonNegative();
// A finite number in [lo, hi].
CLI::Validator FiniteRange(double lo, double hi);
// A scale of the default odometry noise: a finite number in [0, 100]. At 1e308 `simulate` wrote
// poses of 1e304 m, a log its own readers refuse.
CLI::Validator OdometryNoiseScale();
// A floor-plan image's metres per pixel, within io::FloorPlanOptions' range.
CLI::Validator FloorPlanResolution();
// A seed: an integer from 0 to 2^64 - 1 written without a sign.
CLI::Validator Seed();
// A picture's path: ending in .svg or .png (a picture that then cannot be written is a failed
// write, exit 4, not bad input).
CLI::Validator PicturePath();
// An option "X,Y,THETA" (m, m, rad) into *pose (three numbers, or empty when not given).
CLI::Option* AddPoseOption(CLI::App* cmd, const std::string& name, std::vector<double>* pose,
                           const std::string& help);
// --set KEY=VALUE, repeatable, one assignment per --set (so that `--set K=V LOG` leaves the log
// to the positional argument); `example` is an assignment shown in the help.
CLI::Option* AddSetOption(CLI::App* cmd, std::vector<std::string>* sets,
                          const std::string& example);

}  // namespace splam::apps

#endif  // SPLAM_APPS_COMMANDS_H_
