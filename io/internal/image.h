#ifndef SPLAM_IO_INTERNAL_IMAGE_H_
#define SPLAM_IO_INTERNAL_IMAGE_H_

#include <opencv2/core.hpp>
#include <string>

#include "io/result.h"

namespace splam::io::internal {

// The image file at `path` in 8-bit grey levels, read by OpenCV once its first bytes show a PNG,
// JPEG, Netpbm, BMP or TIFF file; an error names the file.
Result<cv::Mat> ReadGreyImage(const std::string& path);

}  // namespace splam::io::internal

#endif  // SPLAM_IO_INTERNAL_IMAGE_H_
