#ifndef SPLAM_IO_RENDER_H_
#define SPLAM_IO_RENDER_H_

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "kernel/pose2.h"
#include "kernel/shapes.h"
#include "kernel/status.h"
#include "sim/world.h"

namespace splam::io {

struct Rgb {
  double r = 0.0, g = 0.0, b = 0.0;
};

// The colours every splam picture uses for the same things.
namespace palette {
inline constexpr Rgb kWorld{0.15, 0.15, 0.15};
inline constexpr Rgb kTrue{0.10, 0.35, 0.85};      // ground truth: blue
inline constexpr Rgb kOdometry{0.85, 0.10, 0.65};  // odometry: magenta
inline constexpr Rgb kEstimate{0.0, 0.0, 0.0};     // estimate: black
inline constexpr Rgb kScan{0.95, 0.45, 0.05};      // laser points: orange
inline constexpr Rgb kMap{0.75, 0.10, 0.10};       // estimated map: dark red
inline constexpr Rgb kOnline{0.55, 0.55, 0.55};    // estimate before optimisation: grey
inline constexpr Rgb kGraph{0.10, 0.60, 0.25};     // keyframe graph and loop closures: green
inline constexpr Rgb kDropped{0.95, 0.55, 0.0};    // loop closures found, then dropped: amber
inline constexpr Rgb kPeople{0.45, 0.70, 0.90};    // where people walk: light blue
inline constexpr Rgb kGlass{0.20, 0.75, 0.75};     // glass the laser reads no return from: teal
}  // namespace palette

// A pixel of 8-bit channels.
struct Rgb8 {
  std::uint8_t r = 0, g = 0, b = 0;
};

struct FigureOptions {
  double pixels_per_meter = 40.0;  // PNG resolution; SVG user units are the same pixels
  double margin_m = 0.5;           // white space around the drawn area
  std::string title;               // drawn above the map when not empty
  int max_pixels = 4000;           // the scale shrinks so that neither side exceeds this

  kernel::Status Validate() const;
};

// A map-like picture in world coordinates (metres, y up) with a title, a legend and a scale
// bar, saved as SVG or PNG. Line widths and text in pixels are those of a picture up to 1000 px
// wide and grow with a wider one, so that it reads the same shown at page width. Drawing is recorded once and replayed into either format.
class Figure {
 public:
  // `area` is the part of the world to show; it must not be empty.
  Figure(const kernel::Box2& area, const FigureOptions& options = {});
  ~Figure();
  Figure(const Figure&) = delete;
  Figure& operator=(const Figure&) = delete;

  // Glass obstacles (World::glass) are drawn in palette::kGlass, with a legend of their own.
  void DrawWorld(const sim::World& world, Rgb color = palette::kWorld,
                 const std::string& legend = "world");
  // A polyline through the poses' positions.
  void DrawPath(const std::vector<kernel::Pose2>& poses, Rgb color, double width_px,
                const std::string& legend);
  void DrawPoints(const std::vector<Eigen::Vector2d>& points, Rgb color, double radius_px,
                  const std::string& legend);
  // A polyline through the points (dashed when `dashed`).
  void DrawPolyline(const std::vector<Eigen::Vector2d>& points, Rgb color, double width_px,
                    const std::string& legend, bool dashed = false);
  // A closed polygon filled with `color` at fill_alpha (0-1) and outlined at width_px (0: no
  // outline).
  void DrawPolygon(const std::vector<Eigen::Vector2d>& points, Rgb color, double fill_alpha,
                   double width_px, const std::string& legend);
  enum class Marker { kCircle, kDiamond };
  // Open markers of `size_px` (radius) at the points: circles mark inflection points and
  // diamonds corners in every splam picture.
  void DrawMarkers(const std::vector<Eigen::Vector2d>& points, Marker marker, Rgb color,
                   double size_px, const std::string& legend);
  // An image over `area` (world frame): pixels row by row from the top (largest y), each row
  // left to right, drawn as sharp squares (an occupancy grid's cells).
  void DrawRaster(const std::vector<Rgb8>& pixels, int columns, int rows, const kernel::Box2& area);
  // A legend entry (a square swatch) for something drawn without one (a raster's colours).
  void AddLegend(const std::string& label, Rgb color);
  // The robot's disc and a heading tick.
  void DrawRobot(const kernel::Pose2& pose, double radius_m, Rgb color);

  // Writes path.svg or path.png by the extension.
  kernel::Status Save(const std::string& path) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace splam::io

#endif  // SPLAM_IO_RENDER_H_
