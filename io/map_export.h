#ifndef SPLAM_IO_MAP_EXPORT_H_
#define SPLAM_IO_MAP_EXPORT_H_

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "estimation/map_line.h"
#include "estimation/map_spline.h"
#include "estimation/slam_method.h"
#include "io/result.h"

namespace splam::io {

// Line maps of the EKF with lines and corners, in world coordinates (metres).
//
// Text (after paper 001, which wrote segment end points for AutoCAD): '#' comments, then
//   segment x1 y1 x2 y2
//   corner x y
// one entity per line. DXF (AutoCAD 2000, readable by CAD programs): LINE entities on layer
// "lines" and POINT entities on layer "corners".
std::string FormatLineMapText(const std::vector<estimation::MapLine>& lines,
                              const std::vector<estimation::MapCorner>& corners);
// Ok, else why the file could not be written.
kernel::Status WriteLineMapText(const std::string& path,
                                const std::vector<estimation::MapLine>& lines,
                                const std::vector<estimation::MapCorner>& corners);
kernel::Status WriteLineMapDxf(const std::string& path,
                               const std::vector<estimation::MapLine>& lines,
                               const std::vector<estimation::MapCorner>& corners);

// B-spline maps of the EKF with B-splines. Text: '#' comments, then one spline a line:
//   spline id n x_0 y_0 ... x_(n-1) y_(n-1) knot_0 ... knot_(n+3)
// DXF: each curve as LINE segments spacing_m long on layer "splines", its control points as
// POINT entities on layer "control_points".
std::string FormatSplineMapText(const std::vector<estimation::MapSpline>& splines);
kernel::Status WriteSplineMapText(const std::string& path,
                                  const std::vector<estimation::MapSpline>& splines);
kernel::Status WriteSplineMapDxf(const std::string& path,
                                 const std::vector<estimation::MapSpline>& splines,
                                 double spacing_m = 0.05);

// The segments and corners of a DXF file (LINE and POINT entities of any layer), for checking
// exports and reading maps back.
struct DxfContent {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> segments;
  std::vector<Eigen::Vector2d> points;
};
Result<DxfContent> ReadDxf(const std::string& path);

// Every loop-closure search of a keyframe graph, one line each: the query and target keyframes
// with their poses, the search's window, the pose the search proposed for the query (empty when
// none) and the outcome (LoopSearch::Outcome's name). Ok, else the error.
kernel::Status WriteLoopSearches(const std::string& path, const estimation::SlamMap& map);

// map.txt and map.dxf of a SLAM map (splines, or lines and corners) into dir, and loops.csv when
// the map has loop-closure searches; every file is tried, the first error is returned.
kernel::Status WriteMap(const estimation::SlamMap& map, const std::string& dir);

}  // namespace splam::io

#endif  // SPLAM_IO_MAP_EXPORT_H_
