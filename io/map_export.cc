#include "io/map_export.h"

#include <dxflib/dl_creationadapter.h>
#include <dxflib/dl_dxf.h>

#include <fmt/format.h>

#include <filesystem>
#include <memory>

#include "io/text.h"
#include "io/trajectory.h"

namespace splam::io {
namespace {

class Collector : public DL_CreationAdapter {
 public:
  void addLine(const DL_LineData& d) override {
    content.segments.push_back({{d.x1, d.y1}, {d.x2, d.y2}});
  }
  void addPoint(const DL_PointData& d) override { content.points.emplace_back(d.x, d.y); }
  DxfContent content;
};

// A DXF layer: LINE and POINT entities.
struct DxfLayer {
  std::string name;
  int color;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> segments;
  std::vector<Eigen::Vector2d> points;
};

}  // namespace

std::string FormatLineMapText(const std::vector<estimation::MapLine>& lines,
                              const std::vector<estimation::MapCorner>& corners) {
  std::string out = "# splam line map: world frame, metres\n# segment x1 y1 x2 y2\n# corner x y\n";
  for (const estimation::MapLine& l : lines) {
    out += "segment " + FormatDouble(l.start.x()) + " " + FormatDouble(l.start.y()) + " " +
           FormatDouble(l.end.x()) + " " + FormatDouble(l.end.y()) + "\n";
  }
  for (const estimation::MapCorner& c : corners) {
    out += "corner " + FormatDouble(c.position.x()) + " " + FormatDouble(c.position.y()) + "\n";
  }
  return out;
}

kernel::Status WriteLineMapText(const std::string& path,
                                const std::vector<estimation::MapLine>& lines,
                                const std::vector<estimation::MapCorner>& corners) {
  return WriteTextFile(path, FormatLineMapText(lines, corners));
}

namespace {

// Beyond this a coordinate is no map's: dxflib's number formatting overflowed its buffer at about
// 1e238 (the process aborted, leaving a truncated file), m.
constexpr double kMaxDxfCoordinateM = 1e6;

// The first coordinate of the layers that is not finite or beyond kMaxDxfCoordinateM; "" if none.
std::string OutOfRange(const std::vector<DxfLayer>& layers) {
  const auto bad = [](const Eigen::Vector2d& p) {
    return !p.allFinite() || p.cwiseAbs().maxCoeff() > kMaxDxfCoordinateM;
  };
  const auto describe = [](const Eigen::Vector2d& p) {
    return "coordinate (" + FormatDouble(p.x()) + ", " + FormatDouble(p.y()) +
           ") is not within +-1e6 m; the map is not written";
  };
  for (const DxfLayer& layer : layers) {
    for (const auto& [a, b] : layer.segments) {
      if (bad(a)) return describe(a);
      if (bad(b)) return describe(b);
    }
    for (const Eigen::Vector2d& p : layer.points)
      if (bad(p)) return describe(p);
  }
  return "";
}

// The minimal complete AutoCAD 2000 file of the dxflib documentation with these layers. Nothing is
// written when a coordinate is out of range (OutOfRange).
kernel::Status WriteDxf(const std::string& path, const std::vector<DxfLayer>& layers) {
  if (const std::string problem = OutOfRange(layers); !problem.empty())
    return FileError(path, 0, problem);
  // Header, tables (viewport, line types, layers, style, view, UCS, application id, dimension
  // style, block records), model and paper space blocks, entities and objects.
  DL_Dxf dxf;
  std::unique_ptr<DL_WriterA> dw(dxf.out(path.c_str(), DL_Codes::AC1015));
  if (dw == nullptr) return FileError(path, 0, "cannot open for writing");
  dxf.writeHeader(*dw);
  dw->sectionEnd();
  dw->sectionTables();
  dxf.writeVPort(*dw);
  dw->tableLinetypes(3);
  dxf.writeLinetype(*dw, DL_LinetypeData("BYBLOCK", "BYBLOCK", 0, 0, 0.0));
  dxf.writeLinetype(*dw, DL_LinetypeData("BYLAYER", "BYLAYER", 0, 0, 0.0));
  dxf.writeLinetype(*dw, DL_LinetypeData("CONTINUOUS", "Continuous", 0, 0, 0.0));
  dw->tableEnd();
  dw->tableLayers(static_cast<int>(layers.size()) + 1);
  dxf.writeLayer(*dw, DL_LayerData("0", 0),
                 DL_Attributes("", DL_Codes::black, 100, "CONTINUOUS", 1.0));
  for (const DxfLayer& layer : layers) {
    dxf.writeLayer(*dw, DL_LayerData(layer.name, 0),
                   DL_Attributes("", layer.color, 35, "CONTINUOUS", 1.0));
  }
  dw->tableEnd();
  dw->tableStyle(1);
  // "Standard": dxflib keeps the handle of the style of that name, which the dimension style
  // refers to (any other name left it uninitialised, and map.dxf differed between identical runs).
  dxf.writeStyle(*dw, DL_StyleData("Standard", 0, 2.5, 1.0, 0.0, 0, 2.5, "txt", ""));
  dw->tableEnd();
  dxf.writeView(*dw);
  dxf.writeUcs(*dw);
  dw->tableAppid(1);
  dxf.writeAppid(*dw, "ACAD");
  dw->tableEnd();
  dxf.writeDimStyle(*dw, 1, 1, 1, 1, 1);
  dxf.writeBlockRecord(*dw);
  dw->tableEnd();
  dw->sectionEnd();
  dw->sectionBlocks();
  dxf.writeBlock(*dw, DL_BlockData("*Model_Space", 0, 0.0, 0.0, 0.0));
  dxf.writeEndBlock(*dw, "*Model_Space");
  dxf.writeBlock(*dw, DL_BlockData("*Paper_Space", 0, 0.0, 0.0, 0.0));
  dxf.writeEndBlock(*dw, "*Paper_Space");
  dxf.writeBlock(*dw, DL_BlockData("*Paper_Space0", 0, 0.0, 0.0, 0.0));
  dxf.writeEndBlock(*dw, "*Paper_Space0");
  dw->sectionEnd();
  dw->sectionEntities();
  for (const DxfLayer& layer : layers) {
    const DL_Attributes attributes(layer.name, 256, -1, "BYLAYER", 1.0);
    for (const auto& [a, b] : layer.segments)
      dxf.writeLine(*dw, DL_LineData(a.x(), a.y(), 0.0, b.x(), b.y(), 0.0), attributes);
    for (const Eigen::Vector2d& p : layer.points)
      dxf.writePoint(*dw, DL_PointData(p.x(), p.y(), 0.0), attributes);
  }
  dw->sectionEnd();
  dxf.writeObjects(*dw);
  dxf.writeObjectsEnd(*dw);
  dw->dxfEOF();
  dw->close();
  return {};
}

}  // namespace

kernel::Status WriteLineMapDxf(const std::string& path,
                               const std::vector<estimation::MapLine>& lines,
                               const std::vector<estimation::MapCorner>& corners) {
  DxfLayer line_layer{"lines", DL_Codes::black, {}, {}};
  for (const estimation::MapLine& l : lines) line_layer.segments.emplace_back(l.start, l.end);
  DxfLayer corner_layer{"corners", DL_Codes::red, {}, {}};
  for (const estimation::MapCorner& c : corners) corner_layer.points.push_back(c.position);
  return WriteDxf(path, {line_layer, corner_layer});
}

std::string FormatSplineMapText(const std::vector<estimation::MapSpline>& splines) {
  std::string out =
      "# splam B-spline map: world frame, metres; cubic, clamped knots\n"
      "# spline id n x_0 y_0 ... x_n-1 y_n-1 knot_0 ... knot_n+3\n";
  for (const estimation::MapSpline& s : splines) {
    const auto& control = s.spline.control_points();
    out += "spline " + std::to_string(s.id) + " " + std::to_string(control.size());
    for (const Eigen::Vector2d& p : control)
      out += " " + FormatDouble(p.x()) + " " + FormatDouble(p.y());
    for (const double k : s.spline.knots()) out += " " + FormatDouble(k);
    out += "\n";
  }
  return out;
}

kernel::Status WriteSplineMapText(const std::string& path,
                                  const std::vector<estimation::MapSpline>& splines) {
  return WriteTextFile(path, FormatSplineMapText(splines));
}

kernel::Status WriteSplineMapDxf(const std::string& path,
                                 const std::vector<estimation::MapSpline>& splines,
                                 double spacing_m) {
  DxfLayer curves{"splines", DL_Codes::black, {}, {}};
  DxfLayer control{"control_points", DL_Codes::red, {}, {}};
  for (const estimation::MapSpline& s : splines) {
    std::vector<Eigen::Vector2d> points = s.spline.ResampleByArcLength(spacing_m);
    points.push_back(s.spline.Point(s.spline.DomainEnd()));
    for (std::size_t k = 1; k < points.size(); ++k)
      curves.segments.emplace_back(points[k - 1], points[k]);
    for (const Eigen::Vector2d& p : s.spline.control_points()) control.points.push_back(p);
  }
  return WriteDxf(path, {curves, control});
}

Result<DxfContent> ReadDxf(const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    return Result<DxfContent>::Fail(FileError(path, 0, "no such file"));
  Collector collector;
  DL_Dxf dxf;
  if (!dxf.in(path, &collector))
    return Result<DxfContent>::Fail(FileError(path, 0, "cannot read as DXF"));
  return Result<DxfContent>::Ok(std::move(collector.content));
}

kernel::Status WriteLoopSearches(const std::string& path, const estimation::SlamMap& map) {
  std::string text =
      "query,target,query_scan,target_scan,query_x,query_y,query_theta,target_x,target_y,"
      "target_theta,window_m,window_rad,searched_x,searched_y,searched_theta,match_x,match_y,"
      "match_theta,relative_x,relative_y,relative_theta,outcome,ms\n";
  const auto pose = [&](int i) -> const kernel::Pose2& {
    return map.keyframes.at(static_cast<std::size_t>(i));
  };
  for (const estimation::LoopSearch& s : map.loop_searches) {
    const kernel::Pose2 &q = pose(s.query), &t = pose(s.target);
    text += fmt::format("{},{},{},{},{:.3f},{:.3f},{:.4f},{:.3f},{:.3f},{:.4f},{:.3f},{:.4f},",
                        s.query, s.target, s.query_scan, s.target_scan, q.x(), q.y(), q.theta(),
                        t.x(), t.y(), t.theta(), s.window_m, s.window_rad);
    text +=
        fmt::format("{:.3f},{:.3f},{:.4f},", s.searched.x(), s.searched.y(), s.searched.theta());
    const kernel::Pose2 relative = s.target_searched.Between(s.match);
    text += s.matched ? fmt::format("{:.3f},{:.3f},{:.4f},{:.3f},{:.3f},{:.4f},", s.match.x(),
                                    s.match.y(), s.match.theta(), relative.x(), relative.y(),
                                    relative.theta())
                      : std::string(",,,,,,");
    text += fmt::format("{},{:.2f}\n", estimation::OutcomeName(s.outcome), s.time_ms);
  }
  return WriteTextFile(path, text);
}

kernel::Status WriteMap(const estimation::SlamMap& map, const std::string& dir) {
  std::vector<kernel::Status> written;
  if (!map.splines.empty() || (map.lines.empty() && map.corners.empty())) {
    written = {WriteSplineMapText(dir + "/map.txt", map.splines),
               WriteSplineMapDxf(dir + "/map.dxf", map.splines)};
  } else {
    written = {WriteLineMapText(dir + "/map.txt", map.lines, map.corners),
               WriteLineMapDxf(dir + "/map.dxf", map.lines, map.corners)};
  }
  if (!map.loop_searches.empty()) written.push_back(WriteLoopSearches(dir + "/loops.csv", map));
  return kernel::FirstError(written);
}

}  // namespace splam::io
