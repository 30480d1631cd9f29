// The meshes of a scene by parts (format ausbau-scene/2, schemas/scene.md):
// each file read once, its parts picked, static entries scaled and placed
// by their pose, S's triangles labelled with the piece they came from, and
// the check that D is not also a part of S. LoadScene uses these after it
// has read scene.yaml; ausbau-assembly lists a file's parts with them.
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include "geometry/mesh.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"

namespace ausbau {

// Every mesh file read once: an assembly names one file for D and for S.
class MeshFileCache {
 public:
  // Throws LoadMeshFile's InputError ("<file>: <problem>").
  const MeshFile& Get(const std::filesystem::path& path);

 private:
  std::map<std::string, MeshFile> files_;
};

// A part's label in messages and in Scene::static_part_names: its name, or
// "#k" for an unnamed part k.
std::string PartLabel(const MeshFile& file, int part);

// The mesh a source stands for in its file's coordinates converted to the
// scene's units (scale), placed by its pose when it has one: the whole file
// (every node, as LoadMesh reads it) when it picks no parts, else its
// resolved parts in the file's order.
TriangleMesh SourceMesh(const MeshSource& source, const MeshFile& file);

// Appends static entry `entry` (scene.static_sources[entry]) to
// scene.static_mesh, one piece per part: label "file" for a file of one
// part taken whole, else "file:part".
void AppendStaticEntry(Scene& scene, int entry, const MeshFile& file);

// The assembly shorthand: appends to scene.static_sources (and
// static_files) the entry "the rest": every part of scene.assembly but D's
// (when D comes from the same file at the same scale) and those its
// `without` picks. Nothing when no part is left and S has other entries;
// InputError (without the scene file's name) when S would be empty or a
// `without` pick names no part.
void AddAssemblyRest(Scene& scene, MeshFileCache& files);

// Throws InputError (without the scene file's name) when D would be its own
// obstacle: D and a static entry without a pose of its own take a common
// part of the same file at the same scale, or, at D's start pose, at least
// kCoincidentShare of D's triangles are triangles of S (the same three
// vertices within 1e-6 of D's diagonal).
inline constexpr double kCoincidentShare = 0.9;
void CheckDynamicApartFromStatic(const Scene& scene, MeshFileCache& files);

// The share of `part`'s triangles that are triangles of `other` (the same
// three vertices within `tolerance`, in any order), and which of other's
// pieces (per `piece_of_triangle`, may be empty) holds most of them.
struct Coincidence {
  long long triangles = 0;  // of part's triangles, how many coincide
  int piece = -1;           // the piece of `other` that holds most of them; -1 when none
};
Coincidence CoincidentTriangles(const TriangleMesh& part, const TriangleMesh& other,
                                const std::vector<int>& piece_of_triangle, double tolerance);

}  // namespace ausbau
