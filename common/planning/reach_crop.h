// Cropping S to the region D can reach (issue 18, item 4): planning time and
// memory then scale with D, not with S.
//
// The region at level L is D's world AABB at the installed pose grown on
// every side by kCropMargin x D's AABB diagonal x 2^L (level 0: 1.5
// diagonals, the margin of the derived bounds). A planner that finds no path
// at level L tries L + 1, until the box holds S's whole AABB: then the scene
// is planned uncropped, as before. A straight pull that is free up to the
// crop's edge grows it at once, before the level's sampling (a pin in a
// tube longer than the crop; workflow/plan_scene.cpp); that is asked only
// once no pull got D out of the level (planning/planner.h).
//
// The cropped mesh remembers its box (TriangleMesh::cropped_to): a closed
// shell of S the crop cut open is complete within it, so near its surface
// it answers inside-or-outside as the closed shell does
// (collision/mesh_depth.h).
//
// Why a cropped answer holds for the full S:
//  - D never leaves the box: the translation bounds of the reference point
//    are the box shrunk by D's radius about it (robot_radius), so D's
//    bounding ball, which holds D at every orientation, stays inside; the
//    bounds are convex, so straight motions between valid poses stay too.
//  - The cropped S keeps every triangle whose AABB overlaps the box grown by
//    the goal clearance. A triangle it drops lies outside that grown box, so
//    it can neither touch D nor come within the clearance of D.
//  - The goal (ReachCrop::InGoal): D's AABB grown by the clearance overlaps
//    no triangle of the cropped S; D is then at least `clearance` from every
//    triangle of the full S. This replaces the uncropped goal (D's AABB
//    separated from S's AABB), which a part fastened to a large body can
//    only meet by travelling across the whole body.
//  - The exact check (planning/exact_check.h) does not trust the planner's
//    bounds: it picks the smallest level whose box holds the path and checks
//    that D stays inside it along the whole interpolated motion.
//
// The rule (which scenes are cropped), so that small scenes keep their
// answers: no goal pose and no bounds in scene.yaml, S has at least
// kCropMinTriangles triangles, the level-0 box keeps at most half of them,
// and D's bounding ball about the reference point fits in the box at the
// installed pose.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/pose.h"

namespace ausbau {

struct Scene;

inline constexpr std::int64_t kCropMinTriangles = 200000;
inline constexpr double kCropMargin = 1.5;     // level-0 growth, in D's AABB diagonals
inline constexpr double kCropClearance = 0.1;  // goal clearance, in D's AABB diagonals

struct ReachCrop {
  int level = 0;
  Aabb box;              // world box D stays inside
  double clearance = 0;  // goal: D at least this far from every triangle of S (scene units)
  std::int64_t full_triangles = 0, kept_triangles = 0;
  TriangleMesh environment;  // S's triangles whose AABB overlaps `box` grown by `clearance`

  // D's world AABB `robot_box` (at some pose inside `box`) grown by the
  // clearance overlaps no triangle of `environment`. Thread-safe.
  bool InGoal(const Aabb& robot_box) const;
  // How far the ball (centre, radius) stays inside `box` (negative: it
  // reaches out of it).
  double BallSlack(const Eigen::Vector3d& centre, double radius) const;

  std::vector<Aabb> triangle_boxes;  // of `environment`, for InGoal's quick rejection
};

// D's world AABB at the scene's start pose.
Aabb InstalledBox(const Scene& scene);

// The crop at `level` (>= 0), or none when the rule above says the scene is
// not cropped, or when the box at this level holds S's whole AABB.
std::optional<ReachCrop> ChooseReachCrop(const Scene& scene, int level);

}  // namespace ausbau
