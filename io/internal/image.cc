#include "io/internal/image.h"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <string_view>

namespace splam::io::internal {
namespace {

// Whether the file starts as a PNG, JPEG, Netpbm (PGM, PPM, PBM), BMP or TIFF image does, as
// OpenCV's decoders of those formats check it. cv::imread picks the first decoder whose check
// passes, whatever the name, and Debian's OpenCV also decodes DICOM, JPEG 2000, OpenEXR, HDR and
// others: files that no earlier decoder took but with "DICM" at byte 128, where DICOM puts it,
// went to GDCM, which aborts on a failed assertion (a ".png" of other bytes, and a "P24" file: a
// Netpbm magic number must be followed by white space). Both found by fuzz_floor_plan.
bool HasImageSignature(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(8, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const auto starts = [&](std::string_view magic) { return head.starts_with(magic); };
  return starts("\x89PNG\r\n\x1a\n") || starts("\xff\xd8\xff") || starts("BM") ||
         starts(std::string_view("II*\0", 4)) || starts(std::string_view("MM\0*", 4)) ||
         (head.size() >= 3 && head[0] == 'P' && head[1] >= '1' && head[1] <= '6' &&
          std::isspace(static_cast<unsigned char>(head[2])));
}

}  // namespace

Result<cv::Mat> ReadGreyImage(const std::string& path) {
  using R = Result<cv::Mat>;
  if (!std::filesystem::is_regular_file(path))
    return R::Fail(FileError(path, 0, "no such image file"));
  if (!HasImageSignature(path))
    return R::Fail(FileError(path, 0, "not a PNG, JPEG, PGM/PPM/PBM, BMP or TIFF image"));
  cv::Mat grey;
  try {
    grey = cv::imread(path, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    return R::Fail(FileError(path, 0, std::string("cannot decode image: ") + e.what()));
  }
  if (grey.empty())
    return R::Fail(FileError(path, 0, "cannot decode image (not a PNG/JPEG/... file?)"));
  return R::Ok(std::move(grey));
}

}  // namespace splam::io::internal
