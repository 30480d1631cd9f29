// Sampling strategies of thesis 2.2.5: uniform, Gaussian (Boor et al. 1999),
// bridge test (Hsu et al. 2003) and a mixture of the three.
#pragma once

#include <string>

#include "planning/state_space.h"

namespace ausbau {

enum class SamplerKind { kUniform, kGaussian, kBridge, kMixed };

// Throws InputError for an unknown name.
SamplerKind ParseSamplerKind(const std::string& name);

class Sampler {
 public:
  // sigma_fraction: standard deviation of the Gaussian perturbation as a
  // fraction of D's AABB diagonal; 0 = automatic (0.25: a perturbation that
  // moves D's vertices by about a quarter of its size).
  Sampler(const PlanningProblem& problem, const MotionChecker& motion, SamplerKind kind, double sigma_fraction);

  // A configuration to grow towards (tree planners) or to add (PRM). The
  // uniform sampler does not check validity; the others return a valid
  // configuration near C_obs when they find one within a bounded number of
  // tries, else a uniform sample (counted in fallbacks()).
  Pose Sample(Random& random);
  // A valid configuration (PRM's CFreeSample): rejection on top of Sample.
  // Returns false when none was found within `max_tries`.
  bool SampleValid(Random& random, Pose* pose, int max_tries = 1000);

  // A pose near `center`: translation N(0, sigma_t^2) per axis, rotation by
  // a rotation vector N(0, sigma_r^2) per axis, sigma_r = sigma_t / r_max.
  Pose Perturb(const Pose& center, Random& random) const;
  std::int64_t fallbacks() const { return fallbacks_; }

 private:
  Pose SampleGaussian(Random& random);
  Pose SampleBridge(Random& random);

  const PlanningProblem* problem_;
  const MotionChecker* motion_;
  SamplerKind kind_;
  double sigma_t_;
  double sigma_r_;
  std::int64_t fallbacks_ = 0;
};

}  // namespace ausbau
