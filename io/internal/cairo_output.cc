#include "io/internal/cairo_output.h"

#include <cairo-svg.h>

#include <cmath>
#include <filesystem>

#include "io/result.h"

namespace splam::io::internal {

kernel::Status WriteCairo(const std::string& path, double width, double height,
                          const std::function<void(cairo_t*)>& paint) {
  const std::string ext = std::filesystem::path(path).extension().string();
  cairo_surface_t* surface = nullptr;
  if (ext == ".svg") {
    surface = cairo_svg_surface_create(path.c_str(), width, height);
  } else if (ext == ".png") {
    surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, static_cast<int>(std::ceil(width)),
                                         static_cast<int>(std::ceil(height)));
  } else {
    return FileError(path, 0, "unknown picture format (use .svg or .png)");
  }
  cairo_t* cr = cairo_create(surface);
  paint(cr);
  cairo_destroy(cr);
  cairo_status_t status = CAIRO_STATUS_SUCCESS;
  if (ext == ".png") {
    status = cairo_surface_write_to_png(surface, path.c_str());
  } else {
    cairo_surface_finish(surface);
    status = cairo_surface_status(surface);
  }
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS) {
    return FileError(path, 0,
                     std::string("cannot write picture: ") + cairo_status_to_string(status));
  }
  return {};
}

}  // namespace splam::io::internal
