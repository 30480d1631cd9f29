#include "scene/scene_check.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <system_error>
#include <utility>

#include "core/format.h"
#include "core/json_writer.h"
#include "scene/mesh_io.h"
#include "scene/units.h"

namespace ausbau {
namespace {

// ---- thresholds (stages/scene-check/README.md explains each)

// No car part is smaller than 1 mm or larger than 10 m across.
constexpr double kSmallestPartMillimetres = 1.0;
constexpr double kLargestPartMillimetres = 10000.0;
// Beyond this distance from the origin a scene is in car coordinates.
constexpr double kCarCoordinatesMillimetres = 1000.0;

// ---- units

enum class UnitsKind { kMissing, kUnitless, kUnknown, kKnown };

struct UnitsReading {
  UnitsKind kind = UnitsKind::kMissing;
  double millimetres_per_unit = 1.0;  // only for kKnown
};

// The names scene/units.h converts, plus "unitless"/"none", which the
// OMPL.app scenes use to say on purpose that their numbers have no unit.
UnitsReading ReadUnits(const std::string& units) {
  if (units.empty()) return {UnitsKind::kMissing, 1.0};
  if (const std::optional<double> per_unit = MillimetresPerUnit(units)) return {UnitsKind::kKnown, *per_unit};
  std::string u;
  for (char c : units) u += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (u == "unitless" || u == "none") return {UnitsKind::kUnitless, 1.0};
  return {UnitsKind::kUnknown, 1.0};
}

// ---- geometry helpers

BoxSummary Summarize(const Aabb& box) {
  BoxSummary out;
  if (box.Empty()) return out;
  out.min = box.min;
  out.max = box.max;
  out.size = box.Size();
  out.center = box.Center();
  out.diagonal = box.Diagonal();
  return out;
}

// D's vertices placed by a pose in the scene convention:
// x_world = R(q) (x - dynamic_origin) + t.
Aabb PlacedBox(const TriangleMesh& mesh, const Eigen::Vector3d& dynamic_origin, const Pose& pose) {
  Aabb box;
  for (const auto& v : mesh.vertices) box.Extend(pose.Apply(v - dynamic_origin));
  return box;
}

// Euclidean distance between two boxes; 0 when they overlap or touch.
double BoxGap(const Aabb& a, const Aabb& b) {
  const Eigen::Vector3d gap = (a.min - b.max).cwiseMax(b.min - a.max).cwiseMax(Eigen::Vector3d::Zero());
  return gap.norm();
}

double PointToBoxDistance(const Eigen::Vector3d& p, const Aabb& box) {
  const Eigen::Vector3d gap = (box.min - p).cwiseMax(p - box.max).cwiseMax(Eigen::Vector3d::Zero());
  return gap.norm();
}

bool BoxInside(const Aabb& inner, const Aabb& outer) {
  return (inner.min.array() >= outer.min.array()).all() && (inner.max.array() <= outer.max.array()).all();
}

bool IsIdentity(const Pose& pose) {
  return pose.t.isZero(0.0) && RotationAngle(pose.q, Eigen::Quaterniond::Identity()) < 1e-9;
}

MeshCounts Count(const std::string& file, const TriangleMesh& mesh) {
  MeshCounts counts;
  counts.file = file;
  counts.triangles = static_cast<long long>(mesh.triangles.size());
  counts.vertices = static_cast<long long>(mesh.vertices.size());
  counts.degenerate_triangles = CountDegenerateTriangles(mesh);
  return counts;
}

bool SameFile(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code error;
  const bool same = std::filesystem::equivalent(a, b, error);
  return !error && same;
}

// Static entry `entry`'s triangles of S (vertices renumbered), by the
// pieces LoadScene recorded: a part picked, scaled or posed is not the file.
TriangleMesh StaticEntryMesh(const Scene& scene, std::size_t entry) {
  TriangleMesh out;
  std::vector<int> renumbered(scene.static_mesh.vertices.size(), -1);
  for (std::size_t t = 0; t < scene.static_mesh.triangles.size() && t < scene.static_part_of_triangle.size(); ++t) {
    if (scene.static_part_entry[scene.static_part_of_triangle[t]] != static_cast<int>(entry)) continue;
    std::array<int, 3> tri = scene.static_mesh.triangles[t];
    for (int& v : tri) {
      if (renumbered[v] < 0) {
        renumbered[v] = static_cast<int>(out.vertices.size());
        out.vertices.push_back(scene.static_mesh.vertices[v]);
      }
      v = renumbered[v];
    }
    out.triangles.push_back(tri);
  }
  return out;
}

// "parts bolt, nut; posed; units mm" for an entry that is not a whole file.
std::string EntryText(const Scene& scene, std::size_t entry) {
  const MeshSource& source = scene.static_sources[entry];
  std::string text = source.rest_of_assembly ? "the assembly's rest: " : "";
  if (!source.picks.empty() || source.rest_of_assembly) {
    text += std::to_string(source.parts.size()) + (source.parts.size() == 1 ? " part" : " parts");
  } else {
    text += "whole file";
  }
  if (source.pose) text += ", posed";
  if (!source.units.empty()) text += ", units " + source.units;
  return text;
}

// ---- text helpers

std::string Vec(const Eigen::Vector3d& v) { return Fmt("[%.6g, %.6g, %.6g]", v.x(), v.y(), v.z()); }

std::string Quat(const Eigen::Quaterniond& q) { return Fmt("[%.6g, %.6g, %.6g, %.6g]", q.w(), q.x(), q.y(), q.z()); }

// "12.5 mm"; scenes without a usable unit say "units".
std::string Length(const SceneSummary& summary, double value) {
  const bool named = summary.millimetres_per_unit.has_value();
  return Fmt("%.6g %s", value, named ? summary.units.c_str() : "units");
}

// ---- the findings, one function per rule

void Add(SceneSummary* summary, SceneFinding::Severity severity, const std::string& code, const std::string& message) {
  summary->findings.push_back({severity, code, message});
}

constexpr auto kInfo = SceneFinding::Severity::kInfo;
constexpr auto kWarning = SceneFinding::Severity::kWarning;

void CheckUnits(const Scene& scene, SceneSummary* summary) {
  const UnitsReading units = ReadUnits(scene.units);
  switch (units.kind) {
    case UnitsKind::kMissing:
      Add(summary, kWarning, "units-missing",
          "scene.yaml gives no units: D's size cannot be checked, and tolerances given in mm (--rigid-tolerance) "
          "are applied as if the scene were in mm");
      return;
    case UnitsKind::kUnknown:
      Add(summary, kWarning, "units-unknown",
          Fmt("units '%s' is none of mm, cm, m, in (or unitless): D's size cannot be checked, and tolerances given "
              "in mm are applied as if the scene were in mm",
              scene.units.c_str()));
      return;
    case UnitsKind::kUnitless:
      Add(summary, kInfo, "units-unitless",
          Fmt("units '%s': D's size is not checked against a unit; tolerances given in mm are applied as scene units",
              scene.units.c_str()));
      return;
    case UnitsKind::kKnown: break;
  }
  const double diagonal_mm = summary->dynamic_mesh_box.diagonal * units.millimetres_per_unit;
  // "17.3 cm = 173 mm"; just "17.3 mm" for a scene in mm.
  std::string diagonal = Length(*summary, summary->dynamic_mesh_box.diagonal);
  if (units.millimetres_per_unit != 1.0) diagonal += Fmt(" = %.6g mm", diagonal_mm);
  if (diagonal_mm < kSmallestPartMillimetres) {
    Add(summary, kWarning, "units-suspect-small",
        Fmt("D's box diagonal is %s, below 1 mm: no car part is that small, the meshes are probably not in '%s' "
            "(metres?); tolerances and voxel sizes in mm would be coarser than D itself",
            diagonal.c_str(), scene.units.c_str()));
  } else if (diagonal_mm > kLargestPartMillimetres) {
    Add(summary, kWarning, "units-suspect-large",
        Fmt("D's box diagonal is %s, above 10 m: no car part is that large, the meshes are probably not in '%s' "
            "(mm?); tolerances in mm would be far too fine",
            diagonal.c_str(), scene.units.c_str()));
  }
  // Car coordinates: the installed part metres from the origin. Normal for CAD exports; said only so that large
  // coordinates in the table are not mistaken for a problem.
  const double centre_mm = summary->dynamic_installed_box.center.norm() * units.millimetres_per_unit;
  if (centre_mm > kCarCoordinatesMillimetres) {
    Add(summary, kInfo, "car-coordinates",
        Fmt("D's installed box centre is %.3g metres from the origin (car coordinates): normal for CAD exports, "
            "the stages plan about a point inside D",
            centre_mm / 1000.0));
  }
}

void CheckMeshes(const Scene& scene, SceneSummary* summary) {
  const struct {
    const MeshCounts* counts;
    const char* part;  // "D" or "S"
    const char* code;  // prefix of the codes
  } parts[] = {{&summary->dynamic, "D", "dynamic"}, {&summary->static_total, "S", "static"}};
  for (const auto& part : parts) {
    const MeshCounts& counts = *part.counts;
    if (counts.degenerate_triangles == counts.triangles) {
      Add(summary, kWarning, std::string(part.code) + "-no-area",
          Fmt("%s has %lld triangles and none of positive area: the collision checks see no surface of %s", part.part,
              counts.triangles, part.part));
    } else if (counts.degenerate_triangles > 0) {
      Add(summary, kInfo, std::string(part.code) + "-degenerate-triangles",
          Fmt("%s has %lld of %lld triangles with zero area (repeated or collinear vertices): they add no surface; "
              "many of them point to a broken export",
              part.part, counts.degenerate_triangles, counts.triangles));
    }
  }
  for (std::size_t i = 0; i < scene.static_files.size(); ++i) {
    if (!SameFile(scene.dynamic_file, scene.static_files[i])) continue;
    if (scene.format_version >= 2) {
      // LoadScene has refused a part taken by both; what is left is meant.
      Add(summary, kInfo, "dynamic-and-static-share-a-file",
          Fmt("D and static entry %zu come from the same file %s, with different parts or a pose of their own", i + 1,
              scene.dynamic_file.string().c_str()));
      continue;
    }
    Add(summary, kWarning, "same-file-dynamic-and-static",
        Fmt("the dynamic file %s is also static file %zu: at the installed pose D lies inside a copy of itself and "
            "cannot be separated from it",
            scene.dynamic_file.string().c_str(), i + 1));
  }
}

// A D whose mesh was written in other units than S's (inches or metres in a
// mm scene) lies scaled about the mesh origin: usually far from S and too
// small or too large. The factor among the common unit ratios that brings
// D's installed box into S's box (about the world origin, where a mesh
// exported in other units is scaled), with a name for D's numbers
// ("inches"); 0 when none does.
double UnitFactorPlacingDInS(const Aabb& installed_box, const Aabb& static_box, const SceneSummary& summary,
                             std::string* d_units) {
  struct Unit {
    double millimetres;
    const char* name;
  };
  constexpr Unit kUnits[] = {{1, "mm"}, {10, "cm"}, {25.4, "inches"}, {1000, "metres"}};
  if (!summary.millimetres_per_unit) return 0;
  const double scene_mm = *summary.millimetres_per_unit;
  for (const Unit& unit : kUnits) {
    const double factor = unit.millimetres / scene_mm;
    if (std::abs(std::log(factor)) < 1e-9) continue;  // the scene's own unit
    const Aabb scaled{installed_box.min * factor, installed_box.max * factor};
    if (BoxInside(scaled, static_box)) {
      *d_units = unit.name;
      return factor;
    }
  }
  return 0;
}

void CheckStart(const Scene& scene, const Aabb& installed_box, const Aabb& static_box, SceneSummary* summary) {
  const double dynamic_diagonal = summary->dynamic_mesh_box.diagonal;
  if (BoxInside(installed_box, static_box)) {
    Add(summary, kInfo, "start-inside-s-box",
        scene.goal ? "D at the start pose lies inside S's box"
                   : "D at the start pose lies inside S's box: the installed pose, as a disassembly expects");
    return;
  }
  const double gap = summary->installed_box_gap;
  if (gap <= dynamic_diagonal) return;  // overlapping, touching or close: D starts in or at S
  const std::string where = Fmt("D at the start pose is %s from S's box, more than D's diagonal (%s)",
                                Length(*summary, gap).c_str(), Length(*summary, dynamic_diagonal).c_str());
  if (scene.goal) {
    // With a goal the scene is a motion task (the OMPL.app scenes), not a removal: starting away from S is normal,
    // unless it is farther than any region around S (FarStartWarning).
    const std::string far = FarStartWarning(scene);
    if (!far.empty()) {
      Add(summary, kWarning, "start-far-outside-s", far);
      return;
    }
    Add(summary, kInfo, "start-outside-s", where + "; the scene has a goal, so it is a motion task, not a removal");
    return;
  }
  std::string d_units;
  const double factor = UnitFactorPlacingDInS(installed_box, static_box, *summary, &d_units);
  if (factor > 0) {
    Add(summary, kWarning, "units-d-mismatch",
        Fmt("%s; read as %s (scaled by %.6g), D lies inside S's box: D's mesh is probably in %s while the scene "
            "says '%s' (export D again in the scene's units, or give the part its own units: in a format /2 scene)",
            where.c_str(), d_units.c_str(), factor, d_units.c_str(), scene.units.c_str()));
    return;
  }
  Add(summary, kWarning, "start-far-from-s",
      where +
          ": the pipeline plans out of the installed pose, so D should start in or at S; usually a wrong start "
          "pose or a missing dynamic_origin (start.t places dynamic_origin, or D's mesh origin without it)");
}

void CheckOrigin(const Scene& scene, const Aabb& mesh_box, SceneSummary* summary) {
  const double dynamic_diagonal = summary->dynamic_mesh_box.diagonal;
  const double distance = summary->origin_to_dynamic_box;
  if (distance <= dynamic_diagonal) return;
  const std::string centre = Vec(mesh_box.Center());
  if (scene.dynamic_origin_given) {
    Add(summary, kWarning, "origin-far-from-d",
        Fmt("dynamic_origin %s lies %s from D's mesh box (diagonal %s): poses place and turn D about that point, so "
            "rotations swing D around a far point; dynamic_origin should be a point of D, e.g. its box centre %s",
            Vec(scene.dynamic_origin).c_str(), Length(*summary, distance).c_str(),
            Length(*summary, dynamic_diagonal).c_str(), centre.c_str()));
    return;
  }
  const bool poses_move_d = !IsIdentity(scene.start) || (scene.goal && !IsIdentity(*scene.goal));
  if (poses_move_d) {
    // A start or goal was written, but it places the far mesh origin: its rotation swings D around that point
    // and its t is not where D ends up; usually the pose was meant for D's centre.
    Add(summary, kWarning, "origin-far-from-d",
        Fmt("D's mesh origin, which the poses place (no dynamic_origin), lies %s from D's mesh box (diagonal %s), "
            "and start or goal is not the identity: their rotation swings D around that far point; set "
            "dynamic_origin (e.g. D's box centre %s) and give t for that point",
            Length(*summary, distance).c_str(), Length(*summary, dynamic_diagonal).c_str(), centre.c_str()));
    return;
  }
  // The CAD convention: D where the export put it, the identity as installed pose. Planning turns D about its box
  // centre; only the poses written out (path.csv) are about the far mesh origin.
  Add(summary, kInfo, "mesh-origin-far-from-d",
      Fmt("D's mesh origin lies %s from D's mesh box (no dynamic_origin, identity start): normal for CAD exports; "
          "planning turns D about its box centre, but poses in path.csv are about the mesh origin",
          Length(*summary, distance).c_str()));
}

// ---- JSON (core/json_writer.h)

std::string JsonBox(const BoxSummary& box) {
  return JsonWriter()
      .Add("min", JsonVector(box.min))
      .Add("max", JsonVector(box.max))
      .Add("size", JsonVector(box.size))
      .Add("center", JsonVector(box.center))
      .Add("diagonal", JsonNumber(box.diagonal))
      .Text();
}

std::string JsonCounts(const MeshCounts& counts) {
  return JsonWriter()
      .Add("file", JsonString(counts.file))
      .Add("triangles", std::to_string(counts.triangles))
      .Add("vertices", std::to_string(counts.vertices))
      .Add("degenerate_triangles", std::to_string(counts.degenerate_triangles))
      .Text();
}

std::string JsonPose(const Pose& pose) {
  return JsonWriter().Add("t", JsonVector(pose.t)).Add("q", JsonQuaternion(pose.q)).Text();
}

std::string CountsText(const MeshCounts& counts) {
  return Fmt("%lld triangles, %lld vertices, %lld degenerate", counts.triangles, counts.vertices,
             counts.degenerate_triangles);
}

std::string BoxText(const SceneSummary& summary, const BoxSummary& box) {
  return "size " + Vec(box.size) + " centre " + Vec(box.center) + ", diagonal " + Length(summary, box.diagonal);
}

}  // namespace

const char* SeverityName(SceneFinding::Severity severity) {
  return severity == SceneFinding::Severity::kWarning ? "warning" : "info";
}

int SceneSummary::WarningCount() const {
  return static_cast<int>(std::count_if(findings.begin(), findings.end(), [](const SceneFinding& finding) {
    return finding.severity == SceneFinding::Severity::kWarning;
  }));
}

long long CountDegenerateTriangles(const TriangleMesh& mesh) {
  const double diagonal = mesh.Bounds().Diagonal();
  const double smallest_double_area = 1e-12 * diagonal * diagonal;
  long long count = 0;
  for (const auto& tri : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[tri[0]];
    const Eigen::Vector3d& b = mesh.vertices[tri[1]];
    const Eigen::Vector3d& c = mesh.vertices[tri[2]];
    if ((b - a).cross(c - a).norm() <= smallest_double_area) ++count;
  }
  return count;
}

std::string FarStartWarning(const Scene& scene) {
  const Aabb installed = PlacedBox(scene.dynamic_mesh, scene.dynamic_origin, scene.start);
  const Aabb static_box = scene.static_mesh.Bounds();
  const double gap = BoxGap(installed, static_box);
  const double larger = std::max(scene.dynamic_mesh.Bounds().Diagonal(), static_box.Diagonal());
  if (!(gap > kFarStartFactor * larger)) return "";
  const std::string reference = scene.dynamic_origin_given ? "dynamic_origin " + Vec(scene.dynamic_origin)
                                                           : std::string("D's mesh origin (no dynamic_origin given)");
  const char* units = scene.units.empty() ? "scene units" : scene.units.c_str();
  return Fmt(
      "D at the start pose lies %.6g %s outside S's box, more than %g times the larger diagonal of D and S "
      "(%.6g %s): start.t places %s, so check that dynamic_origin is the point of D the start pose was "
      "written for (an OMPL.app scene needs OMPL.app's robot centre: ausbau-scene-import)",
      gap, units, kFarStartFactor, larger, units, reference.c_str());
}

SceneSummary CheckScene(const Scene& scene) {
  SceneSummary summary;
  summary.scene_file = scene.file.string();
  summary.name = scene.name;
  summary.units = scene.units;
  const UnitsReading units = ReadUnits(scene.units);
  if (units.kind == UnitsKind::kKnown) summary.millimetres_per_unit = units.millimetres_per_unit;

  summary.dynamic = Count(scene.dynamic_file.string(), scene.dynamic_mesh);
  summary.static_total = Count("", scene.static_mesh);
  if (scene.static_files.size() == 1) {
    summary.statics.push_back(summary.static_total);
    summary.statics.back().file = scene.static_files.front().string();
    if (!scene.static_sources.empty() && !scene.static_sources.front().Plain()) {
      summary.statics.back().file += " (" + EntryText(scene, 0) + ")";
    }
  } else {
    // The scene holds S merged; each file's own counts need the file again.
    for (std::size_t i = 0; i < scene.static_files.size(); ++i) {
      const std::string file = scene.static_files[i].string();
      if (i < scene.static_sources.size() && !scene.static_sources[i].Plain()) {
        summary.statics.push_back(Count(file + " (" + EntryText(scene, i) + ")", StaticEntryMesh(scene, i)));
      } else {
        summary.statics.push_back(Count(file, LoadMesh(scene.static_files[i])));
      }
    }
  }

  const Aabb mesh_box = scene.dynamic_mesh.Bounds();
  const Aabb installed_box = PlacedBox(scene.dynamic_mesh, scene.dynamic_origin, scene.start);
  const Aabb static_box = scene.static_mesh.Bounds();
  summary.dynamic_mesh_box = Summarize(mesh_box);
  summary.dynamic_installed_box = Summarize(installed_box);
  summary.static_box = Summarize(static_box);
  summary.dynamic_origin = scene.dynamic_origin;
  summary.dynamic_origin_given = scene.dynamic_origin_given;
  summary.origin_to_dynamic_box = PointToBoxDistance(scene.dynamic_origin, mesh_box);
  summary.start = scene.start;
  summary.goal = scene.goal;
  summary.bounds = scene.bounds;
  summary.installed_box_gap = BoxGap(installed_box, static_box);

  CheckUnits(scene, &summary);
  CheckMeshes(scene, &summary);
  CheckStart(scene, installed_box, static_box, &summary);
  CheckOrigin(scene, mesh_box, &summary);
  return summary;
}

std::string SceneSummaryText(const SceneSummary& s) {
  std::string out;
  auto row = [&out](const char* label, const std::string& value) { out += Fmt("%-12s %s\n", label, value.c_str()); };
  row("scene", s.scene_file);
  row("name", s.name);
  row("units", s.units.empty() ? "(not given)" : s.units);
  row("D", s.dynamic.file + ": " + CountsText(s.dynamic));
  for (const auto& counts : s.statics) row("S", counts.file + ": " + CountsText(counts));
  if (s.statics.size() > 1) row("S (all)", CountsText(s.static_total));
  row("D mesh box", BoxText(s, s.dynamic_mesh_box));
  row("D at start", BoxText(s, s.dynamic_installed_box));
  row("S box", BoxText(s, s.static_box));
  row("origin", (s.dynamic_origin_given ? "dynamic_origin " : "mesh origin (no dynamic_origin) ") +
                    Vec(s.dynamic_origin) + ", " + Length(s, s.origin_to_dynamic_box) + " from D's mesh box");
  row("start", "t " + Vec(s.start.t) + " q " + Quat(s.start.q));
  row("goal", s.goal ? "t " + Vec(s.goal->t) + " q " + Quat(s.goal->q) : "none (disassembly)");
  row("bounds", s.bounds ? "min " + Vec(s.bounds->min) + " max " + Vec(s.bounds->max) : "none");
  row("gap", Length(s, s.installed_box_gap) + " between D at start and S (boxes)");
  const int warnings = s.WarningCount();
  row("findings",
      Fmt("%d warning%s, %d info", warnings, warnings == 1 ? "" : "s", static_cast<int>(s.findings.size()) - warnings));
  for (const auto& finding : s.findings) {
    out += Fmt("%s %s: %s\n", SeverityName(finding.severity), finding.code.c_str(), finding.message.c_str());
  }
  return out;
}

std::string SceneSummaryJson(const SceneSummary& s) {
  JsonWriter statics(true);
  for (const auto& counts : s.statics) statics.Append(JsonCounts(counts));
  JsonWriter findings(true);
  for (const auto& finding : s.findings) {
    findings.Append(JsonWriter()
                        .Add("severity", JsonString(SeverityName(finding.severity)))
                        .Add("code", JsonString(finding.code))
                        .Add("message", JsonString(finding.message))
                        .Text());
  }
  JsonWriter json;
  json.Add("schema", JsonString("ausbau-scene-check")).Add("version", "1");
  json.Add("scene", JsonString(s.scene_file)).Add("name", JsonString(s.name)).Add("units", JsonString(s.units));
  json.Add("millimetres_per_unit", s.millimetres_per_unit ? JsonNumber(*s.millimetres_per_unit) : "null");
  json.Add("dynamic", JsonWriter()
                          .Add("mesh", JsonCounts(s.dynamic))
                          .Add("mesh_box", JsonBox(s.dynamic_mesh_box))
                          .Add("installed_box", JsonBox(s.dynamic_installed_box))
                          .Add("origin", JsonVector(s.dynamic_origin))
                          .Add("origin_given", s.dynamic_origin_given ? "true" : "false")
                          .Add("origin_to_mesh_box", JsonNumber(s.origin_to_dynamic_box))
                          .Text());
  json.Add("static", JsonWriter()
                         .Add("files", statics.Text())
                         .Add("triangles", std::to_string(s.static_total.triangles))
                         .Add("vertices", std::to_string(s.static_total.vertices))
                         .Add("degenerate_triangles", std::to_string(s.static_total.degenerate_triangles))
                         .Add("box", JsonBox(s.static_box))
                         .Text());
  json.Add("start", JsonPose(s.start));
  json.Add("goal", s.goal ? JsonPose(*s.goal) : "null");
  json.Add("bounds",
           s.bounds ? JsonWriter().Add("min", JsonVector(s.bounds->min)).Add("max", JsonVector(s.bounds->max)).Text()
                    : "null");
  json.Add("installed_box_gap", JsonNumber(s.installed_box_gap));
  json.Add("warnings", std::to_string(s.WarningCount()));
  json.Add("findings", findings.Text());
  return json.Text() + "\n";
}

}  // namespace ausbau
