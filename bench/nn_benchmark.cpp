// ausbau-nn-bench: the kd-tree of planning/nearest_neighbors.h against an
// exact linear scan (the previous implementation, kept here as the reference)
// on uniform poses and on planner-like trees. Prints a markdown table.
//
//   ausbau-nn-bench [--queries N] [--max-n N] [--repetitions R]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

#include "core/random.h"
#include "parse_args.h"
#include "planning/nearest_neighbors.h"
#include "planning/state_space.h"

namespace {

using ausbau::Metric;
using ausbau::NearestNeighbors;
using ausbau::Pose;
using ausbau::Random;
using Clock = std::chrono::steady_clock;

// The reference: a linear scan pruned by the translation term, with
// Metric::Distance's expressions and ties to the lower index.
class LinearScan {
 public:
  explicit LinearScan(const Metric& metric) : metric_(metric) {}
  void Add(const Pose& pose) { poses_.push_back(pose); }
  int Nearest(const Pose& query, double u) const {
    double best = std::numeric_limits<double>::infinity();
    int best_index = -1;
    for (std::size_t i = 0; i < poses_.size(); ++i) {
      const double translation = u * metric_.Translation(poses_[i].t, query.t);
      if (translation >= best) continue;
      const double d = translation + (1.0 - u) * Metric::Rotation(poses_[i].q, query.q);
      if (d < best) best = d, best_index = static_cast<int>(i);
    }
    return best_index;
  }

 private:
  Metric metric_;
  std::vector<Pose> poses_;
};

constexpr double kSide = 100.0;  // translations in [0, kSide]^3

Pose UniformPose(Random& random) {
  Pose p;
  p.t = {random.Uniform(0, kSide), random.Uniform(0, kSide), random.Uniform(0, kSide)};
  p.q = random.UniformQuaternion();
  return p;
}

Eigen::Vector3d RandomDirection(Random& random) {
  return Eigen::Vector3d(random.Normal(), random.Normal(), random.Normal()).normalized();
}

// A pose at most step_t / step_angle away from `from`, clamped to the box.
Pose StepFrom(Random& random, const Pose& from, double step_t, double step_angle) {
  Pose p;
  p.t = from.t + random.Uniform01() * step_t * RandomDirection(random);
  p.t = p.t.cwiseMax(0.0).cwiseMin(kSide);
  p.q = (from.q * Eigen::Quaterniond(Eigen::AngleAxisd(random.Uniform01() * step_angle, RandomDirection(random))))
            .normalized();
  return p;
}

// Moves from `from` towards `to` by at most the given steps (RRT's extend).
Pose StepTowards(const Pose& from, const Pose& to, double step_t, double step_angle) {
  Pose p;
  const Eigen::Vector3d dt = to.t - from.t;
  const double angle = ausbau::RotationAngle(from.q, to.q);
  const double s = std::min({1.0, dt.norm() > 0 ? step_t / dt.norm() : 1.0, angle > 0 ? step_angle / angle : 1.0});
  return ausbau::Interpolate(from, to, s);
}

enum class Data { kUniform, kRandomExtension, kRrtGrowth };

const char* Name(Data data) {
  switch (data) {
    case Data::kUniform: return "uniform";
    case Data::kRandomExtension: return "tree, random extension";
    case Data::kRrtGrowth: return "tree, RRT growth";
  }
  return "?";
}

// The poses of a data set, in insertion order. Planner-like trees start at
// the box centre; steps are 1% of the box side and 0.1 rad.
std::vector<Pose> MakeData(Data data, int n, const Metric& metric, std::uint64_t seed) {
  Random random(seed);
  std::vector<Pose> poses;
  poses.reserve(n);
  const double step_t = 0.01 * kSide, step_angle = 0.1;
  Pose root;
  root.t = Eigen::Vector3d::Constant(kSide / 2);
  root.q = random.UniformQuaternion();
  if (data == Data::kUniform) {
    for (int i = 0; i < n; ++i) poses.push_back(UniformPose(random));
  } else if (data == Data::kRandomExtension) {
    poses.push_back(root);
    while (static_cast<int>(poses.size()) < n)
      poses.push_back(StepFrom(random, poses[random.Index(poses.size())], step_t, step_angle));
  } else {
    NearestNeighbors index(metric);
    poses.push_back(root);
    index.Add(root);
    while (static_cast<int>(poses.size()) < n) {
      const Pose target = UniformPose(random);
      const int near = index.Nearest(target, random.UniformOpen01());
      poses.push_back(StepTowards(poses[near], target, step_t, step_angle));
      index.Add(poses.back());
    }
  }
  return poses;
}

std::string CpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(colon + 2);
    }
  }
  return "unknown";
}

int ProcessorLines() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  int count = 0;
  while (std::getline(in, line))
    if (line.rfind("processor", 0) == 0) ++count;
  return count;
}

double Seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

// Mean microseconds per call of run(i) over `count` calls, the best of
// `repetitions` passes (the machine may be shared; the minimum is the least
// disturbed pass).
template <class Run>
double BestMeanMicroseconds(int count, int repetitions, Run run) {
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repetitions; ++r) {
    const auto begin = Clock::now();
    for (int i = 0; i < count; ++i) run(i);
    best = std::min(best, 1e6 * Seconds(begin, Clock::now()) / count);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  int queries = 2000;
  int max_n = 100000;
  int repetitions = 3;
  CLI::App app("The nearest-neighbour index against a linear scan (planning/nearest_neighbors.h).", "ausbau-nn-bench");
  app.set_version_flag("--version", std::string(AUSBAU_VERSION));
  app.add_option("--queries", queries, "queries per size")->capture_default_str()->check(CLI::Range(1, 100000000));
  app.add_option("--max-n", max_n, "largest index size")->capture_default_str()->check(CLI::Range(1, 100000000));
  app.add_option("--repetitions", repetitions, "runs per size (the fastest counts)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  if (const int code = ausbau::bench::ParseArguments(app, argc, argv); code >= 0) return code;
  const Metric metric{kSide * std::sqrt(3.0)};

  std::printf("# ausbau-nn-bench\n\n");
  std::printf("- CPU: %s\n", CpuModel().c_str());
  std::printf("- cores: %d logical processors in /proc/cpuinfo, hardware_concurrency %u (single-threaded benchmark)\n",
              ProcessorLines(), std::thread::hardware_concurrency());
#ifdef NDEBUG
  std::printf("- build: optimized (NDEBUG), compiler %s\n", __VERSION__);
#else
  std::printf("- build: NOT optimized (assertions on), compiler %s\n", __VERSION__);
#endif
  std::printf("- metric: translations in [0, %g]^3, nu = %g; a new u ~ U(0, 1) per query; queries uniform\n", kSide,
              metric.nu);
  std::printf("- trees: start at the box centre, steps of at most %g (translation) and 0.1 rad\n\n", 0.01 * kSide);
  std::printf("| data | n | kd-tree Nearest (us) | linear scan (us) | speedup | Add (us, mean) | same answers |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---|\n");

  long long sink = 0;
  std::vector<std::string> by_weight;
  for (Data data : {Data::kUniform, Data::kRandomExtension, Data::kRrtGrowth}) {
    for (int n : {1000, 10000, 100000}) {
      if (n > max_n) continue;
      const std::vector<Pose> poses = MakeData(data, n, metric, 1000 + n);
      // Add: the whole build, per pose (best of the repetitions).
      NearestNeighbors index(metric);
      double add_us = std::numeric_limits<double>::infinity();
      for (int r = 0; r < repetitions; ++r) {
        NearestNeighbors built(metric);
        const auto add_begin = Clock::now();
        for (const Pose& p : poses) built.Add(p);
        add_us = std::min(add_us, 1e6 * Seconds(add_begin, Clock::now()) / n);
        if (r == 0) index = built;
      }
      LinearScan scan(metric);
      for (const Pose& p : poses) scan.Add(p);

      Random random(77 + n);
      std::vector<Pose> query_poses(queries);
      std::vector<double> weights(queries);
      for (int i = 0; i < queries; ++i) query_poses[i] = UniformPose(random), weights[i] = random.UniformOpen01();

      std::vector<int> tree_answers(queries), scan_answers(queries);
      const double tree_us = BestMeanMicroseconds(
          queries, repetitions, [&](int i) { tree_answers[i] = index.Nearest(query_poses[i], weights[i]); });
      const double scan_us = BestMeanMicroseconds(
          queries, repetitions, [&](int i) { scan_answers[i] = scan.Nearest(query_poses[i], weights[i]); });
      const int mismatches =
          static_cast<int>(queries - std::inner_product(tree_answers.begin(), tree_answers.end(), scan_answers.begin(),
                                                        0, std::plus<>(), std::equal_to<>()));
      for (int a : tree_answers) sink += a;
      std::printf("| %s | %d | %.2f | %.2f | %.1fx | %.2f | %s |\n", Name(data), n, tree_us, scan_us, scan_us / tree_us,
                  add_us, mismatches == 0 ? "yes" : (std::to_string(mismatches) + " differ").c_str());
      std::fflush(stdout);
      // The largest n again with fixed weights: how the pruning depends on u.
      if (n == std::min(max_n, 100000)) {
        std::string line = std::string("| ") + Name(data) + " | " + std::to_string(n);
        for (double u : {0.05, 0.5, 0.95}) {
          const double tree =
              BestMeanMicroseconds(queries, repetitions, [&](int i) { sink += index.Nearest(query_poses[i], u); });
          const double linear =
              BestMeanMicroseconds(queries, repetitions, [&](int i) { sink += scan.Nearest(query_poses[i], u); });
          char cell[64];
          std::snprintf(cell, sizeof cell, " | %.2f / %.0f", tree, linear);
          line += cell;
        }
        by_weight.push_back(line + " |");
      }
    }
  }
  std::printf("\nFixed weights (kd-tree / linear scan, us per Nearest):\n\n");
  std::printf("| data | n | u = 0.05 | u = 0.5 | u = 0.95 |\n|---|---:|---:|---:|---:|\n");
  for (const std::string& line : by_weight) std::printf("%s\n", line.c_str());
  std::printf("\n%d queries per row; times are the best of %d passes (mean per call within a pass); checksum %lld\n",
              queries, repetitions, sink);
  return 0;
}
