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
    CountCheck(valid);
    return valid;
  }
  std::int64_t checks() const { return checks_.load(std::memory_order_relaxed); }
  std::int64_t invalid_checks() const { return invalid_.load(std::memory_order_relaxed); }

  // Whether every pose of the straight motion from `a` to `b` (Interpolate:
  // t linear, q slerp about D's reference point) is valid: true only where
  // proved for the whole motion at once, by a bound over the volume it
  // sweeps; false where not proved, which does not mean invalid. It never
  // proves a pose that IsValid would reject, so a motion check that skips
  // proved stretches answers exactly as one that checks every pose. Counted
  // as one (valid) check. Only where ProvesMotions().
  bool ProveMotion(const Pose& a, const Pose& b) const {
    const bool proved = MotionFree(a, b);
    CountCheck(true);
    return proved;
  }
  virtual bool ProvesMotions() const { return false; }

  // The same kind of proof by how far D is from S at the motion's middle
  // pose (D's own shape widened by how far its points move from there),
  // where ProvesMotionsByClearance(). It proves short motions close to S,
  // which a bound over D's whole sweep cannot, at the cost of a few checks'
  // time (MotionChecker tries it only where asked: the certification's fine
  // step, MotionChecker::ProveByClearance). Counted as one (valid) check.
  bool ProveMotionByClearance(const Pose& a, const Pose& b) const {
    const bool proved = MotionFreeByClearance(a, b);
    CountCheck(true);
    return proved;
  }
  virtual bool ProvesMotionsByClearance() const { return false; }

 protected:
  // The check itself; must be thread-safe.
  virtual bool CheckValid(const Pose& pose) const = 0;
  virtual bool MotionFree(const Pose& /*a*/, const Pose& /*b*/) const { return false; }
  virtual bool MotionFreeByClearance(const Pose& /*a*/, const Pose& /*b*/) const { return false; }
  void CountCheck(bool valid) const {
    checks_.fetch_add(1, std::memory_order_relaxed);
    if (!valid) invalid_.fetch_add(1, std::memory_order_relaxed);
  }

 private:
  mutable std::atomic<std::int64_t> checks_{0};
  mutable std::atomic<std::int64_t> invalid_{0};
};

// A validity check that also bounds how far D may move and stay valid: the
// motion check then steps by that bound (conservative advancement) instead
// of a fixed step, which is both exact and fast near thin features.
class SlackValidity : public PoseValidity {
 public:
  // >= 0: `pose` is valid, and so is every pose reached by a motion in which
  // no point of D moves farther than the value; < 0: invalid. Counted like
  // IsValid.
  double MeasureSlack(const Pose& pose) const {
    const double slack = Slack(pose);
    CountCheck(slack >= 0);
    return slack;
  }
  // The step a motion check takes where the slack is smaller: the check
  // guarantees the limits plus this much (see collision/rigid_depth.h).
  virtual double MinStep() const = 0;
  // Whether every pose of the translation from `pose` by `move` (world) is
  // valid: true only where proved for the whole motion at once, by a bound
  // over the swept motion (what sliding along a contact needs: its slack
  // stays near zero all the way, so conservative advancement would take a
  // step of MinStep per check); false where not proved, which does not
  // mean invalid. Counted as one check. Only where ProvesTranslations().
  bool ProveTranslation(const Pose& pose, const Eigen::Vector3d& move) const {
    const bool proved = TranslationValid(pose, move);
    CountCheck(true);
    return proved;
  }
  virtual bool ProvesTranslations() const { return false; }

 protected:
  virtual double Slack(const Pose& pose) const = 0;
  virtual bool TranslationValid(const Pose& /*pose*/, const Eigen::Vector3d& /*move*/) const { return false; }
  bool CheckValid(const Pose& pose) const override { return Slack(pose) >= 0; }
};

// How long a stretch of a translation to prove at once
// (SlackValidity::ProveTranslation), in whatever unit the caller walks: the
// first is the whole rest of the motion; one proved doubles the next, one
// not proved halves it. After one not proved, the next are tried at the
// length that was proved until kProofsBeforeGrowing in a row are, and only
// then doubled again: a part sliding along a fit or a contact is proved in
// stretches of about one length all the way, and a proof that is not
// reached costs more than a proof of half its length that is (the swept
// surface-depth search runs to its budget: CAx-IF s1's CATIA foot along
// its fit in the body, 150 ms against 90 ms). Doubling after every proof,
// half of the proofs there failed, and they took two thirds of the time.
class StretchLength {
 public:
  explicit StretchLength(double first) : next_(first) {}
  double next() const { return next_; }
  // `length`: the stretch just tried (next(), or less where the motion ends).
  void Proved(double length) {
    ++proved_in_a_row_;
    next_ = !failed_ || proved_in_a_row_ >= kProofsBeforeGrowing ? 2 * length : length;
  }
  void NotProved(double length) {
    failed_ = true;
    proved_in_a_row_ = 0;
    next_ = 0.5 * length;
  }
  static constexpr int kProofsBeforeGrowing = 4;

 private:
  double next_;
  bool failed_ = false;
  int proved_in_a_row_ = 0;
};

}  // namespace ausbau
