#include "io/world_file.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>

#include "io/text.h"
#include "io/trajectory.h"
#include "sim/builtin_worlds.h"

namespace splam::io {
namespace {

// Thrown inside the parser only, carrying the offending node's line; never escapes this file.
struct EntryError {
  int line;
  std::string message;
};

int LineOf(const YAML::Node& node) { return node.Mark().line + 1; }

[[noreturn]] void Fail(const YAML::Node& node, const std::string& message) {
  throw EntryError{LineOf(node), message};
}

double Number(const YAML::Node& node, const std::string& what) {
  if (!node || !node.IsScalar()) Fail(node, what + " must be a number");
  const auto value = ParseDouble(node.Scalar());
  if (!value || !std::isfinite(*value))
    Fail(node, what + ": '" + node.Scalar() + "' is not a finite number");
  return *value;
}

Eigen::Vector2d Point(const YAML::Node& node, const std::string& what) {
  if (!node.IsSequence() || node.size() != 2) Fail(node, what + " must be a point [x, y]");
  return {Number(node[0], what), Number(node[1], what)};
}

std::vector<Eigen::Vector2d> Points(const YAML::Node& node, const std::string& what) {
  if (!node.IsSequence()) Fail(node, what + " must be a list of points [[x, y], ...]");
  std::vector<Eigen::Vector2d> points;
  for (const YAML::Node& p : node) points.push_back(Point(p, what));
  return points;
}

const YAML::Node Required(const YAML::Node& map, const char* key, const std::string& what) {
  const YAML::Node node = map[key];
  if (!node) Fail(map, what + " needs '" + key + "'");
  return node;
}

void ParseObstacle(const YAML::Node& entry, const std::string& base, sim::World* world) {
  const char* const kShapes =
      "each obstacle is a map with one shape key (polyline, polygon, circle, ellipse, spline, "
      "closed_spline or floor_plan) and optionally glass: true";
  if (!entry.IsMap()) Fail(entry, kShapes);
  std::string kind;
  YAML::Node value;
  bool glass = false;
  for (const auto& field : entry) {
    if (!field.first.IsScalar())
      Fail(field.first, "an obstacle's key must be a plain word, not a list or a map");
    if (field.first.Scalar() == "glass") {
      if (!field.second.IsScalar() || !YAML::convert<bool>::decode(field.second, glass))
        Fail(field.second, "glass must be true or false");
    } else if (kind.empty()) {
      kind = field.first.Scalar();
      value = field.second;
    } else {
      Fail(entry, kShapes);
    }
  }
  if (kind.empty()) Fail(entry, kShapes);
  const std::size_t first = world->obstacles.size();
  if (kind == "polyline" || kind == "polygon") {
    world->obstacles.push_back(sim::Polyline{Points(value, kind), kind == "polygon"});
  } else if (kind == "spline" || kind == "closed_spline") {
    world->obstacles.push_back(sim::Spline{Points(value, kind), kind == "closed_spline"});
  } else if (kind == "circle") {
    if (!value.IsMap()) Fail(value, "circle must be {center: [x, y], radius: r}");
    world->obstacles.push_back(kernel::Circle2{Point(Required(value, "center", kind), "center"),
                                               Number(Required(value, "radius", kind), "radius")});
  } else if (kind == "ellipse") {
    if (!value.IsMap()) Fail(value, "ellipse must be {center: [x, y], radii: [a, b], angle: th}");
    const Eigen::Vector2d radii = Point(Required(value, "radii", kind), "radii");
    const double angle = value["angle"] ? Number(value["angle"], "angle") : 0.0;
    world->obstacles.push_back(kernel::Ellipse2{Point(Required(value, "center", kind), "center"),
                                                radii.x(), radii.y(), angle});
  } else if (kind == "floor_plan") {
    if (!value.IsMap()) Fail(value, "floor_plan must be {image: path, resolution: m_per_px, ...}");
    FloorPlanOptions options;
    options.resolution_m_per_px = Number(Required(value, "resolution", kind), "resolution");
    if (value["origin"]) options.origin_m = Point(value["origin"], "origin");
    if (value["threshold"])
      options.dark_threshold = static_cast<int>(Number(value["threshold"], "threshold"));
    std::filesystem::path image = Required(value, "image", kind).as<std::string>();
    if (image.is_relative()) image = std::filesystem::path(base) / image;
    Result<sim::World> plan = ReadFloorPlan(image.string(), options);
    if (!plan.ok()) Fail(value, plan.error);
    for (sim::Shape& shape : plan.value->obstacles) world->obstacles.push_back(std::move(shape));
  } else {
    Fail(entry, "unknown obstacle kind '" + kind + "'");
  }
  if (glass)
    for (std::size_t i = first; i < world->obstacles.size(); ++i) world->glass.push_back(i);
  // Validate the new obstacles now, while the line is known.
  sim::World probe;
  probe.obstacles.assign(world->obstacles.end() - 1, world->obstacles.end());
  if (kernel::Status problem = probe.Validate(); !problem.ok()) {
    Fail(entry, problem.message().substr(problem.message().find(':') + 2));
  }
}

// A person: {path: [[x, y], ...], speed: m/s, radius: m, offset: m}; all but path optional.
sim::Walker ParseWalker(const YAML::Node& entry) {
  if (!entry.IsMap())
    Fail(entry, "each person is a map {path: [[x, y], ...], speed, radius, offset}");
  sim::Walker w;
  for (const auto& field : entry) {
    const std::string key = field.first.IsScalar() ? field.first.Scalar() : "";
    if (key == "path") {
      w.path = Points(field.second, "person path");
    } else if (key == "speed") {
      w.speed_mps = Number(field.second, "person speed");
    } else if (key == "radius") {
      w.radius_m = Number(field.second, "person radius");
    } else if (key == "offset") {
      w.start_offset_m = Number(field.second, "person offset");
    } else {
      Fail(field.first, "a person has path, speed, radius and offset, not '" + key + "'");
    }
  }
  if (w.path.empty()) Fail(entry, "a person needs 'path'");
  sim::World probe;
  probe.people.push_back(w);
  if (kernel::Status problem = probe.Validate(); !problem.ok()) {
    Fail(entry, problem.message().substr(problem.message().find(':') + 2));
  }
  return w;
}

YAML::Node PointNode(const Eigen::Vector2d& p) {
  YAML::Node node;
  node.SetStyle(YAML::EmitterStyle::Flow);
  node.push_back(FormatDouble(p.x()));
  node.push_back(FormatDouble(p.y()));
  return node;
}

YAML::Node PointsNode(const std::vector<Eigen::Vector2d>& points) {
  YAML::Node node;
  node.SetStyle(YAML::EmitterStyle::Flow);
  for (const auto& p : points) node.push_back(PointNode(p));
  return node;
}

bool HasExtension(const std::string& path, std::initializer_list<const char*> extensions) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return std::any_of(extensions.begin(), extensions.end(), [&](const char* e) { return ext == e; });
}

bool IsImagePath(const std::string& path) {
  return HasExtension(path, {".png", ".jpg", ".jpeg", ".pgm", ".bmp", ".tif", ".tiff"});
}

}  // namespace

Result<sim::World> ParseWorld(const std::string& yaml, const std::string& name,
                              const std::string& base_directory) {
  using R = Result<sim::World>;
  try {
    const YAML::Node root = YAML::Load(yaml);
    if (!root.IsMap()) return R::Fail(FileError(name, LineOf(root), "a world file is a YAML map"));
    sim::World world;
    world.name =
        root["name"] ? root["name"].as<std::string>() : std::filesystem::path(name).stem().string();
    if (const YAML::Node start = root["start"]) {
      if (!start.IsSequence() || start.size() != 3) Fail(start, "start must be [x, y, theta]");
      world.start = kernel::Pose2(Number(start[0], "start"), Number(start[1], "start"),
                                  Number(start[2], "start"));
    }
    if (const YAML::Node route = root["route"]) world.route = Points(route, "route");
    const YAML::Node obstacles = root["obstacles"];
    if (!obstacles || !obstacles.IsSequence() || obstacles.size() == 0) {
      return R::Fail(FileError(name, obstacles ? LineOf(obstacles) : LineOf(root),
                               "needs a non-empty list 'obstacles'"));
    }
    for (const YAML::Node& entry : obstacles) ParseObstacle(entry, base_directory, &world);
    if (const YAML::Node people = root["people"]) {
      if (!people.IsSequence()) Fail(people, "people must be a list of persons");
      for (const YAML::Node& entry : people) world.people.push_back(ParseWalker(entry));
    }
    return R::Ok(std::move(world));
  } catch (const EntryError& e) {
    return R::Fail(FileError(name, e.line, e.message));
  } catch (const YAML::Exception& e) {
    return R::Fail(FileError(name, e.mark.line + 1, e.msg));
  }
}

Result<sim::World> ReadWorldFile(const std::string& path) {
  std::string text;
  if (kernel::Status error = ReadTextFile(path, &text); !error.ok())
    return Result<sim::World>::Fail(error);
  return ParseWorld(text, path, std::filesystem::path(path).parent_path().string());
}

std::string FormatWorld(const sim::World& world) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << world.name;
  if (world.start) {
    YAML::Node start;
    start.SetStyle(YAML::EmitterStyle::Flow);
    start.push_back(FormatDouble(world.start->x()));
    start.push_back(FormatDouble(world.start->y()));
    start.push_back(FormatDouble(world.start->theta()));
    out << YAML::Key << "start" << YAML::Value << start;
  }
  if (!world.route.empty()) out << YAML::Key << "route" << YAML::Value << PointsNode(world.route);
  out << YAML::Key << "obstacles" << YAML::Value << YAML::BeginSeq;
  for (std::size_t i = 0; i < world.obstacles.size(); ++i) {
    const sim::Shape& shape = world.obstacles[i];
    YAML::Node node;
    const std::string kind = sim::ShapeKindName(shape);
    if (const auto* p = std::get_if<sim::Polyline>(&shape)) {
      node[kind] = PointsNode(p->vertices);
    } else if (const auto* s = std::get_if<sim::Spline>(&shape)) {
      node[kind] = PointsNode(s->control_points);
    } else if (const auto* c = std::get_if<kernel::Circle2>(&shape)) {
      node[kind]["center"] = PointNode(c->center);
      node[kind]["radius"] = FormatDouble(c->radius);
      node[kind].SetStyle(YAML::EmitterStyle::Flow);
    } else if (const auto* e = std::get_if<kernel::Ellipse2>(&shape)) {
      node[kind]["center"] = PointNode(e->center);
      node[kind]["radii"] = PointNode({e->radius_x, e->radius_y});
      node[kind]["angle"] = FormatDouble(e->angle_rad);
      node[kind].SetStyle(YAML::EmitterStyle::Flow);
    }
    if (world.IsGlass(i)) node["glass"] = true;
    out << node;
  }
  out << YAML::EndSeq;
  if (!world.people.empty()) {
    out << YAML::Key << "people" << YAML::Value << YAML::BeginSeq;
    for (const sim::Walker& w : world.people) {
      YAML::Node node;
      node["path"] = PointsNode(w.path);
      node["speed"] = FormatDouble(w.speed_mps);
      node["radius"] = FormatDouble(w.radius_m);
      node["offset"] = FormatDouble(w.start_offset_m);
      out << node;
    }
    out << YAML::EndSeq;
  }
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

kernel::Status WriteWorldFile(const std::string& path, const sim::World& world) {
  return WriteTextFile(path, FormatWorld(world));
}

Result<sim::World> LoadWorld(const std::string& name_or_path, const FloorPlanOptions& floor_plan) {
  if (auto builtin = sim::BuiltinWorld(name_or_path))
    return Result<sim::World>::Ok(std::move(*builtin));
  if (IsImagePath(name_or_path)) return ReadFloorPlan(name_or_path, floor_plan);
  if (!std::filesystem::exists(name_or_path)) {
    std::string names;
    for (const std::string& n : sim::BuiltinWorldNames()) names += (names.empty() ? "" : ", ") + n;
    return Result<sim::World>::Fail(
        FileError(name_or_path, 0, "not a built-in world (" + names + ") and no such file"));
  }
  return ReadWorldFile(name_or_path);
}

Result<sim::World> LoadValidWorld(const std::string& name_or_path,
                                  const FloorPlanOptions& floor_plan) {
  Result<sim::World> world = LoadWorld(name_or_path, floor_plan);
  if (!world.ok()) return world;
  if (const kernel::Status problem = world.value->Validate(); !problem.ok())
    return Result<sim::World>::Fail(name_or_path + ": " + problem.message());
  return world;
}

kernel::Status StartProblem(const std::string& name_or_path, const FloorPlanOptions& floor_plan,
                            const kernel::Pose2& start) {
  if (sim::BuiltinWorld(name_or_path) || !IsImagePath(name_or_path)) return {};
  const Result<bool> dark = FloorPlanIsDarkAt(name_or_path, floor_plan, start.translation());
  if (!dark.ok()) return dark.status();
  if (!*dark.value) return {};
  return FileError(name_or_path, 0,
                   "the start pose (" + FormatDouble(start.x()) + ", " + FormatDouble(start.y()) +
                       ") lies on a dark pixel: inside a wall or a solid region");
}

}  // namespace splam::io
