#include "workflow/volume_inputs.h"

#include <cmath>

#include "collision/fcl_checker.h"
#include "collision/scene_parts.h"
#include "core/error.h"
#include "core/hash.h"
#include "core/log.h"
#include "labeling/pbd_label.h"
#include "scene/scene.h"
#include "workflow/made_from.h"

namespace ausbau {
namespace {

bool Covers(const Aabb& outer, const Aabb& inner, double tolerance) {
  return (outer.min.array() <= inner.min.array() + tolerance).all() &&
         (inner.max.array() <= outer.max.array() + tolerance).all();
}

}  // namespace

std::unique_ptr<VolumeModel> LoadVolumeModel(const Scene& scene, const PlanningProblem& problem, ValidityMode mode,
                                             const VolumeInputs& inputs) {
  SceneVoxels voxels;
  if (inputs.voxels.empty()) {
    LogInfo("no --voxels given: voxelizing S and D with the defaults (ausbau-voxelize caches this)");
    voxels = VoxelizeScene(scene, VoxelizeOptions{});
  } else {
    voxels = ReadVoxelArtifact(inputs.voxels);
    CheckMadeFrom(inputs.voxels, kVoxelsSchema, kVoxelsSchemaVersion, scene, MadeFrom::kMeshes);
    const double h = voxels.dynamic_grid.geometry.spacing;
    // D's grid covers D; S's grid covers S near D (VoxelizeScene): it
    // meets S's box.
    if (!Covers(voxels.dynamic_grid.geometry.Bounds(), scene.dynamic_mesh.Bounds(), 1e-6 * h) ||
        voxels.static_grid.geometry.Bounds().SeparatedFrom(scene.static_mesh.Bounds())) {
      throw InputErrorAt(inputs.voxels, "the voxel grids do not cover this scene's D and S (voxels of another scene?)");
    }
    if (voxels.shrink > 0) {
      throw InputErrorAt(inputs.voxels, "D's voxels are eroded (--shrink); volume modes need the unshrunk voxels");
    }
  }
  std::vector<double> deformability;
  if (!inputs.labels.empty()) {
    deformability = ReadLabelsArtifact(inputs.labels).deformability;
    // Labels of another part with the same vertex count passed the count check.
    CheckMadeFrom(inputs.labels, kLabelsSchema, kLabelsSchemaVersion, scene, MadeFrom::kDynamicMesh);
    if (deformability.size() != scene.dynamic_mesh.vertices.size()) {
      throw InputErrorAt(inputs.labels, "labels for " + std::to_string(deformability.size()) + " vertices, but D has " +
                                            std::to_string(scene.dynamic_mesh.vertices.size()) +
                                            " (labels of another part?)");
    }
  } else if (NeedsLabels(mode)) {
    throw InputError("--validity " + ValidityModeName(mode) +
                     " needs --labels (ausbau-medial-spheres, then ausbau-pbd-label)");
  }
  auto model = std::make_unique<VolumeModel>(problem, scene.dynamic_mesh, std::move(voxels), deformability, mode);
  if (mode == ValidityMode::kLabeledMliv) {
    model->GuardRigidParts(problem, RigidToleranceInSceneUnits(inputs.rigid_tolerance_mm, scene, nullptr),
                           SceneFitRule(scene));
  }
  return model;
}

void AddVolumeInputs(const VolumeInputs& inputs, Provenance* provenance) {
  if (!inputs.voxels.empty()) provenance->inputs.emplace_back("voxels", HashFile(inputs.voxels));
  if (!inputs.labels.empty()) provenance->inputs.emplace_back("labels", HashFile(inputs.labels));
}

void DescribeWaypoints(VolumeModel& model, const FclCollisionChecker& collision, const std::vector<Pose>& path,
                       PathArtifact* artifact) {
  artifact->waypoint_volume.clear();
  artifact->waypoint_part.clear();
  artifact->waypoint_deformability.clear();
  for (const Pose& pose : path) {
    VolumeReport report = model.Describe(pose);
    if (!std::isfinite(report.value) && !collision.InCollision(pose)) report = VolumeReport{};
    artifact->waypoint_volume.push_back(report.value);
    artifact->waypoint_part.push_back(report.value > 0 ? report.part : -1);
    artifact->waypoint_deformability.push_back(report.deformability);
  }
}

}  // namespace ausbau
