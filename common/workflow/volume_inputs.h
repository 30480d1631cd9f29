// What the volume validity modes (--validity shrink|iv|mliv|labeled-mliv)
// need from files, shared by ausbau-plan, ausbau-tau-estimate and
// ausbau-smooth: D's and S's voxels (an ausbau-voxelize artifact, or
// voxelized here with the defaults) and D's labels (ausbau-pbd-label).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "artifact/artifact.h"
#include "inistate/volume_model.h"
#include "planning/path_io.h"

namespace ausbau {

struct Scene;

struct VolumeInputs {
  std::string voxels;  // ausbau-voxels artifact; empty = voxelize now (defaults)
  std::string labels;  // ausbau-labels artifact; required for labeled-mliv
  // labeled-mliv: the rigid guard's tolerance (VolumeModel::GuardRigidParts),
  // millimetres, converted by the scene's units; as --rigid-tolerance.
  double rigid_tolerance_mm = 0.05;
};

// Throws InputError naming the file: missing, wrong schema, made for another
// scene (grids that do not cover D's or S's box), labels of another D.
std::unique_ptr<VolumeModel> LoadVolumeModel(const Scene& scene, const PlanningProblem& problem, ValidityMode mode,
                                             const VolumeInputs& inputs);

// Adds the files' content hashes to a provenance (roles "voxels", "labels").
void AddVolumeInputs(const VolumeInputs& inputs, Provenance* provenance);

class FclCollisionChecker;

// The per-waypoint volume, part and deformability a path artifact records
// (inistate/volume, /part, /deformability). Labeled-MLIV's +infinity (a
// voxel component reaching beyond the fasteners) at a pose where the meshes
// do not intersect at all is the voxels' resolution (a surface voxel of D in
// a surface voxel of S), not an overlap: the volume there is 0. A pose whose
// meshes do intersect keeps what the model says.
void DescribeWaypoints(VolumeModel& model, const FclCollisionChecker& collision, const std::vector<Pose>& path,
                       PathArtifact* artifact);

}  // namespace ausbau
