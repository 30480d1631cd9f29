#include "ompl_rrtc.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include <ompl/base/MotionValidator.h>
#include <ompl/base/PlannerData.h>
#include <ompl/base/PlannerStatus.h>
#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/spaces/SE3StateSpace.h>
#include <ompl/config.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include "core/error.h"

namespace ausbau::bench {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;

// SE3 state -> Ausbau pose in the planning convention: t = (x, y, z) of the
// reference point, q = (w, x, y, z) of the SO3 substate.
Pose ToPose(const ob::State* state) {
  const auto* se3 = state->as<ob::SE3StateSpace::StateType>();
  const auto& r = se3->rotation();
  Pose pose;
  pose.t = Eigen::Vector3d(se3->getX(), se3->getY(), se3->getZ());
  pose.q = Eigen::Quaterniond(r.w, r.x, r.y, r.z);
  pose.q.normalize();
  return pose;
}

void FromPose(const Pose& pose, ob::State* state) {
  auto* se3 = state->as<ob::SE3StateSpace::StateType>();
  se3->setXYZ(pose.t.x(), pose.t.y(), pose.t.z());
  auto& r = se3->rotation();
  r.w = pose.q.w();
  r.x = pose.q.x();
  r.y = pose.q.y();
  r.z = pose.q.z();
}

// The validity OMPL sees: our bounds test and our collision checker object.
class AusbauValidityChecker : public ob::StateValidityChecker {
 public:
  AusbauValidityChecker(const ob::SpaceInformationPtr& si, const PlanningProblem& problem, const PoseValidity& validity)
      : ob::StateValidityChecker(si), problem_(problem), validity_(validity) {}
  bool isValid(const ob::State* state) const override {
    const Pose pose = ToPose(state);
    return problem_.InBounds(pose) && validity_.IsValid(pose);
  }

 private:
  const PlanningProblem& problem_;
  const PoseValidity& validity_;
};

// kExact: checks an SE3 motion exactly as Ausbau's MotionChecker does:
// ceil((|dt| + r * angle) / step) equal sub-steps, the end state first (as
// OMPL's DiscreteMotionValidator), then front to back.
class ExactMotionValidator : public ob::MotionValidator {
 public:
  ExactMotionValidator(const ob::SpaceInformationPtr& si, double radius, double step)
      : ob::MotionValidator(si), radius_(radius), step_(step) {}

  int Steps(const ob::State* a, const ob::State* b) const {
    const double d = MaxDisplacement(ToPose(a), ToPose(b), radius_);
    return std::max(1, static_cast<int>(std::ceil(d / step_)));
  }

  bool checkMotion(const ob::State* s1, const ob::State* s2) const override {
    if (!si_->isValid(s2)) {
      ++invalid_;
      return false;
    }
    const int n = Steps(s1, s2);
    ob::State* test = si_->allocState();
    bool ok = true;
    for (int j = 1; j < n && ok; ++j) {
      si_->getStateSpace()->interpolate(s1, s2, static_cast<double>(j) / n, test);
      ok = si_->isValid(test);
    }
    si_->freeState(test);
    ok ? ++valid_ : ++invalid_;
    return ok;
  }

  bool checkMotion(const ob::State* s1, const ob::State* s2, std::pair<ob::State*, double>& last_valid) const override {
    const int n = Steps(s1, s2);
    ob::State* test = si_->allocState();
    for (int j = 1; j <= n; ++j) {
      si_->getStateSpace()->interpolate(s1, s2, static_cast<double>(j) / n, test);
      if (!si_->isValid(test)) {
        last_valid.second = static_cast<double>(j - 1) / n;
        if (last_valid.first) si_->getStateSpace()->interpolate(s1, s2, last_valid.second, last_valid.first);
        si_->freeState(test);
        ++invalid_;
        return false;
      }
    }
    si_->freeState(test);
    ++valid_;
    return true;
  }

 private:
  double radius_;
  double step_;
};

}  // namespace

void InitOmpl(std::uint32_t seed) {
  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
  ompl::RNG::setSeed(seed);
}

std::string OmplVersion() {
  return std::to_string(OMPL_MAJOR_VERSION) + "." + std::to_string(OMPL_MINOR_VERSION) + "." +
         std::to_string(OMPL_PATCH_VERSION);
}

std::string OmplStatusEnumLine() {
  std::string line = "status";
  for (int i = 0; i < ob::PlannerStatus::TYPE_COUNT; ++i) {
    line += "|" + ob::PlannerStatus(static_cast<ob::PlannerStatus::StatusType>(i)).asString();
  }
  return line;
}

int OmplStatusExactSolution() { return ob::PlannerStatus::EXACT_SOLUTION; }
int OmplStatusTimeout() { return ob::PlannerStatus::TIMEOUT; }

OmplResolution ParseOmplResolution(const std::string& text) {
  if (text == "matched") return OmplResolution::kMatched;
  if (text == "extent") return OmplResolution::kExtent;
  if (text == "ompl") return OmplResolution::kOmplApp;
  if (text == "exact") return OmplResolution::kExact;
  throw InputError("--ompl-resolution: unknown value '" + text + "' (expected matched, exact, extent or ompl)");
}

std::string OmplResolutionName(OmplResolution mode) {
  switch (mode) {
    case OmplResolution::kMatched: return "matched";
    case OmplResolution::kExtent: return "extent";
    case OmplResolution::kOmplApp: return "ompl";
    case OmplResolution::kExact: return "exact";
  }
  return "?";
}

struct OmplRrtConnect::Impl {
  const PlanningProblem* problem = nullptr;
  const PoseValidity* validity = nullptr;
  std::shared_ptr<ob::SE3StateSpace> space;
  double fraction = 0.01;
  OmplResolution mode = OmplResolution::kMatched;
  double step = 0;
  std::map<double, std::unique_ptr<og::SimpleSetup>> setups;  // by range (<= 0: default)

  og::SimpleSetup& SetupFor(double range) {
    const double key = range > 0 ? range : 0.0;
    auto it = setups.find(key);
    if (it != setups.end()) return *it->second;
    auto ss = std::make_unique<og::SimpleSetup>(space);
    const ob::SpaceInformationPtr& si = ss->getSpaceInformation();
    ss->setStateValidityChecker(std::make_shared<AusbauValidityChecker>(si, *problem, *validity));
    si->setStateValidityCheckingResolution(fraction);
    if (mode == OmplResolution::kExact) {
      si->setMotionValidator(std::make_shared<ExactMotionValidator>(si, problem->robot_radius, step));
    }
    ob::ScopedState<ob::SE3StateSpace> start(space), goal(space);
    FromPose(problem->start, start.get());
    FromPose(*problem->goal, goal.get());
    ss->setStartAndGoalStates(start, goal);
    auto planner = std::make_shared<og::RRTConnect>(si);
    if (key > 0) planner->setRange(key);
    ss->setPlanner(planner);
    ss->setup();
    return *setups.emplace(key, std::move(ss)).first->second;
  }
};

OmplRrtConnect::OmplRrtConnect(const PlanningProblem& problem, const PoseValidity& validity, double step,
                               OmplResolution mode)
    : impl_(std::make_unique<Impl>()) {
  if (!problem.goal) throw InputError("OMPL RRT-Connect needs a goal pose");
  impl_->problem = &problem;
  impl_->validity = &validity;
  impl_->space = std::make_shared<ob::SE3StateSpace>();
  ob::RealVectorBounds bounds(3);
  for (int i = 0; i < 3; ++i) {
    bounds.setLow(i, problem.bounds.min[i]);
    bounds.setHigh(i, problem.bounds.max[i]);
  }
  impl_->space->setBounds(bounds);
  impl_->space->setup();
  const double translation_extent = impl_->space->getSubspace(0)->getMaximumExtent();
  const double r = problem.robot_radius;
  double fraction = 0.01;
  switch (mode) {
    case OmplResolution::kMatched: fraction = step / (translation_extent + M_PI * r); break;
    case OmplResolution::kExtent: fraction = step / (std::max(1.0, 2.0 * r) * impl_->space->getMaximumExtent()); break;
    case OmplResolution::kOmplApp: fraction = 0.01; break;
    case OmplResolution::kExact: fraction = step / (translation_extent + M_PI * r); break;  // unused by the validator
  }
  impl_->fraction = std::min(1.0, fraction);
  impl_->mode = mode;
  impl_->step = step;
}

OmplRrtConnect::~OmplRrtConnect() = default;

double OmplRrtConnect::MaximumExtent() const { return impl_->space->getMaximumExtent(); }
double OmplRrtConnect::SegmentFraction() const { return impl_->fraction; }
double OmplRrtConnect::DefaultRange() const {
  return impl_->SetupFor(0).getPlanner()->as<og::RRTConnect>()->getRange();
}

unsigned int OmplRrtConnect::SegmentCount(const Pose& a, const Pose& b) const {
  og::SimpleSetup& ss = impl_->SetupFor(0);
  ob::ScopedState<ob::SE3StateSpace> sa(impl_->space), sb(impl_->space);
  FromPose(a, sa.get());
  FromPose(b, sb.get());
  if (impl_->mode == OmplResolution::kExact) {
    const auto* exact = dynamic_cast<const ExactMotionValidator*>(ss.getSpaceInformation()->getMotionValidator().get());
    if (exact) return static_cast<unsigned int>(exact->Steps(sa.get(), sb.get()));
  }
  return ss.getStateSpace()->validSegmentCount(sa.get(), sb.get());
}

OmplRun OmplRrtConnect::Solve(double range, double time_limit_s) {
  og::SimpleSetup& ss = impl_->SetupFor(range);
  ss.clear();  // planner trees and previous solutions
  OmplRun run;
  const std::int64_t checks_before = impl_->validity->checks();
  const auto begin = std::chrono::steady_clock::now();
  const ob::PlannerStatus status = ss.solve(ob::timedPlannerTerminationCondition(time_limit_s));
  run.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  run.collision_checks = impl_->validity->checks() - checks_before;
  run.status = static_cast<int>(static_cast<ob::PlannerStatus::StatusType>(status));
  run.solved = ss.haveExactSolutionPath();
  if (run.solved) {
    const og::PathGeometric& path = ss.getSolutionPath();
    for (std::size_t i = 0; i < path.getStateCount(); ++i) run.path.push_back(ToPose(path.getState(i)));
  }
  ob::PlannerData data(ss.getSpaceInformation());
  ss.getPlannerData(data);
  run.nodes = static_cast<std::int64_t>(data.numVertices());
  return run;
}

}  // namespace ausbau::bench
