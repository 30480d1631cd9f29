// ausbau-smooth's work: shortcut smoothing of a planned path under the
// validity it was planned with, never returning a path that fails the
// independent re-check (the dense check, or the exact check for
// rigid-exact paths); then the input path is kept.
//   collision     SmoothPath under FCL
//   rigid-exact   SmoothPath under the exact rigid check, densified for
//                 plain interpolation and checked exactly as written
//   volume modes  sigma_1 under its volume (no shortcut deepening any
//                 intersection), sigma_2 under collision; no shortcut
//                 crosses c_inter
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "inistate/volume_model.h"
#include "planning/path_io.h"
#include "planning/smoother.h"
#include "scene/scene.h"
#include "workflow/volume_inputs.h"

namespace ausbau {

struct SmoothPlannedPathOptions {
  SmoothOptions smooth;
  VolumeInputs volume;  // volume modes: the voxels and labels the path was planned with
};

struct SmoothedPath {
  PathArtifact artifact;               // scene convention, ready to write
  std::vector<Pose> planning_path;     // the same poses in planning convention (for the profile)
  std::unique_ptr<VolumeModel> model;  // volume modes; null otherwise
  SmoothResult result;                 // lengths before and after, shortcuts
  // The part of D whose clearance the profile measures (PathClearanceRobot:
  // the rigid shells of a rigid-exact path, else all of D), as the
  // smoothing classified it.
  TriangleMesh clearance_robot;
};

// `input_file` names the input in errors. Throws InputError when the input
// holds no path, was planned about another reference point, or fails its
// check in this scene.
SmoothedPath SmoothPlannedPath(const Scene& scene, const PlanningProblem& problem, const PathArtifact& input,
                               const std::string& input_file, const SmoothPlannedPathOptions& options);

}  // namespace ausbau
