#ifndef SPLAM_IO_PLOT_H_
#define SPLAM_IO_PLOT_H_

#include <string>
#include <vector>

#include "io/render.h"
#include "kernel/status.h"

namespace splam::io {

struct PlotSeries {
  std::string label;
  Rgb color;
  std::vector<double> x, y;  // same length
  // Drawn as bars from 0 to y at each x (grouped side by side with the panel's other bar series,
  // x one apart), instead of a line.
  bool bars = false;
  // Drawn as dots at (x, y), without a line (strip plots).
  bool points = false;
};

// One chart; panels of a plot share the x axis and are stacked top to bottom.
struct PlotPanel {
  std::string y_label;
  std::vector<PlotSeries> series;
};

struct PlotOptions {
  std::string title;
  std::string x_label;
  double width_px = 900.0;
  double panel_height_px = 200.0;
  // When given: the x axis is categorical, ticks at x = 0, 1, ... labelled with these.
  std::vector<std::string> x_labels;

  kernel::Status Validate() const;
};

// Draws line charts (axes with ticks, a zero line, a legend per panel) to each path (.svg or
// .png). Ok, else the first error. Panels without data are drawn empty.
kernel::Status SavePlot(const std::vector<PlotPanel>& panels, const PlotOptions& options,
                        const std::vector<std::string>& paths);

}  // namespace splam::io

#endif  // SPLAM_IO_PLOT_H_
