#include "planning/prm.h"

#include <omp.h>

#include <functional>
#include <numeric>
#include <queue>

#include "planning/sampler.h"
#include "planning/tree.h"

namespace ausbau {
namespace {

class DisjointSets {
 public:
  int Add() {
    parent_.push_back(static_cast<int>(parent_.size()));
    return parent_.back();
  }
  int Find(int i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  void Unite(int a, int b) {
    a = Find(a), b = Find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

struct Roadmap {
  explicit Roadmap(const Metric& metric) : index(metric) {}
  std::vector<Pose> vertices;
  std::vector<std::vector<std::pair<int, double>>> adjacency;
  NearestNeighbors index;
  DisjointSets components;
  std::vector<char> in_goal_region;

  int Add(const Pose& pose, bool goal_region) {
    vertices.push_back(pose);
    adjacency.emplace_back();
    index.Add(pose);
    components.Add();
    in_goal_region.push_back(goal_region ? 1 : 0);
    return static_cast<int>(vertices.size()) - 1;
  }
};

// Dijkstra from `from` to the nearest vertex that satisfies `is_target`.
std::vector<int> ShortestPath(const Roadmap& roadmap, int from, const std::function<bool(int)>& is_target) {
  const std::size_t n = roadmap.vertices.size();
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  std::vector<int> previous(n, -1);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  distance[from] = 0;
  open.emplace(0.0, from);
  while (!open.empty()) {
    const auto [d, v] = open.top();
    open.pop();
    if (d > distance[v]) continue;
    if (is_target(v)) {
      std::vector<int> path;
      for (int i = v; i >= 0; i = previous[i]) path.push_back(i);
      std::reverse(path.begin(), path.end());
      return path;
    }
    for (const auto& [w, length] : roadmap.adjacency[v]) {
      if (d + length < distance[w]) {
        distance[w] = d + length;
        previous[w] = v;
        open.emplace(distance[w], w);
      }
    }
  }
  return {};
}

}  // namespace

PrmResult RunPrm(const PlanningProblem& problem, const MotionChecker& motion, const std::vector<PrmQuery>& queries,
                 const PrmSettings& settings, const PlannerOptions& options) {
  const StatsScope scope(motion.validity());
  const Budget budget(options, scope);
  Random random(options.seed);
  Sampler sampler(problem, motion, ParseSamplerKind(options.sampler), options.sampler_sigma);
  Roadmap roadmap(problem.metric);
  const bool any_region_query = std::any_of(queries.begin(), queries.end(), [](const PrmQuery& q) { return !q.goal; });

  std::vector<int> start_vertex, goal_vertex;
  for (const PrmQuery& query : queries) {
    start_vertex.push_back(roadmap.Add(query.start, problem.InGoalRegion(query.start)));
    goal_vertex.push_back(query.goal ? roadmap.Add(*query.goal, false) : -1);
  }
  // Which queries are answered: a goal pose in the start's component, or a
  // goal-region vertex in it.
  auto solved = [&](std::size_t q) {
    const int c = roadmap.components.Find(start_vertex[q]);
    if (queries[q].goal) return roadmap.components.Find(goal_vertex[q]) == c;
    for (std::size_t v = 0; v < roadmap.vertices.size(); ++v) {
      if (roadmap.in_goal_region[v] && roadmap.components.Find(static_cast<int>(v)) == c) return true;
    }
    return false;
  };
  auto all_solved = [&] {
    for (std::size_t q = 0; q < queries.size(); ++q) {
      if (!solved(q)) return false;
    }
    return true;
  };
  const int threads = settings.threads > 0 ? settings.threads : omp_get_max_threads();

  std::int64_t samples = 0, edges = 0;
  std::size_t connected_up_to = 0;  // vertices below this index have been connected
  int batch = settings.first_batch;
  PlanStatus status = PlanStatus::kTimeLimit;  // overwritten by the budget when it stops
  bool stop = false;
  while (true) {
    // Connect the vertices not yet connected (the queries' in the first round).
    const std::size_t first_new = connected_up_to;
    std::vector<std::pair<int, int>> candidates;
    for (std::size_t v = first_new; v < roadmap.vertices.size(); ++v) {
      for (int w : roadmap.index.KNearest(roadmap.vertices[v], 0.5, settings.max_neighbours + 1)) {
        if (w == static_cast<int>(v)) continue;
        if (w > static_cast<int>(v) && w >= static_cast<int>(first_new)) continue;  // each new pair once
        if (problem.metric.Distance(roadmap.vertices[v], roadmap.vertices[w], 0.5) > settings.radius) continue;
        candidates.emplace_back(static_cast<int>(v), w);
      }
    }
    std::vector<char> valid(candidates.size(), 0);
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads)
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      valid[i] = motion.MotionValid(roadmap.vertices[candidates[i].first], roadmap.vertices[candidates[i].second]);
    }
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (!valid[i]) continue;
      const auto [v, w] = candidates[i];
      const double length = problem.metric.Distance(roadmap.vertices[v], roadmap.vertices[w], 0.5);
      roadmap.adjacency[v].emplace_back(w, length);
      roadmap.adjacency[w].emplace_back(v, length);
      roadmap.components.Unite(v, w);
      ++edges;
    }
    connected_up_to = roadmap.vertices.size();
    if (all_solved()) break;
    if (stop) break;
    // Next round: a batch of valid samples, plus goal-region poses.
    for (int i = 0; i < batch; ++i) {
      if (!budget.Continue(samples, &status)) {
        stop = true;  // connect what was sampled, then stop
        break;
      }
      ++samples;
      Pose pose;
      if (any_region_query && random.Uniform01() < 0.05) {
        if (SampleGoalRegion(problem, random, &pose)) roadmap.Add(pose, true);
      } else if (sampler.SampleValid(random, &pose, 1)) {
        roadmap.Add(pose, problem.InGoalRegion(pose));
      }
    }
    batch *= 2;
  }

  PrmResult result;
  result.stats.iterations = samples;
  result.stats.nodes = static_cast<std::int64_t>(roadmap.vertices.size());
  scope.Fill(&result.stats);
  result.edges = edges;
  for (std::size_t q = 0; q < queries.size(); ++q) {
    PlanResult answer;
    answer.stats = result.stats;
    answer.status = status;
    if (solved(q)) {
      const int goal = goal_vertex[q];
      const auto ids = ShortestPath(roadmap, start_vertex[q], [&](int v) {
        return queries[q].goal ? v == goal : roadmap.in_goal_region[v] != 0;
      });
      for (int v : ids) answer.path.push_back(roadmap.vertices[v]);
      answer.status = PlanStatus::kSolved;
    }
    result.queries.push_back(answer);
  }
  return result;
}

}  // namespace ausbau
