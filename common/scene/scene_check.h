// A look at a scene before planning: what it contains (files, sizes, boxes,
// poses) and what in it is suspicious (units that do not fit D's size, a
// start far from S, a reference point far from D, degenerate meshes). Used
// by ausbau-scene-check (stages/scene-check/README.md); nothing here plans
// or checks collisions, so it is cheap on any scene.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/pose.h"
#include "scene/scene.h"

namespace ausbau {

struct SceneFinding {
  // kWarning: probably a mistake in the scene (wrong units, wrong pose).
  // kInfo: worth knowing but normal (a scene in car coordinates).
  enum class Severity { kInfo, kWarning };
  Severity severity = Severity::kInfo;
  std::string code;     // stable short name, e.g. "start-far-from-s"
  std::string message;  // one line: the numbers with units, and why it matters
};

// "info" or "warning".
const char* SeverityName(SceneFinding::Severity severity);

struct MeshCounts {
  std::string file;  // as resolved by LoadScene
  long long triangles = 0;
  long long vertices = 0;
  long long degenerate_triangles = 0;  // zero area (see CountDegenerateTriangles)
};

struct BoxSummary {
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double diagonal = 0;
};

struct SceneSummary {
  std::string scene_file;
  std::string name;
  std::string units;                           // as written, empty when not given
  std::optional<double> millimetres_per_unit;  // none for missing, unknown or unitless units

  MeshCounts dynamic;               // D
  std::vector<MeshCounts> statics;  // one per static file
  MeshCounts static_total;          // S: all static files merged

  BoxSummary dynamic_mesh_box;       // D in its mesh coordinates
  BoxSummary dynamic_installed_box;  // D at the start (installed) pose, world
  BoxSummary static_box;             // S, world

  Eigen::Vector3d dynamic_origin = Eigen::Vector3d::Zero();  // the point of D that a pose places
  bool dynamic_origin_given = false;
  double origin_to_dynamic_box = 0;  // distance of dynamic_origin from D's mesh box (0 inside)

  Pose start;
  std::optional<Pose> goal;
  std::optional<Aabb> bounds;
  // Gap between D's installed box and S's box (0 when they overlap or touch).
  double installed_box_gap = 0;

  std::vector<SceneFinding> findings;
  int WarningCount() const;
};

// A start pose that puts D far outside S's region: the gap between D's box
// at the start pose and S's box is more than kFarStartFactor times the
// larger of the two boxes' diagonals. Factor 2: any region a task around S
// is posed in hugs S's box (OMPL.app's volumes are S's box; the planner's
// derived bounds grow it by 1.5 of D's diagonals), so a D that starts two
// whole diagonals of the larger body away is in no such region; what puts
// it there is nearly always a pose written for another reference point
// (start.t places dynamic_origin: a dynamic_origin missing or given in
// other coordinates moves D by the offset between the two, metres in car
// coordinates). Used with and without a goal (a motion task may start away
// from S, but not that far).
inline constexpr double kFarStartFactor = 2.0;

// The one-line warning for such a start (it names dynamic_origin and the
// numbers), or "" when the start is not that far.
std::string FarStartWarning(const Scene& scene);

// Summarizes the scene and lists its findings (codes in
// stages/scene-check/README.md). Reads the static files again, one by one,
// only when there are several (for their own counts; LoadMesh's InputError
// if one changed since LoadScene); nothing else reads files or throws.
SceneSummary CheckScene(const Scene& scene);

// Triangles whose area is zero up to rounding: twice the area at most
// 1e-12 times the squared diagonal of the mesh's box (repeated or collinear
// vertices; CAD exports have some).
long long CountDegenerateTriangles(const TriangleMesh& mesh);

// The summary as a short human-readable table followed by one line per
// finding, "warning <code>: <message>" or "info <code>: <message>".
std::string SceneSummaryText(const SceneSummary& summary);

// The summary and the findings as one JSON object (schema
// ausbau-scene-check, version 1; stages/scene-check/README.md).
std::string SceneSummaryJson(const SceneSummary& summary);

}  // namespace ausbau
