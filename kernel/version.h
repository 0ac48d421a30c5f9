#ifndef SPLAM_KERNEL_VERSION_H_
#define SPLAM_KERNEL_VERSION_H_

#include <string_view>

namespace splam::kernel {

// The git commit splam was built from ("0123abcd4567", with "-dirty" when the tree had changes
// to tracked files; "unknown" outside a git checkout). Run reports record it.
std::string_view GitCommit();

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_VERSION_H_
