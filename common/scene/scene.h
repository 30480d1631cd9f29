// The scene description read by every stage: scene.yaml plus its meshes.
//
// scene.yaml (format ausbau-scene/1, see schemas/scene.md):
//   format: ausbau-scene/1
//   name: alpha-1.5
//   units: mm                      # informative
//   static: [env.dae]              # one or more mesh files: the environment S
//   dynamic: robot.dae             # the part D to move
//   dynamic_origin: [x, y, z]      # optional; the point of D that a pose places
//   start: {t: [x, y, z], q: [qw, qx, qy, qz]}   # default identity
//   goal:  {t: [x, y, z], q: [qw, qx, qy, qz]}   # optional; absent = disassembly
//   goal:  {clearance: 50, region: {min: [..], max: [..]}}  # or a condition (either key or both)
//   bounds: {min: [x, y, z], max: [x, y, z]}     # optional bounds on t
// Paths are relative to the YAML file. A pose maps D's mesh coordinates to
// the world: x_world = R(q) (x - dynamic_origin) + t.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/pose.h"

namespace ausbau {

// A goal that is a condition on where D ends instead of a pose (`goal:
// {clearance: c}`, `goal: {region: {min, max}}` or both, schemas/scene.md
// "Goals"); every part given must hold. planning/scene_goal.h tests it.
struct GoalCondition {
  double clearance = 0;        // > 0: the exact distance between D and S at least this (scene units)
  std::optional<Aabb> region;  // dynamic_origin's world position (t) inside this box, D not touching S
};

struct Scene {
  std::filesystem::path file;  // the scene.yaml itself
  std::string name;
  std::string units;                                // informative only
  std::vector<std::filesystem::path> static_files;  // resolved paths
  std::filesystem::path dynamic_file;               // resolved path
  TriangleMesh static_mesh;                         // all static files merged
  TriangleMesh dynamic_mesh;                        // D in its mesh coordinates
  Eigen::Vector3d dynamic_origin = Eigen::Vector3d::Zero();
  bool dynamic_origin_given = false;
  Pose start;                                   // scene convention
  std::optional<Pose> goal;                     // scene convention; none = disassembly
  std::optional<GoalCondition> goal_condition;  // set only when `goal` (the pose) is not
  std::optional<Aabb> bounds;                   // bounds on t as given (scene convention)
};

// Reads and validates scene.yaml and loads its meshes. Throws InputError with
// a one-line message naming the file and the problem: missing file, YAML
// syntax error, unknown key, wrong format string, missing required key,
// malformed vector, malformed or non-unit quaternion (|q| off 1 by more than
// 1e-3; smaller deviations are renormalized), min > max in bounds, and every
// mesh error of LoadMesh. Range checks that need the planner's conventions
// (start outside bounds, goal in collision) are done by the planner set-up.
Scene LoadScene(const std::filesystem::path& path);

// Writes a scene.yaml for the given meshes (paths written relative to the
// YAML file's folder). Used by generators and tests.
void SaveSceneYaml(const Scene& scene, const std::filesystem::path& path);
// The text SaveSceneYaml writes at `path` (paths relative to its folder).
std::string SceneYamlText(const Scene& scene, const std::filesystem::path& path);

}  // namespace ausbau
