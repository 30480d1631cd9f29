#include "planning/passage_direction.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace ausbau {
namespace {

// Metric::Range of a motion along `tangent`: d'_t = |t| / nu, d'_q = angle / (2 pi).
double RangeOf(const Metric& metric, const PoseTangent& tangent) {
  return std::max(tangent.head<3>().norm() / metric.nu, tangent.tail<3>().norm() / (2.0 * M_PI));
}

}  // namespace

PoseTangent TangentBetween(const Pose& from, const Pose& to) {
  PoseTangent tangent;
  tangent.head<3>() = to.t - from.t;
  Eigen::Quaterniond turn = to.q * from.q.conjugate();
  if (turn.w() < 0) turn.coeffs() = -turn.coeffs();  // the shorter way round
  const Eigen::AngleAxisd axis_angle(turn.normalized());
  tangent.tail<3>() = axis_angle.axis() * axis_angle.angle();
  return tangent;
}

Pose MoveAlong(const Pose& from, const PoseTangent& tangent) {
  Pose out;
  out.t = from.t + tangent.head<3>();
  const Eigen::Vector3d rotation = tangent.tail<3>();
  const double angle = rotation.norm();
  const Eigen::Quaterniond turn =
      angle > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation / angle)) : Eigen::Quaterniond::Identity();
  out.q = (turn * from.q).normalized();
  return out;
}

bool ShapeAlongPassage(const Metric& metric, const Pose& from, const Pose& to, const std::vector<Pose>& neighbors,
                       Pose* shaped) {
  if (static_cast<int>(neighbors.size()) < kPassageMinNeighbors) return false;
  // Tangents in the metric's units: the shift over nu, the angle over 2 pi.
  PoseTangent units;
  const double per_shift = 1.0 / metric.nu, per_radian = 1.0 / (2.0 * M_PI);
  units << per_shift, per_shift, per_shift, per_radian, per_radian, per_radian;
  // The neighbours in the tangent space at `from`, centred on their mean.
  std::vector<PoseTangent> points;
  points.reserve(neighbors.size());
  PoseTangent mean = PoseTangent::Zero();
  for (const Pose& neighbor : neighbors) {
    points.push_back(TangentBetween(from, neighbor).cwiseProduct(units));
    mean += points.back();
  }
  mean /= static_cast<double>(points.size());
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  for (const PoseTangent& point : points) covariance += (point - mean) * (point - mean).transpose();
  covariance /= static_cast<double>(points.size());

  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> solver(covariance);
  if (solver.info() != Eigen::Success) return false;
  const double largest = solver.eigenvalues().maxCoeff();
  if (!(largest > 0)) return false;
  const PoseTangent scale = (solver.eigenvalues() / largest).cwiseMax(0.0).cwiseSqrt();
  const PoseTangent direction = TangentBetween(from, to);
  const Eigen::Matrix<double, 6, 6>& axes = solver.eigenvectors();
  PoseTangent along =
      (axes * scale.asDiagonal() * (axes.transpose() * direction.cwiseProduct(units))).cwiseQuotient(units);
  const double range = RangeOf(metric, direction), kept = RangeOf(metric, along);
  if (!(kept > 1e-9 * range)) return false;
  along *= range / kept;
  *shaped = MoveAlong(from, along);
  return true;
}

}  // namespace ausbau
