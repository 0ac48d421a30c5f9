#include "io/render.h"

#include <cairo.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <filesystem>

#include "io/internal/cairo_output.h"
#include "io/result.h"

namespace splam::io {
namespace {

constexpr double kTitleBand = 28.0;   // px above the map when there is a title
constexpr double kFooterBand = 30.0;  // px below the map for the scale bar and legend
constexpr double kLegendRow = 16.0;   // px per extra legend row
using internal::kFont;

enum class LegendKind { kLine, kPoints, kCircle, kDiamond };

struct LegendEntry {
  std::string label;
  Rgb color;
  LegendKind kind;
};

void SetColor(cairo_t* cr, Rgb c, double alpha = 1.0) {
  cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha);
}

// 1, 2 or 5 times a power of ten, close to `target`.
double NiceLength(double target) {
  const double p = std::pow(10.0, std::floor(std::log10(target)));
  for (double m : {5.0, 2.0, 1.0}) {
    if (m * p <= target) return m * p;
  }
  return p;
}

}  // namespace

kernel::Status FigureOptions::Validate() const {
  if (!(pixels_per_meter > 0.0) || !std::isfinite(pixels_per_meter))
    return kernel::Status::Error("pixels_per_meter must be positive");
  if (!(margin_m >= 0.0)) return kernel::Status::Error("margin_m must be >= 0");
  if (max_pixels < 100) return kernel::Status::Error("max_pixels must be at least 100");
  return kernel::Status::Ok();
}

struct Figure::Impl {
  kernel::Box2 area;
  FigureOptions options;
  double ppm = 1.0;
  double width = 0.0, map_height = 0.0;
  cairo_surface_t* recording = nullptr;
  cairo_t* cr = nullptr;
  std::vector<LegendEntry> legend;
  // Text, legend, scale bar and line widths grow with the picture (a 4000 px map shown 800 px
  // wide in a page shrinks them five times): sizes in pixels are for a picture up to 1000 px
  // wide. Markers and points do not: grown, a long log's thousands of them bury the map.
  double text_scale = 1.0;

  Eigen::Vector2d ToPixel(const Eigen::Vector2d& p) const {
    return {(p.x() - area.min.x() + options.margin_m) * ppm,
            (area.max.y() - p.y() + options.margin_m) * ppm};
  }
  // Starts a path through the points (world coordinates).
  void Trace(const std::vector<Eigen::Vector2d>& points) const {
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector2d q = ToPixel(points[i]);
      if (i == 0) {
        cairo_move_to(cr, q.x(), q.y());
      } else {
        cairo_line_to(cr, q.x(), q.y());
      }
    }
  }
  void AddLegend(const std::string& label, Rgb color, LegendKind kind) {
    if (label.empty()) return;
    for (const LegendEntry& e : legend) {
      if (e.label == label) return;
    }
    legend.push_back({label, color, kind});
  }
  // Legend entries laid out left to right after the scale bar, wrapping into rows that fit the
  // width: the x offset and row of each entry.
  struct Slot {
    double x;
    int row;
  };
  std::vector<Slot> LayoutLegend(double* scale_length_m) const;
  double Height() const;
  void Paint(cairo_t* target) const;
};

std::vector<Figure::Impl::Slot> Figure::Impl::LayoutLegend(double* scale_length_m) const {
  *scale_length_m = NiceLength(0.2 * width / ppm);
  cairo_surface_t* scratch = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1);
  cairo_t* measure = cairo_create(scratch);
  cairo_select_font_face(measure, kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(measure, 11.0 * text_scale);
  const double start = 24.0 * text_scale + *scale_length_m * ppm;
  std::vector<Slot> slots;
  double x = start;
  int row = 0;
  for (const LegendEntry& e : legend) {
    cairo_text_extents_t extents;
    cairo_text_extents(measure, e.label.c_str(), &extents);
    const double w = 34.0 * text_scale + extents.x_advance;
    if (x > start && x + w > width) {
      x = start;
      ++row;
    }
    slots.push_back({x, row});
    x += w;
  }
  cairo_destroy(measure);
  cairo_surface_destroy(scratch);
  return slots;
}

double Figure::Impl::Height() const {
  double scale_length_m = 0.0;
  const std::vector<Slot> slots = LayoutLegend(&scale_length_m);
  const int rows = slots.empty() ? 1 : slots.back().row + 1;
  return (options.title.empty() ? 0.0 : kTitleBand * text_scale) + map_height +
         (kFooterBand + kLegendRow * (rows - 1)) * text_scale;
}

Figure::Figure(const kernel::Box2& area, const FigureOptions& options)
    : impl_(std::make_unique<Impl>()) {
  assert(!area.IsEmpty() && options.Validate().ok());
  impl_->area = area;
  impl_->options = options;
  const Eigen::Vector2d size = area.Size() + Eigen::Vector2d::Constant(2.0 * options.margin_m);
  impl_->ppm =
      std::min(options.pixels_per_meter, options.max_pixels / std::max(size.maxCoeff(), 1e-9));
  impl_->width = std::ceil(size.x() * impl_->ppm);
  impl_->map_height = std::ceil(size.y() * impl_->ppm);
  impl_->text_scale = std::max(1.0, impl_->width / 1000.0);
  const cairo_rectangle_t extents{0.0, 0.0, impl_->width, impl_->map_height};
  impl_->recording = cairo_recording_surface_create(CAIRO_CONTENT_COLOR_ALPHA, &extents);
  impl_->cr = cairo_create(impl_->recording);
  cairo_set_line_join(impl_->cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(impl_->cr, CAIRO_LINE_CAP_ROUND);
}

Figure::~Figure() {
  cairo_destroy(impl_->cr);
  cairo_surface_destroy(impl_->recording);
}

void Figure::DrawWorld(const sim::World& world, Rgb color, const std::string& legend) {
  if (world.obstacles.empty()) return;
  cairo_t* cr = impl_->cr;
  for (std::size_t i = 0; i < world.obstacles.size(); ++i) {
    const bool glass = world.IsGlass(i);
    sim::Primitives p;
    world.AppendPrimitives(i, &p);
    // Chained segments and Bezier pieces continue the current sub-path, so closed outlines fill.
    for (const auto& s : p.segments) {
      const Eigen::Vector2d a = impl_->ToPixel(s.a), b = impl_->ToPixel(s.b);
      if (!cairo_has_current_point(cr)) cairo_move_to(cr, a.x(), a.y());
      cairo_line_to(cr, b.x(), b.y());
    }
    for (const auto& b : p.beziers) {
      const Eigen::Vector2d q0 = impl_->ToPixel(b.p[0]), q1 = impl_->ToPixel(b.p[1]),
                            q2 = impl_->ToPixel(b.p[2]), q3 = impl_->ToPixel(b.p[3]);
      if (!cairo_has_current_point(cr)) cairo_move_to(cr, q0.x(), q0.y());
      cairo_curve_to(cr, q1.x(), q1.y(), q2.x(), q2.y(), q3.x(), q3.y());
    }
    for (const auto& c : p.circles) {
      const Eigen::Vector2d q = impl_->ToPixel(c.center);
      cairo_new_sub_path(cr);
      cairo_arc(cr, q.x(), q.y(), c.radius * impl_->ppm, 0.0, 2.0 * M_PI);
    }
    for (const auto& e : p.ellipses) {
      const Eigen::Vector2d q = impl_->ToPixel(e.center);
      cairo_save(cr);
      cairo_translate(cr, q.x(), q.y());
      cairo_rotate(cr, -e.angle_rad);  // pixel y points down
      cairo_scale(cr, e.radius_x * impl_->ppm, e.radius_y * impl_->ppm);
      cairo_new_sub_path(cr);
      cairo_arc(cr, 0.0, 0.0, 1.0, 0.0, 2.0 * M_PI);
      cairo_restore(cr);
    }
    const bool closed = std::visit(
        [](const auto& shape) {
          if constexpr (requires { shape.closed; })
            return shape.closed;
          else
            return true;
        },
        world.obstacles[i]);
    const Rgb drawn = glass ? palette::kGlass : color;
    if (closed) {
      cairo_close_path(cr);
      SetColor(cr, drawn, 0.15);
      cairo_fill_preserve(cr);
    }
    SetColor(cr, drawn);
    cairo_set_line_width(cr, (glass ? 3.0 : 2.0) * impl_->text_scale);
    cairo_stroke(cr);
  }
  impl_->AddLegend(legend, color, LegendKind::kLine);
  if (!world.glass.empty())
    impl_->AddLegend("glass (no laser returns)", palette::kGlass, LegendKind::kLine);
}

void Figure::DrawPath(const std::vector<kernel::Pose2>& poses, Rgb color, double width_px,
                      const std::string& legend) {
  if (poses.empty()) return;
  cairo_t* cr = impl_->cr;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Vector2d q = impl_->ToPixel(poses[i].translation());
    if (i == 0)
      cairo_move_to(cr, q.x(), q.y());
    else
      cairo_line_to(cr, q.x(), q.y());
  }
  SetColor(cr, color);
  cairo_set_line_width(cr, width_px * impl_->text_scale);
  cairo_stroke(cr);
  impl_->AddLegend(legend, color, LegendKind::kLine);
}

void Figure::DrawPoints(const std::vector<Eigen::Vector2d>& points, Rgb color, double radius_px,
                        const std::string& legend) {
  if (points.empty()) return;
  cairo_t* cr = impl_->cr;
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2d q = impl_->ToPixel(p);
    cairo_rectangle(cr, q.x() - radius_px, q.y() - radius_px, 2 * radius_px, 2 * radius_px);
  }
  SetColor(cr, color, 0.6);
  cairo_fill(cr);
  impl_->AddLegend(legend, color, LegendKind::kPoints);
}

void Figure::DrawPolyline(const std::vector<Eigen::Vector2d>& points, Rgb color, double width_px,
                          const std::string& legend, bool dashed) {
  if (points.empty()) return;
  cairo_t* cr = impl_->cr;
  impl_->Trace(points);
  SetColor(cr, color);
  cairo_set_line_width(cr, width_px * impl_->text_scale);
  const double dash[] = {4.0, 3.0};
  cairo_set_dash(cr, dash, dashed ? 2 : 0, 0.0);
  cairo_stroke(cr);
  cairo_set_dash(cr, nullptr, 0, 0.0);
  impl_->AddLegend(legend, color, LegendKind::kLine);
}

void Figure::DrawPolygon(const std::vector<Eigen::Vector2d>& points, Rgb color, double fill_alpha,
                         double width_px, const std::string& legend) {
  if (points.size() < 3) return;
  cairo_t* cr = impl_->cr;
  impl_->Trace(points);
  cairo_close_path(cr);
  SetColor(cr, color, fill_alpha);
  cairo_fill_preserve(cr);
  SetColor(cr, color);
  cairo_set_line_width(cr, width_px * impl_->text_scale);
  if (width_px > 0.0) {
    cairo_stroke(cr);
  } else {
    cairo_new_path(cr);
  }
  impl_->AddLegend(legend, color, LegendKind::kPoints);
}

void Figure::DrawMarkers(const std::vector<Eigen::Vector2d>& points, Marker marker, Rgb color,
                         double size_px, const std::string& legend) {
  if (points.empty()) return;
  cairo_t* cr = impl_->cr;
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2d q = impl_->ToPixel(p);
    cairo_new_sub_path(cr);
    if (marker == Marker::kCircle) {
      cairo_arc(cr, q.x(), q.y(), size_px, 0.0, 2.0 * M_PI);
    } else {
      cairo_move_to(cr, q.x(), q.y() - size_px);
      cairo_line_to(cr, q.x() + size_px, q.y());
      cairo_line_to(cr, q.x(), q.y() + size_px);
      cairo_line_to(cr, q.x() - size_px, q.y());
      cairo_close_path(cr);
    }
  }
  SetColor(cr, color);
  cairo_set_line_width(cr, 2.0);
  cairo_stroke(cr);
  impl_->AddLegend(legend, color,
                   marker == Marker::kCircle ? LegendKind::kCircle : LegendKind::kDiamond);
}

void Figure::DrawRaster(const std::vector<Rgb8>& pixels, int columns, int rows,
                        const kernel::Box2& area) {
  assert(pixels.size() == static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows));
  if (columns <= 0 || rows <= 0) return;
  cairo_surface_t* image = cairo_image_surface_create(CAIRO_FORMAT_RGB24, columns, rows);
  cairo_surface_flush(image);
  unsigned char* data = cairo_image_surface_get_data(image);
  const int stride = cairo_image_surface_get_stride(image);
  for (int r = 0; r < rows; ++r) {
    auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(r) * stride);
    for (int c = 0; c < columns; ++c) {
      const Rgb8& p = pixels[static_cast<std::size_t>(r) * static_cast<std::size_t>(columns) +
                             static_cast<std::size_t>(c)];
      row[c] = (std::uint32_t{p.r} << 16) | (std::uint32_t{p.g} << 8) | std::uint32_t{p.b};
    }
  }
  cairo_surface_mark_dirty(image);
  cairo_t* cr = impl_->cr;
  const Eigen::Vector2d top_left = impl_->ToPixel({area.min.x(), area.max.y()});
  cairo_save(cr);
  cairo_translate(cr, top_left.x(), top_left.y());
  cairo_scale(cr, area.Size().x() * impl_->ppm / columns, area.Size().y() * impl_->ppm / rows);
  cairo_set_source_surface(cr, image, 0.0, 0.0);
  // Every cell a sharp square, however much the picture enlarges it.
  cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
  cairo_rectangle(cr, 0.0, 0.0, columns, rows);
  cairo_fill(cr);
  cairo_restore(cr);
  cairo_surface_destroy(image);
}

void Figure::AddLegend(const std::string& label, Rgb color) {
  impl_->AddLegend(label, color, LegendKind::kPoints);
}

void Figure::DrawRobot(const kernel::Pose2& pose, double radius_m, Rgb color) {
  cairo_t* cr = impl_->cr;
  const Eigen::Vector2d c = impl_->ToPixel(pose.translation());
  const Eigen::Vector2d tip = impl_->ToPixel(pose * Eigen::Vector2d(radius_m, 0.0));
  cairo_new_sub_path(cr);
  cairo_arc(cr, c.x(), c.y(), radius_m * impl_->ppm, 0.0, 2.0 * M_PI);
  cairo_move_to(cr, c.x(), c.y());
  cairo_line_to(cr, tip.x(), tip.y());
  SetColor(cr, color);
  cairo_set_line_width(cr, 1.5 * impl_->text_scale);
  cairo_stroke(cr);
}

void Figure::Impl::Paint(cairo_t* target) const {
  const double k = text_scale;
  const double top = options.title.empty() ? 0.0 : kTitleBand * k;
  cairo_set_source_rgb(target, 1, 1, 1);
  cairo_paint(target);
  // The recording holds only what lies in the area (plus margin), so no clip is needed; a clip
  // here made cairo emit a reference to an undefined clip path in SVG output.
  cairo_set_source_surface(target, recording, 0.0, top);
  cairo_paint(target);

  cairo_select_font_face(target, kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  if (!options.title.empty()) {
    // 15 px (scaled), smaller when a long title would run past the right edge.
    cairo_set_font_size(target, 15.0 * k);
    cairo_text_extents_t extents;
    cairo_text_extents(target, options.title.c_str(), &extents);
    const double room = width - 16.0 * k;
    if (extents.x_advance > room)
      cairo_set_font_size(target, std::max(15.0 * k * room / extents.x_advance, 8.0));
    cairo_set_source_rgb(target, 0, 0, 0);
    cairo_move_to(target, 8.0 * k, 19.0 * k);
    cairo_show_text(target, options.title.c_str());
  }
  // Scale bar, bottom left.
  const double y = top + map_height + 12.0 * k;
  double length_m = 0.0;
  const std::vector<Slot> slots = LayoutLegend(&length_m);
  cairo_set_source_rgb(target, 0, 0, 0);
  cairo_set_line_width(target, 2.0 * k);
  cairo_move_to(target, 8.0 * k, y - 4.0 * k);
  cairo_line_to(target, 8.0 * k, y);
  cairo_line_to(target, 8.0 * k + length_m * ppm, y);
  cairo_line_to(target, 8.0 * k + length_m * ppm, y - 4.0 * k);
  cairo_stroke(target);
  cairo_set_font_size(target, 11.0 * k);
  char label[32];
  std::snprintf(label, sizeof(label), "%g m", length_m);
  cairo_move_to(target, 8.0 * k, y + 13.0 * k);
  cairo_show_text(target, label);
  // Legend, to the right of the scale bar.
  for (std::size_t i = 0; i < legend.size(); ++i) {
    const LegendEntry& e = legend[i];
    const double x = slots[i].x;
    const double y_row = y + kLegendRow * k * slots[i].row;
    SetColor(target, e.color);
    switch (e.kind) {
      case LegendKind::kPoints:
        cairo_rectangle(target, x + 4.0 * k, y_row - 4.0 * k, 8.0 * k, 8.0 * k);
        cairo_fill_preserve(target);
        cairo_set_source_rgb(target, 0.3, 0.3, 0.3);  // a white swatch stays visible
        cairo_set_line_width(target, 0.5 * k);
        cairo_stroke(target);
        break;
      case LegendKind::kLine:
        cairo_set_line_width(target, 2.5 * k);
        cairo_move_to(target, x, y_row);
        cairo_line_to(target, x + 16.0 * k, y_row);
        cairo_stroke(target);
        break;
      case LegendKind::kCircle:
        cairo_set_line_width(target, 2.0 * k);
        cairo_new_sub_path(target);
        cairo_arc(target, x + 8.0 * k, y_row, 4.0 * k, 0.0, 2.0 * M_PI);
        cairo_stroke(target);
        break;
      case LegendKind::kDiamond:
        cairo_set_line_width(target, 2.0 * k);
        cairo_move_to(target, x + 8.0 * k, y_row - 5.0 * k);
        cairo_line_to(target, x + 13.0 * k, y_row);
        cairo_line_to(target, x + 8.0 * k, y_row + 5.0 * k);
        cairo_line_to(target, x + 3.0 * k, y_row);
        cairo_close_path(target);
        cairo_stroke(target);
        break;
    }
    cairo_set_source_rgb(target, 0, 0, 0);
    cairo_move_to(target, x + 20.0 * k, y_row + 4.0 * k);
    cairo_show_text(target, e.label.c_str());
  }
}

kernel::Status Figure::Save(const std::string& path) const {
  return internal::WriteCairo(path, impl_->width, impl_->Height(),
                              [&](cairo_t* cr) { impl_->Paint(cr); });
}

}  // namespace splam::io
