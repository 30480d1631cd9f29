// The FARR look-up table (thesis 4.2.2): per mesh a distance field on a
// regular grid of cubic cells covering 1.3x the mesh's AABB. Each cell
// stores
//   - its class: outside, inside or surface (a triangle passes through it),
//   - the nearest point on the mesh's surface to the cell centre (float3),
//   - the triangle that point lies on (int32).
// Queries are one integer division and one array look-up; a point outside
// the grid uses the cell of its orthogonal projection onto the grid's
// boundary (the clamped index).
//
// Construction (BuildDistanceField):
//   1. Surface cells: an octree over the grid subdivides only nodes that a
//      triangle overlaps (separating-axis test, boxes inflated by 1e-6 of a
//      cell so that the set is conservative), down to single cells; the
//      leaves carry their triangle lists. Homogeneous nodes are not split.
//   2. Surface band (surface cells and their 26 neighbours): the exact
//      point-triangle distance from the cell centre to every triangle of the
//      surface cells in its 3x3x3 block. Exact for every cell whose distance
//      to the surface is at most one cell size h (any triangle within h of
//      the centre passes through a cell of that block), which covers every
//      surface cell (distance <= h sqrt(3)/2).
//   3. Far cells: nearest surface points are propagated from the band by
//      separable sweeps (forward and backward along x, then y, then z, each
//      cell keeping the closer of its own and its predecessor's point); then
//      each far cell takes the closest point on the triangle it received and
//      on the triangles of its six face neighbours. Approximate: the stored
//      point always lies on the surface, and is near-nearest
//      (tests/collision/test_farr.cpp measures the error against brute force).
//   4. Inside/outside: six axis-parallel rays from every cell centre (+-x,
//      +-y, +-z), counted for all cells at once per grid line (scanline
//      crossings with the top-left rule of rasterization on canonically
//      ordered edges, so that a line through a shared edge or vertex counts
//      once). First the mesh is cleaned for this purpose only: vertices
//      merged by position, duplicate triangles (the same three positions in
//      any order: double-sided exports such as the OMPL.app meshes) kept
//      once, orientations made consistent across manifold edges, each
//      component turned to a positive volume.
//      - Closed and consistently oriented (every edge shared by exactly two
//        triangles): each ray counts its *signed* crossings (+1 leaving
//        through a triangle facing along the ray, -1 entering), i.e. the
//        winding number along it, and a cell is inside when the mean of the
//        six is at least 1/2 in magnitude: a six-direction discretization of
//        the generalized winding number, exact for closed meshes, also for
//        several overlapping closed parts (their union) and inverted ones.
//      - Otherwise (open, non-manifold, T-junctions, non-orientable): each
//        ray's crossing parity, and a cell is inside when at least five of
//        the six rays are odd: a hole fools only the rays through it (a box
//        with one face missing stays inside inside, outside outside).
//      Failure modes: overlapping parts of an *open* mesh count as their
//      symmetric difference (parity); a region seen through holes by two or
//      more of its rays counts as outside; a closed mesh whose orientation
//      is inconsistent (a flipped face) is corrected by the propagation
//      only across manifold edges; thin features below a cell are surface
//      cells, never inside.
// All steps run in parallel with OpenMP; the result does not depend on the
// number of threads.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/log.h"
#include "geometry/mesh.h"

namespace ausbau {

enum class CellClass : std::uint8_t { kOutside = 0, kInside = 1, kSurface = 2 };

struct DistanceFieldOptions {
  int resolution = 256;  // cells along the longest axis of the padded AABB
  int threads = 0;       // 0 = all cores
  double padding = 1.3;  // the grid covers this factor times the AABB (about its centre)
  std::uint64_t memory_budget_bytes = std::uint64_t{4} << 30;  // refuse larger fields
  ProgressCallback progress;                                   // permille of the build (core/log.h); empty = silent

  // Throws InputError naming the option when a value is out of range.
  void Check() const;
};

// The largest resolution BuildDistanceField accepts at all.
constexpr int kMaxDistanceFieldResolution = 1024;

class DistanceField {
 public:
  // One cell as the query reads it: 16 bytes, one cache line access.
  struct Cell {
    float nearest[3];       // nearest surface point to the cell centre
    std::int32_t triangle;  // the triangle it lies on
  };

  DistanceField() = default;

  // Grid geometry: cell (x, y, z) covers origin + h [x, x+1) x [y, y+1) x
  // [z, z+1); its linear index is x + nx (y + ny z) (x fastest).
  const Eigen::Vector3d& origin() const { return origin_; }
  double spacing() const { return spacing_; }
  const std::array<int, 3>& dims() const { return dims_; }
  std::int64_t size() const { return static_cast<std::int64_t>(dims_[0]) * dims_[1] * dims_[2]; }
  int resolution() const { return resolution_; }
  double padding() const { return padding_; }
  // Content hash of the mesh the field was built for (MeshContentHash).
  const std::string& mesh_hash() const { return mesh_hash_; }
  std::int64_t triangle_count() const { return triangle_count_; }

  std::int64_t Index(int x, int y, int z) const {
    return x + static_cast<std::int64_t>(dims_[0]) * (y + static_cast<std::int64_t>(dims_[1]) * z);
  }
  Eigen::Vector3d CellCenter(int x, int y, int z) const {
    return origin_ + spacing_ * Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5);
  }
  // The cell of p, or of its orthogonal projection onto the grid when p
  // lies outside.
  std::int64_t Locate(const Eigen::Vector3d& p) const;
  std::array<int, 3> LocateCell(const Eigen::Vector3d& p) const;

  const Cell& cell(std::int64_t index) const { return cells_[index]; }
  CellClass cell_class(std::int64_t index) const { return static_cast<CellClass>(classes_[index]); }
  Eigen::Vector3d NearestPoint(std::int64_t index) const {
    const Cell& c = cells_[index];
    return {c.nearest[0], c.nearest[1], c.nearest[2]};
  }

  // Raw arrays (size() entries each) for the query loop and serialization.
  const Cell* cells() const { return cells_.data(); }
  const std::uint8_t* classes() const { return classes_.data(); }

  // Bytes the field occupies once built.
  std::uint64_t MemoryBytes() const { return static_cast<std::uint64_t>(size()) * (sizeof(Cell) + 1); }

 private:
  friend class DistanceFieldBuilder;
  friend std::shared_ptr<DistanceField> ReadDistanceField(const std::filesystem::path& path);

  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  double spacing_ = 1.0;
  std::array<int, 3> dims_{0, 0, 0};
  int resolution_ = 0;
  double padding_ = 1.3;
  std::string mesh_hash_;
  std::int64_t triangle_count_ = 0;
  std::vector<Cell> cells_;
  std::vector<std::uint8_t> classes_;
};

// XXH3-128 over the vertex coordinates (float64) and triangle indices
// (int32), little-endian: the key of a field in the cache.
std::string MeshContentHash(const TriangleMesh& mesh);

// Grid dimensions and memory a field would take, without building it.
struct DistanceFieldPlan {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double spacing = 0;
  std::array<int, 3> dims{0, 0, 0};
  std::uint64_t cells = 0;
  std::uint64_t bytes = 0;  // peak during construction (the field plus temporaries)
};
// Throws InputError for an empty mesh, a resolution outside [2, 1024] or a
// field larger than the memory budget, before anything is allocated.
DistanceFieldPlan PlanDistanceField(const TriangleMesh& mesh, const DistanceFieldOptions& options);

// Builds the field (see the top of this file). Throws Cancelled between its
// steps when cancelled (core/cancel.h).
std::shared_ptr<DistanceField> BuildDistanceField(const TriangleMesh& mesh, const DistanceFieldOptions& options);

// The artifact (schemas/distfield.md): schema ausbau-distfield, version 1.
inline constexpr const char* kDistanceFieldSchema = "ausbau-distfield";
inline constexpr int kDistanceFieldSchemaVersion = 1;

// The provenance a field of this mesh and these options carries: the cache
// key. `units` and `frame` are descriptive attributes, not part of the key.
struct DistanceFieldProvenanceInfo {
  std::string mesh_hash;
  int resolution = 256;
  double padding = 1.3;
};
std::string DistanceFieldProvenanceHash(const DistanceFieldProvenanceInfo& info);

// Writes atomically. `units` (e.g. "mm") and `frame` (e.g. "world",
// "D relative to its reference point") are recorded as attributes.
void WriteDistanceField(const std::filesystem::path& path, const DistanceField& field, const std::string& units = "",
                        const std::string& frame = "");
// Throws InputError on a missing, corrupt or wrong-schema file, or a dataset
// of the wrong shape, and when the cells do not match the root attribute
// content_hash (an edited or damaged field: a cache entry is then built
// again).
std::shared_ptr<DistanceField> ReadDistanceField(const std::filesystem::path& path);
// XXH3-128 over the grid (dims, origin, spacing), the mesh hash and
// triangle count, and every cell's class, nearest point and triangle: the
// root attribute content_hash that ReadDistanceField checks.
std::string DistanceFieldContentHash(const DistanceField& field);

// The cache: <cache_dir>/distfield-<first 16 hex digits of the mesh hash>-r<resolution>.h5.
std::filesystem::path DistanceFieldCachePath(const std::filesystem::path& cache_dir, const std::string& mesh_hash,
                                             int resolution);
// $AUSBAU_CACHE_DIR when set and not empty, else <folder of scene_file>/.ausbau-cache,
// except for a scene folder marked read-only (no owner write bit, as the
// shared benchmark data): then $XDG_CACHE_HOME/ausbau or ~/.cache/ausbau,
// and where neither XDG_CACHE_HOME nor HOME is set, no cache (an empty
// path, with a note): never a fixed folder that other users can write.
std::filesystem::path DefaultDistanceFieldCacheDir(const std::filesystem::path& scene_file);

// ausbau-distfield-build's step for one mesh: the field at
// `explicit_target` (empty: in the cache) when up to date (same mesh and
// resolution, its cells matching their content hash) and not `force`; else
// copied from the cache (checked the same way); else built and written to
// the target and, when that is another file, to the cache. An empty
// `cache_dir` is no cache (then `explicit_target` is needed: InputError
// otherwise). Returns the file.
std::filesystem::path MakeDistanceFieldFile(const TriangleMesh& mesh, const DistanceFieldOptions& options,
                                            const std::filesystem::path& cache_dir,
                                            const std::filesystem::path& explicit_target, bool force,
                                            const std::string& name, const std::string& units,
                                            const std::string& frame);

struct CachedFieldInfo {
  std::filesystem::path path;  // the cache file (empty when nothing could be written)
  bool reused = false;         // read from the cache instead of built
  double seconds = 0;          // time spent building or reading
};
// The field for (mesh, options.resolution) from `cache_dir`: reused when the
// file's provenance matches, else built and written atomically (a cache
// folder that cannot be written only costs a warning). Empty cache_dir: no
// cache, always build.
std::shared_ptr<DistanceField> LoadOrBuildDistanceField(const TriangleMesh& mesh, const DistanceFieldOptions& options,
                                                        const std::filesystem::path& cache_dir,
                                                        const std::string& name = "distance field",
                                                        const std::string& units = "", const std::string& frame = "",
                                                        CachedFieldInfo* info = nullptr);

}  // namespace ausbau
