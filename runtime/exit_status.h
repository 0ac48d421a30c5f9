#ifndef SPLAM_RUNTIME_EXIT_STATUS_H_
#define SPLAM_RUNTIME_EXIT_STATUS_H_

namespace splam::runtime {

// Exit statuses of every command and experiment.
inline constexpr int kExitOk = 0;
inline constexpr int kExitBadInput = 2;     // unreadable or malformed input, invalid options
inline constexpr int kExitIncomplete = 3;   // the job ran but stopped early (results written)
inline constexpr int kExitWriteFailed = 4;  // a result file could not be written (named)

}  // namespace splam::runtime

#endif  // SPLAM_RUNTIME_EXIT_STATUS_H_
