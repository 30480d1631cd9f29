// Topology of the part D for deformability labeling (thesis 5.4.1): welded
// vertices, edges, triangle adjacency and consistent outward normals, plus
// the spatial queries the labeling needs (a BVH over triangles) and a PLY
// writer for looking at per-vertex results.
//
// How the normals are made consistent (CAD exports and assimp's per-face
// normals leave duplicated vertices and triangles of either orientation):
//  1. Weld: vertices closer than `weld_tolerance` x D's AABB diagonal become
//     one (grid hashing; the first vertex of a cluster in input order is its
//     representative, so the result does not depend on anything but the
//     input order). `welded_of_original` maps every input vertex to its
//     welded vertex: results are computed per welded vertex and reported per
//     input vertex.
//  2. Clean: triangles that lose a corner to welding or have (numerically)
//     zero area are dropped, and of triangles over the same three vertices
//     (double-sided faces, exact duplicates) only the first is kept.
//  3. Orient patches: a breadth-first search over manifold edges (exactly two
//     triangles) flips a neighbour whose shared edge runs in the same
//     direction as in the current triangle. The triangles reached form a
//     patch; non-manifold edges (three or more triangles) are not crossed.
//  4. Orient each patch globally:
//     - closed patch (no boundary or non-manifold edge): flipped when its
//       signed volume is negative, so normals point outward; a closed patch
//       that lies entirely inside other surfaces (every sample point has odd
//       ray parity against the other patches) is a cavity and is oriented the
//       other way (normals into the cavity, out of the material);
//     - open patch: an area-weighted ray-parity vote. From the centroid of
//       up to `orientation_samples` triangles, three rays leave on the normal's
//       side; an odd number of crossings with the mesh means that side is
//       inside (majority of the three rays). The patch is flipped when more
//       area votes "inside" than "outside". A single open sheet (no inside)
//       gets no votes either way and keeps its input orientation.
//  5. Vertex normals: the area-weighted mean of the incident (oriented)
//     triangle normals, normalized; where that sum vanishes, the normal of the
//     largest incident triangle. Vertices in no triangle get a zero normal.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/triangle_bvh.h"

namespace ausbau {

struct MeshTopologyOptions {
  double weld_tolerance = 1e-7;  // fraction of the AABB diagonal; 0 welds exact duplicates only
  int orientation_samples = 32;  // triangles sampled per patch for the ray-parity votes
  bool orient = true;            // false: keep the triangles' orientation as given (steps 3-4 skipped)
  std::string source;            // the mesh's file, named in error messages ("" = none)
};

struct MeshTopologyStats {
  int input_vertices = 0;
  int input_triangles = 0;
  int welded_vertices = 0;
  int unreferenced_vertices = 0;  // welded vertices in no kept triangle
  int degenerate_triangles = 0;   // dropped: collapsed by welding or zero area
  int duplicate_triangles = 0;    // dropped: same three vertices as an earlier triangle
  int boundary_edges = 0;         // one triangle
  int non_manifold_edges = 0;     // three or more triangles
  int patches = 0;                // consistently oriented patches
  int closed_patches = 0;
  int cavity_patches = 0;     // closed patches found inside other surfaces
  int flipped_triangles = 0;  // kept triangles whose orientation differs from the input
  int components = 0;         // connected components (over shared edges)
};

struct MeshTopology {
  std::vector<Eigen::Vector3d> vertices;          // welded
  std::vector<int> welded_of_original;            // input vertex -> welded vertex
  std::vector<std::array<int, 3>> triangles;      // welded indices, oriented outward
  std::vector<int> source_triangle;               // kept triangle -> input triangle
  std::vector<Eigen::Vector3d> triangle_normals;  // unit, outward
  std::vector<double> triangle_areas;
  std::vector<int> triangle_patch;  // orientation patch of each triangle

  // Unique undirected edges (a < b), sorted; the triangles of edge e are
  // edge_triangles[edge_triangle_offsets[e] .. edge_triangle_offsets[e + 1]).
  std::vector<std::array<int, 2>> edges;
  std::vector<int> edge_triangle_offsets;
  std::vector<int> edge_triangles;

  std::vector<Eigen::Vector3d> vertex_normals;  // unit, outward; zero where referenced == 0
  std::vector<double> vertex_areas;             // a third of the area of the incident triangles
  std::vector<std::uint8_t> referenced;         // 1 where the vertex is in a kept triangle
  std::vector<int> component;                   // connected component of each vertex (-1: unreferenced)

  Aabb bounds;            // of the referenced welded vertices
  double diagonal = 0.0;  // of `bounds`
  MeshTopologyStats stats;

  int VertexCount() const { return static_cast<int>(vertices.size()); }
  int OriginalVertexCount() const { return static_cast<int>(welded_of_original.size()); }
};

// Throws InputError when the mesh has no triangle of positive area (naming
// options.source when given).
MeshTopology BuildMeshTopology(const TriangleMesh& mesh, const MeshTopologyOptions& options = {});

// Per ORIGINAL vertex: 0 where it lies inside (or on) another component of
// the mesh (a clip's root embedded in the panel: ray parity, two of three
// rays), 1 otherwise. Such vertices cannot move on their own nor touch S, so
// label quality (clip/rigid separation) is measured without them.
std::vector<std::uint8_t> ExposedVertices(const MeshTopology& topology);

// A closed, consistently oriented (outward) surface of a union of cells of a
// rectilinear grid: cell (i, j, k) spans [xs[i], xs[i+1]] x [ys[j], ys[j+1]] x
// [zs[k], zs[k+1]] and is solid where filled(i, j, k). Every cell face between
// a solid and an empty cell becomes two triangles; grid points are shared, so
// the mesh is connected where the solid is. Used by tests and benchmarks to
// build parts with known thin features (a thick box with a thin tongue).
TriangleMesh MakeGridSolidMesh(const std::vector<double>& xs, const std::vector<double>& ys,
                               const std::vector<double>& zs, const std::function<bool(int, int, int)>& filled);

// Colour ramps for per-vertex PLY output, t in [0, 1] (clamped).
enum class ColorRamp {
  kRigidToDeformable,  // blue (0) - cyan - green - yellow - red (1)
  kLargeToSmall,       // yellow (0: small) to blue (1: large), as the thesis's figure 41
};
std::array<std::uint8_t, 3> RampColor(ColorRamp ramp, double t);

// Writes `mesh` as a binary little-endian PLY with per-vertex colours and one
// extra float property `property` per vertex (values[i] for vertex i), mapped
// onto the ramp by (value - lo) / (hi - lo). Written atomically (temporary
// file, then rename). Throws std::runtime_error naming the file on failure.
void WriteColoredPly(const std::filesystem::path& path, const TriangleMesh& mesh, const std::vector<double>& values,
                     const std::string& property, ColorRamp ramp, double lo, double hi, const std::string& comment);

}  // namespace ausbau
