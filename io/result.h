#ifndef SPLAM_IO_RESULT_H_
#define SPLAM_IO_RESULT_H_

#include <string>

#include "kernel/status.h"

namespace splam::io {

// Readers return kernel::Result: the value, or a message that starts with "path:line: ".
template <class T>
using Result = kernel::Result<T>;

// The failure "path:line: message" (line omitted when 0).
kernel::Status FileError(const std::string& path, int line, const std::string& message);

}  // namespace splam::io

#endif  // SPLAM_IO_RESULT_H_
