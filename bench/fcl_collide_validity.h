// FCL's own collide as a validity: the reference the benchmarks measure
// against. OMPL.app's planners check poses with fcl::collide, so
// ausbau-bench's OMPL side uses this, not ausbau-plan's faster walk of the
// same trees (collision/fcl_tree_walk.h): the same answers, FCL's time.
#pragma once

#include "collision/fcl_checker.h"

namespace ausbau::bench {

class FclCollideValidity : public PoseValidity {
 public:
  explicit FclCollideValidity(const FclCollisionChecker& checker) : checker_(checker) {}

 protected:
  bool CheckValid(const Pose& pose) const override { return !checker_.InCollisionByFclCollide(pose); }

 private:
  const FclCollisionChecker& checker_;
};

}  // namespace ausbau::bench
