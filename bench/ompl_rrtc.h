// OMPL's RRT-Connect on an Ausbau planning problem, for the side-by-side
// benchmark (ausbau-bench). Only ompl_rrtc.cpp includes OMPL's headers.
//
// The OMPL problem is the OMPL.app one: SE(3) with translation bounds on the
// reference point, validity = InBounds && the SAME collision checker object
// our planners use (so a collision check costs the same on both sides).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "collision/validity.h"
#include "planning/state_space.h"

namespace ausbau::bench {

// Seeds OMPL's global RNG and silences its console (warnings and errors
// still print). Call once, before any OMPL object exists.
void InitOmpl(std::uint32_t seed);
// "1.5.2" (Debian's OMPL_VERSION macro is empty; built from the parts).
std::string OmplVersion();
// The "status|..." enum line of OMPL's benchmark log (PlannerStatus names).
std::string OmplStatusEnumLine();
int OmplStatusExactSolution();
int OmplStatusTimeout();

// How the OMPL edge check resolution (longest valid segment fraction) is
// chosen. Our planners check edges so that no vertex of D moves more than
// `step` between checked poses.
//   kMatched:  the same guarantee with as few checks as one fraction allows.
//              OMPL's SE3 space is a compound space whose validSegmentCount
//              is the MAX of its components' counts, each component using
//              fraction x its own extent (R3: bounds diagonal; SO3: pi/2 in
//              half-angle units). Per segment a vertex at distance r moves at
//              most f*diag + r*(f*pi) = f*(diag + pi*r), so f = step/(diag + pi*r).
//   kExtent:   step / (max(1, 2r) * maximum extent): the bound derived as if
//              OMPL measured segments by the summed SE3 distance; correct but
//              up to ~2r times finer in translation than needed.
//   kOmplApp:  0.01, OMPL's (and OMPL.app's) default.
//   kExact:    OMPL's motion validator replaced by one that steps exactly
//              like Ausbau's (ceil((|dt| + r*angle) / step) sub-steps), so
//              both sides check the same poses per edge.
enum class OmplResolution { kMatched, kExtent, kOmplApp, kExact };
OmplResolution ParseOmplResolution(const std::string& text);  // throws InputError
std::string OmplResolutionName(OmplResolution mode);

struct OmplRun {
  bool solved = false;  // exact solution only
  int status = 0;       // ompl::base::PlannerStatus::StatusType
  double time_s = 0;    // wall clock around solve()
  std::int64_t collision_checks = 0;
  std::int64_t nodes = 0;  // planner data vertices (both trees)
  std::vector<Pose> path;  // planning convention; empty unless solved
};

class OmplRrtConnect {
 public:
  // `problem` and `validity` must outlive this object. The problem must have
  // a goal pose.
  OmplRrtConnect(const PlanningProblem& problem, const PoseValidity& validity, double step, OmplResolution mode);
  ~OmplRrtConnect();
  OmplRrtConnect(const OmplRrtConnect&) = delete;
  OmplRrtConnect& operator=(const OmplRrtConnect&) = delete;

  double MaximumExtent() const;    // SE3: bounds diagonal + pi/2
  double SegmentFraction() const;  // the longest valid segment fraction used
  double DefaultRange() const;     // what RRTConnect picks without setRange: 0.2 x extent
  // Number of checked segments OMPL uses for the motion a -> b (for tests of
  // the resolution argument above).
  unsigned int SegmentCount(const Pose& a, const Pose& b) const;

  // One run. range <= 0: OMPL's default (no setRange). Each distinct range
  // gets its own SimpleSetup, reused (cleared) between runs.
  OmplRun Solve(double range, double time_limit_s);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ausbau::bench
