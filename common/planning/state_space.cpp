#include "planning/state_space.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <sstream>

#include "core/cancel.h"
#include "core/error.h"
#include "core/log.h"
#include "geometry/placed_box.h"
#include "planning/scene_goal.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

std::string Format(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out.precision(10);
  out << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return out.str();
}

}  // namespace

Pose PlanningProblem::SceneToPlanning(const Pose& scene_pose) const {
  // R (x - o) + t = R (x - r) + R (r - o) + t
  Pose out = scene_pose;
  out.t = scene_pose.t + scene_pose.q * (reference_point - dynamic_origin);
  return out;
}

Pose PlanningProblem::PlanningToScene(const Pose& planning_pose) const {
  Pose out = planning_pose;
  out.t = planning_pose.t - planning_pose.q * (reference_point - dynamic_origin);
  return out;
}

bool PlanningProblem::InBounds(const Pose& pose) const { return bounds.Contains(pose.Apply(bounded_point)); }

Aabb PlanningProblem::RobotBoxAt(const Pose& pose) const { return PlacedBox(robot_local_box, pose); }

namespace {

// Pose i of a motion from a to b walked in `steps` equal steps (b itself
// exactly at the end).
Pose PoseAtStep(const Pose& a, const Pose& b, std::int64_t i, std::int64_t steps) {
  return i == steps ? b : Interpolate(a, b, static_cast<double>(i) / static_cast<double>(steps));
}

// A pose near the path `guide`: a uniform pose of a uniformly chosen
// segment, moved in a uniform direction by a distance log-uniform in
// [diagonal / 1000, diagonal] (no scale to tune: every passage width in that
// range gets its share of samples) and turned about a uniform axis by up to
// that distance over `radius`.
Pose SampleNearGuide(const std::vector<Pose>& guide, double diagonal, double radius, Random& random) {
  const std::size_t i = guide.size() > 1 ? random.Index(guide.size() - 1) : 0;
  Pose pose = Interpolate(guide[i], guide[std::min(i + 1, guide.size() - 1)], random.Uniform01());
  const double distance = diagonal * std::pow(10.0, -3.0 * random.Uniform01());
  Eigen::Vector3d direction(random.Normal(), random.Normal(), random.Normal());
  if (direction.norm() < 1e-12) direction = Eigen::Vector3d::UnitX();
  pose.t += direction.normalized() * distance;
  Eigen::Vector3d axis(random.Normal(), random.Normal(), random.Normal());
  if (axis.norm() < 1e-12) axis = Eigen::Vector3d::UnitZ();
  const double angle = random.Uniform01() * distance / std::max(radius, 1e-12);
  pose.q = (pose.q * Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()))).normalized();
  return pose;
}

}  // namespace

Pose PlanningProblem::SampleUniform(Random& random) const {
  if (!sampling_guide.empty() && random.Index(2) == 0) {
    Pose pose = SampleNearGuide(sampling_guide, robot_diagonal, robot_radius, random);
    if (fixed_rotation) pose.q = *fixed_rotation;
    return pose;
  }
  Pose pose;
  pose.q = random.UniformQuaternion();
  if (fixed_rotation) pose.q = *fixed_rotation;  // the same draws either way
  Eigen::Vector3d bounded;
  for (int i = 0; i < 3; ++i) bounded[i] = random.Uniform(bounds.min[i], bounds.max[i]);
  pose.t = bounded - pose.q * bounded_point;  // places bounded_point at `bounded`
  return pose;
}

namespace {

// A part whose triangles all have zero area is invisible to the collision
// checks: planning with it would answer for nothing.
void CheckHasArea(const TriangleMesh& mesh, const std::filesystem::path& file, const char* what) {
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    if ((mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a).norm() > 0) return;
  }
  throw InputErrorAt(file.string(), std::string(what) + " has no triangle of positive area");
}

}  // namespace

namespace {

// Applies a crop (planning/reach_crop.h) when D's bounding ball fits in its
// box at the start; otherwise the problem stays uncropped.
void ApplyCrop(std::optional<ReachCrop> crop, PlanningProblem* problem) {
  if (!crop) return;
  Aabb bounds = crop->box;
  bounds.min.array() += problem->robot_radius;
  bounds.max.array() -= problem->robot_radius;
  if (bounds.Empty() || !bounds.Contains(problem->start.t)) return;
  auto shared = std::make_shared<const ReachCrop>(std::move(*crop));
  problem->environment = shared->environment;
  problem->environment_box = problem->environment.Bounds();
  problem->bounds = bounds;
  problem->bounded_point.setZero();
  problem->crop = shared;
  const Aabb local = problem->robot_local_box;
  problem->goal_test = [shared, local](const Pose& pose) { return shared->InGoal(PlacedBox(local, pose)); };
}

}  // namespace

PlanningProblem MakePlanningProblem(const Scene& scene, int crop_level) {
  CheckHasArea(scene.dynamic_mesh, scene.dynamic_file, "the part D");
  PlanningProblem problem;
  const Aabb mesh_box = scene.dynamic_mesh.Bounds();
  problem.dynamic_origin = scene.dynamic_origin;
  problem.reference_point = scene.dynamic_origin_given ? scene.dynamic_origin : mesh_box.Center();

  problem.robot = scene.dynamic_mesh;
  for (auto& v : problem.robot.vertices) v -= problem.reference_point;
  problem.environment = scene.static_mesh;
  problem.robot_local_box = problem.robot.Bounds();
  problem.robot_diagonal = mesh_box.Diagonal();
  for (const auto& v : problem.robot.vertices) problem.robot_radius = std::max(problem.robot_radius, v.norm());
  problem.environment_box = problem.environment.Bounds();

  problem.start = problem.SceneToPlanning(scene.start);
  if (scene.goal) problem.goal = problem.SceneToPlanning(*scene.goal);
  if (scene.goal_condition) {
    problem.goal_test = ConditionGoalTest(scene, problem.robot, problem.reference_point - problem.dynamic_origin);
    problem.goal_region = scene.goal_condition->region;
  }

  const std::string where = scene.file.string();
  if (!scene.bounds && !scene.goal) ApplyCrop(ChooseReachCrop(scene, crop_level), &problem);
  if (scene.bounds) {
    problem.bounds = *scene.bounds;
    problem.bounds_given = true;
    problem.bounded_point = problem.dynamic_origin - problem.reference_point;
    if (!problem.bounds.Contains(scene.start.t)) {
      throw InputErrorAt(where, "start position " + Format(scene.start.t) + " lies outside bounds " +
                                    Format(problem.bounds.min) + " .. " + Format(problem.bounds.max));
    }
    if (scene.goal && !problem.bounds.Contains(scene.goal->t)) {
      throw InputErrorAt(where, "goal position " + Format(scene.goal->t) + " lies outside bounds " +
                                    Format(problem.bounds.min) + " .. " + Format(problem.bounds.max));
    }
  } else if (problem.crop) {
    LogInfo("S cropped to D's reach (level %d): %lld of %lld triangles, box %s .. %s, goal clearance %.4g",
            problem.crop->level, static_cast<long long>(problem.crop->kept_triangles),
            static_cast<long long>(problem.crop->full_triangles), Format(problem.crop->box.min).c_str(),
            Format(problem.crop->box.max).c_str(), problem.crop->clearance);
  } else {
    Aabb box = problem.environment_box;
    box.Extend(problem.start.t);
    if (problem.goal) box.Extend(problem.goal->t);
    const double margin = 1.5 * problem.robot_diagonal + (scene.goal_condition ? scene.goal_condition->clearance : 0.0);
    box.min.array() -= margin;
    box.max.array() += margin;
    problem.bounds = box;
    problem.bounded_point.setZero();
  }
  if (problem.goal_region && ((problem.goal_region->max.array() < problem.bounds.min.array()).any() ||
                              (problem.goal_region->min.array() > problem.bounds.max.array()).any())) {
    throw InputErrorAt(where, "goal.region " + Format(problem.goal_region->min) + " .. " +
                                  Format(problem.goal_region->max) + " lies outside the bounds " +
                                  Format(problem.bounds.min) + " .. " + Format(problem.bounds.max));
  }
  problem.metric.nu = problem.bounds.Diagonal();
  if (!(problem.metric.nu > 0) || !std::isfinite(problem.metric.nu)) {
    throw InputErrorAt(where, "translation bounds are degenerate (zero or infinite extent)");
  }
  if (!(problem.robot_diagonal > 0)) throw InputErrorAt(where, "the dynamic part D has zero extent");
  return problem;
}

PlanningProblem MakePlanningProblemHolding(const Scene& scene, const std::vector<Pose>& scene_waypoints) {
  for (int level = 0;; ++level) {
    PlanningProblem problem = MakePlanningProblem(scene, level);
    if (!problem.crop) return problem;
    const bool holds = std::all_of(scene_waypoints.begin(), scene_waypoints.end(),
                                   [&](const Pose& pose) { return problem.InBounds(problem.SceneToPlanning(pose)); });
    if (holds) return problem;
  }
}

bool SampleGoalRegion(const PlanningProblem& problem, Random& random, Pose* pose) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    Pose candidate = problem.SampleUniform(random);
    if (problem.goal_region) {
      // dynamic_origin uniformly in the region (scene convention t), the rotation as drawn.
      Eigen::Vector3d origin;
      for (int i = 0; i < 3; ++i) origin[i] = random.Uniform(problem.goal_region->min[i], problem.goal_region->max[i]);
      candidate.t = origin + candidate.q * (problem.reference_point - problem.dynamic_origin);
    }
    if (problem.InGoalRegion(candidate) && problem.InBounds(candidate)) {
      *pose = candidate;
      return true;
    }
  }
  return false;
}

MotionChecker::MotionChecker(const PlanningProblem& problem, const PoseValidity& validity, double step,
                             std::chrono::steady_clock::time_point deadline)
    : problem_(&problem),
      validity_(&validity),
      slack_(dynamic_cast<const SlackValidity*>(&validity)),
      step_(step),
      deadline_(deadline) {}

double MotionChecker::Advance(const Pose& a, const Pose& b, Pose* last_valid, double a_slack) const {
  // Conservative advancement: from a pose with slack d, any motion in which
  // no point of D moves farther than d stays valid; the straight motion
  // moves a point at most MaxDisplacement per unit of s (slerp turns at a
  // constant rate about one axis), so the next pose to check is d further.
  const double per_unit = MaxDisplacement(a, b, problem_->robot_radius);
  // A translation is proved in stretches where the validity bounds a swept
  // motion (SlackValidity::ProveTranslation): a part sliding along a fit or
  // a contact has a slack near zero all the way. Only once the walk has
  // taken kStepsBeforeSweeping steps (most motions a planner or the
  // smoother tries are blocked within a few; a sweep would only add to
  // their cost) and only where the stretch's end is valid. The first
  // stretch is the rest of the motion; one proved doubles the next, one
  // not proved halves it, and where it is no longer than the slack's step
  // the walk goes on pose by pose (StretchLength). Both ends of a stretch in
  // bounds keep it in (the bounds are a box).
  const bool sweeps = slack_->ProvesTranslations() && per_unit > 0 && a.q.coeffs() == b.q.coeffs();
  StretchLength stretch(1.0);
  int walked = 0;
  bool proved = false;                    // `pose` ends a proved stretch (valid; its slack not measured)
  double s = 0, valid = -1.0, slack = 0;  // valid: the last valid pose's s
  Pose pose = a;
  for (bool pose_is_a = true;; pose_is_a = false) {
    if (!proved) {
      if (pose_is_a && !std::isnan(a_slack)) {
        slack = a_slack;  // measured by the caller (StartSlack)
      } else {
        Count();
        slack = problem_->InBounds(pose) ? slack_->MeasureSlack(pose) : -1.0;
      }
      if (slack < 0) return valid;
    }
    valid = s;
    if (last_valid) *last_valid = pose;
    if (s >= 1.0) return 1.0;
    if (deadline_ != std::chrono::steady_clock::time_point::max() && std::chrono::steady_clock::now() >= deadline_)
      return valid;                       // out of time: blocked here
    if (CancelRequested()) return valid;  // the caller throws (core/cancel.h)
    if (sweeps && (proved || walked >= kStepsBeforeSweeping)) {
      const double length = std::min(stretch.next(), 1.0 - s);
      const double step = proved ? 0.0 : std::max(slack, slack_->MinStep()) / per_unit;
      if (length > step) {
        const double end = length >= 1.0 - s ? 1.0 : s + length;
        Pose next = b;  // a translation: its rotation is a's all the way
        if (end < 1.0) next.t = a.t + end * (b.t - a.t);
        Count();
        if (problem_->InBounds(next) && slack_->IsValid(next) && slack_->ProveTranslation(pose, next.t - pose.t)) {
          s = end;
          pose = next;
          stretch.Proved(length);
          proved = true;
          continue;
        }
        stretch.NotProved(length);
      }
      if (proved) {  // measure the slack here, then step
        proved = false;
        continue;
      }
    }
    ++walked;
    s = std::min(1.0, s + (per_unit > 0 ? std::max(slack, slack_->MinStep()) / per_unit : 1.0));
    pose = s == 1.0 ? b : Interpolate(a, b, s);
  }
}

std::int64_t MotionChecker::Steps(const Pose& a, const Pose& b) const {
  // In 64 bits: a motion across bounds of 1e9 (goal: {clearance: 1e9}) at
  // a step of 0.1 is 1e10 steps, past an int.
  const double displacement = MaxDisplacement(a, b, problem_->robot_radius);
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(std::min(std::ceil(displacement / step_), 1e18)));
}

bool MotionChecker::OutOfTime() const {
  return (deadline_ != std::chrono::steady_clock::time_point::max() && std::chrono::steady_clock::now() >= deadline_) ||
         CancelRequested();  // the caller throws (core/cancel.h)
}

bool MotionChecker::StretchInBounds(const Pose& a, const Pose& b) const {
  // The bounded point turns with D: between two poses in bounds it may bulge
  // out of them, at most MaxChordDeviation from its chord (the same bound as
  // the sphere's centre, collision/swept_sphere.h). Both ends that
  // far inside (and a hair more, so that rounding never matters) keep all of
  // it in: the bounds are a box.
  const Aabb& bounds = problem_->bounds;
  const double bulge =
      MaxChordDeviation(a, b, problem_->bounded_point) + 1e-9 * (bounds.max - bounds.min).cwiseAbs().maxCoeff();
  const Eigen::Vector3d low = bounds.min.array() + bulge, high = bounds.max.array() - bulge;
  auto inside = [&](const Pose& pose) {
    const Eigen::Vector3d p = pose.Apply(problem_->bounded_point);
    return (p.array() >= low.array()).all() && (p.array() <= high.array()).all();
  };
  return inside(a) && inside(b);
}

bool MotionChecker::SweepWorthTrying() const {
  if (sweep_gain_.load(std::memory_order_relaxed) > 0) return true;
  return sweep_chances_.fetch_add(1, std::memory_order_relaxed) % kSweepProbe == 0;
}

void MotionChecker::RecordSweep(std::int64_t proved_steps) const {
  constexpr double kWindow = 32, kLargestGain = 64;
  const double gain = proved_steps > 0 ? std::min<double>(kLargestGain, static_cast<double>(proved_steps - 1)) : -1.0;
  const double average = sweep_gain_.load(std::memory_order_relaxed);
  sweep_gain_.store(average + (gain - average) / kWindow, std::memory_order_relaxed);
}

bool MotionChecker::MotionValid(const Pose& a, const Pose& b) const {
  if (slack_) return Advance(a, b, nullptr) >= 1.0;
  const std::int64_t steps = Steps(a, b);
  if (!IsValid(b)) return false;
  const bool sweeps = validity_->ProvesMotions();
  auto pose_at = [&](std::int64_t i) { return PoseAtStep(a, b, i, steps); };
  // Bisection order (as OMPL's discrete motion validator): a collision in
  // the middle of an edge is found after few checks. Where the validity
  // proves motions, an interval long enough is first tried as a whole, if
  // it stays in bounds (StretchInBounds).
  std::queue<std::pair<std::int64_t, std::int64_t>> intervals;
  intervals.emplace(0, steps);
  for (std::int64_t checked = 0; !intervals.empty(); ++checked) {
    // Past the deadline the motion counts as blocked, as Advance's does: a
    // huge one (bounds of 1e9) had run for hours past --time-limit.
    if (checked % 64 == 63 && OutOfTime()) return false;
    const auto [lo, hi] = intervals.front();
    intervals.pop();
    if (hi - lo < 2) continue;
    if (sweeps && hi - lo >= kShortestSweep && SweepWorthTrying()) {
      const Pose from = pose_at(lo), to = pose_at(hi);
      const bool proved =
          StretchInBounds(from, to) &&
          (validity_->ProveMotion(from, to) || (clearance_proofs_ && validity_->ProveMotionByClearance(from, to)));
      RecordSweep(proved ? hi - lo - 1 : 0);
      if (proved) continue;
    }
    const std::int64_t mid = lo + (hi - lo) / 2;
    if (!IsValid(pose_at(mid))) return false;
    intervals.emplace(lo, mid);
    intervals.emplace(mid, hi);
  }
  return true;
}

double MotionChecker::StartSlack(const Pose& a) const {
  Count();
  if (!problem_->InBounds(a)) return -1.0;
  if (slack_) return slack_->MeasureSlack(a);
  return validity_->IsValid(a) ? 0.0 : -1.0;
}

bool MotionChecker::MotionValidFrom(const Pose& a, double start_slack, const Pose& b) const {
  if (!slack_) return MotionValid(a, b);                                // the walk without slack does not check a
  const double length = MaxDisplacement(a, b, problem_->robot_radius);  // of D's farthest point
  if (length > step_ && !IsValid(Interpolate(a, b, step_ / length))) return false;  // see the header
  return Advance(a, b, nullptr, start_slack) >= 1.0;
}

double MotionChecker::ValidPrefix(const Pose& a, const Pose& b, Pose* last_valid) const {
  if (slack_) {
    Pose last = a;
    const double reached = Advance(a, b, &last);
    if (last_valid) *last_valid = last;
    return std::max(0.0, reached);
  }
  const std::int64_t steps = Steps(a, b);
  auto pose_at = [&](std::int64_t i) { return PoseAtStep(a, b, i, steps); };
  // Where the validity proves motions (PoseValidity::ProveMotion), the walk
  // tries the rest of the motion as a whole once it has taken
  // kStepsBeforeSweeping steps (most extensions are blocked within a few;
  // a sweep would only add to their cost): one proved doubles the next
  // stretch, one not proved halves it, down to kShortestSweep. The answer
  // is the same as the walk pose by pose.
  const bool sweeps = validity_->ProvesMotions();
  std::int64_t stretch = steps, walked = 0, valid = 0;
  Pose last = a;
  for (std::int64_t round = 1; valid < steps; ++round) {
    if (round % 64 == 0 && OutOfTime()) break;  // blocked here, as in Advance
    if (sweeps && walked >= kStepsBeforeSweeping && stretch >= kShortestSweep && SweepWorthTrying()) {
      const std::int64_t end = steps - valid <= stretch ? steps : valid + stretch;
      const Pose end_pose = pose_at(end);
      const bool proved = StretchInBounds(last, end_pose) && validity_->ProveMotion(last, end_pose);
      RecordSweep(proved ? end - valid : 0);
      if (proved) {
        valid = end;
        last = end_pose;
        stretch = stretch > steps / 2 ? steps : 2 * stretch;
        continue;
      }
      stretch /= 2;
    }
    const Pose pose = pose_at(valid + 1);
    if (!IsValid(pose)) break;
    ++valid;
    ++walked;
    last = pose;
  }
  if (last_valid) *last_valid = last;
  return static_cast<double>(valid) / static_cast<double>(steps);
}

}  // namespace ausbau
