// Voxelization of S and D for the intersection volumes of thesis 5.4.2-5.4.3
// (the voxmap of VPS, extended by a voxelization of D).
//
// A grid is a regular lattice of cubic voxels: voxel (i, j, k) is the box
// origin + spacing * ([i, i+1] x [j, j+1] x [k, k+1]); cells are stored x
// fastest: index = (k * ny + j) * nx + i. S's grid is in world coordinates,
// D's in D's own mesh coordinates.
//
// Classification of a voxel (VoxelizeMesh):
//   surface  the voxel's closed box touches a triangle (exact triangle-box
//            overlap test, separating axes);
//   inside   not surface, and the generalized winding number (Jacobson et al.
//            2013) of the mesh at the voxel's centre is >= 0.5;
//   empty    otherwise.
// The winding number is robust on triangle soups: overlapping closed parts
// add up (2 inside both, still inside), duplicate triangles are harmless, and
// a small hole only lowers the value near the hole. It is computed in two
// parts. The mesh's vertices are welded by position and its triangles split
// into edge-connected components; a component is *closed* when each of its
// edges is used as often in one direction as in the other (a 2-cycle), and
// *open* otherwise. Closed components are oriented outwards (flipped when
// their signed volume is negative); open ones are flipped when their signed
// volume about their own centroid is negative (a heuristic). A closed
// component's winding number is an integer that only changes across its
// surface, so it is constant on each 6-connected region of non-surface voxels:
// it is evaluated once per region (at the region's first voxel, rounded). The
// open components' winding number varies continuously and is evaluated at
// every non-surface voxel, hierarchically (Barill et al. 2018, dipole terms
// for BVH nodes seen from farther than 2x their radius, exact solid angles
// below).
//
// Failure modes, all of them documented behaviours rather than crashes:
//   * A part thinner than a voxel is kept (its voxels are surface voxels) but
//     thickened to whole voxels; surface voxels reach up to one voxel
//     diagonal beyond the surface, so D and S closer than ~1.5 voxels along
//     an axis (2.6 voxel diagonals in the worst case) register an overlap.
//   * A surface-only part (a single sheet, no volume) is classified by its
//     own winding number: about 0.5 on its inner side, so its non-surface
//     neighbourhood may flip between inside and outside; only its surface
//     voxels are reliable (thesis 5.5.3: such parts have no volume).
//   * A box with one face missing: the winding number is >= 0.5 on the box's
//     side of the missing face's plane (5/6 at the centre, 1/2 on the plane
//     inside the opening), so the box is filled as if closed; outside that
//     plane it drops below 0.5 (tested in tests/inistate/test_intersection_volume.cpp).
//   * Open components oriented inwards and not fixed by the centroid
//     heuristic come out inverted (their inside empty, parts of the outside
//     near them inside).
//   * Large holes (a mesh that is mostly open) give values around 0.5 and an
//     arbitrary classification near the threshold.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "artifact/artifact.h"
#include "core/log.h"
#include "geometry/mesh.h"
#include "geometry/winding_bvh.h"

namespace ausbau {

struct Scene;

enum VoxelState : std::uint8_t { kVoxelEmpty = 0, kVoxelSurface = 1, kVoxelInside = 2 };

struct VoxelGridGeometry {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // corner of voxel (0, 0, 0)
  double spacing = 1.0;                              // voxel edge length
  std::array<int, 3> dims{0, 0, 0};                  // nx, ny, nz
  // The grid's axes (columns, orthonormal, right-handed) in the coordinates
  // of the mesh it voxelizes: voxel (i, j, k) is origin + axes (spacing
  // ([i, i+1] x [j, j+1] x [k, k+1])). VoxelizeScene puts D's grid in D's
  // principal frame and S's in that frame at the installed pose, so that a
  // part turned in car coordinates gets the voxels it would get aligned.
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();

  std::int64_t Count() const { return static_cast<std::int64_t>(dims[0]) * dims[1] * dims[2]; }
  std::int64_t Index(int i, int j, int k) const { return (static_cast<std::int64_t>(k) * dims[1] + j) * dims[0] + i; }
  // (i, j, k) of a cell index, the inverse of Index.
  Eigen::Vector3i Cell(std::int64_t index) const {
    const std::int64_t plane = static_cast<std::int64_t>(dims[0]) * dims[1];
    return {static_cast<int>(index % dims[0]), static_cast<int>((index / dims[0]) % dims[1]),
            static_cast<int>(index / plane)};
  }
  bool Contains(int i, int j, int k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < dims[0] && j < dims[1] && k < dims[2];
  }
  Eigen::Vector3d Center(int i, int j, int k) const {
    return origin + axes * (spacing * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5));
  }
  Eigen::Vector3d Center(std::int64_t index) const;
  double VoxelVolume() const { return spacing * spacing * spacing; }
  Aabb Bounds() const;  // of the grid's 8 corners, in the mesh's coordinates
};

struct VoxelGrid {
  VoxelGridGeometry geometry;
  std::vector<std::uint8_t> cells;  // VoxelState per voxel

  bool Occupied(int i, int j, int k) const {
    return geometry.Contains(i, j, k) && cells[geometry.Index(i, j, k)] != kVoxelEmpty;
  }
  std::int64_t Count(VoxelState state) const;
  std::int64_t CountOccupied() const { return Count(kVoxelSurface) + Count(kVoxelInside); }
};

struct VoxelizeOptions {
  double voxel_size = 0;  // scene units; 0 = automatic (AutomaticVoxelSize)
  // Automatic size: about this many voxels in D's AABB (why 4M, not 1M:
  // stages/voxelize/README.md).
  std::int64_t voxel_budget = 4000000;
  // Bytes. Grids at an explicit voxel_size that need more are refused
  // (InputError); the automatic size is coarsened until they fit.
  std::int64_t memory_limit = std::int64_t{2} << 30;
  // Triangles of S or of D at most (refused up front, InputError naming the
  // file): the open parts' winding number is evaluated per voxel over the
  // triangles, and a 10M-triangle S had taken over 600 s (issue 16).
  // stages/voxelize/README.md documents the limit.
  std::int64_t max_triangles = 2000000;
  // Work bounds (issue 16: a single triangle as D gave a fine automatic size
  // and S's large triangles then took 75-82 s and 5.5 GB): at most this many
  // triangle/voxel tests in the surface pass (the voxels of each triangle's
  // box) and this many voxels in both grids. The automatic size is coarsened
  // until both hold; an explicit --voxel-size that breaks them is refused.
  // Above what real scenes need (clips-ds*: a few million of each; the
  // goldens are unchanged); a flat D's grids (73 s before) now take seconds.
  double max_surface_tests = 1e8;
  std::int64_t max_voxels = std::int64_t{1} << 25;
  double shrink = 0;  // erode D's voxels by this distance (scene units), thesis 5.3
  double winding_threshold = 0.5;
  // S's grid: all of S instead of S near D (VoxelizeScene). For checkers
  // that judge a whole path by its voxels (ausbau-check-path).
  bool whole_static = false;
  ProgressCallback progress;  // each step's voxels done (core/log.h); empty = silent
  void Check() const;         // throws InputError
};

struct VoxelizeStats {
  double time_s = 0;
  std::int64_t surface = 0, inside = 0;  // voxel counts
  std::int64_t regions = 0;              // 6-connected regions of non-surface voxels
  std::int64_t closed_triangles = 0, open_triangles = 0;
  std::int64_t winding_evaluations = 0;
};

// The automatic voxel edge: the cube root of D's AABB volume over the budget
// (each extent counted as at least 1% of the AABB's diagonal), i.e. about
// `budget` voxels in D's AABB. No thickness is estimated here (the medial
// spheres of the labeling know the thinnest part; pass a voxel size when
// clips must be resolved finer): a clip thinner than a voxel is still found,
// as a layer of surface voxels, but its volume is over-estimated. At the
// default budget of 10^6 the clips-ds* scenes get 0.6-0.9 mm voxels for
// 1.2-4 mm thick clips.
double AutomaticVoxelSize(const Aabb& dynamic_box, std::int64_t budget);

// A grid of the given spacing covering `box` with more than `padding` voxels
// of margin on every side (the grid is centred on the box), so that a face of
// the box never touches the outermost voxels.
VoxelGridGeometry GridAround(const Aabb& box, double spacing, int padding = 1);

// Bytes VoxelizeMesh needs for a grid (the cells, region labels and the
// intersection volume's distance grid). Throws InputError naming `what` when
// it exceeds `limit`.
std::int64_t VoxelizeMemoryBytes(const VoxelGridGeometry& geometry);
void CheckVoxelMemory(const VoxelGridGeometry& geometry, std::int64_t limit, const std::string& what);

// Voxelizes a mesh on the given grid (multi-threaded with OpenMP).
VoxelGrid VoxelizeMesh(const TriangleMesh& mesh, const VoxelGridGeometry& geometry, const VoxelizeOptions& options = {},
                       VoxelizeStats* stats = nullptr);

// Erosion by a ball: a voxel stays when every voxel whose centre lies within
// `distance` of its centre is occupied (voxels outside the grid count as
// empty). Kept voxels with an empty 6-neighbour become surface voxels, the
// others inside voxels. The "shrunk D" baseline of thesis 5.3 (as Ma and Wan
// 2001 compute it on a voxelization).
VoxelGrid ErodeVoxels(const VoxelGrid& grid, double distance);

struct SceneVoxels {
  VoxelGrid static_grid;   // S in world coordinates
  VoxelGrid dynamic_grid;  // D in D's mesh coordinates (eroded when shrink > 0)
  double shrink = 0;
  VoxelizeStats static_stats, dynamic_stats;
};

// Voxelizes a scene's S and D at one voxel size (options.voxel_size, or the
// automatic size). D's grid lies in D's principal frame (PrincipalAxes) and
// covers D's box there; the automatic size is taken from that box, so a
// panel turned arbitrarily in car coordinates gets the voxels it gets
// aligned (its world AABB can hold 10-50 times its volume). S's grid lies in
// the same frame at the installed pose (S is mostly what D is fitted into,
// turned with it) and covers S where D can reach in the volume phase:
// within D's diagonal of D's installed box (the volume model governs
// sigma_1, the fasteners' release near the installed pose; S farther out is
// left to FCL and the exact check; options.whole_static for all of S), so
// memory follows D's neighbourhood, not the size of S (a whole vehicle).
// Each grid is padded by one voxel. Throws InputError when a grid exceeds
// the memory limit.
SceneVoxels VoxelizeScene(const Scene& scene, const VoxelizeOptions& options);

// Per cell of D's grid, colorValue in [0 = deformable, 1 = rigid] (thesis
// 5.4.3): 1 - deformability at the point of D's surface closest to the
// voxel's centre, interpolated barycentrically from the three vertex labels
// of that triangle. Empty cells get 0. `deformability` has one value in [0, 1]
// per vertex of `dynamic_mesh` (higher = more deformable). Nearest surface
// rather than nearest vertex because clips are often coarsely tessellated (a
// tongue may be a box with 8 vertices next to a finely meshed panel): the
// nearest surface of a voxel inside the tongue is the tongue's own.
std::vector<float> ColorValues(const VoxelGrid& dynamic_grid, const TriangleMesh& dynamic_mesh,
                               const std::vector<double>& deformability);

// The `ausbau-voxels` artifact (schemas/voxels.md).
inline constexpr char kVoxelsSchema[] = "ausbau-voxels";
inline constexpr int kVoxelsSchemaVersion = 1;

struct VoxelArtifactInfo {
  std::string scene;  // scene name
  std::string units;  // scene units ("mm")
};
void WriteVoxelArtifact(const std::filesystem::path& file, const SceneVoxels& voxels, const VoxelArtifactInfo& info,
                        const Provenance& provenance);
SceneVoxels ReadVoxelArtifact(const std::filesystem::path& file, VoxelArtifactInfo* info = nullptr);

}  // namespace ausbau
