// Collision between D and S with FCL's BVH (OBBRSS, triangle soups).
#pragma once

#include <memory>

#include "collision/validity.h"
#include "geometry/mesh.h"

namespace ausbau {

class FclCollisionChecker : public PoseValidity {
 public:
  // `robot` is D relative to its reference point (planning convention);
  // `environment` is S in world coordinates.
  FclCollisionChecker(const TriangleMesh& robot, const TriangleMesh& environment);
  ~FclCollisionChecker() override;

  // True when D at `pose` touches or intersects S's surface: FCL's answer,
  // by a walk of FCL's trees (collision/fcl_tree_walk.h). Like FCL (and
  // like OMPL.app), a part entirely inside a closed part of S is not
  // detected: only surfaces are intersected.
  bool InCollision(const Pose& pose) const;
  // The same answer by FCL's own collide: the reference the walk is
  // measured against (ausbau-collision-bench), and the check OMPL.app's
  // planners use (ausbau-bench's OMPL side).
  bool InCollisionByFclCollide(const Pose& pose) const;

  // Minimum distance between D at `pose` and S (0 when in collision).
  double Distance(const Pose& pose) const;

  // The distance (0 in contact) and the pair of triangles it is attained at
  // (indices into the meshes given to the constructor; -1 where FCL names
  // none).
  struct Nearest {
    double distance = 0;
    int robot_triangle = -1, environment_triangle = -1;
  };
  Nearest NearestTriangles(const Pose& pose) const;
  // The distance with where it is attained (world coordinates): the
  // nearest points of D and of S; in collision, distance 0 and both points
  // at one contact point.
  struct Closest {
    double distance = 0;
    Eigen::Vector3d on_robot = Eigen::Vector3d::Zero();
    Eigen::Vector3d on_environment = Eigen::Vector3d::Zero();
  };
  Closest ClosestPoints(const Pose& pose) const;

  // True when no pose of the straight motion a -> b has D touch S, proved
  // for the whole motion at once by D's bounding sphere swept along it
  // (collision/swept_sphere.h), with a margin of a thousandth of D's size
  // (far above FCL's tolerances), so InCollision is false on all of them.
  // False says nothing. One query of a tree over S's triangles, however
  // long the motion: what makes a long edge through open space cheap.
  bool SweepClear(const Pose& a, const Pose& b) const;

  // True when D at the middle pose of the straight motion a -> b is farther
  // from S than any point of D moves from there along it (half the
  // motion's MaxDisplacement) plus SweepClear's margin
  // (FclTreeWalk::Apart): so no pose of the motion touches S. D's own
  // shape, not its bounding sphere: what proves short motions close to S
  // (a smoothed path keeping its clearance; the certification's 0.25%
  // steps). False says nothing.
  bool ApartAlong(const Pose& a, const Pose& b) const;

  bool ProvesMotions() const override { return true; }
  bool ProvesMotionsByClearance() const override { return true; }

 protected:
  bool CheckValid(const Pose& pose) const override { return !InCollision(pose); }
  bool MotionFree(const Pose& a, const Pose& b) const override { return SweepClear(a, b); }
  bool MotionFreeByClearance(const Pose& a, const Pose& b) const override { return ApartAlong(a, b); }

 private:
  struct Models;
  std::unique_ptr<Models> models_;
};

}  // namespace ausbau
