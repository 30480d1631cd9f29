// The features that stand out of a plate-like solid (ribs, pins, rails,
// snap clips moulded into a trim panel), found on its one welded, closed
// shell, each with a box that holds it and nothing else of the shell.
//
// Why: an injection-moulded panel is exported as ONE closed solid, its snap
// clips part of it. The exact rigid check (collision/rigid_depth.h) then
// sees one rigid shell that intersects S at the installed pose (the clips'
// hooks behind their rims) and can only call it a clash. Chapter 5's premise
// says which part of D is deformed there: the part that intersects. On one
// shell that needs a way to tell "the part" apart: here, the features that
// stand out of the plate. rigid_depth.cpp decides which of them are
// fasteners (those that intersect S at the installed pose) and leaves their
// boxes out of the rigid check.
//
// The rule (docs/rigid-exact.md "Moulded fasteners"):
//  1. The plate: the direction n carrying the most triangle area parallel to
//     it (up to kParallelDegrees) and, along n, the largest face facing +n
//     (at offset `high`) and the largest facing -n (at `low` < `high`). Both
//     must hold at least kMinFaceShare of the shell's area: a plate's two
//     sides (a bracket, a block or a cap has no such pair, and nothing is
//     split there).
//  2. Features: the triangles whose centroid lies beyond the plate (offset
//     above high + eps or below low - eps), connected through shared edges,
//     each side on its own. A feature that leans over the plate's rim or
//     stands out of the rim within the plate's thickness is not found (its
//     triangles' centroids lie within the slab): a clip there stays a clash,
//     the safe answer.
//  3. Each feature's box: axes n and the principal axes of its vertices in
//     the plate's plane; from the plate's face (offset high - eps, or low +
//     eps) out to the feature's farthest vertex, laterally its vertices'
//     extent, all grown by a margin (a quarter of the plate's thickness) so
//     that a surface crossing the feature is inside the box wherever it is
//     inside the feature. Features whose boxes overlap are merged (their
//     box is the box of both) until no two overlap: a box holds D's material
//     of its own feature only, never a neighbouring rib's (the mask is sound
//     only so).
// eps: 1e-5 of the shell's diagonal (rounding of stored coordinates).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "geometry/shells.h"

namespace ausbau {

// A box turned into the shell's coordinates: p is inside when
// |axes^T (p - center)| <= half componentwise.
struct TurnedBox {
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // columns: the box's axes
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d half = Eigen::Vector3d::Zero();
  bool Contains(const Eigen::Vector3d& p) const {
    return ((axes.transpose() * (p - center)).cwiseAbs() - half).maxCoeff() <= 0;
  }
  double Volume() const { return 8 * half.prod(); }
};

struct Protrusion {
  std::vector<int> triangles;  // into the shell's triangles: those beyond the plate
  TurnedBox box;               // holds the feature and no other material of the shell
  int side = 0;                // +1: beyond `high`, -1: below `low`
  double volume = 0;           // between its triangles and the plate's face
};

struct PlateFeatures {
  bool found = false;
  std::string reason;  // why not (or what was found), for logs
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double low = 0, high = 0;  // the plate: low <= normal . p <= high
  std::vector<Protrusion> features;
  // Whether triangle t of the shell lies in the plane of one of the plate's
  // two faces (all three corners within eps of it).
  std::vector<char> on_face;
};

struct PlateRule {
  static constexpr double kParallelDegrees = 1.0;
  static constexpr double kMinFaceShare = 0.2;
  static constexpr double kMarginOfThickness = 0.25;
  static constexpr double kEpsilonOfDiagonal = 1e-5;
};

// The plate and its features of a closed shell (see above); `found` false
// with a reason where the shell is not a plate or stands nothing out.
PlateFeatures FindPlateFeatures(const Shell& shell);

}  // namespace ausbau
