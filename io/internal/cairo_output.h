#ifndef SPLAM_IO_INTERNAL_CAIRO_OUTPUT_H_
#define SPLAM_IO_INTERNAL_CAIRO_OUTPUT_H_

#include <cairo.h>

#include <functional>
#include <string>

#include "kernel/status.h"

namespace splam::io::internal {

// Creates an SVG or PNG surface (by the path's extension) of width x height pixels, lets `paint`
// draw on it and writes the file. Ok, else "path: why".
kernel::Status WriteCairo(const std::string& path, double width, double height,
                          const std::function<void(cairo_t*)>& paint);

inline constexpr const char* kFont = "DejaVu Sans";

}  // namespace splam::io::internal

#endif  // SPLAM_IO_INTERNAL_CAIRO_OUTPUT_H_
