// The pre-flight check's look at the installed pose (ausbau-scene-check):
// which parts of S D touches or overlaps there, how deep, and what the
// planner will make of it (collision/rigid_depth.h: contacts within the
// tolerance, fits, clashes, fasteners), and fits finer than the planner's
// check step. Measured, so it belongs above the scene layer's CheckScene.
#pragma once

#include <vector>

#include "scene/scene.h"
#include "scene/scene_check.h"

namespace ausbau {

struct InstalledCheckOptions {
  double rigid_tolerance_mm = 0.05;  // as the stages' --rigid-tolerance
  double resolution = 0.01;          // the planner's edge step, a fraction of D's box diagonal
};

// Findings (codes in stages/scene-check/README.md, "At the installed pose"):
// installed-clash, installed-fit, installed-fasteners, installed-contact,
// fit-finer-than-step. Nothing for a scene with a goal pose (a motion task,
// not a removal).
std::vector<SceneFinding> CheckInstalledPose(const Scene& scene, const InstalledCheckOptions& options);

}  // namespace ausbau
