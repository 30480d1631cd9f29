// The kd-tree of planning/nearest_neighbors.h against brute force: Nearest,
// Within and KNearest must be identical (same indices, same order, ties to the
// lower index) for any u, on uniform, degenerate and planner-like data.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/random.h"
#include "planning/nearest_neighbors.h"
#include "planning/state_space.h"

namespace ausbau {
namespace {

// Brute force with Metric::Distance itself.
std::vector<std::pair<double, int>> SortedDistances(const Metric& metric, const std::vector<Pose>& poses,
                                                    const Pose& query, double u) {
  std::vector<std::pair<double, int>> all;
  all.reserve(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) all.emplace_back(metric.Distance(poses[i], query, u), int(i));
  std::sort(all.begin(), all.end());
  return all;
}

int BruteNearest(const Metric& metric, const std::vector<Pose>& poses, const Pose& query, double u) {
  int best = -1;
  double best_distance = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const double d = metric.Distance(poses[i], query, u);
    if (best < 0 || d < best_distance) best = int(i), best_distance = d;
  }
  return best;
}

std::vector<int> Take(const std::vector<std::pair<double, int>>& sorted, std::size_t count) {
  std::vector<int> out;
  for (std::size_t i = 0; i < std::min(count, sorted.size()); ++i) out.push_back(sorted[i].second);
  return out;
}

std::vector<int> UpTo(const std::vector<std::pair<double, int>>& sorted, double radius) {
  std::vector<int> out;
  for (const auto& p : sorted) {
    if (p.first <= radius) out.push_back(p.second);
  }
  return out;
}

// The weights every check runs under: random ones and the extremes.
std::vector<double> Weights(Random& random, int random_count) {
  std::vector<double> u = {1e-6, 1.0 - 1e-6, 0.5, 0.583};
  for (int i = 0; i < random_count; ++i) u.push_back(random.UniformOpen01());
  return u;
}

// Compares all three queries with brute force for one query pose and weight.
void ExpectSameAsBruteForce(const Metric& metric, const std::vector<Pose>& poses, const NearestNeighbors& index,
                            const Pose& query, double u, Random& random) {
  ASSERT_EQ(index.size(), poses.size());
  const auto sorted = SortedDistances(metric, poses, query, u);
  const int expected = BruteNearest(metric, poses, query, u);
  ASSERT_EQ(index.Nearest(query, u), expected) << "n " << poses.size() << " u " << u;
  if (!sorted.empty()) {
    ASSERT_EQ(sorted.front().second, expected);
  }

  const int n = static_cast<int>(poses.size());
  for (int k : {1, 2, 5, 17, n, n + 3, 0, -1}) {
    ASSERT_EQ(index.KNearest(query, u, k), Take(sorted, k < 0 ? 0 : std::size_t(k)))
        << "n " << n << " k " << k << " u " << u;
  }
  if (n > 0) {
    const std::size_t r = std::min<std::size_t>(random.Index(std::min(n, 64)), sorted.size() - 1);
    // Radii equal to stored distances (inclusive boundary, ties), between them, and extremes.
    for (double radius : {sorted[r].first, sorted[r].first * (1 - 1e-15), std::nextafter(sorted[r].first, 0.0),
                          sorted.front().first, sorted.back().first, 0.0, -1.0, 2.0,
                          0.5 * (sorted[r].first + sorted[std::min(r + 1, sorted.size() - 1)].first)}) {
      ASSERT_EQ(index.Within(query, u, radius), UpTo(sorted, radius))
          << "n " << n << " radius " << radius << " u " << u;
    }
  } else {
    EXPECT_TRUE(index.Within(query, u, 1.0).empty());
  }
}

Pose RandomPose(Random& random, double half_extent) {
  Pose p;
  p.t = {random.Uniform(-half_extent, half_extent), random.Uniform(-half_extent, half_extent),
         random.Uniform(-half_extent, half_extent)};
  p.q = random.UniformQuaternion();
  if (random.Uniform01() < 0.5) p.q.coeffs() = -p.q.coeffs();  // both signs are stored
  return p;
}

// A small random rotation composed onto q, and a small translation step: the
// way a planner tree grows.
Pose Step(Random& random, const Pose& from, double step_t, double step_angle) {
  Pose p;
  Eigen::Vector3d dir(random.Normal(), random.Normal(), random.Normal());
  dir.normalize();
  p.t = from.t + random.Uniform01() * step_t * dir;
  Eigen::Vector3d axis(random.Normal(), random.Normal(), random.Normal());
  axis.normalize();
  p.q = (from.q * Eigen::Quaterniond(Eigen::AngleAxisd(random.Uniform01() * step_angle, axis))).normalized();
  return p;
}

void RunUniform(int n, int queries, std::uint64_t seed) {
  const Metric metric{25.0 * std::sqrt(3.0)};
  Random random(seed);
  NearestNeighbors index(metric);
  std::vector<Pose> poses;
  for (int i = 0; i < n; ++i) {
    poses.push_back(RandomPose(random, 12.5));
    index.Add(poses.back());
  }
  for (int i = 0; i < queries; ++i) {
    // Queries: random, slightly outside the data, or exactly a stored pose.
    Pose query = RandomPose(random, 15.0);
    if (n > 0 && i % 4 == 0) query = poses[random.Index(n)];
    for (double u : Weights(random, 2)) ExpectSameAsBruteForce(metric, poses, index, query, u, random);
  }
}

TEST(NearestNeighbors, EmptyIndex) {
  NearestNeighbors index(Metric{1.0});
  Pose query;
  EXPECT_EQ(index.size(), 0u);
  EXPECT_EQ(index.Nearest(query, 0.5), -1);
  EXPECT_TRUE(index.Within(query, 0.5, 10.0).empty());
  EXPECT_TRUE(index.KNearest(query, 0.5, 3).empty());
}

TEST(NearestNeighbors, UniformSmallSizes) {
  for (int n : {0, 1, 2, 3, 17, 31, 32, 33, 100}) RunUniform(n, 30, 100 + n);
}

TEST(NearestNeighbors, Uniform1000) { RunUniform(1000, 100, 7); }

TEST(NearestNeighbors, Uniform20000) { RunUniform(20000, 25, 8); }

// Identical poses, and q next to -q: distances tie exactly, the lower index wins.
TEST(NearestNeighbors, DuplicatesAndAntipodesTie) {
  const Metric metric{10.0};
  Random random(3);
  NearestNeighbors index(metric);
  std::vector<Pose> poses;
  std::vector<Pose> distinct;
  for (int i = 0; i < 40; ++i) distinct.push_back(RandomPose(random, 5.0));
  for (int i = 0; i < 3000; ++i) {
    Pose p = distinct[random.Index(distinct.size())];
    if (random.Uniform01() < 0.5) p.q.coeffs() = -p.q.coeffs();
    poses.push_back(p);
    index.Add(p);
  }
  for (int i = 0; i < 60; ++i) {
    const Pose query = i % 2 ? distinct[random.Index(distinct.size())] : RandomPose(random, 6.0);
    for (double u : Weights(random, 2)) ExpectSameAsBruteForce(metric, poses, index, query, u, random);
  }
}

TEST(NearestNeighbors, AllPosesIdentical) {
  const Metric metric{3.0};
  Random random(4);
  NearestNeighbors index(metric);
  std::vector<Pose> poses;
  const Pose same = RandomPose(random, 1.0);
  for (int i = 0; i < 500; ++i) {
    poses.push_back(same);
    index.Add(same);
  }
  for (int i = 0; i < 10; ++i) {
    const Pose query = i == 0 ? same : RandomPose(random, 1.5);
    for (double u : Weights(random, 2)) ExpectSameAsBruteForce(metric, poses, index, query, u, random);
  }
  EXPECT_EQ(index.Nearest(same, 0.3), 0);
}

// Quaternions on and near the hemisphere boundary w = 0, with antipodal pairs.
TEST(NearestNeighbors, QuaternionsNearWZero) {
  const Metric metric{5.0};
  Random random(5);
  NearestNeighbors index(metric);
  std::vector<Pose> poses;
  auto near_w_zero = [&random]() {
    const double ws[] = {0.0, -0.0, 1e-17, -1e-17, 1e-9, -1e-9, 1e-4, -1e-4};
    Eigen::Vector3d v(random.Normal(), random.Normal(), random.Normal());
    const int which = static_cast<int>(random.Index(10));
    if (which == 8) v = {0, random.Normal(), random.Normal()};  // x = 0 as well
    if (which == 9) v = {0, 0, random.Uniform01() < 0.5 ? 1.0 : -1.0};
    const double w = ws[random.Index(8)];
    v = v.normalized() * std::sqrt(1 - w * w);
    return Eigen::Quaterniond(w, v.x(), v.y(), v.z());
  };
  for (int i = 0; i < 4000; ++i) {
    Pose p;
    p.t = {random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1)};
    p.q = near_w_zero();
    poses.push_back(p);
    index.Add(p);
    if (i % 3 == 0) {  // its antipode, elsewhere
      Pose a = p;
      a.q.coeffs() = -a.q.coeffs();
      if (i % 2 == 0) a.t = {random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1)};
      poses.push_back(a);
      index.Add(a);
    }
  }
  for (int i = 0; i < 80; ++i) {
    Pose query;
    query.t = {random.Uniform(-1.2, 1.2), random.Uniform(-1.2, 1.2), random.Uniform(-1.2, 1.2)};
    query.q = i % 2 ? near_w_zero() : random.UniformQuaternion();
    if (i % 5 == 0) query = poses[random.Index(poses.size())];
    for (double u : Weights(random, 2)) ExpectSameAsBruteForce(metric, poses, index, query, u, random);
  }
}

// Degenerate clusters: all translations identical (only the rotation term
// separates), all rotations identical (only the translation term does).
TEST(NearestNeighbors, AllTranslationsIdentical) {
  const Metric metric{7.0};
  Random random(6);
  NearestNeighbors index(metric);
  std::vector<Pose> poses;
  for (int i = 0; i < 3000; ++i) {
    Pose p = RandomPose(random, 1.0);
    p.t = {0.25, -1.0, 3.0};
    poses.push_back(p);
    index.Add(p);
  }
  for (int i = 0; i < 40; ++i) {
    Pose query = RandomPose(random, 2.0);
    if (i % 3 == 0) query.t = {0.25, -1.0, 3.0};
    for (double u : Weights(random, 2)) ExpectSameAsBruteForce(metric, poses, index, query, u, random);
  }
}

TEST(NearestNeighbors, AllRotationsIdentical) {
  const Metric metric{7.0};
  Random random(7);
  NearestNeighbors index(metric);
  std::vector<Pose> poses;
  const Eigen::Quaterniond q = random.UniformQuaternion();
  for (int i = 0; i < 3000; ++i) {
    Pose p = RandomPose(random, 3.0);
    p.q = q;
    if (i % 2) p.q.coeffs() = -p.q.coeffs();
    poses.push_back(p);
    index.Add(p);
  }
  for (int i = 0; i < 40; ++i) {
    Pose query = RandomPose(random, 3.5);
    if (i % 3 == 0) query.q = q;
    for (double u : Weights(random, 2)) ExpectSameAsBruteForce(metric, poses, index, query, u, random);
  }
}

// Planner-like: a tree grown by small random steps from random nodes, queries
// interleaved with the insertions (as RRT does), and both weights at 0 and 1
// (outside the planner's open interval, but well defined).
TEST(NearestNeighbors, InterleavedInsertsAndQueriesOnAGrowingTree) {
  const Metric metric{100.0};
  Random random(8);
  NearestNeighbors index(metric);
  std::vector<Pose> poses;
  Pose root;
  poses.push_back(root);
  index.Add(root);
  for (int i = 1; i < 6000; ++i) {
    const Pose query = RandomPose(random, 60.0);
    const double u = random.UniformOpen01();
    const int near = index.Nearest(query, u);
    ASSERT_EQ(near, BruteNearest(metric, poses, query, u)) << "after " << poses.size() << " poses";
    if (i % 97 == 0) {
      for (double w : {0.0, 1.0, 1e-6, 1 - 1e-6, u}) ExpectSameAsBruteForce(metric, poses, index, query, w, random);
    }
    // Mostly extend towards the query from its nearest, sometimes from a random node.
    const Pose& from = i % 3 ? poses[near] : poses[random.Index(poses.size())];
    poses.push_back(Step(random, from, 2.0, 0.1));
    index.Add(poses.back());
  }
}

// Far from the origin with tiny steps (a CAD scene in mm): node boxes are
// stored as floats, whose spacing there (~0.008) exceeds the steps.
TEST(NearestNeighbors, LargeCoordinatesTinySteps) {
  const Metric metric{2000.0};
  Random random(10);
  NearestNeighbors index(metric);
  std::vector<Pose> poses;
  Pose root;
  root.t = {1.0e5, -2.5e5, 7.0e4};
  root.q = random.UniformQuaternion();
  poses.push_back(root);
  index.Add(root);
  for (int i = 1; i < 4000; ++i) {
    poses.push_back(Step(random, poses[random.Index(poses.size())], 1e-3, 1e-4));
    index.Add(poses.back());
  }
  for (int i = 0; i < 40; ++i) {
    Pose query = Step(random, poses[random.Index(poses.size())], 2e-3, 2e-4);
    for (double u : Weights(random, 2)) ExpectSameAsBruteForce(metric, poses, index, query, u, random);
  }
}

// Adversarial insertion orders: sorted along one axis (a line growing
// outwards) and along a rotation (a growing angle about one axis).
TEST(NearestNeighbors, SortedInsertionOrder) {
  const Metric metric{50.0};
  Random random(9);
  NearestNeighbors line(metric), spin(metric);
  std::vector<Pose> line_poses, spin_poses;
  for (int i = 0; i < 5000; ++i) {
    Pose a;
    a.t = {0.01 * i, 0, 0};
    a.q = Eigen::Quaterniond(Eigen::AngleAxisd(1e-3 * (i % 7), Eigen::Vector3d::UnitZ()));
    line_poses.push_back(a);
    line.Add(a);
    Pose b;
    b.q = Eigen::Quaterniond(Eigen::AngleAxisd(2.0 * M_PI * i / 5000.0, Eigen::Vector3d::UnitX()));
    spin_poses.push_back(b);
    spin.Add(b);
    if (i % 500 == 499) {
      for (double u : Weights(random, 1)) {
        ExpectSameAsBruteForce(metric, line_poses, line, RandomPose(random, 30.0), u, random);
        ExpectSameAsBruteForce(metric, spin_poses, spin, RandomPose(random, 1.0), u, random);
      }
    }
  }
}

// The same insertions give the same answers, and a copy answers like the original.
TEST(NearestNeighbors, DeterministicAndCopyable) {
  const Metric metric{20.0};
  Random a(11), b(11);
  NearestNeighbors x(metric), y(metric);
  for (int i = 0; i < 3000; ++i) {
    x.Add(RandomPose(a, 10.0));
    y.Add(RandomPose(b, 10.0));
  }
  const NearestNeighbors z = x;
  Random random(12);
  for (int i = 0; i < 200; ++i) {
    const Pose query = RandomPose(random, 12.0);
    const double u = random.UniformOpen01();
    EXPECT_EQ(x.Nearest(query, u), y.Nearest(query, u));
    EXPECT_EQ(x.Nearest(query, u), z.Nearest(query, u));
    EXPECT_EQ(x.KNearest(query, u, 10), z.KNearest(query, u, 10));
  }
}

}  // namespace
}  // namespace ausbau
