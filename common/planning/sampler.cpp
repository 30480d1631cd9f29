#include "planning/sampler.h"

#include "core/error.h"

namespace ausbau {
namespace {
constexpr int kMaxTries = 100;  // per Gaussian / bridge sample before falling back
}

SamplerKind ParseSamplerKind(const std::string& name) {
  if (name == "uniform") return SamplerKind::kUniform;
  if (name == "gaussian") return SamplerKind::kGaussian;
  if (name == "bridge") return SamplerKind::kBridge;
  if (name == "mixed") return SamplerKind::kMixed;
  throw InputError("unknown sampler '" + name + "' (expected uniform, gaussian, bridge or mixed)");
}

Sampler::Sampler(const PlanningProblem& problem, const MotionChecker& motion, SamplerKind kind, double sigma_fraction)
    : problem_(&problem), motion_(&motion), kind_(kind) {
  sigma_t_ = (sigma_fraction > 0 ? sigma_fraction : 0.25) * problem.robot_diagonal;
  sigma_r_ = sigma_t_ / std::max(problem.robot_radius, 1e-12);
}

Pose Sampler::Perturb(const Pose& center, Random& random) const {
  Pose out;
  out.t = center.t + sigma_t_ * Eigen::Vector3d(random.Normal(), random.Normal(), random.Normal());
  const Eigen::Vector3d rotation = sigma_r_ * Eigen::Vector3d(random.Normal(), random.Normal(), random.Normal());
  const double angle = rotation.norm();
  const Eigen::Quaterniond delta =
      angle > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation / angle)) : Eigen::Quaterniond::Identity();
  out.q = (center.q * delta).normalized();
  return out;
}

// The obstacle test of Gaussian and bridge sampling is collision only: the
// translation bounds are not obstacles (counting them would pile samples up
// along the bounds). Perturbed poses outside the bounds are discarded.
Pose Sampler::SampleGaussian(Random& random) {
  // Keep the free one of a pair (uniform, nearby) when exactly one is free.
  const PoseValidity& collision = motion_->validity();
  for (int i = 0; i < kMaxTries; ++i) {
    const Pose a = problem_->SampleUniform(random);
    const Pose b = Perturb(a, random);
    if (!problem_->InBounds(b)) continue;
    const bool a_free = collision.IsValid(a), b_free = collision.IsValid(b);
    if (a_free != b_free) return a_free ? a : b;
  }
  ++fallbacks_;
  return problem_->SampleUniform(random);
}

Pose Sampler::SampleBridge(Random& random) {
  // Two invalid ends, a valid midpoint: the midpoint lies in a narrow passage.
  const PoseValidity& collision = motion_->validity();
  for (int i = 0; i < kMaxTries; ++i) {
    const Pose a = problem_->SampleUniform(random);
    if (collision.IsValid(a)) continue;
    const Pose b = Perturb(a, random);
    if (!problem_->InBounds(b) || collision.IsValid(b)) continue;
    const Pose middle = Interpolate(a, b, 0.5);
    if (problem_->InBounds(middle) && collision.IsValid(middle)) return middle;
  }
  ++fallbacks_;
  return problem_->SampleUniform(random);
}

Pose Sampler::Sample(Random& random) {
  switch (kind_) {
    case SamplerKind::kUniform: return problem_->SampleUniform(random);
    case SamplerKind::kGaussian: return SampleGaussian(random);
    case SamplerKind::kBridge: return SampleBridge(random);
    case SamplerKind::kMixed: {
      const std::uint64_t which = random.Index(3);
      return which == 0 ? problem_->SampleUniform(random) : which == 1 ? SampleGaussian(random) : SampleBridge(random);
    }
  }
  return problem_->SampleUniform(random);
}

bool Sampler::SampleValid(Random& random, Pose* pose, int max_tries) {
  for (int i = 0; i < max_tries; ++i) {
    const std::int64_t fallbacks_before = fallbacks_;
    const bool checked_kind = kind_ == SamplerKind::kGaussian || kind_ == SamplerKind::kBridge;
    const Pose candidate = Sample(random);
    // Gaussian and bridge samples are valid by construction unless they
    // fell back to a uniform one; everything else is checked here.
    const bool known_valid = checked_kind && fallbacks_ == fallbacks_before;
    if (known_valid || motion_->IsValid(candidate)) {
      *pose = candidate;
      return true;
    }
  }
  return false;
}

}  // namespace ausbau
