// OMPL.app problem files (.cfg, the SE(3) rigid-body problems of omplapp's
// benchmark) read and turned into an Ausbau scene (ausbau-scene-import).
//
// The file is INI-style: sections [problem], [benchmark], [planner]; lines
// `key = value`; `#` starts a comment. Only [problem] matters to a scene:
//   robot, world                   mesh files (relative to the .cfg's folder)
//   start.x/y/z, goal.x/y/z        where the robot's reference point lies
//   start.theta, start.axis.x/y/z  the orientation as an axis-angle (theta in
//   (goal likewise)                radians; the axis need not be unit length)
//   volume.min.x/y/z, .max.x/y/z   bounds on the reference point (optional:
//                                  all six or none)
// The robot's reference point is OMPL.app's: the mean of the robot's vertices
// as assimp imports them with OMPL.app's flags (float arithmetic, node
// transforms applied, the COLLADA Z_UP -> Y_UP root rotation included), in
// the robot's mesh coordinates; it becomes the scene's `dynamic_origin`, so
// that a pose means the same in both (schemas/scene.md "Pose convention").
// How OMPL.app reads a .cfg: ../shared/benchmarks/ompl/README.md.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "geometry/mesh.h"
#include "geometry/pose.h"
#include "scene/scene.h"

namespace ausbau {

struct OmplProblem {
  std::filesystem::path file;   // the .cfg
  std::string name;             // problem.name (empty when absent)
  std::filesystem::path robot;  // resolved against the .cfg's folder
  std::filesystem::path world;  // likewise
  Pose start, goal;             // t: the reference point; q from theta about axis
  std::optional<Aabb> volume;   // volume.* as given
  // What was read but goes into no scene: [problem]'s planning keys
  // (sampler, objective, ...), then every [benchmark] and [planner] line
  // ("[benchmark] time_limit = 10"): how OMPL.app plans, not the problem.
  std::vector<std::string> notes;
};

// Reads a .cfg. Throws InputError "<cfg>: <key>: <problem>" for: a missing
// or unreadable file, a line that is neither a section, a comment nor
// `key = value`, a key outside any section, an unknown section, an unknown
// or repeated key in [problem], a missing required key (robot, world, start.*,
// goal.*), a value that is not a finite number, a zero rotation axis, only
// some of the six volume keys, volume.min > volume.max, and a control-based
// problem (problem.control). Mesh files are resolved, not read.
OmplProblem ReadOmplCfg(const std::filesystem::path& cfg);

// OMPL.app's robot reference point: the float mean of the vertices of every
// mesh of every node (transforms accumulated from the root), as imported by
// assimp with GenNormals | Triangulate | JoinIdenticalVertices | SortByPType
// | OptimizeGraph. Throws InputError naming the file when assimp cannot read
// it or it has no vertex.
Eigen::Vector3d OmplRobotCenter(const std::filesystem::path& mesh);

// The box OMPL.app bounds the reference point by: volume.* when given, else
// the AABB of the world mesh's vertices (imported as above); either way grown
// to hold the start and goal positions. `grown` (may be null) tells whether
// the box had to grow.
Aabb OmplBounds(const OmplProblem& problem, bool* grown);

// The scene with the same meaning as the problem: static = world, dynamic =
// robot, dynamic_origin = OmplRobotCenter(robot), start/goal as read,
// bounds = OmplBounds. Loads both meshes (LoadMesh's InputError is reported
// as "<cfg>: problem.robot: <mesh>: <problem>"). The name is the .cfg's stem.
Scene SceneFromOmplProblem(const OmplProblem& problem);

// scene.yaml's text for `scene` written at `output` (mesh paths relative to
// output's folder), headed by comments that say where it came from.
std::string OmplSceneYaml(const Scene& scene, const OmplProblem& problem, const std::filesystem::path& output);

// Writes `text` to `output` atomically and returns true. Without `force` an
// existing output is left alone when it holds exactly `text` (returns false:
// up to date) and refused when it holds anything else (InputError naming
// it), so that a scene edited by hand is never replaced unasked.
bool WriteImportedScene(const std::filesystem::path& output, const std::string& text, bool force);

}  // namespace ausbau
