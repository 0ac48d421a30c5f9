#include "io/map_export.h"

#include <dxflib/dl_creationadapter.h>
#include <dxflib/dl_dxf.h>

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

std::string WriteLineMapText(const std::string& path, const std::vector<estimation::MapLine>& lines,
                             const std::vector<estimation::MapCorner>& corners) {
  return WriteTextFile(path, FormatLineMapText(lines, corners));
}

std::string WriteLineMapDxf(const std::string& path, const std::vector<estimation::MapLine>& lines,
                            const std::vector<estimation::MapCorner>& corners) {
  // The minimal complete AutoCAD 2000 file of the dxflib documentation: header, tables
  // (viewport, line types, layers, style, view, UCS, application id, dimension style, block
  // records), model and paper space blocks, entities and objects.
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
  dw->tableLayers(3);
  dxf.writeLayer(*dw, DL_LayerData("0", 0),
                 DL_Attributes("", DL_Codes::black, 100, "CONTINUOUS", 1.0));
  dxf.writeLayer(*dw, DL_LayerData("lines", 0),
                 DL_Attributes("", DL_Codes::black, 35, "CONTINUOUS", 1.0));
  dxf.writeLayer(*dw, DL_LayerData("corners", 0),
                 DL_Attributes("", DL_Codes::red, 35, "CONTINUOUS", 1.0));
  dw->tableEnd();
  dw->tableStyle(1);
  dxf.writeStyle(*dw, DL_StyleData("standard", 0, 2.5, 1.0, 0.0, 0, 2.5, "txt", ""));
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
  const DL_Attributes lines_layer("lines", 256, -1, "BYLAYER", 1.0);
  const DL_Attributes corners_layer("corners", 256, -1, "BYLAYER", 1.0);
  for (const estimation::MapLine& l : lines) {
    dxf.writeLine(*dw, DL_LineData(l.start.x(), l.start.y(), 0.0, l.end.x(), l.end.y(), 0.0),
                  lines_layer);
  }
  for (const estimation::MapCorner& c : corners) {
    dxf.writePoint(*dw, DL_PointData(c.position.x(), c.position.y(), 0.0), corners_layer);
  }
  dw->sectionEnd();
  dxf.writeObjects(*dw);
  dxf.writeObjectsEnd(*dw);
  dw->dxfEOF();
  dw->close();
  return "";
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

}  // namespace splam::io
