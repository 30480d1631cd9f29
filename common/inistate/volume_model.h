// The validity modes of InIState planning (thesis 5.3-5.4) and the scene
// data behind them: D's and S's voxels, D's colour values from the labels,
// and D's parts (to say which part of D an intersection belongs to).
//
//   collision     FCL, no intersection at all (rigid planning, ch. 3)
//   shrink        D's voxels eroded until the start is free, then IV <= tau
//                 (tau 0 by default: the shrunk D must not touch S; the
//                 "shrink" baseline of 5.3, as Ma and Wan 2001)
//   iv            IV <= tau            (5.3, def. 5)
//   mliv          MLIV <= tau          (alg. 11)
//   labeled-mliv  Labeled-MLIV <= tau  (alg. 12, the thesis's InIState check)
//                 and no intersection beyond the fasteners' reach (the
//                 fastener guard below; ours, not the thesis's)
//   labeled-mliv-unguarded
//                 Labeled-MLIV <= tau alone: alg. 12 exactly as the thesis
//                 has it, for comparison
//
// The fastener guard. Chapter 5's premise is that D intersects S at its
// installed pose because of its fastening elements (relaxed clips) or
// friction fits, and psi (5.4.4) is the largest extent of a fastening
// element. So an intersection of a voxel of D that lies farther than psi
// (geodesically, through D's own voxels) from every voxel of D that
// intersects S at the start cannot be a fastener giving way: it is a rigid
// part of D cutting into S. The guard forbids those: such voxels get the
// colorValue +infinity, so a component holding one exceeds every tau. Why:
// alg. 12 alone lets a rigid part of D overlap S by up to tau / colorValue,
// and tau is at least what pulling the stiffest clip through costs; with our
// PBD labels (rigid parts at 0.4-0.8 of a clip's deformation) that let the
// planner cut rails into S by up to 45 mm^3 on 3-4 of 5 clips-ds3 scenes;
// guarded, none (docs/results/inistate-ds3-2026-11-22.md). Within psi of
// the installed intersections alg. 12 decides as before. Limits: a fastener that first
// touches S during the motion, and a rigid part passing S closer than about a
// voxel (which the voxels count as an intersection, voxel_grid.h) after the
// start, are refused; labeled-mliv-unguarded plans those. A start that is
// free of S has no reach at all: every intersection is then refused. The
// reach is the labels' psi (EstimatePsi), also where a stage is given --psi
// for the hand-over.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "collision/rigid_depth.h"
#include "inistate/intersection_volume.h"
#include "inistate/voxel_grid.h"
#include "planning/state_space.h"
#include "planning/validity_mode.h"

namespace ausbau {

// The volume modes of ValidityMode (planning/validity_mode.h):
VolumeMeasure MeasureOf(ValidityMode mode);  // shrink and iv: IV; both labeled modes: Labeled-MLIV
bool NeedsLabels(ValidityMode mode);         // the two labeled modes

// One intersection of D with S at a pose, described for a user.
struct VolumeReport {
  double value = 0;          // the mode's volume (Labeled-MLIV weighted), scene units^3; +infinity
                             // when the component reaches beyond the fasteners (labeled-mliv)
  std::int64_t voxels = 0;   // voxels of the reported component (IV: all intersecting)
  int part = -1;             // D's part (connected mesh component) nearest the component's centre; -1 none
  double deformability = 0;  // mean deformability (1 - colorValue) over the component's voxels
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // component's centre, D's mesh coordinates
};

class VolumeModel {
 public:
  // `dynamic_mesh`: D in its mesh coordinates (as the scene loads it);
  // `deformability`: per vertex of it (the labels artifact), required for
  // labeled-mliv and used for the reports of the other modes when given
  // (empty: all rigid). Shrink erodes D's voxels by the smallest multiple of
  // the voxel size that frees the start (InputError when D vanishes first). `mode` must not be collision.
  VolumeModel(const PlanningProblem& problem, const TriangleMesh& dynamic_mesh, SceneVoxels voxels,
              const std::vector<double>& deformability, ValidityMode mode);
  ~VolumeModel();
  VolumeModel(const VolumeModel&) = delete;
  VolumeModel& operator=(const VolumeModel&) = delete;

  ValidityMode mode() const { return mode_; }
  VolumeMeasure measure() const { return MeasureOf(mode_); }
  const IntersectionVolume& volume() const { return *volume_; }
  // For queries that need the model's own buffers (MaxVolumeAlong); not
  // thread-safe, as Measure.
  IntersectionVolume& volume() { return *volume_; }
  double voxel_size() const { return voxels_.dynamic_grid.geometry.spacing; }
  double shrink() const { return shrink_; }                           // erosion distance (shrink mode), scene units
  const std::vector<float>& color_values() const { return colors_; }  // the labels' colorValues, unguarded
  // The fastener guard (labeled-mliv): D's voxels intersecting S at the
  // start, and those within psi of them (the reach; the start's included).
  bool guarded() const { return mode_ == ValidityMode::kLabeledMliv; }
  std::int64_t start_voxels() const { return start_voxels_; }
  std::int64_t reach_voxels() const { return reach_voxels_; }
  const SceneVoxels& voxels() const { return voxels_; }
  int part_count() const { return part_count_; }

  // The mode's volume at a planning-convention pose (no early out). Not
  // thread-safe (uses the model's own query buffers).
  double Measure(const Pose& pose);
  // The same, with the part and deformability of the reported component.
  VolumeReport Describe(const Pose& pose);

  // psi of 5.4.4: the largest extent of the largest 6-connected component of
  // deformable voxels (colorValue < kDeformableColor) plus two voxels (the
  // voxels' surface margin); two voxels when D has no deformable voxel.
  // Measured on D's voxels before shrinking.
  // psi only decides where sigma_1 hands over to the rigid planner (c_inter
  // is collision-free whatever psi > 0 is), so a rough value is enough.
  // The threshold: on the clip scenes the labels put clips at 0.75-1 and
  // rims, rails and panel edges at up to ~0.65 (median 0.15-0.5), so 0.5
  // would join a whole rim into one "fastener".
  static constexpr float kDeformableColor = 0.25f;
  double EstimatePsi() const;

  // The rigid guard (labeled-mliv; intersection_volume.h): D's solids that
  // the exact check calls rigid (ClassifyParts at the start, an installed
  // intersection it cannot measure left to the volume model) may not go
  // deeper into S than half of `tolerance` (scene units; the final check
  // allows all of it), checked exactly at every pose the volume is measured
  // at. A volume threshold cannot forbid a rail grazing a 2 mm plate by a
  // few tenths of a mm (under a voxel); this does. Returns the number of
  // rigid solids guarded (0: none; also when a rigid solid already
  // penetrates S at the start, which the verdict then refuses).
  int GuardRigidParts(const PlanningProblem& problem, double tolerance, const FitRule& fit = {});

 private:
  ValidityMode mode_;
  SceneVoxels voxels_;
  std::vector<float> colors_;
  std::int64_t start_voxels_ = 0, reach_voxels_ = 0;
  std::unique_ptr<IntersectionVolume> volume_;
  double shrink_ = 0;
  double psi_ = 0;
  // D's parts: per triangle of D its connected component; a BVH to find the
  // triangle nearest a point.
  std::vector<int> triangle_part_;
  int part_count_ = 0;
  std::unique_ptr<WindingBvh> bvh_;
};

}  // namespace ausbau
