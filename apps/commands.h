#ifndef SPLAM_APPS_COMMANDS_H_
#define SPLAM_APPS_COMMANDS_H_

#include <CLI/CLI.hpp>

namespace splam::apps {

// Each Add*Command registers a subcommand whose callback stores its exit status in *exit_code.
void AddSimulateCommand(CLI::App* app, int* exit_code);
void AddRenderCommand(CLI::App* app, int* exit_code);
void AddSlamCommand(CLI::App* app, int* exit_code);
void AddEvalCommand(CLI::App* app, int* exit_code);
void AddExperimentCommand(CLI::App* app, int* exit_code);
void AddExploreCommand(CLI::App* app, int* exit_code);
void AddConfigCommand(CLI::App* app, int* exit_code);

// Exit statuses of every command.
inline constexpr int kExitOk = 0;
inline constexpr int kExitBadInput = 2;    // unreadable or malformed input, invalid options
inline constexpr int kExitIncomplete = 3;  // the job ran but stopped early (results written)

}  // namespace splam::apps

#endif  // SPLAM_APPS_COMMANDS_H_
