// Vertex welding: one index per group of vertices at the same position (or
// within a tolerance), so that triangles written with their own corners (STL,
// seams of CAD exports) share vertices.
//
// One implementation for the distance field, the FARR checker, the
// voxelizer's topology, the volume model's parts (exact positions), the
// labeling topology and the shell split (a tolerance).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace ausbau {

// Input vertex -> welded index; welded indices count 0, 1, ... in the order
// of their first vertex in the input. Vertices weld only where all three
// coordinates compare equal (-0 and +0 are equal; NaN equals nothing).
std::vector<int> WeldExactPositions(const std::vector<Eigen::Vector3d>& vertices);

// How the distance between two vertices is measured for welding.
enum class WeldDistance {
  kEuclidean,          // |p - q| <= tolerance (the labeling topology)
  kLargestCoordinate,  // max over k of |p[k] - q[k]| <= tolerance (the shell split)
};

// Vertices within `tolerance` of a representative become that one: the
// first vertex of a group in input order is its representative and keeps its
// position; a vertex joins the first representative within the tolerance
// found in a grid of cubic cells (`cell_size`, at least the tolerance, cells
// counted from `grid_origin`), scanning the 27 cells about its own in x, y, z
// order (-1, 0, +1 each, z fastest) and each cell in input order. Which
// representative is found first depends on the grid where a vertex lies
// within the tolerance of two; the grid is therefore the caller's to give.
// Returns input vertex -> welded index (0, 1, ... in order of the
// representatives), and the representatives' positions in `welded`.
std::vector<int> WeldWithinTolerance(const std::vector<Eigen::Vector3d>& vertices, double tolerance,
                                     WeldDistance distance, const Eigen::Vector3d& grid_origin, double cell_size,
                                     std::vector<Eigen::Vector3d>* welded);

}  // namespace ausbau
