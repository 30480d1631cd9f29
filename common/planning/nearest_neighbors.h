// Exact nearest neighbour under the thesis metric d'_c with a weight u that
// may change from query to query (CR-RRTC draws a new u per extension).
//
// A linear scan over a flat array, pruned by the translation term: d'_c >=
// u d'_t, so a node whose weighted translation alone exceeds the best distance
// so far is skipped before the (costly) acos of the rotation term.
#pragma once

#include <limits>
#include <vector>

#include "planning/state_space.h"

namespace ausbau {

class NearestNeighbors {
 public:
  explicit NearestNeighbors(const Metric& metric) : metric_(metric) {}

  void Add(const Pose& pose) {
    data_.insert(data_.end(), {pose.t.x(), pose.t.y(), pose.t.z(), pose.q.w(), pose.q.x(), pose.q.y(), pose.q.z()});
  }
  std::size_t size() const { return data_.size() / 7; }

  // Index of the nearest stored pose (-1 when empty). Ties go to the lower index.
  int Nearest(const Pose& query, double u) const {
    const double wt = u / metric_.nu, wq = (1.0 - u) / M_PI;
    double best = std::numeric_limits<double>::infinity();
    int best_index = -1;
    const double* d = data_.data();
    const std::size_t n = size();
    for (std::size_t i = 0; i < n; ++i, d += 7) {
      const double dx = d[0] - query.t.x(), dy = d[1] - query.t.y(), dz = d[2] - query.t.z();
      const double squared = dx * dx + dy * dy + dz * dz;
      const double translation = wt * std::sqrt(squared);
      if (translation >= best) continue;
      const double dot = std::min(
          1.0, std::abs(d[3] * query.q.w() + d[4] * query.q.x() + d[5] * query.q.y() + d[6] * query.q.z()));
      const double distance = translation + wq * std::acos(dot);
      if (distance < best) {
        best = distance;
        best_index = static_cast<int>(i);
      }
    }
    return best_index;
  }

 private:
  Metric metric_;
  std::vector<double> data_;  // tx ty tz qw qx qy qz per node
};

}  // namespace ausbau
