// Mesh loading through assimp: every mesh of every node of a file, with the
// node transforms accumulated from the root, triangulated; faces that are
// not triangles after triangulation (points, lines) are dropped.
#pragma once

#include <filesystem>

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

// Writes a mesh as Wavefront OBJ (used by generators and tests).
void SaveObj(const TriangleMesh& mesh, const std::filesystem::path& path);

}  // namespace ausbau
