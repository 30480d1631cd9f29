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

// A named piece of a loaded mesh: the triangles [first_triangle,
// first_triangle + triangle_count) came from one mesh of one assimp node.
// `name` is the node's name, with the mesh's name after a '/' where it has
// another one; empty where the file names neither (assimp's placeholders
// such as "<STL_BINARY>" count as no name).
struct MeshPart {
  std::string name;
  int first_triangle = 0;
  int triangle_count = 0;
};

// LoadMesh, also listing the parts in triangle order (`parts` may be null).
TriangleMesh LoadMesh(const std::filesystem::path& path, std::vector<MeshPart>* parts);

// Writes a mesh as Wavefront OBJ (used by generators and tests).
void SaveObj(const TriangleMesh& mesh, const std::filesystem::path& path);

}  // namespace ausbau
