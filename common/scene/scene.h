// The scene description read by every stage: scene.yaml plus its meshes.
//
// scene.yaml (format ausbau-scene/2, see schemas/scene.md; /1 is read too):
//   format: ausbau-scene/2
//   name: joint
//   units: cm                      # the world's unit; mm, cm, m, inch, unitless
//   assembly: beam.obj             # optional: D picked from it, S = the rest
//   static:                        # more of S: files, parts, poses, units
//     - floor.obj
//     - {file: clamp.obj, part: jaw, pose: {t: [0, 0, 10], q: [1, 0, 0, 0]}, units: mm}
//   dynamic: {part: peg}           # the part D to move (or a file)
//   dynamic_origin: [x, y, z]      # optional; the point of D that a pose places
//   start: {t: [x, y, z], q: [qw, qx, qy, qz]}   # default identity
//   goal:  {t: [x, y, z], q: [qw, qx, qy, qz]}   # optional; absent = disassembly
//   goal:  {clearance: 50, region: {min: [..], max: [..]}}  # or a condition (either key or both)
//   bounds: {min: [x, y, z], max: [x, y, z]}     # optional bounds on t
//   up_axis: z                     # optional: x, y, z, -x, -y, -z (views only)
// Paths are relative to the YAML file. A pose maps D's mesh coordinates to
// the world: x_world = R(q) (x - dynamic_origin) + t.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/pose.h"
#include "scene/mesh_io.h"

namespace ausbau {

// Where one mesh of the scene comes from (format /2): a file, some of its
// parts, its units and, for a static entry, its pose in the world.
struct MeshSource {
  std::filesystem::path file;     // resolved
  std::string written;            // the file as written in scene.yaml
  std::vector<PartPick> picks;    // `part:` as written; empty: the whole file
  std::vector<PartPick> without;  // `assembly: {without: ...}`: parts left out of the rest
  std::vector<int> parts;         // resolved: indices into the file's parts (MeshFile::parts), ascending
  std::string units;              // `units:` of the entry; empty: the scene's
  double scale = 1;               // mesh units -> scene units (1 without `units:`)
  std::optional<Pose> pose;       // static entries: x_world = R(q) (scale x) + t
  bool rest_of_assembly = false;  // the static entry the assembly shorthand adds: every part but D's
  // A whole file in the scene's units at identity: what format /1 can say.
  bool Plain() const { return picks.empty() && without.empty() && units.empty() && !pose && !rest_of_assembly; }
};

// A goal that is a condition on where D ends instead of a pose (`goal:
// {clearance: c}`, `goal: {region: {min, max}}` or both, schemas/scene.md
// "Goals"); every part given must hold. planning/scene_goal.h tests it.
// The narrowest goal region on any axis, relative to 1 + the region's
// largest |coordinate| (scene units): what the planner can still resolve
// (LoadScene refuses a narrower one).
inline constexpr double kMinGoalRegionWidth = 1e-6;

struct GoalCondition {
  double clearance = 0;        // > 0: the exact distance between D and S at least this (scene units)
  std::optional<Aabb> region;  // dynamic_origin's world position (t) inside this box, D not touching S
};

struct Scene {
  std::filesystem::path file;  // the scene.yaml itself
  std::string name;
  std::string units;                                // the world's unit; informative in /1
  std::vector<std::filesystem::path> static_files;  // resolved paths, one per static entry
  std::filesystem::path dynamic_file;               // resolved path
  // Format /2's detail of the same files. Filled by LoadScene (for /1 too:
  // plain sources); SaveSceneYaml uses a source only while its file is the
  // one static_files / dynamic_file names (so code that swaps a file gets
  // the plain file written). static_sources[i] describes static_files[i];
  // the assembly's rest, when there is one, is the last entry.
  int format_version = 1;              // as read (1 or 2)
  std::optional<MeshSource> assembly;  // `assembly:`
  std::vector<MeshSource> static_sources;
  MeshSource dynamic_source;
  TriangleMesh static_mesh;  // all static files merged
  // Which piece of S each triangle of static_mesh came from, so that a
  // result can name the part of S that blocks D: static_part_names holds one
  // label per piece (the static file as written in scene.yaml, and
  // "file:part" for a part picked from a multi-part file), and
  // static_part_of_triangle[i] indexes it for triangle i of static_mesh
  // (same size as static_mesh.triangles).
  // static_part_entry[k] is the static entry (index into static_files)
  // piece k came from.
  std::vector<std::string> static_part_names;
  std::vector<int> static_part_of_triangle;
  std::vector<int> static_part_entry;
  TriangleMesh dynamic_mesh;  // D in its mesh coordinates
  Eigen::Vector3d dynamic_origin = Eigen::Vector3d::Zero();
  bool dynamic_origin_given = false;
  Pose start;                                   // scene convention
  std::optional<Pose> goal;                     // scene convention; none = disassembly
  std::optional<GoalCondition> goal_condition;  // set only when `goal` (the pose) is not
  std::optional<Aabb> bounds;                   // bounds on t as given (scene convention)
  // `fit_interference`: the deepest installed interference of a rigid part
  // that is a fit (a press fit, a tessellation overlap) and not a clash, in
  // mm (collision/rigid_depth.h FitRule; 0: none is). None: the default
  // rule (a thin layer along a surface, small against the parts).
  std::optional<double> fit_interference_mm;
  // `tessellation_deflection`: the chord error of the meshes (mm), as the
  // tessellation of a CAD model recorded it (ausbau-assembly from STEP).
  // Two surfaces that touch in CAD overlap by at most this in the meshes,
  // so an installed interference no deeper is a fit whatever its shape
  // (FitRule::tessellation_depth). Absent: unknown.
  std::optional<double> tessellation_deflection_mm;
  // Per mesh file of the scene (the resolved path, as in static_files and
  // dynamic_file): the other files its importer read (MeshFile::also_read,
  // a glTF's external buffers). Files that read none are absent.
  std::map<std::filesystem::path, std::vector<std::filesystem::path>> also_read;
  // `up_axis`: the world axis that points up, for views (the report's 3D
  // view): "x", "y", "z", "-x", "-y" or "-z"; empty where the key is absent
  // (SceneUpAxis then picks it from the mesh files).
  std::string up_axis;
  // The coarsest spacing of the stored coordinates of any mesh file the
  // scene loads (scene units), with that file and the largest magnitude of
  // its coordinates (the file's units). Every mesh passes through single
  // precision on its way in (assimp's float, binary STL's float32): far from
  // the origin its corners are rounded to this spacing before any check
  // sees them (CheckStoredPrecision in collision/scene_parts.h).
  double stored_spacing = 0;
  double stored_magnitude = 0;
  std::filesystem::path stored_spacing_file;
};

// The up axis of a view of the scene and where it came from: `up_axis` where
// the scene gives it, else from the data: "y" where every mesh file is glTF
// (.gltf/.glb, y-up by its spec) or COLLADA (.dae: assimp turns a file's
// Z_UP or X_UP into Y-up as it imports it), "z" otherwise (OBJ, STL, PLY,
// STEP tessellations: the CAD convention).
struct UpAxis {
  std::string axis;    // "x", "y", "z", "-x", "-y" or "-z"
  std::string source;  // "scene key", "default for glTF/COLLADA data" or "default for OBJ/STL/STEP data"
};
UpAxis SceneUpAxis(const Scene& scene);

// Reads and validates scene.yaml (format /1 or /2) and loads its meshes. Throws InputError with
// a one-line message naming the file and the problem: missing file, YAML
// syntax error, unknown key, wrong format string, missing required key,
// malformed vector, malformed or non-unit quaternion (|q| off 1 by more than
// 1e-3; smaller deviations are renormalized), min > max in bounds, and every
// mesh error of LoadMesh; in /2 also an unknown part (the message lists the
// file's parts), unknown units, and D taking the same geometry as S (the
// same part of the same file, or at its start pose D's triangles are S's).
// Range checks that need the planner's conventions
// (start outside bounds, goal in collision) are done by the planner set-up.
Scene LoadScene(const std::filesystem::path& path);

// Writes a scene.yaml for the given meshes (paths written relative to the
// YAML file's folder). Used by generators and tests.
// Writes format /1 when every source is plain (a whole file, no pose, no
// units, no assembly), else /2.
void SaveSceneYaml(const Scene& scene, const std::filesystem::path& path);
// The text SaveSceneYaml writes at `path` (paths relative to its folder).
std::string SceneYamlText(const Scene& scene, const std::filesystem::path& path);

// D's content hash, the role "dynamic" of every provenance (cli/stage_main.h) and
// what CheckMadeFrom compares (workflow/made_from.h): the hash of D's
// file, and for a D picked from a file (format /2: `part:`, `units:`) the
// hash of that and of the parts and scale, so that two parts of one
// assembly file never share a cached artifact (the medial spheres hash D
// alone). A plain D keeps the plain file hash, as before /2.
std::string DynamicContentHash(const Scene& scene);

// The content hash of one mesh file of the scene, as every cache key and
// made-from check records it: the file's bytes, and where its importer read
// other files (Scene::also_read: a glTF's external .bin), those too (each
// by its name relative to the mesh file's folder and its bytes), so that an
// edited buffer is a changed input. A file that reads no other keeps its
// plain HashFile, so caches of OBJ and STL scenes stay valid.
std::string MeshFileHash(const Scene& scene, const std::filesystem::path& file);

// The scene's inputs as every artifact's provenance records them, one
// definition for the writer (cli/stage_main.h AddSceneInputs) and the check
// (workflow/made_from.h CheckMadeFrom): the role "scene" (scene.yaml),
// "static" for a single static file or "static[0]", "static[1]", ... for
// several (one role per file, so that a change to any of them changes the
// provenance; the single "static" keeps caches written before lists of
// static files valid), and "dynamic" (D: DynamicContentHash).
struct SceneInput {
  std::string role;
  std::filesystem::path file;
};
enum class SceneInputs { kAll, kDynamicOnly };
std::vector<SceneInput> SceneInputFiles(const Scene& scene, SceneInputs which = SceneInputs::kAll);
// Its content hash as recorded: HashFile of scene.yaml, MeshFileHash of a
// static file, DynamicContentHash of D.
std::string SceneInputHash(const Scene& scene, const SceneInput& input);

}  // namespace ausbau
