// Penetration depth of two triangle shells that need not be convex, as an
// upper bound with a stated resolution (docs/rigid-exact.md "Non-convex
// depth").
//
// The measure (the "surface depth" of A and B):
//   depth(A, B) = max( max over points p of A's surface inside B of d(p, surface of B),
//                      max over points q of B's surface inside A of d(q, surface of A) )
// It is 0 for shells that touch, the exact penetration depth where a convex
// corner or face of one pokes into the other, and it is 1-Lipschitz in the
// motion (moving every point of A by at most e changes it by at most e), so
// conservative advancement stays rigorous. What it guarantees: a feature of
// one shell can pass through a wall of the other undetected only when both
// are thinner than twice the allowed depth (the mid-surface of a wall of
// thickness w is at depth w / 2).
//
// How it is bounded: every triangle of A near B is subdivided (branch and
// bound). For a sub-triangle t with centroid m and radius R (the largest
// distance of a corner from m), and f the triangle of B nearest to m:
//   - a lower bound: d(m, surface of B) when m is inside B (m is a point of
//     A's surface);
//   - an upper bound on the depth of any point of t: d(m) + R when m is
//     inside, R when m is outside (a point of t inside B is within R of m,
//     and the segment to m crosses B's surface), and max over the corners
//     of d(corner, P) where P is f's convex planar patch (f, or the convex
//     polygon of coplanar triangles around it: a CAD face, a cylinder's
//     facet): the distance to a convex set is convex, so its maximum over t
//     is at a corner, and d(p, surface) <= d(p, P);
//   - t is wholly outside when m is outside and farther than R from B's
//     surface, or when m is outside and t crosses no triangle of B;
//   - against a flat face region of B (any outline, its measured
//     deviation from flat added) or across a convex planar patch of B:
//     FaceRegionBound and StraddleBound below;
//   - `shift` when t moved that far off B's surface is wholly outside:
//     ShiftOffBound below (surfaces in contact).
// A sub-triangle is refined until its upper bound is within `resolution` of
// the best lower bound (or, for a yes/no question, below the allowed
// depth). The answer's `upper` is thus never below the true depth and at
// most `resolution` above it (smaller sub-triangles than resolution / 8 are
// not made: their bound is kept as it is, still an upper bound).
//
// Inside or outside: for a closed, consistently oriented shell, the sign of
// the nearest point's angle-weighted pseudo-normal (Baerentzen and Aanaes
// 2005; exact for such meshes); for an open shell (boundary edges: a hole
// block exported with a gap, a shell cut by a crop), the generalized
// winding number (Jacobson et al. 2013: inside where it exceeds 1/2), by a
// hierarchy that sums exactly where its error bound does not decide
// (geometry/winding_bvh.h); a shell the reach crop cut open, consistently
// oriented and open only outside the crop's box, answers by the
// pseudo-normal wherever its nearest point is nearer than the box's faces
// (no triangle the crop dropped can be nearer: the whole shell's nearest
// point), with the side the winding number calls inside (InsideByNormalWithinCrop).
// Only where the openings are gaps (at most 1% of
// the shell's area, DepthSurface::solid): a bowl or a surface model bounds no
// volume, and its winding number would make the air it holds material.
// Two such sheets have no depth at all: the caller decides what their
// meeting means (collision/rigid_depth.cpp: not measured).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/protrusions.h"
#include "geometry/shells.h"
#include "geometry/triangle_bvh.h"
#include "geometry/winding_bvh.h"

namespace ausbau {

// One shell prepared for depth queries (in its own coordinates).
class DepthSurface {
 public:
  explicit DepthSurface(const Shell& shell);

  // Signed distance: > 0 inside, < 0 outside; `triangle` receives the
  // nearest triangle.
  double SignedDistance(const Eigen::Vector3d& p, int* triangle = nullptr) const;
  bool oriented() const { return oriented_; }  // closed and consistently oriented
  // Whether the shell bounds a volume: closed, or open only by gaps (its
  // boundary loops, filled, are at most kMaxGapShare of its area: cracks
  // between unwelded faces, a missing sliver). Otherwise it is a sheet (a
  // surface model, a bowl open at the top): nothing is inside it, and a
  // depth against it comes from the other shell's volume alone.
  static constexpr double kMaxGapShare = 0.01;
  bool solid() const { return solid_; }
  // A solid shell the reach crop cut open, answering inside-or-outside by
  // its pseudo-normals within the crop's box (InsideByNormalWithinCrop).
  bool inside_by_normal_within_crop() const { return complete_within_.has_value(); }
  const Aabb& box() const { return box_; }
  // The shell's triangles (indices into its vertices) and their tree.
  const std::vector<Eigen::Vector3d>& vertices() const { return vertices_; }
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }
  const TriangleBvh& bvh() const { return bvh_; }
  // Whether triangle t (in the shell's coordinates) may touch the surface:
  // false only when every triangle near it is more than `gap` apart from it
  // along a separating axis.
  bool MayMeet(const std::array<Eigen::Vector3d, 3>& t, double gap) const;
  // An upper bound on the depth of every point of triangle t inside this
  // (closed, oriented) shell, from the plane of triangle `face`'s convex
  // patch P, for a t that straddles that plane; infinite where it gives
  // none. The part of t behind the plane: the largest distance of its
  // corners from P (the distance to a convex set is convex). The part in
  // front: no depth at all, when its cut with the plane has a point inside
  // P and it crosses no triangle outside P (nearer than `gap`): points just
  // in front of P's inside are outside the shell, and that part is joined
  // to them without crossing its surface. A wall of S standing on a face of
  // D that it enters by a few micrometres is settled whole, instead of
  // being refined along the line where it crosses the face.
  double StraddleBound(const std::array<Eigen::Vector3d, 3>& t, int face, double gap) const;
  // The same from the planar region of triangle `face` (its coplanar
  // neighbours, any outline, holes and all), for a t whose shadow on the
  // plane lies in the region (no boundary edge of it within `gap`): a point
  // of t behind the plane is no deeper than its height below it (the point
  // straight above it is on the surface); the part in front, if any, is
  // outside when it crosses no triangle off the region. A face of S lying a
  // little inside a face of D is settled whole, however that face is cut
  // into triangles (a plate's face around the feet of its ribs and clips).
  // `below`: only a bound below it is of use (else infinite, at once).
  double FaceRegionBound(const std::array<Eigen::Vector3d, 3>& t, int face, double gap,
                         double below = std::numeric_limits<double>::infinity()) const;

  // An upper bound on the depth of every point of triangle t from moving t
  // off the surface: when t moved by `shift` along the outward normal at
  // the nearest point of its centre (`nearest`; that triangle's face
  // normal, else the pseudo-normal of the nearest edge or corner) is wholly
  // outside (its centre outside, crossing no triangle nearer than `gap`),
  // each point of t is within `shift` of a point outside, so its depth (its
  // distance to the surface) is at most `shift`. Infinite where neither
  // move frees t. Surfaces in contact (a pin's facets lying on its bore's,
  // the same polygon from one tessellator) are settled whole, instead of
  // being refined along every edge where a facet meets the bore's rim.
  // `into_own_shell` (zero: none): a unit direction tried first, into the
  // shell t belongs to; the argument holds for any direction of the move.
  // `corner_directions`: where none of those frees t, also the directions
  // halfway between into_own_shell and the outward normal at the nearest
  // point of each corner of t (t at a concave edge of this shell).
  double ShiftOffBound(const std::array<Eigen::Vector3d, 3>& t, const TriangleBvh::Nearest& nearest, double shift,
                       double gap, const Eigen::Vector3d& into_own_shell = Eigen::Vector3d::Zero(),
                       bool corner_directions = false) const;

  // A convex planar patch (see below).
  struct Patch {
    Eigen::Vector3d normal, origin;
    std::vector<Eigen::Vector3d> edge_a, edge_b, inward;  // boundary edges, in-plane inward unit normals
  };

 private:
  friend class SurfaceDepthSearch;
  bool Inside(const Eigen::Vector3d& p, const TriangleBvh::Nearest& nearest) const;
  // face_normal_, edge_normal_, vertex_normal_ with outward_.
  void BuildPseudoNormals();
  // A solid shell the reach crop cut open (Shell::complete_within): where it
  // is consistently oriented and open only outside the crop's box, its
  // pseudo-normals with the side the winding number calls inside, and
  // complete_within_ set; otherwise nothing changes.
  void InsideByNormalWithinCrop(const std::map<std::pair<int, int>, int>& directed, const Aabb& box);
  // The outward pseudo-normal at the nearest point's feature (the face, an
  // edge or a corner of the nearest triangle); oriented shells, and shells
  // the crop cut (complete_within_), only.
  Eigen::Vector3d NormalAtNearest(const Eigen::Vector3d& p, const TriangleBvh::Nearest& nearest) const;

  std::vector<Eigen::Vector3d> vertices_;
  std::vector<std::array<int, 3>> triangles_;
  TriangleBvh bvh_;
  std::shared_ptr<const WindingBvh> winding_;  // shells not closed and oriented, but solid
  // Set for a shell the crop cut (InsideByNormalWithinCrop): within this
  // box no triangle of the whole shell is missing, so a point whose nearest
  // point is nearer than the box's faces is inside or not by its
  // pseudo-normal (outward_ then set), as for a closed shell.
  std::optional<Aabb> complete_within_;
  bool oriented_ = false;
  bool solid_ = true;
  bool convex_ = false;  // a convex shell (oriented): every face plane supports it
  // +1 where the triangles' corner order gives the outward normal, -1 where
  // it gives the inward one (oriented shells; 0 otherwise).
  double outward_ = 0;
  // Its face planes (outward normal, offset), at most kMaxConvexPlanes
  // (none beyond: the patch bound alone).
  static constexpr int kMaxConvexPlanes = 64;
  std::vector<std::pair<Eigen::Vector3d, double>> planes_;
  double GapShare(const std::map<std::pair<int, int>, int>& directed_edges) const;
  // Outward pseudo-normals (closed, oriented shells): per triangle, per
  // triangle edge (k: the edge opposite corner k), per vertex.
  std::vector<Eigen::Vector3d> face_normal_;
  std::vector<std::array<Eigen::Vector3d, 3>> edge_normal_;
  std::vector<Eigen::Vector3d> vertex_normal_;
  // Convex planar patches: coplanar neighbours whose union is a convex
  // polygon (a CAD face split into triangles, a cylinder's facet, the fan
  // of a disc); the distance to a convex set is convex, so the bound at the
  // corners holds for the patch, which straddles the triangles' shared
  // edges. Per triangle the index of its patch, or -1 (the triangle alone).
  static constexpr int kMaxPatchEdges = 256;
  std::vector<Patch> patches_;
  std::vector<int> patch_of_;
  double PatchDistance(const Eigen::Vector3d& p, int triangle) const;
  // Whether the projection of p onto the plane of triangle's patch is inside
  // the patch (or the triangle alone) by more than `margin`.
  bool InsidePatch(const Eigen::Vector3d& p, int triangle, double margin) const;
  // MayMeet for a convex polygon (corners in order), leaving out
  // `triangle` and the triangles of its group (group_of: patch_of_ or
  // region_of_; null: none).
  bool MayMeetOutside(const std::vector<Eigen::Vector3d>& polygon, double gap, const std::vector<int>* group_of,
                      int triangle) const;
  // Flat regions (closed, oriented shells): triangles joined through edges
  // whose normals agree (within about 1.4 mrad), whatever their outline (a
  // CAD face with holes), with how far they lie off their plane.
  struct FaceRegion {
    Eigen::Vector3d normal, origin, u, v;         // outward normal; u, v span the plane
    double deviation = 0;                         // the largest distance of a corner from the plane
    std::vector<Eigen::Vector2d> edge_a, edge_b;  // its boundary edges, in (u, v)
    Eigen::Vector2d InPlane(const Eigen::Vector3d& p) const { return {(p - origin).dot(u), (p - origin).dot(v)}; }
  };
  std::vector<FaceRegion> regions_;
  std::vector<int> region_of_;  // per triangle, or -1
  void BuildFaceRegions(const std::map<std::pair<int, int>, std::vector<int>>& triangles_by_edge);
  double flat_ = 0;  // coplanar within this (BuildConvexPlanarPatches)
  Aabb box_;
};

struct SurfaceDepth {
  double lower = 0;  // a depth attained (>= 0)
  double upper = 0;  // never below the true depth
  // Where the surfaces are deeper than `region_depth` inside each other
  // (world frame, B's coordinates): the box of the sub-triangle centres
  // found there. Empty when nowhere.
  Aabb region;
  // The area of that surface (of the sub-triangles whose centres are that
  // deep; the larger of the two surfaces).
  double region_area = 0;
  // The normal tensor of that surface (both shells' sub-triangles there,
  // world frame): the sum of area n n^T. Where some direction d has
  // d^T N d near 0, the surfaces there are parallel to d (a pin in its
  // bore: d its axis), and the overlap slides out along it.
  Eigen::Matrix3d region_normals = Eigen::Matrix3d::Zero();
  long long sub_triangles = 0;  // the work done: sub-triangles bounded
};

struct SurfaceDepthOptions {
  double resolution = 0;  // > 0: upper - true depth <= resolution (where sub-triangles can be refined)
  // A yes/no question: once the lower bound exceeds it, stop (the depth
  // exceeds it); a sub-triangle whose bound is below it is not refined.
  // Infinite: measure.
  double decide = std::numeric_limits<double>::infinity();
  double region_depth = std::numeric_limits<double>::infinity();  // see SurfaceDepth::region
  // Precision below this depth does not matter to the caller (a validity
  // check's slack only sets a step, never shorter than its floor): a
  // sub-triangle whose bound is below it is not refined. The answer's
  // `upper` is then at most max(settle, true depth + resolution).
  double settle = -std::numeric_limits<double>::infinity();
  // Precision above this depth does not matter either (the caller's answer
  // is already "too deep"; only a report shows the number): once the lower
  // bound exceeds it, the upper bound need only be within kCoarseShare of
  // it. Without this a plate pushed through a plate is refined to
  // `resolution` along every line where the nearest face changes, minutes
  // per pose.
  static constexpr double kCoarseShare = 1.0 / 16;
  double coarse_above = std::numeric_limits<double>::infinity();
};

// Where A may reach into B without it counting: features moulded into A
// that are fasteners (collision/rigid_depth.h), each in a box of A's
// coordinates that holds A's material of that feature only
// (geometry/protrusions.h). The depth is then taken over A's surface
// outside the boxes and over B's surface inside A outside the boxes:
//  - a triangle of A wholly inside a box (`skip_triangle`) is left out;
//  - a sub-triangle of B wholly inside one box is left out; one whose
//    centre is inside a box gives no lower bound, and its upper bound (which
//    holds for all its points) is refined like any other, so the answer is
//    still an upper bound on the depth of every point outside the boxes.
struct DepthMask {
  std::vector<TurnedBox> boxes;     // in A's coordinates
  std::vector<char> skip_triangle;  // per triangle of A
  bool Contains(const Eigen::Vector3d& p) const {
    for (const auto& box : boxes)
      if (box.Contains(p)) return true;
    return false;
  }
  bool ContainsAll(const std::array<Eigen::Vector3d, 3>& t) const {
    for (const auto& box : boxes)
      if (box.Contains(t[0]) && box.Contains(t[1]) && box.Contains(t[2])) return true;
    return false;
  }
};

// The surface depth of A, moved by `pose_a` (A's coordinates -> B's), and B;
// `mask_a` (or null): regions of A whose reach into B does not count.
SurfaceDepth MeasureSurfaceDepth(const DepthSurface& a, const Eigen::Isometry3d& pose_a, const DepthSurface& b,
                                 const SurfaceDepthOptions& options, const DepthMask* mask_a = nullptr);

// The largest surface depth of A and B over a translation: A at pose_a
// moved by s * move (B's coordinates) for every s in [0, 1], as an upper
// bound with the guarantees above, so that a motion along a fit or a
// contact (a bolt drawn through its bore, a pin out of its sleeve) is
// proved in one query instead of a pose per tolerance of the way.
// The same branch and bound, over sub-triangles swept along a stretch w of
// the motion: the prism of t and t + w (their convex hull; B's triangles
// swept by -move in A's coordinates). What carries over to a convex set:
// the ball about its centre (the centre is a point of the surface at the
// stretch's middle: the lower bound), the patch bound and a convex shell's
// planes (a convex function is largest at one of the six corners), "wholly
// outside" (its centre outside, and no triangle of the other meets it by a
// separating axis: a prism is convex and connected), and the shift off the
// surface (ShiftOffBound, for the moved prism). The face-region and
// straddle bounds are for triangles and are not used. A prism is split
// across the motion (w halved) while w is longer than its triangle's
// longest edge, else along that edge. Meant for yes/no questions
// (options.decide; region_depth is ignored); at most `max_sub_triangles`
// prisms are bounded (the rest keep their bound, an answer on the safe
// side).
// Whether the surface of A (triangles of `vertices`, moved by pose_a and
// then by s * move, s in [0, 1]) may meet B's surface anywhere on the way:
// false only when the prism each of A's triangles sweeps (the convex hull of
// it at both ends) is more than `gap` apart from every triangle of B by a
// separating axis. Surfaces that do not meet at the start and never on the
// way cannot hold one another at the end either.
bool SweptSurfacesMayMeet(const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<std::array<int, 3>>& triangles, const Eigen::Isometry3d& pose_a,
                          const Eigen::Vector3d& move, const DepthSurface& b, double gap);

SurfaceDepth MeasureSweptSurfaceDepth(const DepthSurface& a, const Eigen::Isometry3d& pose_a,
                                      const Eigen::Vector3d& move, const DepthSurface& b,
                                      const SurfaceDepthOptions& options, int max_sub_triangles,
                                      const DepthMask* mask_a = nullptr);

}  // namespace ausbau
