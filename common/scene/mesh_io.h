// Mesh loading through assimp: every mesh of every node of a file, with the
// node transforms accumulated from the root, triangulated; faces that are
// not triangles after triangulation (points, lines) are dropped.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "geometry/mesh.h"

namespace ausbau {

// The largest |coordinate| a mesh vertex may have (after the node
// transforms): 1e9 is 1000 km in mm; beyond it a file is broken, and the
// squared distances of the checks would lose all precision or overflow.
inline constexpr double kMaxMeshCoordinate = 1e9;

// Throws InputError ("<file>: <problem>") when the file is missing, not a
// regular file (FIFO, device, folder) or larger than 4 GiB, when its
// extension names no format assimp reads, when assimp cannot parse it, when
// a face refers to a vertex out of range, when it holds no triangle, or when
// a vertex is NaN, infinite or beyond kMaxMeshCoordinate.
TriangleMesh LoadMesh(const std::filesystem::path& path);

// One node of a mesh file's node tree that holds meshes: what an assembly
// file calls a part (an OBJ object `o` or group `g`, a glTF or COLLADA node).
struct MeshPart {
  std::string name;                     // the node's name; its first named mesh's when the node has none; may be empty
  std::string node_name;                // the node's own name, as assimp gives it
  std::vector<std::string> mesh_names;  // its meshes' names, in order
  std::vector<std::string> groups;      // the names of its ancestor nodes, root first
  TriangleMesh mesh;                    // its meshes merged, placed by the node transforms (file coordinates)
};

// A mesh file node by node. `nodes` holds every node that holds a mesh,
// depth-first in pre-order (children in file order): its triangles appended
// in this order are exactly LoadMesh's mesh. `parts` indexes the nodes with
// at least one triangle; part k of the file is nodes[parts[k]] (what
// `part: k` in scene.yaml picks).
struct MeshFile {
  std::vector<MeshPart> nodes;
  std::vector<int> parts;
  // The other files the importer read for it, in the order it opened them
  // (a glTF's external .bin buffers, ...): what its geometry also depends
  // on, so that they go into every cache key with the file (scene.h
  // MeshFileHash). Empty for OBJ, STL, PLY and OFF, which read one file.
  std::vector<std::string> also_read;

  TriangleMesh Merged() const;  // every node appended: LoadMesh's mesh
  const MeshPart& Part(int k) const { return nodes[parts[k]]; }
};

// LoadMesh, node by node; the same checks and errors. Where MeshCacheDir()
// names a folder, an OBJ, STL, PLY or OFF file is parsed once: its MeshFile
// is kept there under a hash of the file's bytes, and every later load of the
// same bytes (any name, any process) reads that entry instead, after checking
// its header and the hash of its contents. For a car body of 1.2M triangles
// that is a few hundredths of a second instead of seconds of assimp.
MeshFile LoadMeshFile(const std::filesystem::path& path);

// The mesh cache's folder: $AUSBAU_MESH_CACHE, which the pipelines set to
// their cache inside OUT (OUT/.ausbau-cache, beside the distance fields),
// one for every part of an assembly (pipelines/batch.mk, the Snakefile);
// files under 1 MiB are not cached (they parse faster than an entry is read);
// empty (no cache) when unset, so a stage run by hand writes nothing beside
// its outputs.
std::filesystem::path MeshCacheDir();

// One pick of parts from a mesh file (scene.yaml `part:`): by index into
// MeshFile::parts, or by name.
struct PartPick {
  int index = -1;    // >= 0: by index
  std::string name;  // index < 0: by name
  std::string Text() const { return index >= 0 ? std::to_string(index) : "'" + name + "'"; }
};

// The parts the picks name, as ascending indices into file.parts, each once.
// A name picks the parts of that name; when none has it, every part below
// a node of that name (a glTF or COLLADA group); when none, the parts with
// a mesh of that name. Throws InputError("part 'x' not found (parts: 0 base,
// 1 bolt, ...)") for a name that picks nothing or an index out of range.
std::vector<int> PickParts(const MeshFile& file, const std::vector<PartPick>& picks);

// "0 base, 1 bolt, 2 (unnamed)": the file's parts for messages; at most
// `limit` of them, then "... (N more)".
std::string PartListText(const MeshFile& file, std::size_t limit = 40);

// Writes a mesh as Wavefront OBJ (used by generators and tests).
void SaveObj(const TriangleMesh& mesh, const std::filesystem::path& path);

// One named part of an OBJ file to write (SaveObjParts).
struct ObjPart {
  std::string name;  // letters, digits, '.', '_', '-' only (assimp ends a name at a blank)
  const TriangleMesh* mesh = nullptr;
};

// Writes several parts into one OBJ, atomically: an object `o name` per
// part, in order, so that LoadMeshFile reads them back as its parts.
// `header` lines are written as comments first.
void SaveObjParts(const std::vector<ObjPart>& parts, const std::filesystem::path& path,
                  const std::vector<std::string>& header = {});

}  // namespace ausbau
