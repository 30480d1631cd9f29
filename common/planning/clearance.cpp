#include "planning/clearance.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>

#include "collision/rigid_depth.h"
#include "scene/units.h"

namespace ausbau {

double ClearanceInSceneUnits(double clearance, const std::string& units) {
  return MillimetresInSceneUnits(clearance >= 0 ? clearance : kDefaultClearanceMm, units);
}

double ClearanceStep(const PlanningProblem& problem, double clearance) {
  return std::clamp(clearance, 0.001 * problem.robot_diagonal, 0.01 * problem.robot_diagonal);
}

TriangleMesh ClearanceRobot(const PlanningProblem& problem, const PartModel* parts) {
  if (parts == nullptr || parts->FastenerCount() == 0) return problem.robot;
  TriangleMesh rigid;
  for (std::size_t s = 0; s < parts->robot_shells.size(); ++s) {
    if (parts->role[s] != ShellRole::kRigid) continue;
    const Shell& shell = parts->robot_shells[s];
    const DepthMask* mask = parts->Mask(static_cast<int>(s));  // its moulded fasteners' triangles left out
    const int offset = static_cast<int>(rigid.vertices.size());
    rigid.vertices.insert(rigid.vertices.end(), shell.vertices.begin(), shell.vertices.end());
    for (std::size_t k = 0; k < shell.triangles.size(); ++k) {
      if (mask && mask->skip_triangle[k]) continue;
      const auto& t = shell.triangles[k];
      rigid.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    }
  }
  // The anchor is always rigid, so this holds a shell unless D has none.
  return rigid.triangles.empty() ? problem.robot : rigid;
}

ClearanceMeter::ClearanceMeter(const PlanningProblem& problem, const TriangleMesh& robot)
    : problem_(&problem), fcl_(robot, problem.environment) {}

ClearanceSample ClearanceMeter::At(const Pose& pose, bool with_points) const {
  ClearanceSample sample;
  sample.segment = 0;
  if (!with_points) {
    sample.clearance = fcl_.Distance(pose);  // 0 in contact, as ClosestPoints
    return sample;
  }
  const FclCollisionChecker::Closest closest = fcl_.ClosestPoints(pose);
  sample.clearance = closest.distance;
  sample.segment = 0;
  sample.on_robot = closest.on_robot;
  sample.on_static = closest.on_environment;
  return sample;
}

void ClearanceMeter::Walk(const Pose& a, const Pose& b, double floor, double step, bool with_points,
                          const std::function<bool(const ClearanceSample&)>& visit) const {
  const double total = MaxDisplacement(a, b, problem_->robot_radius);
  double f = 0;
  for (;;) {
    ClearanceSample sample = At(f == 0 ? a : Interpolate(a, b, f), with_points);
    sample.fraction = f;
    if (!visit(sample) || f >= 1 || !(total > 0)) break;
    const double advance = std::max(step, sample.clearance - floor);
    f = std::min(1.0, f + advance / total);
  }
}

ClearanceSample ClearanceMeter::Along(const Pose& a, const Pose& b, double floor, double step, double stop_below,
                                      bool with_points) const {
  ClearanceSample best;
  Walk(a, b, floor, step, with_points, [&](const ClearanceSample& sample) {
    if (sample.clearance < best.clearance) best = sample;
    return !(sample.clearance < stop_below);
  });
  return best;
}

ClearanceSample ClearanceMeter::AlongPath(const std::vector<Pose>& path, double floor, double step, double stop_below,
                                          bool with_points) const {
  ClearanceSample best;
  if (path.size() == 1) best = At(path.front(), with_points);
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    ClearanceSample sample = Along(path[i], path[i + 1], floor, step, stop_below, with_points);
    sample.segment = static_cast<int>(i);
    if (sample.clearance < best.clearance) best = sample;
    if (best.clearance < stop_below) break;
  }
  return best;
}

ClearanceGuard::ClearanceGuard(const PlanningProblem& problem, const TriangleMesh& robot, double clearance, double step,
                               const std::vector<Pose>& input, double contact)
    : meter_(problem, robot),
      clearance_(clearance),
      step_(step),
      // A retreat's end is computed along its direction: on the line up to rounding.
      on_line_(1e-6 * problem.robot_diagonal),
      contact_(contact),
      input_(input) {}

double ClearanceGuard::floor() const {
  if (!floor_) floor_ = FloorOf(input_);
  return *floor_;
}

double ClearanceGuard::FloorOf(const std::vector<Pose>& path) const {
  if (!(clearance_ > 0) || path.empty()) return clearance_;
  bool reached = false;  // a sample at least d from S so far
  double after = std::numeric_limits<double>::infinity(), overall = after;
  const auto visit = [&](const ClearanceSample& sample) {
    overall = std::min(overall, sample.clearance);
    if (reached) after = std::min(after, sample.clearance);
    if (sample.clearance >= clearance_) reached = true;
    return true;
  };
  if (path.size() == 1) visit(meter_.At(path.front(), false));
  for (std::size_t i = 0; i + 1 < path.size(); ++i) meter_.Walk(path[i], path[i + 1], clearance_, step_, false, visit);
  return std::min(clearance_, reached ? after : overall);
}

bool ClearanceGuard::RetracesFirstSegment(const std::vector<Pose>& replaced,
                                          const std::vector<Pose>& replacement) const {
  if (replaced.size() < 2 || replacement.size() != 2) return false;
  const Pose& a = replaced[0];
  const Pose& b = replaced[1];
  const Pose& end = replacement[1];
  if (replacement[0].t != a.t || replacement[0].q.coeffs() != a.q.coeffs()) return false;
  if (b.q.coeffs() != a.q.coeffs() || end.q.coeffs() != a.q.coeffs()) return false;  // translations only
  const Eigen::Vector3d along = b.t - a.t;
  const double length = along.norm();
  if (!(length > 0)) return false;
  const Eigen::Vector3d direction = along / length;
  const double s = (end.t - a.t).dot(direction);
  const double off_line = (end.t - a.t - s * direction).norm();
  return s >= 0 && s <= length + on_line_ && off_line <= on_line_;
}

bool ClearanceGuard::Accepts(const std::vector<Pose>& replaced, const std::vector<Pose>& replacement) const {
  if (!(clearance_ > 0)) return true;
  // The replaced part's walk starts at its first pose. Where D touches S
  // there (a path out of an installed pose in contact), the part comes
  // within 0 of S and every replacement is accepted: one query instead of
  // walking the replacement (as1's rod at a fine tessellation: 384 distance
  // queries in contact along its 192 mm pull, 21 s, for each retreat).
  // Within `contact` of S is touching too: a Voron M3 screw 0.003 mm from
  // its hole's wall at the installed pose kept its turning path (0.315 rad)
  // because the straight pull out of the hole ran 0.001 mm from the wall.
  if (!replaced.empty() && meter_.At(replaced.front(), false).clearance <= contact_) return true;
  if (RetracesFirstSegment(replaced, replacement)) return true;
  const double kNoStop = -std::numeric_limits<double>::infinity();
  const double added = meter_.AlongPath(replacement, clearance_, step_, kNoStop, false).clearance;
  if (added >= clearance_ || added >= floor()) return true;
  // Below d: accepted only when the replaced part comes at least as close
  // (its walk stops at the first sample that does).
  const double removed = meter_.AlongPath(replaced, clearance_, step_, added, false).clearance;
  return added >= std::min(clearance_, removed);
}

ClearanceSample ClearanceGuard::Closest(const std::vector<Pose>& path) const {
  return meter_.AlongPath(path, clearance_, step_, -std::numeric_limits<double>::infinity(), false);
}

double ClearanceGuard::MinCapped(const std::vector<Pose>& path) const {
  if (!(clearance_ > 0)) return 0;
  return std::min(clearance_,
                  meter_.AlongPath(path, clearance_, step_, -std::numeric_limits<double>::infinity(), false).clearance);
}

namespace {

class ClearanceValidity : public PoseValidity {
 public:
  ClearanceValidity(const PoseValidity& base, const PlanningProblem& problem, const TriangleMesh& robot, double floor)
      : base_(base), fcl_(robot, problem.environment), floor_(floor) {}

 protected:
  bool CheckValid(const Pose& pose) const override {
    return base_.IsValid(pose) && !fcl_.InCollision(pose) && fcl_.Distance(pose) >= floor_;
  }

 private:
  const PoseValidity& base_;
  FclCollisionChecker fcl_;
  double floor_;
};

class ClearanceSlackValidity : public SlackValidity {
 public:
  ClearanceSlackValidity(const SlackValidity& base, const PlanningProblem& problem, const TriangleMesh& robot,
                         double floor)
      : base_(base), fcl_(robot, problem.environment), floor_(floor) {}
  double MinStep() const override { return base_.MinStep(); }

 protected:
  double Slack(const Pose& pose) const override {
    const double slack = base_.MeasureSlack(pose);
    if (slack < 0) return slack;
    if (fcl_.InCollision(pose)) return -1.0;
    const double gap = fcl_.Distance(pose) - floor_;
    return gap < 0 ? -1.0 : std::min(slack, gap);
  }

 private:
  const SlackValidity& base_;
  FclCollisionChecker fcl_;
  double floor_;
};

}  // namespace

std::unique_ptr<PoseValidity> WithClearance(const PoseValidity& base, const PlanningProblem& problem,
                                            const TriangleMesh& robot, double floor) {
  if (const auto* slack = dynamic_cast<const SlackValidity*>(&base)) {
    return std::make_unique<ClearanceSlackValidity>(*slack, problem, robot, floor);
  }
  return std::make_unique<ClearanceValidity>(base, problem, robot, floor);
}

}  // namespace ausbau
