// A second try for an extension that a narrow passage blocked: the
// direction towards the sample, shaped by the principal components of the
// tree's nodes around the node it grows from (Dalibard & Laumond 2011,
// "Linear dimensionality reduction in random motion planning", IJRR 30(12):
// PCA-RRT).
//
// Why: where D sits in a passage a few hundredths of its size wide (a tube
// in a plate's hole, a key in a slot), a random direction leaves the
// passage at the first checked pose, so almost every extension is trapped
// (Parasol's flange-1.0: 1,000 start-tree nodes in 628,000 iterations).
// The nodes a tree did manage to add there lie along the passage, so their
// spread is wide along it and thin across it. Scaling each principal
// direction of the random direction by the square root of its variance
// over the largest one keeps what points along the passage and drops what
// points into its walls. In open space the nodes spread every way and the
// shaping changes little. RRT-Connect tries it only for a tree whose
// extensions were nearly all trapped lately (rrt_connect.cpp).
#pragma once

#include <vector>

#include "planning/state_space.h"

namespace ausbau {

// The tangent of a motion from `from` to `to`: the translation, then the
// world rotation vector (axis times angle, the shorter way round).
using PoseTangent = Eigen::Matrix<double, 6, 1>;
PoseTangent TangentBetween(const Pose& from, const Pose& to);
// The pose reached from `from` along `tangent` (the inverse of TangentBetween).
Pose MoveAlong(const Pose& from, const PoseTangent& tangent);

// Fewer neighbours than this give no shaping.
inline constexpr int kPassageMinNeighbors = 3;

// `to` (a target of an extension from `from`) moved so that the motion from
// `from` follows the principal directions of `neighbors` (the tree's poses
// near `from`, `from` among them or not), each direction of the motion's
// tangent scaled by sqrt(variance / largest variance), then scaled back to
// the metric's range of the original motion. Variances are taken in the
// metric's units (the shift over nu, the angle over 2 pi: those of
// Metric::Range). Measured on flange-1.0 (seeds 1-4, 120 s, the second try
// on every trapped extension): 3 of 4 solved; in units of how far D's points
// move (the angle times D's radius), 0 of 4.
// False (and *shaped untouched) with fewer than kPassageMinNeighbors
// neighbours, when they do not spread, or when nothing of the motion is left
// along them.
bool ShapeAlongPassage(const Metric& metric, const Pose& from, const Pose& to, const std::vector<Pose>& neighbors,
                       Pose* shaped);

}  // namespace ausbau
