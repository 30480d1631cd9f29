// Fast Alternating Random Rays (thesis 4.2, algorithms 6-8): an early out in
// front of FCL for configurations that are in collision, with answers equal
// to FCL's.
//
// A query starts k rays at random vertices of D (alg. 7). A ray alternates
// between the distance fields (alg. 6): a point a on D, mapped into S's
// field, gives the nearest point b on S and its triangle; b, mapped back
// into D's field, gives the next a on D and its triangle; and so on, at most
// `max_alternations` times, until a repeats (a local distance minimum).
// Whenever a look-up lands within epsilon (6e-6 x D's AABB diagonal, the
// thesis's convergence test) or within `band` cell diagonals of the surface
// it looked up, the two triangles involved are tested for intersection,
// together with their edge neighbours (the stored triangle is the nearest
// one to the cell's centre, not necessarily the one crossing the other
// surface at the ray's point): at most 6 x 6 pairs, each first rejected
// cheaply when one triangle lies on one side of the other's plane, then
//   - by a robust Moeller-style test that accepts only proper crossings
//     (every vertex clearly off the other triangle's plane, the two
//     intersection intervals overlapping by more than a tolerance), so that
//     touching, coplanar and nearly degenerate pairs are never a witness, and
//   - by FCL's own leaf test (Intersect::intersect_Triangle) on the same
//     vertices and the same relative transform FCL's traversal uses.
// Only a pair accepted by both is a witness: FCL's traversal, whose bounding
// volume tests are conservative, reaches that pair and reports the same
// collision. Without a witness the answer is FCL's (alg. 8, the BVH
// fallback), so "free" always comes from FCL.
//
// Adaptive rays (option `adaptive`, on by default; not in the thesis): the
// rays pay only where enough queries are in collision (thesis 4.3.5: the
// invalid portion decides). The checker measures it while it runs, on a
// uniform sample of its queries (the first 64, then every 32nd, after 4096
// queries every 256th, after 65536 every 1024th): these run all `rays` rays
// to the end (recording the lowest ray that proves a collision) and FCL as
// well, both timed. Every 8th regular probe without a witness is timed too.
// Every 256 queries it decides between k = `rays` and k = 0 (no rays), by
// the expected time per query
//   k * cost_per_ray * P(not proven by k rays) - E[FCL time on the queries k rays prove]
// (FCL's time on exactly those queries: deep collisions, which the rays find
// first, are also the ones FCL decides fastest), switching only for a gain
// above 2% of FCL's mean time. It starts with the rays on. Where FARR does not
// pay, the checker falls back to plain FCL plus the sampling. Only the work
// depends on it, never the answers.
//
// Containment (one surface entirely inside the other's solid) is no
// collision for FCL. When FCL finds no intersection, the fields can still
// tell it: k random vertices of D (at least 16) in "inside" or "surface"
// cells of S's field and none in an "outside" cell, at least one inside (or
// the same for S's vertices in D's field). With report_containment such a
// pose is reported as a collision (and counted); by default it is not, so
// the checker equals FCL exactly. On open meshes "inside" is the field's
// documented classification (collision/distance_field.h).
//
// Each query draws its start vertices from its own stream, seeded from the
// checker's seed and the bits of the pose: the planner's random stream is
// untouched, and k rays on a pose do the same work whatever the order of the
// queries or the thread (the adaptive k itself depends on what came before).
// A query whose D, as a ball about its reference point, is clear of S by the
// field's estimate goes to FCL without rays. The answers are FCL's in every
// case. Thread-safe; the ray loop allocates nothing (structure of arrays, all
// active rays advanced in lockstep, so that their look-ups overlap).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>

#include "collision/distance_field.h"
#include "collision/fcl_checker.h"
#include "collision/validity.h"
#include "geometry/mesh.h"

namespace ausbau {

struct FarrOptions {
  int rays = 30;              // k, random start vertices per query (at most kMaxRays)
  int max_alternations = 19;  // per ray
  double epsilon = 6e-6;      // convergence distance, times D's AABB diagonal
  // Triangle pairs are also tested when a look-up lands within this many
  // cell diagonals of the surface (0: only the thesis's epsilon test).
  double band = 1.0;
  // A ray also stops when an alternation brings it less than this fraction
  // closer to the other surface (0: only when a repeats, as in the thesis).
  double stall = 0.0;
  // Containment: report it as a collision (true) or, like FCL, not (false).
  bool report_containment = false;
  // Count containment cases even when not reporting them (costs k class
  // look-ups per query that FCL finds free).
  bool count_containment = false;
  // Adapt the number of rays per query (at most `rays`) to what pays, by an
  // online cost model (see FarrCollisionChecker); false: always `rays`, as
  // in the thesis.
  bool adaptive = true;

  static constexpr int kMaxRays = 128;
  // Throws InputError naming the option.
  void Check() const;
};

struct FarrStats {
  std::int64_t queries = 0;
  std::int64_t witnesses = 0;       // collisions proven by a ray
  std::int64_t fcl_calls = 0;       // fallbacks to FCL
  std::int64_t fcl_collisions = 0;  // collisions only FCL found
  std::int64_t containments = 0;    // FCL free, but one surface inside the other's solid
  std::int64_t skipped = 0;         // rays skipped: D's bounding sphere clear of S
  std::int64_t pair_tests = 0;      // triangle pairs tested
  std::int64_t pair_rejects = 0;    // pairs the robust test accepted but FCL's leaf test did not
  std::int64_t explored = 0;        // adaptive: queries probed with all rays to measure
  int rays_now = 0;                 // adaptive: the number of rays currently used
};

class FarrCollisionChecker : public PoseValidity {
 public:
  // `robot` is D relative to its reference point (planning convention),
  // `environment` S in world coordinates, as for FclCollisionChecker; the
  // fields must have been built for exactly these meshes (MeshContentHash),
  // otherwise std::invalid_argument.
  FarrCollisionChecker(const TriangleMesh& robot, const TriangleMesh& environment,
                       std::shared_ptr<const DistanceField> robot_field,
                       std::shared_ptr<const DistanceField> environment_field, std::uint64_t seed = 1,
                       const FarrOptions& options = {});
  ~FarrCollisionChecker() override;

  // FCL's answer (plus containment when report_containment is set).
  bool InCollision(const Pose& pose) const;

  // Algorithm 7 alone: `rays` rays, no FCL. witness = a proven collision.
  struct ProbeResult {
    bool witness = false;
    int witness_ray = -1;  // which ray (0-based, in drawing order) found it
    int rays_used = 0;
    int lookups = 0;
  };
  // complete: run on after a witness until the lowest-numbered ray that
  // finds one is known (witness_ray), as if each ray ran alone.
  ProbeResult Probe(const Pose& pose, int rays, bool complete = false) const;
  // The plain FCL answer of the fallback.
  bool FclInCollision(const Pose& pose) const { return fcl_.InCollision(pose); }

  FarrStats stats() const;
  void ResetStats() const;
  const FarrOptions& options() const { return options_; }

  // FCL's proofs of a whole motion (FclCollisionChecker::SweepClear and
  // ApartAlong): the answers are FCL's, and so is what a proof shows. Not
  // with report_containment, which neither can see.
  bool ProvesMotions() const override { return !options_.report_containment; }
  bool ProvesMotionsByClearance() const override { return !options_.report_containment; }

 protected:
  bool CheckValid(const Pose& pose) const override { return !InCollision(pose); }
  bool MotionFree(const Pose& a, const Pose& b) const override { return fcl_.SweepClear(a, b); }
  bool MotionFreeByClearance(const Pose& a, const Pose& b) const override { return fcl_.ApartAlong(a, b); }

 private:
  struct FieldView;
  ProbeResult Rays(const Pose& pose, int rays, bool complete) const;
  bool Contained(const Pose& pose) const;
  bool Skip(const Pose& pose) const;

  struct MeshData;
  struct QueryFrame;
  struct Adaptive;
  void Recompute() const;
  bool PatchWitness(QueryFrame& frame, int robot_triangle, int environment_triangle, bool* rejected,
                    std::int64_t* pair_tests) const;

  FclCollisionChecker fcl_;
  std::shared_ptr<const DistanceField> robot_field_, environment_field_;
  std::unique_ptr<FieldView> robot_view_, environment_view_;
  std::unique_ptr<MeshData> robot_, environment_;
  std::unique_ptr<Adaptive> adaptive_;
  std::vector<int> start_vertices_;        // vertices of D used by a triangle
  std::vector<int> environment_vertices_;  // vertices of S used by a triangle
  std::vector<int> start_triangle_;        // one triangle per start vertex
  double robot_radius_ = 0;                // farthest vertex of D from its reference point
  std::uint64_t seed_;
  FarrOptions options_;
  double epsilon2_ = 0;  // squared absolute epsilon

  mutable std::atomic<std::int64_t> queries_{0}, witnesses_{0}, fcl_calls_{0}, fcl_collisions_{0}, containments_{0},
      skipped_{0}, pair_tests_{0}, pair_rejects_{0};
};

// Robust triangle-triangle intersection: true only when the triangles cross
// properly (see the top of this file); touching, coplanar or nearly
// degenerate configurations give false. `tolerance` is relative to the
// triangles' extent.
bool RobustTrianglesIntersect(const Eigen::Vector3d p[3], const Eigen::Vector3d q[3], double tolerance = 1e-9);

}  // namespace ausbau
