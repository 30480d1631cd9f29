// Intersection volumes of D at a pose against S, on voxels (thesis 5.3-5.4):
//
//   IV            (def. 5) the number of D's voxels whose transformed centre
//                 lands in an occupied voxel of S, times D's voxel volume;
//   MLIV          (def. 5, alg. 11) the volume of the largest 6-connected
//                 component of those intersecting voxels, connectivity taken
//                 in D's own grid;
//   Labeled-MLIV  (alg. 12) the largest sum over a component of voxel volume
//                 x colorValue(voxel), colorValue in [0 = deformable,
//                 1 = rigid] (voxel_grid.h: ColorValues), or +infinity for a
//                 voxel that must not intersect S at all (the fastener
//                 guard of volume_model.h); with a threshold
//                 tau it stops as soon as one component's running sum exceeds
//                 tau (the early out of 5.4.4) and returns that sum (> tau).
// So IV >= MLIV >= Labeled-MLIV. Poses are in the planning convention
// (planning/state_space.h): x_world = R(q) (x_mesh - reference_point) + t,
// with the reference point given at construction (pass the scene's
// dynamic_origin to use scene-convention poses instead).
//
// Speed (the query runs inside a planner): D's voxels are a compact list
// sorted into 2x2x2 bricks within 8x8x8 groups, with the 6 neighbour indices
// of every voxel. A query maps D-grid indices to S-grid indices by one affine
// map (3x3 + 3); it culls a group, then a brick, with one look-up each in a
// chessboard distance grid of S (voxels to the nearest occupied voxel, capped
// at 255: a group or brick whose bounding ball cannot reach an occupied voxel
// is skipped), tests the remaining voxels lazily, one byte look-up each, and
// flood-fills from every intersecting voxel with reusable buffers (a stamp
// per voxel, no clearing, no allocation per query). As in alg. 11 every
// voxel is a seed, not only surface voxels, so the IV is exact on the voxels
// and a component wholly inside D is found too. On the clips-ds3 scene (189k
// voxels of D) a query along the first part of the known path takes 65-80 us
// (thread CPU time) against 40-45 us for FCL's collision query (README.md).
//
// An IntersectionVolume is not thread-safe (it owns its query buffers):
// Clone() one per thread; clones share the precomputed data.
#pragma once

#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include "collision/validity.h"
#include "geometry/pose.h"
#include "inistate/voxel_grid.h"

namespace ausbau {

// Which intersection volume a validity check thresholds.
enum class VolumeMeasure { kIv, kMliv, kLabeledMliv };

struct VolumeQuery {
  // In: also return the cells of the reported component (or of all
  // intersecting voxels for IV) in `cells`.
  bool record_cells = false;

  double value = 0;               // volume, scene units^3 (weighted for Labeled-MLIV)
  std::int64_t voxels = 0;        // voxels behind `value`: IV all intersecting, (Labeled-)MLIV the component's
  std::int64_t intersecting = 0;  // intersecting voxels found (all of them unless early_out)
  int components = 0;             // connected components found
  bool early_out = false;         // Labeled-MLIV: a component exceeded tau, the search stopped
  std::int64_t tested = 0;        // D voxels looked up in S's grid
  std::int64_t visited = 0;       // D voxels taken into a component by the flood fill
  std::int64_t bricks_culled = 0, bricks = 0;
  std::vector<Eigen::Vector3i> cells;  // D-grid cells (i, j, k), when record_cells
};

class IntersectionVolume {
 public:
  // static_grid: S in world coordinates; dynamic_grid: D's voxels in D's mesh
  // coordinates (any spacing; usually the same as S's). color_values: one per
  // cell of dynamic_grid (ColorValues), or empty for all 1 (then
  // Labeled-MLIV = MLIV); finite values are clamped to [0, 1], +infinity
  // is kept (a component holding such a voxel exceeds every tau). Throws
  // InputError on size mismatches.
  IntersectionVolume(const VoxelGrid& static_grid, const VoxelGrid& dynamic_grid,
                     const Eigen::Vector3d& reference_point, const std::vector<float>& color_values = {});
  IntersectionVolume(IntersectionVolume&&) noexcept;
  IntersectionVolume& operator=(IntersectionVolume&&) noexcept;
  ~IntersectionVolume();

  // A copy that shares the precomputed data and has its own buffers.
  IntersectionVolume Clone() const;
  // A copy with other colour values (as the constructor's), reusing the
  // voxel lists and S's distances instead of computing them again.
  IntersectionVolume Reweighted(const std::vector<float>& color_values) const;

  double Iv(const Pose& pose, VolumeQuery* query = nullptr);
  double Mliv(const Pose& pose, VolumeQuery* query = nullptr);
  double LabeledMliv(const Pose& pose, double tau = std::numeric_limits<double>::infinity(),
                     VolumeQuery* query = nullptr);
  // One of the three; tau is used by Labeled-MLIV's early out only.
  // +infinity where the rigid guard (below) refuses the pose.
  double Measure(VolumeMeasure measure, const Pose& pose, double tau = std::numeric_limits<double>::infinity(),
                 VolumeQuery* query = nullptr);

  // The rigid guard: an exact check of D's rigid part (collision/
  // rigid_depth.h) that Measure consults first; a pose it refuses measures
  // +infinity, beyond every tau, so validity, smoothing and tau estimation
  // all keep the rigid part out of S, however thin S is and whatever the
  // voxels see. Shared by clones. Empty: none.
  void SetRigidGuard(std::shared_ptr<const PoseValidity> guard) { rigid_guard_ = std::move(guard); }
  const PoseValidity* rigid_guard() const { return rigid_guard_.get(); }

  std::int64_t voxel_count() const;  // D's voxels
  double voxel_volume() const;       // of D's voxels
  const Eigen::Vector3d& reference_point() const;
  // colorValue of D's voxel at cell (i, j, k) of its grid (0 where empty).
  float color_value(int i, int j, int k) const;

 private:
  struct Data;
  struct Buffers;
  IntersectionVolume(std::shared_ptr<const Data> data);
  enum class Mode { kIv, kMliv, kLabeled };
  double Run(const Pose& pose, Mode mode, double tau, VolumeQuery* query);

  std::shared_ptr<const Data> data_;
  std::unique_ptr<Buffers> buffers_;
  std::shared_ptr<const PoseValidity> rigid_guard_;
};

// The InIState validity test (5.4.4): a pose is valid when its volume
// (IV, MLIV or Labeled-MLIV) is at most tau; Labeled-MLIV stops early once a
// component exceeds tau (alg. 12). Thread-safe: each check borrows a clone
// from a pool. `volume` must outlive it.
class VolumeValidity : public PoseValidity {
 public:
  VolumeValidity(const IntersectionVolume& volume, VolumeMeasure measure, double tau);
  ~VolumeValidity() override;
  double tau() const { return tau_; }
  VolumeMeasure measure() const { return measure_; }

 protected:
  bool CheckValid(const Pose& pose) const override;

 private:
  const IntersectionVolume* prototype_;
  VolumeMeasure measure_;
  double tau_;
  mutable std::mutex mutex_;
  mutable std::vector<std::unique_ptr<IntersectionVolume>> pool_;
};

// Labeled-MLIV <= tau, the thesis's InIState validity.
class LabeledMlivValidity : public VolumeValidity {
 public:
  LabeledMlivValidity(const IntersectionVolume& volume, double tau)
      : VolumeValidity(volume, VolumeMeasure::kLabeledMliv, tau) {}
};

}  // namespace ausbau
