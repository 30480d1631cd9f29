// Whether rigid D at a pose touches S: FCL's own bounding volume trees
// (OBBRSS, collision/fcl_model.h) walked by a plain loop instead of FCL's
// collide, with FCL's answer.
//
// Why: with --validity collision about 80% of a plan's time was in
// fcl::collide, and most of that not in the geometric tests but around
// them: a traversal object set up per query, virtual calls per node pair,
// the box test out of line, nodes twice the bytes of their box (each also
// carries an RSS). The
// loop here walks the same trees in the same order (FCL's collisionRecurse:
// depth first, left child first, the larger box split unless it is a leaf;
// the boxes copied into a compact array) with the same tests:
//   - a pair of nodes is skipped when their oriented boxes are apart by the
//     separating-axis test (15 axes) with the direction cosines widened by
//     1e-6, as FCL's obbDisjoint does (the products are grouped otherwise,
//     a difference of rounding far below that widening);
//   - a pair of leaves is tested by FCL's own triangle test,
//     Intersect::intersect_Triangle, on the same vertices with the same
//     relative transform as FCL's OBBRSS traversal.
// So the answer is FCL's: `ausbau-collision-bench` replays every pose a
// planner checked through both (0 differing answers on the OMPL.app scenes,
// the same paths) and times them side by side: 1.5-2.4x faster per pose
// (docs/benchmarks.md, "The collision check").
//
// Tried first, not kept: trees of axis-aligned boxes (D's in its frame, S's
// in the world) separated on 6 of the 15 axes: on cubicles no faster than
// FCL, on alpha-1.5 12x slower (axis-aligned boxes around the puzzle's
// thin turned bars overlap far more often).
//
// Like FCL, only surfaces meet: D entirely inside a closed part of S is not
// a collision. Thread-safe: a query keeps its state on its own stack.
#pragma once

#include <memory>
#include <vector>

#include "collision/fcl_model.h"
#include "geometry/pose.h"

namespace ausbau {

class FclTreeWalk {
 public:
  // `robot` is D in its own frame (the planning convention: about its
  // reference point); `environment` is S in the world.
  FclTreeWalk(std::shared_ptr<const FclModel> robot, std::shared_ptr<const FclModel> environment);
  // D placed at `pose`. False when either has no triangles.
  bool Collide(const Pose& pose) const;
  // Whether every triangle of D placed at `pose` is farther than `margin`
  // (> 0) from every triangle of S (FCL's triangle distance at the leaves;
  // D's boxes widened by the margin). True when either has no triangles.
  // What proves a whole motion free (FclCollisionChecker::ApartAlong) when
  // no point of D moves farther than the margin from where it is here.
  bool Apart(const Pose& pose, double margin) const;

 private:
  // The walk: whether `hit` is true for some pair of triangles (D's placed
  // at pose) whose boxes, D's widened by `widen` along its axes, overlap.
  template <typename LeafHit>
  bool AnyLeafPair(const Pose& pose, double widen, const LeafHit& hit) const;

  // A node's oriented box, copied out of FCL's nodes (half their bytes: the
  // walk reads fewer cache lines; 5% faster on the bench).
  struct Node {
    Eigen::Matrix3d axis;
    Eigen::Vector3d centre, extent;
    double size;      // FCL's size(): the squared half-diagonal
    int first_child;  // FCL's: < 0 a leaf of triangle -(first_child + 1)
  };
  std::shared_ptr<const FclModel> robot_, environment_;
  std::vector<Node> robot_nodes_, environment_nodes_;
};

}  // namespace ausbau
