// Correctness of an InIState path on a generated clip scene, against the
// scene generator's ground truth (scene/clip_scenes.h), for the thesis
// table 16 benchmark and the end-to-end tests. A path is correct when
//   * the rigid (non-clip) parts of D never penetrate S: along the path,
//     densely interpolated, the largest connected intersection of D's rigid
//     voxels with S (MLIV with ground-truth colours: clip voxels 0, rigid 1)
//     never exceeds its value at the installed pose (ds4's friction fit
//     overlaps there) by more than `tolerance_voxels` voxels; and
//   * it ends in the disassembly region (D's AABB separated from S's).
// Voxels register an overlap up to ~1.5 voxels before the surfaces touch
// (voxel_grid.h), so a rigid part that grazes S within a voxel counts; the
// tolerance (default 8 voxels, a 2x2x2 block) absorbs such grazing but not
// a rail pulled through its lip (hundreds of voxels).
#pragma once

#include <string>
#include <vector>

#include "geometry/pose.h"
#include "inistate/voxel_grid.h"
#include "scene/clip_scenes.h"

namespace ausbau {

struct Scene;

struct GroundTruthCheck {
  bool correct = false;
  bool rigid_ok = false;
  bool ends_disassembled = false;
  double start_rigid_volume = 0;  // rigid MLIV at the installed pose
  double max_rigid_volume = 0;    // along the path
  int worst_segment = -1;         // where the maximum is
  std::string worst_part;         // ground-truth part (e.g. "rail-0", "rim") nearest the worst component
  std::int64_t poses_checked = 0;
  std::string reason;             // empty when correct
};

// `waypoints` in the scene convention, interpolated about `reference_point`
// (D's mesh coordinates) as the path artifact says; between two checked
// poses no vertex of D moves more than step_fraction x D's diagonal.
GroundTruthCheck CheckPathAgainstGroundTruth(const Scene& scene, const ClipGroundTruth& truth,
                                             const SceneVoxels& voxels, const Eigen::Vector3d& reference_point,
                                             const std::vector<Pose>& waypoints, double step_fraction = 0.0025,
                                             double tolerance_voxels = 8);

}  // namespace ausbau
