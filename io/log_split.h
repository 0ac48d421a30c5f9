#ifndef SPLAM_IO_LOG_SPLIT_H_
#define SPLAM_IO_LOG_SPLIT_H_

#include <cstdint>
#include <string>
#include <vector>

#include "io/carmen.h"
#include "io/result.h"
#include "kernel/pose2.h"
#include "kernel/status.h"

// Cuts one log into sessions that look as if different robots, or the same robot on different
// days, had recorded them: consecutive stretches with equally many scans, each with its odometry
// moved by a rigid motion that nothing in the session tells. A method that maps the sessions
// together must find how they join from the scans alone; scored with the whole log's relations
// (relative motions, which no rigid motion of a session changes), the relations whose two ends
// lie in different sessions measure the joins (`splam split`, docs/sessions.md).
namespace splam::io {

struct LogSplitOptions {
  int sessions = 3;  // 2-10
  // Each session's first pose is moved to a pose this far (uniformly in [min, max]) from where
  // the log had it, in a uniform direction, with a uniform heading, m. 50-150 m: far beyond any
  // loop-closure window, so that only a search of the whole map can join the session.
  double min_offset_m = 50.0;
  double max_offset_m = 150.0;
  std::uint64_t seed = 1;

  kernel::Status Validate() const;
};

struct LogSession {
  std::string name;  // "session1", ...
  CarmenLog log;     // its messages, in file order, odometry moved; time stamps kept
  // The session's odometry frame in the log's: a pose p the session's odometry reports is
  // log_T_session * p in the log's. Ground truth (TRUEPOS true poses) is left as it was.
  kernel::Pose2 log_T_session;
  int scans = 0;
  double first_time_s = 0.0, last_time_s = 0.0;  // of its first and last scan
};

// The sessions of `log` (every message in exactly one, in order: a session runs from its first
// scan to the message before the next session's first scan; messages before the first scan go
// to the first). Fails when the log has fewer than 10 scans per session.
Result<std::vector<LogSession>> SplitLog(const CarmenLog& log, const LogSplitOptions& options);

}  // namespace splam::io

#endif  // SPLAM_IO_LOG_SPLIT_H_
