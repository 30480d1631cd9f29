// A scene's parts as the checks see them: D's solids classified against S
// at the start pose, the scene's fit rule, the rigid tolerance in scene
// units, and the refusal of meshes stored coarser than that tolerance.
// Here in collision/ (not planning/) so that labeling/ (the solid labels)
// needs no planner: ARCHITECTURE.md "Layers".
#pragma once

#include <memory>
#include <string>

#include "collision/rigid_depth.h"

namespace ausbau {

struct Scene;

// ClassifyParts for a scene's D and S at its start pose, in the scene's pose
// convention (D's mesh shifted by dynamic_origin), as the exact check
// (planning/exact_check.h) and the solid labels (labeling/solid_labels.h)
// use it.
std::shared_ptr<const PartModel> ClassifySceneParts(const Scene& scene, double tolerance,
                                                    UnmeasuredInterference unmeasured);

// The rigid tolerance in scene units: `millimetres` converted by the scene's
// `units` (mm, cm, m, in; empty or unknown units are taken as mm, with a
// warning the caller prints when `*assumed` is set).
double RigidToleranceInSceneUnits(double millimetres, const std::string& units, bool* assumed);
// The same for `scene`'s units, after CheckStoredPrecision(scene, the
// tolerance): every stage that judges with the rigid tolerance takes it
// from here, so that none judges a scene whose meshes were rounded
// coarser than the tolerance allows.
double RigidToleranceInSceneUnits(double millimetres, const Scene& scene, bool* assumed);

// Throws InputErrorAt(<mesh file>, "... move the model nearer the origin")
// when single precision stored a mesh file's coordinates more than
// 1/kStoredSpacingShare of `tolerance` (scene units) apart
// (Scene::stored_spacing). Rounding moves a corner by at most sqrt(3)/2 of
// the spacing, so a depth between D and S by at most sqrt(3) of it: under
// a quarter of the tolerance at 1/8. At the default 0.05 mm this refuses
// coordinates from 65536 mm (65 m) on; assimp here is built with float
// (ai_real), so reading in double would mean readers of our own for every
// format, while a model in a car's own frame lies within a few metres.
inline constexpr double kStoredSpacingShare = 8;
void CheckStoredPrecision(const Scene& scene, double tolerance);

// The fit rule the scene asks for: its `fit_interference` key (mm) in scene
// units, or the default rule. Every stage classifies D's parts with it, so
// that planners, smoother and the verdict judge one rule.
FitRule SceneFitRule(const Scene& scene);

}  // namespace ausbau
