#ifndef SPLAM_IO_RELATIONS_H_
#define SPLAM_IO_RELATIONS_H_

#include <string>
#include <vector>

#include "estimation/evaluation/metrics.h"
#include "io/result.h"

namespace splam::io {

// Relations files of the SLAM benchmark of Kümmerle et al. 2009: one relation per line,
//   t1 t2 x y z roll pitch yaw
// the motion from the pose at t1 to the pose at t2 in the frame of the first (z, roll and pitch
// are 0 in 2-D); '#' starts a comment line. Errors name the file and line.
Result<std::vector<evaluation::Relation>> ReadRelations(const std::string& path);
Result<std::vector<evaluation::Relation>> ParseRelations(const std::string& text,
                                                         const std::string& name);

}  // namespace splam::io

#endif  // SPLAM_IO_RELATIONS_H_
