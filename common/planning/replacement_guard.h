// A condition a smoother puts on its changes beyond the validity of their
// motions: a change replacing part of a path (shortcut, retreat, dropped
// waypoint) is kept only when the guard accepts the replacement in
// comparison with what it replaces. Two guards exist: keeping a clearance
// (planning/clearance.h) and never deepening an intersection on sigma_1
// (inistate/volume_smoother.h), so the one smoother serves both.
#pragma once

#include <vector>

#include "planning/state_space.h"

namespace ausbau {

class ReplacementGuard {
 public:
  virtual ~ReplacementGuard() = default;
  // Whether `replacement` (poses joined by straight motions, planning
  // convention) may take the place of `replaced`; both start at the same pose.
  virtual bool Accepts(const std::vector<Pose>& replaced, const std::vector<Pose>& replacement) const = 0;
};

}  // namespace ausbau
