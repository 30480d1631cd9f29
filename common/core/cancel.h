// Cancellation, one rule for every layer: the stage runner raises a
// process-wide flag when the user interrupts (SIGINT, SIGTERM, SIGHUP; a
// second signal ends the process at once); long work polls it and stops at
// its next safe point by throwing Cancelled, which the runner turns into
// exit 130 with "cancelled". Artifacts and text files are never committed
// once the flag is up (artifact.h, atomic_file.h), so a cancelled run leaves
// what was there before and no half answer: a planner stopped early must not
// become a "not removable".
//
// Where to poll: serial loops call ThrowIfCancelled() once per step; an
// OpenMP loop must not throw out of its region, so its body skips the rest
// of the work once CancelRequested() and the caller calls ThrowIfCancelled()
// after the region; planners stop with PlanStatus::kCancelled (tree.h) and
// their callers throw.
#pragma once

#include <stdexcept>

namespace ausbau {

class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

// Raises the flag; async-signal-safe (a lock-free atomic store).
void RequestCancel();
// Lowers it again (tests; a stage never does).
void ResetCancel();
bool CancelRequested();
// Throws Cancelled when the flag is up.
void ThrowIfCancelled();

}  // namespace ausbau
