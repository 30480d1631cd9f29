// Mesh loading through assimp: every mesh of every node of a file, with the
// node transforms accumulated from the root, triangulated; faces that are
// not triangles after triangulation (points, lines) are dropped.
#pragma once

#include <filesystem>

#include "geometry/mesh.h"

namespace ausbau {

// Throws InputError ("<file>: <problem>") when the file is missing or
// unreadable, when assimp cannot parse it, when it holds no triangle, or when
// a vertex is NaN or infinite.
TriangleMesh LoadMesh(const std::filesystem::path& path);

// Writes a mesh as Wavefront OBJ (used by generators and tests).
void SaveObj(const TriangleMesh& mesh, const std::filesystem::path& path);

}  // namespace ausbau
