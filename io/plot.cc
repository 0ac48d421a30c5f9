#include "io/plot.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "io/internal/cairo_output.h"

namespace splam::io {
namespace {

constexpr double kLeft = 70.0, kRight = 20.0, kTitle = 30.0, kGap = 18.0, kBottom = 45.0;

// About `target` ticks at 1, 2 or 5 times a power of ten covering [lo, hi].
std::vector<double> Ticks(double lo, double hi, int target = 5) {
  const double raw = (hi - lo) / target;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  double step = p;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * p >= raw) {
      step = m * p;
      break;
    }
  }
  std::vector<double> ticks;
  for (double t = std::ceil(lo / step) * step; t <= hi + 1e-9 * step; t += step)
    ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  return ticks;
}

void Text(cairo_t* cr, double x, double y, const std::string& text, double size,
          double align = 0.0) {
  cairo_set_font_size(cr, size);
  cairo_text_extents_t e;
  cairo_text_extents(cr, text.c_str(), &e);
  cairo_move_to(cr, x - align * e.x_advance, y);
  cairo_show_text(cr, text.c_str());
}

}  // namespace

kernel::Status PlotOptions::Validate() const {
  if (!(width_px >= 200.0) || !(panel_height_px >= 80.0))
    return kernel::Status::Error("plot too small");
  return kernel::Status::Ok();
}

kernel::Status SavePlot(const std::vector<PlotPanel>& panels, const PlotOptions& options,
                        const std::vector<std::string>& paths) {
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
  for (const PlotPanel& panel : panels) {
    for (const PlotSeries& s : panel.series) {
      for (double x : s.x) x_lo = std::min(x_lo, x), x_hi = std::max(x_hi, x);
    }
  }
  if (!options.x_labels.empty()) {
    x_lo = std::min(x_lo, 0.0);
    x_hi = std::max(x_hi, static_cast<double>(options.x_labels.size()) - 1.0);
  }
  if (!(x_lo <= x_hi)) x_lo = 0.0, x_hi = 1.0;  // no data
  if (x_lo == x_hi) x_lo -= 0.5, x_hi += 0.5;
  bool any_bars = false;
  for (const PlotPanel& panel : panels) {
    for (const PlotSeries& s : panel.series) any_bars = any_bars || s.bars;
  }
  if (any_bars || !options.x_labels.empty()) x_lo -= 0.5, x_hi += 0.5;  // room at the ends
  const double width = options.width_px;
  const double height =
      kTitle + static_cast<double>(panels.size()) * (options.panel_height_px + kGap) + kBottom;
  const double plot_w = width - kLeft - kRight;

  auto paint = [&](cairo_t* cr) {
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_select_font_face(cr, internal::kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_source_rgb(cr, 0, 0, 0);
    Text(cr, 8, 20, options.title, 15);
    for (std::size_t k = 0; k < panels.size(); ++k) {
      const PlotPanel& panel = panels[k];
      const double top = kTitle + static_cast<double>(k) * (options.panel_height_px + kGap);
      const double h = options.panel_height_px - 10.0;
      double y_lo = std::numeric_limits<double>::infinity(), y_hi = -y_lo;
      for (const PlotSeries& s : panel.series) {
        for (double y : s.y) y_lo = std::min(y_lo, y), y_hi = std::max(y_hi, y);
      }
      if (!(y_lo <= y_hi)) y_lo = -1.0, y_hi = 1.0;
      y_lo = std::min(y_lo, 0.0);
      y_hi = std::max(y_hi, 0.0);
      if (y_hi - y_lo < 1e-12) y_lo -= 1.0, y_hi += 1.0;
      const double pad = 0.05 * (y_hi - y_lo);
      y_lo -= pad;
      y_hi += pad;
      auto px = [&](double x) { return kLeft + (x - x_lo) / (x_hi - x_lo) * plot_w; };
      auto py = [&](double y) { return top + h - (y - y_lo) / (y_hi - y_lo) * h; };
      // Frame, grid and ticks.
      cairo_set_line_width(cr, 1.0);
      cairo_set_source_rgb(cr, 0.85, 0.85, 0.85);
      for (double t : Ticks(y_lo, y_hi)) {
        cairo_move_to(cr, kLeft, py(t));
        cairo_line_to(cr, kLeft + plot_w, py(t));
      }
      cairo_stroke(cr);
      cairo_set_source_rgb(cr, 0.5, 0.5, 0.5);
      cairo_move_to(cr, kLeft, py(0.0));
      cairo_line_to(cr, kLeft + plot_w, py(0.0));
      cairo_stroke(cr);
      cairo_set_source_rgb(cr, 0, 0, 0);
      cairo_rectangle(cr, kLeft, top, plot_w, h);
      cairo_stroke(cr);
      for (double t : Ticks(y_lo, y_hi)) {
        char label[32];
        std::snprintf(label, sizeof(label), "%g", t);
        Text(cr, kLeft - 6, py(t) + 4, label, 10, 1.0);
      }
      if (k + 1 == panels.size()) {
        if (options.x_labels.empty()) {
          for (double t : Ticks(x_lo, x_hi, 8)) {
            char label[32];
            std::snprintf(label, sizeof(label), "%g", t);
            Text(cr, px(t), top + h + 14, label, 10, 0.5);
          }
        }
        for (std::size_t i = 0; i < options.x_labels.size(); ++i)
          Text(cr, px(static_cast<double>(i)), top + h + 14, options.x_labels[i], 10, 0.5);
        Text(cr, kLeft + plot_w / 2, top + h + 32, options.x_label, 12, 0.5);
      }
      cairo_save(cr);
      cairo_translate(cr, 16, top + h / 2);
      cairo_rotate(cr, -M_PI / 2);
      Text(cr, 0, 0, panel.y_label, 12, 0.5);
      cairo_restore(cr);
      // Series, clipped to the panel.
      cairo_save(cr);
      cairo_rectangle(cr, kLeft, top, plot_w, h);
      cairo_clip(cr);
      const int bar_series = static_cast<int>(std::count_if(
          panel.series.begin(), panel.series.end(), [](const PlotSeries& s) { return s.bars; }));
      int bar_index = 0;
      for (const PlotSeries& s : panel.series) {
        if (s.bars) {
          const double w = 0.8 / bar_series;
          const double offset = (bar_index++ - 0.5 * (bar_series - 1)) * w;
          for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
            const double x0 = px(s.x[i] + offset - 0.5 * w), x1 = px(s.x[i] + offset + 0.5 * w);
            cairo_rectangle(cr, x0, py(std::max(0.0, s.y[i])), x1 - x0,
                            std::abs(py(s.y[i]) - py(0.0)));
          }
          cairo_set_source_rgb(cr, s.color.r, s.color.g, s.color.b);
          cairo_fill(cr);
          continue;
        }
        if (s.points) {
          for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
            cairo_new_sub_path(cr);
            cairo_arc(cr, px(s.x[i]), py(s.y[i]), 2.8, 0.0, 2.0 * M_PI);
          }
          cairo_set_source_rgb(cr, s.color.r, s.color.g, s.color.b);
          cairo_fill(cr);
          continue;
        }
        for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
          if (i == 0)
            cairo_move_to(cr, px(s.x[i]), py(s.y[i]));
          else
            cairo_line_to(cr, px(s.x[i]), py(s.y[i]));
        }
        cairo_set_source_rgb(cr, s.color.r, s.color.g, s.color.b);
        cairo_set_line_width(cr, 1.5);
        cairo_stroke(cr);
      }
      cairo_restore(cr);
      // Legend, top right inside the panel.
      double ly = top + 14;
      for (const PlotSeries& s : panel.series) {
        if (s.label.empty()) continue;
        cairo_set_source_rgb(cr, s.color.r, s.color.g, s.color.b);
        cairo_set_line_width(cr, 2.5);
        cairo_move_to(cr, kLeft + plot_w - 150, ly - 4);
        cairo_line_to(cr, kLeft + plot_w - 134, ly - 4);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        Text(cr, kLeft + plot_w - 128, ly, s.label, 11);
        ly += 15;
      }
    }
  };
  for (const std::string& path : paths) {
    if (kernel::Status error = internal::WriteCairo(path, width, height, paint); !error.ok())
      return error;
  }
  return {};
}

}  // namespace splam::io
