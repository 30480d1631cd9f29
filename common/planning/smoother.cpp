#include "planning/smoother.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>

#include "core/cancel.h"
#include "core/error.h"
#include "core/log.h"
#include "core/random.h"
#include "planning/clearance.h"
#include "planning/planner.h"

namespace ausbau {

void SmoothOptions::Check() const {
  if (attempts < 0) throw OptionError(&attempts, "attempts", "must be >= 0");
  if (!(time_limit_s > 0) || !std::isfinite(time_limit_s))
    throw OptionError(&time_limit_s, "time_limit", "must be positive");
  if (!(resolution > 0 && resolution <= 0.1)) throw OptionError(&resolution, "resolution", "must lie in (0, 0.1]");
  if (!(clearance == -1 || (clearance >= 0 && std::isfinite(clearance)))) {
    throw OptionError(&clearance, "clearance", "must be a finite number >= 0 (scene units)");
  }
}

PathLength MeasurePath(const PlanningProblem& problem, const std::vector<Pose>& path) {
  PathLength length;
  for (std::size_t i = 1; i < path.size(); ++i) {
    length.translation += (path[i].t - path[i - 1].t).norm();
    length.rotation += RotationAngle(path[i - 1].q, path[i].q);
    length.normalized += problem.metric.Distance(path[i - 1], path[i], 0.5);
  }
  return length;
}

std::optional<Pose> StraightExitPose(const PlanningProblem& problem, const Pose& from, Eigen::Vector3d direction) {
  if (!(direction.norm() > 1e-12)) return std::nullopt;
  direction.normalize();
  const Aabb box = problem.RobotBoxAt(from);
  const Aabb& env = problem.environment_box;
  double needed = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    const double d = direction[axis];
    if (std::abs(d) < 1e-9) continue;
    const double gap = d > 0 ? env.max[axis] - box.min[axis] : box.max[axis] - env.min[axis];
    needed = std::min(needed, std::max(0.0, gap) / std::abs(d));
  }
  if (!std::isfinite(needed)) return std::nullopt;
  Pose end = from;
  end.t += (needed + 0.01 * problem.robot_diagonal) * direction;
  if (!problem.InBounds(end) || !problem.InGoalRegion(end)) return std::nullopt;
  return end;
}

namespace {

double SegmentCost(const PlanningProblem& problem, const std::vector<Pose>& path, std::size_t from, std::size_t to) {
  double cost = 0;
  for (std::size_t i = from; i < to; ++i) cost += problem.metric.Distance(path[i], path[i + 1], 0.5);
  return cost;
}

// Where the path is a disassembly (no goal pose), its end may move: any
// pose in the goal region will do.
bool EndIsFree(const PlanningProblem& problem) { return !problem.goal.has_value(); }

// The 26 directions of a 3x3x3 grid's neighbours: the axes, the face and
// the space diagonals (CAD parts leave along these far more often than not).
std::vector<Eigen::Vector3d> AxisDirections() {
  std::vector<Eigen::Vector3d> directions;
  for (int x = -1; x <= 1; ++x) {
    for (int y = -1; y <= 1; ++y) {
      for (int z = -1; z <= 1; ++z) {
        if (x != 0 || y != 0 || z != 0) directions.emplace_back(x, y, z);
      }
    }
  }
  return directions;
}

// Whether the straight motion from -> end may replace the path from `from`
// (on segment `segment`) to its end, as far as the guard goes.
bool KeepsGuard(const ReplacementGuard* guard, const std::vector<Pose>& path, const Pose& from, std::size_t segment,
                const Pose& end) {
  if (guard == nullptr) return true;
  std::vector<Pose> replaced = {from};
  replaced.insert(replaced.end(), path.begin() + segment + 1, path.end());
  return guard->Accepts(replaced, {from, end});
}

// Step 2: of 64 points evenly spread along the path from waypoint `first`
// on (by its metric length), the one from which one straight translation
// leaves S and makes the whole path shortest. Directions: the way to the
// current end, the path's own direction there, the axes and diagonals. A
// candidate is motion-checked only when it would beat the best so far (by
// more than rounding), so blocked directions cost little. Returns the
// segment the retreat leaves from (the path then ends with the pose it
// leaves from, unless that is the segment's start, and the retreat's end),
// or -1.
int StraightRetreat(const PlanningProblem& problem, const MotionChecker& motion, const ReplacementGuard* guard,
                    std::size_t first, std::vector<Pose>* path_in) {
  std::vector<Pose>& path = *path_in;
  if (!EndIsFree(problem) || path.size() < 2 || first + 1 >= path.size()) return -1;
  std::vector<double> cost_to(path.size(), 0.0);  // metric length from the start to waypoint i
  for (std::size_t i = 1; i < path.size(); ++i) {
    cost_to[i] = cost_to[i - 1] + problem.metric.Distance(path[i - 1], path[i], 0.5);
  }
  double best_cost = cost_to.back() * (1 - 1e-9);
  std::optional<Pose> best_from, best_end;
  std::size_t best_segment = 0;
  constexpr int kPoints = 64;
  std::size_t segment = first;
  // A retreat back along a translation segment from a point of it passes
  // through the segment's earlier points and then runs along the same ray:
  // blocked from one point, it is blocked from the later ones too, and is
  // not walked again. (A bolt pulled out of its bore, retraced into it from
  // each point, slid up to 17 mm in contact each time: 55 s on as1 at a
  // fine tessellation.) The segment where one was blocked:
  std::optional<std::size_t> blocked_back_on;
  for (int point = 0; point < kPoints; ++point) {
    // The point at this fraction of the length, on segment [segment, segment + 1].
    const double at = cost_to[first] + (cost_to.back() - cost_to[first]) * point / kPoints;
    while (segment + 2 < path.size() && cost_to[segment + 1] <= at) ++segment;
    const double span = cost_to[segment + 1] - cost_to[segment];
    const Pose from =
        span > 0 ? Interpolate(path[segment], path[segment + 1], (at - cost_to[segment]) / span) : path[segment];
    // The path's own ways first: of retreats equally short (a peg through
    // a block, out at either end), the first tried is kept, and the
    // planner's way is the one its user saw.
    std::vector<Eigen::Vector3d> directions = {path.back().t - from.t, path[segment + 1].t - path[segment].t};
    for (const Eigen::Vector3d& axis : AxisDirections()) directions.push_back(axis);
    // Whether `from` is valid, and its slack, measured once per point, not
    // once per direction (each a check; in rigid-exact a surface-depth
    // search, and in a part held in bores every sideways retreat is blocked
    // after one step: half of its cost was measuring `from` again).
    std::optional<double> from_slack;
    const auto valid_from = [&] {
      if (!from_slack) from_slack = motion.StartSlack(from);
      return *from_slack >= 0;
    };
    const Eigen::Vector3d along = path[segment + 1].t - path[segment].t;
    const bool translation = along.norm() > 0 && path[segment].q.coeffs() == path[segment + 1].q.coeffs();
    for (const Eigen::Vector3d& direction : directions) {
      const bool back = translation && direction.norm() > 0 &&
                        direction.normalized().dot(along.normalized()) < -1 + 1e-9;  // within 5e-5 rad
      if (back && blocked_back_on == segment) continue;
      const std::optional<Pose> end = StraightExitPose(problem, from, direction);
      if (!end) continue;
      // Better by more than rounding: along a straight path, every point's
      // retreat along the path costs the same, and each is a long motion.
      const double cost = at + problem.metric.Distance(from, *end, 0.5);
      if (!(cost < best_cost * (1 - 1e-9)) || !valid_from()) continue;
      if (!motion.MotionValidFrom(from, *from_slack, *end)) {
        if (back) blocked_back_on = segment;
        continue;
      }
      if (KeepsGuard(guard, path, from, segment, *end)) {
        best_from = from;
        best_end = end;
        best_cost = cost;
        best_segment = segment;
      }
    }
  }
  if (!best_end) return -1;
  path.resize(best_segment + 1);
  if (best_from->t != path.back().t || best_from->q.coeffs() != path.back().q.coeffs()) path.push_back(*best_from);
  path.push_back(*best_end);
  return static_cast<int>(best_segment);
}

// The pose `pose` with degree of freedom `dof` (0..2: x, y, z; 3: the
// rotation) taken from `from` -> `to` at fraction s.
Pose WithDof(Pose pose, const Pose& from, const Pose& to, int dof, double s) {
  if (dof < 3) {
    pose.t[dof] = from.t[dof] + s * (to.t[dof] - from.t[dof]);
  } else {
    pose.q = from.q.slerp(s, to.q).normalized();
  }
  return pose;
}

// Step 3, one attempt: between waypoints i < j, degree of freedom `dof`
// made linear in the path parameter (the metric length along the path);
// with `freeze_tail` (j is the end of a disassembly path) the rotation stays
// at waypoint i's instead. Kept when valid, still ending in the goal region,
// and shorter.
bool PartialShortcut(const PlanningProblem& problem, const MotionChecker& motion, const ReplacementGuard* guard,
                     std::vector<Pose>* path_in, std::size_t i, std::size_t j, int dof, bool freeze_tail) {
  const std::vector<Pose>& path = *path_in;
  std::vector<double> along(j - i + 1, 0.0);
  for (std::size_t m = i + 1; m <= j; ++m) {
    along[m - i] = along[m - i - 1] + problem.metric.Distance(path[m - 1], path[m], 0.5);
  }
  if (!(along.back() > 0)) return false;
  Pose target = path[j];
  if (freeze_tail) target.q = path[i].q;
  std::vector<Pose> next(path.begin() + i, path.begin() + j + 1);
  double old_cost = along.back(), new_cost = 0;
  for (std::size_t m = i + 1; m <= j; ++m) {
    next[m - i] = WithDof(path[m], path[i], target, dof, freeze_tail ? 1.0 : along[m - i] / along.back());
    new_cost += problem.metric.Distance(next[m - i - 1], next[m - i], 0.5);
  }
  if (!(new_cost < old_cost - 1e-9 * (1.0 + old_cost))) return false;
  if (freeze_tail && !problem.InGoalRegion(next.back())) return false;
  for (std::size_t m = 1; m < next.size(); ++m) {
    if (!motion.MotionValid(next[m - 1], next[m])) return false;
  }
  if (guard != nullptr && !guard->Accepts(std::vector<Pose>(path.begin() + i, path.begin() + j + 1), next)) {
    return false;
  }
  std::copy(next.begin(), next.end(), path_in->begin() + i);
  return true;
}

// Step 3's freeze: the first pose along the path (FirstFreezeThatWorks)
// from which the rest of a disassembly path can keep that pose's rotation.
// Spread by length, not by waypoint: a smoothed path is often one long
// turning segment and a retreat, whose only waypoints are the start and the
// turned end.
void FreezeTailRotation(const PlanningProblem& problem, const MotionChecker& motion, const ReplacementGuard* guard,
                        SmoothResult* result) {
  std::vector<Pose>& path = result->path;
  if (!EndIsFree(problem) || path.size() < 3) return;
  std::vector<Pose> frozen_path;
  const bool frozen = FirstFreezeThatWorks([&](double fraction) {
    std::size_t from = 0;
    std::vector<Pose> candidate = WithWaypointAt(problem, path, path.size() - 1, fraction, &from);
    // A tail that does not turn cannot be shortened by freezing its
    // rotation (PartialShortcut's cost test); asked first, because the
    // motion check below is of a stretch of the path, long where the path
    // is one straight pull (a rod pulled through bores: 16 tries of seconds).
    const bool turns = std::any_of(candidate.begin() + from + 1, candidate.end(),
                                   [&](const Pose& pose) { return pose.q.coeffs() != candidate[from].q.coeffs(); });
    if (!turns) return false;
    if (candidate.size() > path.size() && !motion.MotionValid(candidate[from - 1], candidate[from])) return false;
    if (!PartialShortcut(problem, motion, guard, &candidate, from, candidate.size() - 1, 3, true)) return false;
    frozen_path = std::move(candidate);
    return true;
  });
  if (frozen) {
    path = std::move(frozen_path);
    ++result->shortcuts;
    ++result->partial_shortcuts;
  }
}

// Step 1, one attempt: two random points on two different segments; the
// path between them replaced by the straight motion when valid and shorter.
bool FullShortcut(const PlanningProblem& problem, const MotionChecker& motion, const ReplacementGuard* guard,
                  Random& random, std::vector<Pose>* path_in) {
  std::vector<Pose>& path = *path_in;
  const std::size_t segments = path.size() - 1;
  std::size_t i = random.Index(segments), j = random.Index(segments);
  const double fa = random.Uniform01(), fb = random.Uniform01();
  if (i == j) return false;
  if (i > j) std::swap(i, j);
  const Pose a = fa == 0.0 ? path[i] : Interpolate(path[i], path[i + 1], fa);
  const Pose b = Interpolate(path[j], path[j + 1], fb);
  const double old_cost = problem.metric.Distance(a, path[i + 1], 0.5) + SegmentCost(problem, path, i + 1, j) +
                          problem.metric.Distance(path[j], b, 0.5);
  const double new_cost = problem.metric.Distance(a, b, 0.5);
  if (!(new_cost < old_cost - 1e-12)) return false;
  if (!motion.IsValid(a) || !motion.MotionValid(a, b)) return false;
  if (guard != nullptr) {
    std::vector<Pose> replaced = {a};
    replaced.insert(replaced.end(), path.begin() + i + 1, path.begin() + j + 1);
    replaced.push_back(b);
    if (!guard->Accepts(replaced, {a, b})) return false;
  }
  std::vector<Pose> next(path.begin(), path.begin() + i + 1);
  if (fa != 0.0) next.push_back(a);
  next.push_back(b);
  next.insert(next.end(), path.begin() + j + 1, path.end());
  path.swap(next);
  return true;
}

using Clock = std::chrono::steady_clock;

// Drops waypoints whose neighbours see each other directly: the kept path
// is built anew (erasing in place was quadratic in the waypoints), and
// past `deadline` the rest is kept as it is.
void DropNeedlessWaypoints(const MotionChecker& motion, const ReplacementGuard* guard, Clock::time_point deadline,
                           std::vector<Pose>* path) {
  const std::vector<Pose>& p = *path;
  if (p.size() < 3) return;
  std::vector<Pose> kept = {p.front()};
  for (std::size_t k = 1; k + 1 < p.size(); ++k) {
    // kept.back() and p[k + 1] are the neighbours of p[k] in the path as it
    // stands once the waypoints before p[k] are dropped or kept.
    const bool needless = Clock::now() < deadline && motion.MotionValid(kept.back(), p[k + 1]) &&
                          (guard == nullptr || guard->Accepts({kept.back(), p[k], p[k + 1]}, {kept.back(), p[k + 1]}));
    if (!needless) kept.push_back(p[k]);
  }
  kept.push_back(p.back());
  path->swap(kept);
}

// Steps 1-4 on one path. The work is counted (`attempts` full shortcuts, a
// quarter of them partial ones); `deadline` is only the safety net: past it
// the steps stop and the path is kept as it is (the caller marks the result
// cut short). No step gets a share of the time: a share ends work earlier
// on a slower or busier machine, and the path would depend on the load.
void SmoothOnce(const PlanningProblem& problem, const MotionChecker& motion, const ReplacementGuard* guard,
                int attempts, Random& random, Clock::time_point deadline, const ProgressCallback& progress,
                SmoothResult* result) {
  const auto out_of_time = [&] { return Clock::now() >= deadline; };
  std::vector<Pose>& path = result->path;
  const int partial_attempts = std::max(20, attempts / 4);
  // Each attempt: the progress, and the place to stop when cancelled.
  const auto next_attempt = [&] {
    ThrowIfCancelled();
    if (progress) progress(result->attempts, attempts + partial_attempts);
    ++result->attempts;
  };
  for (int attempt = 0; attempt < attempts && path.size() >= 3 && !out_of_time(); ++attempt) {
    next_attempt();
    if (FullShortcut(problem, motion, guard, random, &path)) ++result->shortcuts;
  }
  DropNeedlessWaypoints(motion, guard, deadline, &path);
  if (!out_of_time()) result->retreat_from = StraightRetreat(problem, motion, guard, 0, &path);

  // Partial shortcuts: a quarter of the attempts, each on one degree of
  // freedom, between two freezes of a disassembly's tail rotation (the
  // second after the others have straightened the course).
  FreezeTailRotation(problem, motion, guard, result);
  for (int attempt = 0; attempt < partial_attempts && path.size() >= 3 && !out_of_time(); ++attempt) {
    next_attempt();
    std::size_t i = random.Index(path.size() - 1), j = random.Index(path.size());
    if (i > j) std::swap(i, j);
    if (j < i + 2) continue;
    if (PartialShortcut(problem, motion, guard, &path, i, j, static_cast<int>(random.Index(4)), false)) {
      ++result->shortcuts;
      ++result->partial_shortcuts;
    }
  }
  if (!out_of_time()) FreezeTailRotation(problem, motion, guard, result);
  DropNeedlessWaypoints(motion, guard, deadline, &path);
  if (progress) progress(attempts + partial_attempts, attempts + partial_attempts);
}

// The summed turn (radians) of a smoothed path above which step 5 plans a
// translation-only alternative: the allowance of issue 29's path-quality
// bound (a path turns at most 0.1 rad more than the scene's known path;
// scripts/path-quality-bench.sh), about 6 degrees in all. Measured (seeds
// 1-10 of panel-channel, 1-5 of panel-zchannel: every one of their
// alternatives that found a path left a turning path of 0.11-0.64 rad;
// the external clip panels, where none finds one, 0.03-0.20 rad).
constexpr double kTurnWorthAnAlternative = 0.1;

// Step 5 (disassembly): most CAD parts come out without turning, but a
// path planned with rotation seldom loses it by local changes (its course
// was found with the part turned). So a translation-only path is planned
// too (RRT-Connect with D's start orientation fixed, a bounded number of
// iterations, so that the answer does not depend on the machine), smoothed
// the same way, and kept when it is shorter. Half of its samples lie near
// the turning path's course (`sampling_guide`): in a narrow channel,
// uniform samples in the bounds almost never fall inside it.
std::optional<SmoothResult> TranslationOnly(const PlanningProblem& problem, const PoseValidity& validity,
                                            const MotionChecker& motion, const SmoothOptions& options, int attempts,
                                            const std::vector<Pose>& turning, Clock::time_point deadline) {
  PlanningProblem fixed = problem;
  fixed.fixed_rotation = problem.start.q;
  fixed.sampling_guide = turning;
  PlannerOptions planner;
  planner.planner = "rrtc";
  planner.seed = options.seed;
  planner.max_iterations = 20000;
  // The smoothing's own safety net, what is left of it (no share of it: the
  // iterations are the budget).
  planner.time_limit_s = std::max(0.01, std::chrono::duration<double>(deadline - Clock::now()).count());
  planner.resolution = options.resolution;
  planner.progress = options.progress;
  PlanResult planned;
  try {
    planned = Plan(fixed, validity, planner);
  } catch (const InputError&) {
    return std::nullopt;  // e.g. a start the planner does not take: no alternative then
  }
  ThrowIfCancelled();
  if (!planned.solved() || Clock::now() >= deadline) {
    LogInfo("translation-only alternative: %s after %lld iterations", planned.solved() ? "out of time" : "no path",
            static_cast<long long>(planned.stats.iterations));
    return std::nullopt;
  }
  LogInfo("translation-only alternative: a path after %lld iterations",
          static_cast<long long>(planned.stats.iterations));
  SmoothResult result;
  result.path = planned.path;
  Random random(options.seed + 1);
  // Smoothed without the guard: the whole alternative is held to the input's
  // clearance instead (SmoothPath), or a guard that a sliding contact trips
  // at every shortcut would keep its detours.
  SmoothOnce(problem, motion, nullptr, attempts, random, deadline, options.progress, &result);
  return result;
}

}  // namespace

std::vector<Pose> WithWaypointAt(const PlanningProblem& problem, const std::vector<Pose>& path, std::size_t last,
                                 double fraction, std::size_t* index) {
  std::vector<double> along(last + 1, 0.0);
  for (std::size_t m = 1; m <= last; ++m) along[m] = along[m - 1] + problem.metric.Distance(path[m - 1], path[m], 0.5);
  const double at = std::clamp(fraction, 0.0, 1.0) * along[last];
  std::size_t segment = 0;
  while (segment + 1 < last && along[segment + 1] <= at) ++segment;
  const double length = last > 0 ? along[segment + 1] - along[segment] : 0.0;
  const double s = length > 0 ? (at - along[segment]) / length : 0.0;
  std::vector<Pose> out(path.begin(), path.begin() + segment + 1);
  if (s > 1e-9 && s < 1.0 - 1e-9) out.push_back(Interpolate(path[segment], path[segment + 1], s));
  if (s >= 1.0 - 1e-9) out.push_back(path[segment + 1]);
  *index = out.size() - 1;
  out.insert(out.end(), path.begin() + static_cast<std::ptrdiff_t>(s >= 1.0 - 1e-9 ? segment + 2 : segment + 1),
             path.end());
  return out;
}

bool FirstFreezeThatWorks(const std::function<bool(double fraction)>& try_at) {
  constexpr int kTries = 16, kFiner = 8;
  for (int n = 0; n < kTries; ++n) {
    if (!try_at(static_cast<double>(n) / kTries)) continue;
    // Between the failure at n - 1 and n, nearest the former first.
    for (int k = 1; n > 0 && k < kFiner; ++k) {
      if (try_at((n - 1 + static_cast<double>(k) / kFiner) / kTries)) break;
    }
    return true;
  }
  return false;
}

bool StraightenRotation(const PlanningProblem& problem, const PoseValidity& validity, const SmoothOptions& options,
                        const ReplacementGuard* guard, std::size_t first, std::size_t last, std::vector<Pose>* path) {
  options.Check();
  if (last >= path->size() || last < first + 2) return false;
  const MotionChecker motion(problem, validity, options.resolution * problem.robot_diagonal / 4.0);
  // Longest sections first; at most 200 tries (a smoothed sigma_1 has some
  // ten waypoints: about 50 sections).
  bool changed = false;
  int tries = 0;
  for (std::size_t span = last - first; span >= 2 && tries < 200; --span) {
    for (std::size_t i = first; i + span <= last && tries < 200; ++i, ++tries) {
      changed |= PartialShortcut(problem, motion, guard, path, i, i + span, 3, false);
    }
  }
  return changed;
}

int StraightRetreatFrom(const PlanningProblem& problem, const PoseValidity& validity, const SmoothOptions& options,
                        const ReplacementGuard* guard, std::size_t first, std::vector<Pose>* path) {
  options.Check();
  const MotionChecker motion(problem, validity, options.resolution * problem.robot_diagonal / 4.0);
  if (StraightRetreat(problem, motion, guard, first, path) < 0) return -1;
  return static_cast<int>(path->size()) - 2;
}

SmoothResult SmoothPath(const PlanningProblem& problem, const PoseValidity& validity, const std::vector<Pose>& input,
                        const SmoothOptions& options, const ReplacementGuard* guard) {
  options.Check();
  const Clock::time_point start = Clock::now();
  // (At most 30 years: a longer limit would overflow the clock's count.)
  const Clock::time_point deadline = start + std::chrono::duration_cast<Clock::duration>(
                                                 std::chrono::duration<double>(std::min(options.time_limit_s, 1e9)));
  // Shortcuts are few: check them at the certification step (planner step / 4,
  // planning/certify.h) so that smoothing never trades certainty for length.
  // Past the deadline a motion counts as blocked (the path is kept as it
  // is): a shortcut of billions of steps (a D of 1e-6 mm) had run far past
  // --time-limit.
  const MotionChecker motion(problem, validity, options.resolution * problem.robot_diagonal / 4.0, deadline);
  SmoothResult result;
  result.path = input;
  result.before = MeasurePath(problem, input);
  Random random(options.seed);
  const int attempts =
      options.attempts > 0 ? options.attempts : std::min<int>(2000, 100 + 10 * static_cast<int>(input.size()));
  SmoothOnce(problem, motion, guard, attempts, random, deadline, options.progress, &result);
  LogInfo("shortcuts: %d kept of %d attempts, %lld poses checked", result.shortcuts, result.attempts,
          static_cast<long long>(motion.checks()));
  result.after = MeasurePath(problem, result.path);
  // Step 5 only where the turning left is more than the tolerance a path is
  // held to (kTurnWorthAnAlternative): it removes no more than that, and
  // where D cannot come out without turning, its RRT-Connect spends all
  // 20,000 iterations (external clip panels: 20-24 s of a 25 s pipeline,
  // docs/benchmarks.md).
  const bool turns = result.after.rotation > kTurnWorthAnAlternative;
  if (EndIsFree(problem) && !turns && result.after.rotation > 1e-9) {
    LogInfo("translation-only alternative: not tried (the path turns D %.3g rad in all, within %.3g)",
            result.after.rotation, kTurnWorthAnAlternative);
  }
  if (EndIsFree(problem) && turns && Clock::now() < deadline) {
    LogInfo("translation-only alternative: tried (the path turns D %.3g rad in all)", result.after.rotation);
    const std::optional<SmoothResult> straight =
        TranslationOnly(problem, validity, motion, options, attempts, result.path, deadline);
    // With a clearance guard, the alternative (planned without it) must
    // also come no closer to S below d than the input path: smoothing as a
    // whole never makes the clearance worse below d (compared with the
    // smoothed path instead, an alternative without needless turning would
    // lose to any that the turning path's shortcuts happened to widen).
    if (straight) {
      LogInfo("translation-only alternative: length %.4f against %.4f (normalized)",
              MeasurePath(problem, straight->path).normalized, result.after.normalized);
    }
    if (straight && MeasurePath(problem, straight->path).normalized < result.after.normalized &&
        (guard == nullptr || guard->Accepts(input, straight->path))) {
      result.path = straight->path;
      result.after = MeasurePath(problem, result.path);
      result.shortcuts += straight->shortcuts;
      result.partial_shortcuts += straight->partial_shortcuts;
      result.retreat_from = straight->retreat_from;
      result.translation_only = true;
    }
  }
  // Every clock check above is "now >= deadline" against this one deadline,
  // so a check that fired implies this (which may, rarely, also mark a run
  // that finished its work just as the limit passed: cut short, never the
  // other way round).
  result.cut_short = Clock::now() >= deadline;
  if (result.cut_short) {
    LogWarn(
        "smoothing was cut short by its time limit of %.1f s (a safety net): the path is valid but not the "
        "deterministic one (a slower or busier machine)",
        options.time_limit_s);
  }
  return result;
}

}  // namespace ausbau
