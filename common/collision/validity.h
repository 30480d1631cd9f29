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
  // Pose in the planning convention (about D's reference point). Safe to
  // call from several threads at once. Counts checks and invalid answers.
  bool IsValid(const Pose& pose) const {
    const bool valid = CheckValid(pose);
    checks_.fetch_add(1, std::memory_order_relaxed);
    if (!valid) invalid_.fetch_add(1, std::memory_order_relaxed);
    return valid;
  }
  std::int64_t checks() const { return checks_.load(std::memory_order_relaxed); }
  std::int64_t invalid_checks() const { return invalid_.load(std::memory_order_relaxed); }

 protected:
  // The check itself; must be thread-safe.
  virtual bool CheckValid(const Pose& pose) const = 0;

 private:
  mutable std::atomic<std::int64_t> checks_{0};
  mutable std::atomic<std::int64_t> invalid_{0};
};

}  // namespace ausbau
