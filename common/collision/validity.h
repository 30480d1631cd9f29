// What a planner asks of a validity check: is D at this pose acceptable?
// Implementations: FCL collision (collision/fcl_checker.h); later FARR and
// intersection-volume checks plug in here.
#pragma once

#include <atomic>
#include <cstdint>

#include "geometry/pose.h"

namespace ausbau {

class PoseValidity {
 public:
  virtual ~PoseValidity() = default;
  // Pose in the planning convention (about D's reference point). Must be
  // safe to call from several threads at once.
  virtual bool IsValid(const Pose& pose) const = 0;
  std::int64_t checks() const { return checks_.load(std::memory_order_relaxed); }

 protected:
  void CountCheck() const { checks_.fetch_add(1, std::memory_order_relaxed); }

 private:
  mutable std::atomic<std::int64_t> checks_{0};
};

}  // namespace ausbau
