#include "labeling/pbd_label.h"

#include <immintrin.h>
#include <omp.h>

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <queue>
#include <unordered_map>

#include "core/atomic_file.h"
#include "core/cancel.h"
#include "core/error.h"

namespace ausbau {

void PbdLabelOptions::Check() const {
  if (!(time_step > 0)) throw OptionError(&time_step, "time_step", "must be positive");
  if (!(duration > 0)) throw OptionError(&duration, "duration", "must be positive");
  if (Steps() > 100000) throw OptionError(&duration, "duration", "more than 100000 time steps (duration / time_step)");
  if (solver_iterations < 1 || solver_iterations > 1000) {
    throw OptionError(&solver_iterations, "solver_iterations",
                      "must lie in 1 .. 1000 (solver iterations per step; the thesis uses 3)");
  }
  if (!(damping >= 0 && damping <= 1)) throw OptionError(&damping, "damping", "must lie in [0, 1]");
  if (!(stiffness >= 0 && stiffness <= 1)) throw OptionError(&stiffness, "stiffness", "must lie in [0, 1]");
  if (stiffness_formula != "thesis" && stiffness_formula != "mueller") {
    throw OptionError(&stiffness_formula, "stiffness_formula",
                      "expected thesis or mueller, got '" + stiffness_formula + "'");
  }
  if (!(kappa > 0)) throw OptionError(&kappa, "kappa", "must be positive");
  if (!(density >= 0)) throw OptionError(&density, "density", "must be positive (or 0: automatic)");
  if (measure != "self" && measure != "sum")
    throw OptionError(&measure, "measure", "expected self or sum, got '" + measure + "'");
  if (threads < 0) throw OptionError(&threads, "threads", "must be at least 0");
  if (max_load_cases < 0) throw OptionError(&max_load_cases, "max_load_cases", "must be at least 0 (0: every vertex)");
  if (!(refine >= 0)) throw OptionError(&refine, "refine", "must be at least 0 (0: off)");
  if (refine > 0 && !(refine_min_length > 0 && refine_min_length < 1)) {
    throw InputError("refine_min_length: must lie in (0, 1) (a fraction of D's AABB diagonal)");
  }
  if (!(glue_tolerance >= 0 && glue_tolerance < 1)) {
    throw OptionError(&glue_tolerance, "glue_tolerance", "must lie in [0, 1) (a fraction of D's AABB diagonal)");
  }
}

int PbdLabelOptions::Steps() const {
  const double steps = std::ceil(duration / time_step - 1e-9);
  return steps > 1e6 ? 1000000 : std::max(1, static_cast<int>(steps));
}

double PbdLabelOptions::SolverStiffness() const {
  const double exponent =
      stiffness_formula == "mueller" ? 1.0 / solver_iterations : static_cast<double>(solver_iterations);
  return 1.0 - std::pow(1.0 - stiffness, exponent);
}

namespace {

constexpr int kLanes = 8;              // load cases simulated together (SIMD lanes)
constexpr double kLoadStrength = 0.1;  // lambda of the automatic density (pbd_label.h)

struct Constraint {
  int i, j;      // simulation vertex indices, i < j
  float rest;    // rest length
  float wi, wj;  // k' w_i / (w_i + w_j), k' w_j / (w_i + w_j)
};

// One Gauss-Seidel sweep over `count` constraints for kLanes simulations.
// p: positions of the component, [vertex][coordinate][lane], vertex indices
// relative to the component's first vertex `base`. Two implementations of
// the same arithmetic (AVX: one 8-wide vector per coordinate; SSE2: two
// 4-wide ones); every operation is an IEEE-exact elementwise sub, mul, add,
// sqrt, div or max in the same order, so both give bit-identical results.
// (Auto-vectorization does not happen here: GCC keeps the 8-lane loops
// scalar.)
__attribute__((target("avx"))) void ProjectConstraintsAvx(const Constraint* constraints, int count, float* p,
                                                          int base) {
  const __m256 tiny = _mm256_set1_ps(1e-20f);
  for (int c = 0; c < count; ++c) {
    const Constraint& k = constraints[c];
    float* pi = p + static_cast<std::size_t>(k.i - base) * 3 * kLanes;
    float* pj = p + static_cast<std::size_t>(k.j - base) * 3 * kLanes;
    const __m256 xi = _mm256_loadu_ps(pi), yi = _mm256_loadu_ps(pi + kLanes), zi = _mm256_loadu_ps(pi + 2 * kLanes);
    const __m256 xj = _mm256_loadu_ps(pj), yj = _mm256_loadu_ps(pj + kLanes), zj = _mm256_loadu_ps(pj + 2 * kLanes);
    const __m256 dx = _mm256_sub_ps(xj, xi), dy = _mm256_sub_ps(yj, yi), dz = _mm256_sub_ps(zj, zi);
    const __m256 length = _mm256_sqrt_ps(
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz)));
    const __m256 s = _mm256_div_ps(_mm256_sub_ps(length, _mm256_set1_ps(k.rest)), _mm256_max_ps(length, tiny));
    const __m256 a = _mm256_mul_ps(_mm256_set1_ps(k.wi), s), b = _mm256_mul_ps(_mm256_set1_ps(k.wj), s);
    _mm256_storeu_ps(pi, _mm256_add_ps(xi, _mm256_mul_ps(a, dx)));
    _mm256_storeu_ps(pi + kLanes, _mm256_add_ps(yi, _mm256_mul_ps(a, dy)));
    _mm256_storeu_ps(pi + 2 * kLanes, _mm256_add_ps(zi, _mm256_mul_ps(a, dz)));
    _mm256_storeu_ps(pj, _mm256_sub_ps(xj, _mm256_mul_ps(b, dx)));
    _mm256_storeu_ps(pj + kLanes, _mm256_sub_ps(yj, _mm256_mul_ps(b, dy)));
    _mm256_storeu_ps(pj + 2 * kLanes, _mm256_sub_ps(zj, _mm256_mul_ps(b, dz)));
  }
}

void ProjectConstraintsSse(const Constraint* constraints, int count, float* p, int base) {
  static_assert(kLanes == 8, "two 4-wide halves");
  const __m128 tiny = _mm_set1_ps(1e-20f);
  for (int c = 0; c < count; ++c) {
    const Constraint& k = constraints[c];
    float* pi = p + static_cast<std::size_t>(k.i - base) * 3 * kLanes;
    float* pj = p + static_cast<std::size_t>(k.j - base) * 3 * kLanes;
    const __m128 rest = _mm_set1_ps(k.rest), wi = _mm_set1_ps(k.wi), wj = _mm_set1_ps(k.wj);
    for (int h = 0; h < kLanes; h += 4) {
      const __m128 xi = _mm_loadu_ps(pi + h), yi = _mm_loadu_ps(pi + kLanes + h),
                   zi = _mm_loadu_ps(pi + 2 * kLanes + h);
      const __m128 xj = _mm_loadu_ps(pj + h), yj = _mm_loadu_ps(pj + kLanes + h),
                   zj = _mm_loadu_ps(pj + 2 * kLanes + h);
      const __m128 dx = _mm_sub_ps(xj, xi), dy = _mm_sub_ps(yj, yi), dz = _mm_sub_ps(zj, zi);
      const __m128 length =
          _mm_sqrt_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz)));
      const __m128 s = _mm_div_ps(_mm_sub_ps(length, rest), _mm_max_ps(length, tiny));
      const __m128 a = _mm_mul_ps(wi, s), b = _mm_mul_ps(wj, s);
      _mm_storeu_ps(pi + h, _mm_add_ps(xi, _mm_mul_ps(a, dx)));
      _mm_storeu_ps(pi + kLanes + h, _mm_add_ps(yi, _mm_mul_ps(a, dy)));
      _mm_storeu_ps(pi + 2 * kLanes + h, _mm_add_ps(zi, _mm_mul_ps(a, dz)));
      _mm_storeu_ps(pj + h, _mm_sub_ps(xj, _mm_mul_ps(b, dx)));
      _mm_storeu_ps(pj + kLanes + h, _mm_sub_ps(yj, _mm_mul_ps(b, dy)));
      _mm_storeu_ps(pj + 2 * kLanes + h, _mm_sub_ps(zj, _mm_mul_ps(b, dz)));
    }
  }
}

void ProjectConstraints(const Constraint* constraints, int count, float* p, int base) {
  static const bool avx = __builtin_cpu_supports("avx");
  if (avx) {
    ProjectConstraintsAvx(constraints, count, p, base);
  } else {
    ProjectConstraintsSse(constraints, count, p, base);
  }
}

// v <- damping v; p <- x + dt v (all lanes, `values` floats).
__attribute__((target_clones("avx2", "default"))) void Predict(float* __restrict v, float* __restrict p,
                                                               const float* __restrict x, std::size_t values,
                                                               float damping, float dt) {
  for (std::size_t k = 0; k < values; ++k) {
    v[k] *= damping;
    p[k] = x[k] + dt * v[k];
  }
}

// v <- (p - x) / dt; x <- p.
__attribute__((target_clones("avx2", "default"))) void UpdateVelocities(float* __restrict v, const float* __restrict p,
                                                                        float* __restrict x, std::size_t values,
                                                                        float inverse_dt) {
  for (std::size_t k = 0; k < values; ++k) {
    v[k] = (p[k] - x[k]) * inverse_dt;
    x[k] = p[k];
  }
}

struct Model {
  int n = 0;                   // simulated vertices
  std::vector<int> welded;     // simulation index -> welded vertex
  std::vector<float> rest;     // [n][3], scaled and centred
  std::vector<double> mass;    // [n]
  std::vector<float> load_dv;  // [n][3]: velocity increment per step of the load case on that vertex
  std::vector<Constraint> constraints;
  std::vector<int> vertex_begin;      // per component, size components + 1
  std::vector<int> constraint_begin;  // per component, size components + 1
};

struct Batch {
  int component;
  int count;         // load cases in the batch, <= kLanes
  int load[kLanes];  // load vertex of each lane (simulation index)
};

// Mass-weighted best rigid transform of `rest` onto lane `lane` of `x`; writes
// each vertex's distance from its rigidly moved rest position.
void RigidResiduals(const Model& model, int begin, int end, const float* x, int lane, double* residual) {
  const int count = end - begin;
  double total = 0.0;
  Eigen::Vector3d rest_centre = Eigen::Vector3d::Zero(), moved_centre = Eigen::Vector3d::Zero();
  const auto moved = [&](int local) {
    const float* q = x + static_cast<std::size_t>(local) * 3 * kLanes + lane;
    return Eigen::Vector3d(q[0], q[kLanes], q[2 * kLanes]);
  };
  const auto rest = [&](int v) {
    return Eigen::Vector3d(model.rest[3 * v], model.rest[3 * v + 1], model.rest[3 * v + 2]);
  };
  for (int local = 0; local < count; ++local) {
    const double m = model.mass[begin + local];
    total += m;
    rest_centre += m * rest(begin + local);
    moved_centre += m * moved(local);
  }
  rest_centre /= total;
  moved_centre /= total;
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (int local = 0; local < count; ++local) {
    h += model.mass[begin + local] * (rest(begin + local) - rest_centre) * (moved(local) - moved_centre).transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d correction = Eigen::Matrix3d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0) correction(2, 2) = -1;
  const Eigen::Matrix3d rotation = svd.matrixV() * correction * svd.matrixU().transpose();
  for (int local = 0; local < count; ++local) {
    residual[local] = (moved(local) - (rotation * (rest(begin + local) - rest_centre) + moved_centre)).norm();
  }
}

// Contacts between separate components (CAD parts modelled as separate,
// overlapping or touching solids): a vertex of one component that lies
// within `tolerance` of another component's surface, or inside another
// closed component (ray parity, majority of three rays), is tied to the three
// vertices of the nearest triangle of that component. Returns (vertex,
// vertex) pairs of welded indices, sorted.
std::vector<std::pair<int, int>> FindGlue(const MeshTopology& topology, double tolerance, int threads) {
  const int components = topology.stats.components;
  std::vector<std::pair<int, int>> pairs;
  if (components < 2) return pairs;
  const int m = static_cast<int>(topology.triangles.size());
  const int n = topology.VertexCount();
  std::vector<int> triangle_component(m);
  std::vector<Aabb> boxes(components);
  for (int t = 0; t < m; ++t) {
    triangle_component[t] = topology.component[topology.triangles[t][0]];
    for (int v : topology.triangles[t]) boxes[triangle_component[t]].Extend(topology.vertices[v]);
  }
  std::vector<std::uint8_t> closed(components, 1);
  for (std::size_t e = 0; e < topology.edges.size(); ++e) {
    if (topology.edge_triangle_offsets[e + 1] - topology.edge_triangle_offsets[e] != 2) {
      closed[topology.component[topology.edges[e][0]]] = 0;
    }
  }
  const TriangleBvh bvh(topology.vertices, topology.triangles);
  static const Eigen::Vector3d kDirections[3] = {
      Eigen::Vector3d(0.5773502691896258, 0.5914394147712337, 0.5632542613410031),
      Eigen::Vector3d(-0.7071067811865476, 0.3111442126341125, 0.6348234758123451),
      Eigen::Vector3d(0.1357890123456789, -0.8124038404635961, 0.5670102939401234)};
  std::vector<std::vector<int>> targets(n);
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads)
  for (int v = 0; v < n; ++v) {
    if (!topology.referenced[v]) continue;
    const int a = topology.component[v];
    const Eigen::Vector3d& p = topology.vertices[v];
    bool near_other = false;
    for (int b = 0; b < components && !near_other; ++b) {
      if (b == a) continue;
      Aabb grown = boxes[b];
      grown.min.array() -= tolerance;
      grown.max.array() += tolerance;
      near_other = grown.Contains(p);
    }
    if (!near_other) continue;
    const auto touching = bvh.NearestPoint(p, [&](int t) { return triangle_component[t] == a; });
    if (touching.triangle >= 0 && touching.distance_squared <= tolerance * tolerance) {
      targets[v].push_back(touching.triangle);
    }
    for (int b = 0; b < components; ++b) {
      if (b == a || !closed[b] || !boxes[b].Contains(p)) continue;
      if (touching.triangle >= 0 && triangle_component[touching.triangle] == b && !targets[v].empty()) continue;
      const auto other = [&](int t) { return triangle_component[t] != b; };
      int odd = 0;
      for (const auto& direction : kDirections) odd += bvh.CountCrossings(p, direction, 0.0, other) % 2;
      if (odd >= 2) targets[v].push_back(bvh.NearestPoint(p, other).triangle);
    }
  }
  for (int v = 0; v < n; ++v) {
    for (int t : targets[v]) {
      for (int w : topology.triangles[t]) pairs.emplace_back(v, w);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

// Longest-edge bisection: while an edge is longer than its limit, split it
// at its midpoint in every triangle that has it (each triangle (u, w, c)
// with edge u-w becomes (u, m, c) and (m, w, c), keeping its orientation).
// Edges are split longest first, ties by vertex indices: deterministic.
// limit(a, b) = max(factor x 2 min(r_a, r_b), min_length). A new vertex gets
// the mean radius of the edge's ends. Vertices keep their indices; new ones
// are appended.
struct RefinedMesh {
  TriangleMesh mesh;
  std::vector<double> radii;
};

RefinedMesh Refine(const MeshTopology& topology, const std::vector<double>& radii, double factor, double min_length) {
  RefinedMesh out;
  out.mesh.vertices = topology.vertices;
  out.mesh.triangles = topology.triangles;
  out.radii = radii;
  auto& vertices = out.mesh.vertices;
  auto& triangles = out.mesh.triangles;
  const auto key = [](int a, int b) {
    return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
  };
  std::unordered_map<std::uint64_t, std::vector<int>> edge_triangles;
  for (int t = 0; t < static_cast<int>(triangles.size()); ++t) {
    for (int k = 0; k < 3; ++k) edge_triangles[key(triangles[t][k], triangles[t][(k + 1) % 3])].push_back(t);
  }
  struct Long {
    double length;
    int a, b;
    bool operator<(const Long& o) const {  // max-heap: longest first, then lowest indices
      if (length != o.length) return length < o.length;
      if (a != o.a) return a > o.a;
      return b > o.b;
    }
  };
  std::priority_queue<Long> queue;
  const auto consider = [&](int a, int b) {
    const double length = (vertices[a] - vertices[b]).norm();
    const double limit = std::max(factor * 2.0 * std::min(out.radii[a], out.radii[b]), min_length);
    if (length > limit) queue.push({length, std::min(a, b), std::max(a, b)});
  };
  for (const auto& e : topology.edges) consider(e[0], e[1]);
  const std::size_t max_vertices = 4 * vertices.size() + 1000;  // a guard; the floor bounds it long before
  while (!queue.empty() && vertices.size() < max_vertices) {
    const Long top = queue.top();
    queue.pop();
    const auto found = edge_triangles.find(key(top.a, top.b));
    if (found == edge_triangles.end()) continue;  // already split
    const std::vector<int> incident = found->second;
    edge_triangles.erase(found);
    const int m = static_cast<int>(vertices.size());
    vertices.push_back(0.5 * (vertices[top.a] + vertices[top.b]));
    out.radii.push_back(0.5 * (out.radii[top.a] + out.radii[top.b]));
    std::vector<int> opposite;
    for (int t : incident) {
      auto& tri = triangles[t];
      int k = 0;
      while (!((tri[k] == top.a && tri[(k + 1) % 3] == top.b) || (tri[k] == top.b && tri[(k + 1) % 3] == top.a))) ++k;
      const int u = tri[k], w = tri[(k + 1) % 3], c = tri[(k + 2) % 3];
      const int added = static_cast<int>(triangles.size());
      tri = {u, m, c};
      triangles.push_back({m, w, c});
      edge_triangles[key(u, m)].push_back(t);
      edge_triangles[key(m, w)].push_back(added);
      auto& mc = edge_triangles[key(m, c)];
      mc.push_back(t);
      mc.push_back(added);
      for (int& x : edge_triangles[key(w, c)]) {
        if (x == t) x = added;
      }
      opposite.push_back(c);
    }
    consider(top.a, m);
    consider(m, top.b);
    for (int c : opposite) consider(m, c);
  }
  return out;
}

int FindRoot(std::vector<int>& parent, int x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

// The steps of BuildModel, in order.

// Simulation order: (glued) component by component; within one, breadth
// first from its lowest vertex (neighbours in increasing order), for memory
// locality. Glued components (`parent`: union-find over the topology's
// components) are simulated together. Returns the simulation index of each
// welded vertex (-1: unreferenced).
std::vector<int> OrderForSimulation(const MeshTopology& topology, const std::vector<std::pair<int, int>>& glue,
                                    std::vector<int>& parent, Model* model_out, PbdLabels* labels) {
  Model& model = *model_out;
  const int welded_count = topology.VertexCount();
  const int topology_components = topology.stats.components;
  std::vector<std::vector<int>> neighbours(welded_count);
  for (const auto& e : topology.edges) {
    neighbours[e[0]].push_back(e[1]);
    neighbours[e[1]].push_back(e[0]);
  }
  for (const auto& [v, w] : glue) {
    neighbours[v].push_back(w);
    neighbours[w].push_back(v);
  }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  std::vector<int> sim_of_welded(welded_count, -1);
  std::vector<int> seeds;  // lowest vertex of each glued component, in increasing order
  {
    std::vector<std::uint8_t> seen(topology_components, 0);
    for (int v = 0; v < welded_count; ++v) {
      if (!topology.referenced[v]) continue;
      const int root = FindRoot(parent, topology.component[v]);
      if (!seen[root]) {
        seen[root] = 1;
        seeds.push_back(v);
      }
    }
  }
  const int components = static_cast<int>(seeds.size());
  labels->components = components;
  model.vertex_begin.push_back(0);
  for (int seed : seeds) {
    std::size_t head = model.welded.size();
    model.welded.push_back(seed);
    sim_of_welded[seed] = static_cast<int>(model.welded.size()) - 1;
    for (; head < model.welded.size(); ++head) {
      for (int u : neighbours[model.welded[head]]) {
        if (sim_of_welded[u] >= 0) continue;
        sim_of_welded[u] = static_cast<int>(model.welded.size());
        model.welded.push_back(u);
      }
    }
    model.vertex_begin.push_back(static_cast<int>(model.welded.size()));
  }
  model.n = static_cast<int>(model.welded.size());

  return sim_of_welded;
}

// Radii, r_min and sigma (in *labels), rest positions (scaled and centred)
// and masses, with the density given or automatic.
void SetRestAndMasses(const MeshTopology& topology, const std::vector<double>& radii, double scale,
                      const Eigen::Vector3d& centre, const PbdLabelOptions& options, Model* model_out,
                      PbdLabels* labels) {
  Model& model = *model_out;
  const int n = model.n;
  std::vector<double> radius(n);
  double r_min = std::numeric_limits<double>::infinity(), r_sum = 0.0;
  for (int i = 0; i < n; ++i) {
    radius[i] = radii[model.welded[i]] * scale;
    r_sum += radius[i];
    if (radius[i] > 0) r_min = std::min(r_min, radius[i]);
  }
  if (!std::isfinite(r_min)) throw InputError("every medial-sphere radius of D is 0");
  labels->r_min = r_min;
  labels->sigma = options.kappa * r_min;
  const double mean_diameter = 2.0 * r_sum / n;

  // Rest positions and masses.
  model.rest.resize(3 * static_cast<std::size_t>(n));
  model.mass.resize(n);
  double mass_sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const int w = model.welded[i];
    const Eigen::Vector3d x = (topology.vertices[w] - centre) * scale;
    for (int k = 0; k < 3; ++k) model.rest[3 * i + k] = static_cast<float>(x[k]);
    const double height = options.thickness ? 2.0 * radius[i] : mean_diameter;
    model.mass[i] = topology.vertex_areas[w] * scale * scale * height;  // x density below
    mass_sum += model.mass[i];
  }
  // Density: given, or automatic (see pbd_label.h): rho = dt^2 kappa / (2
  // lambda h^3), h the mean edge length of the scaled mesh.
  double edge_sum = 0.0;
  for (const auto& e : topology.edges) edge_sum += (topology.vertices[e[1]] - topology.vertices[e[0]]).norm() * scale;
  const double mean_edge = edge_sum / std::max<std::size_t>(1, topology.edges.size());
  labels->mean_edge = mean_edge;
  labels->density = options.density > 0 ? options.density
                                        : options.time_step * options.time_step * options.kappa /
                                              (2.0 * kLoadStrength * mean_edge * mean_edge * mean_edge);
  for (double& m : model.mass) m *= labels->density;
  mass_sum *= labels->density;
  const double mass_floor = 1e-6 * mass_sum / n;
  for (double& m : model.mass) m = std::max(m, mass_floor);
}

// Constraints: edges and bending pairs (and glue), once per vertex pair,
// sorted; model.constraint_begin per component.
void BuildConstraints(const MeshTopology& topology, const std::vector<int>& sim_of_welded,
                      const std::vector<std::pair<int, int>>& glue, const PbdLabelOptions& options, Model* model_out) {
  Model& model = *model_out;
  const int components = static_cast<int>(model.vertex_begin.size()) - 1;
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(topology.edges.size() * 2);
  for (std::size_t e = 0; e < topology.edges.size(); ++e) {
    const int a = sim_of_welded[topology.edges[e][0]], b = sim_of_welded[topology.edges[e][1]];
    pairs.emplace_back(std::min(a, b), std::max(a, b));
    if (!options.bending) continue;
    const int begin = topology.edge_triangle_offsets[e], end = topology.edge_triangle_offsets[e + 1];
    for (int s = begin; s < end; ++s) {
      for (int t = s + 1; t < end; ++t) {
        int opposite[2];
        for (int side = 0; side < 2; ++side) {
          const auto& tri = topology.triangles[topology.edge_triangles[side == 0 ? s : t]];
          for (int v : tri) {
            if (v != topology.edges[e][0] && v != topology.edges[e][1]) opposite[side] = sim_of_welded[v];
          }
        }
        if (opposite[0] != opposite[1]) {
          pairs.emplace_back(std::min(opposite[0], opposite[1]), std::max(opposite[0], opposite[1]));
        }
      }
    }
  }
  for (const auto& [v, w] : glue) {
    const int a = sim_of_welded[v], b = sim_of_welded[w];
    if (a != b) pairs.emplace_back(std::min(a, b), std::max(a, b));
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  const double k_prime = options.SolverStiffness();
  model.constraints.reserve(pairs.size());
  for (const auto& [i, j] : pairs) {
    Constraint c;
    c.i = i;
    c.j = j;
    // Computed exactly as the projection computes lengths, so that the rest
    // state is an exact fixed point.
    const float dx = model.rest[3 * j] - model.rest[3 * i];
    const float dy = model.rest[3 * j + 1] - model.rest[3 * i + 1];
    const float dz = model.rest[3 * j + 2] - model.rest[3 * i + 2];
    c.rest = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double wi = 1.0 / model.mass[i], wj = 1.0 / model.mass[j];
    c.wi = static_cast<float>(k_prime * wi / (wi + wj));
    c.wj = static_cast<float>(k_prime * wj / (wi + wj));
    model.constraints.push_back(c);
  }
  // Constraints are sorted by their lower vertex and components are
  // contiguous, so each component's constraints are contiguous too.
  model.constraint_begin.assign(components + 1, 0);
  {
    std::size_t c = 0;
    for (int comp = 0; comp < components; ++comp) {
      model.constraint_begin[comp] = static_cast<int>(c);
      while (c < model.constraints.size() && model.constraints[c].i < model.vertex_begin[comp + 1]) ++c;
    }
    model.constraint_begin[components] = static_cast<int>(model.constraints.size());
  }
}

// Gauss-Seidel order: within each component, greedy colouring (in the
// sorted order, each constraint takes the lowest colour that neither of its
// vertices has yet), then colour by colour, each in the sorted order. Two
// consecutive constraints of one colour share no vertex, so the processor
// overlaps their projections instead of waiting for one to store what the
// next loads.
void OrderConstraintsByColour(Model* model_out) {
  Model& model = *model_out;
  const int n = model.n;
  const int components = static_cast<int>(model.vertex_begin.size()) - 1;
  {
    std::vector<std::uint64_t> used(n, 0);
    std::vector<int> colour(model.constraints.size());
    for (std::size_t c = 0; c < model.constraints.size(); ++c) {
      const Constraint& k = model.constraints[c];
      const std::uint64_t taken = used[k.i] | used[k.j];
      const int lowest = taken == ~std::uint64_t{0} ? 63 : __builtin_ctzll(~taken);
      colour[c] = lowest;
      used[k.i] |= std::uint64_t{1} << lowest;
      used[k.j] |= std::uint64_t{1} << lowest;
    }
    std::vector<Constraint> ordered;
    ordered.reserve(model.constraints.size());
    for (int comp = 0; comp < components; ++comp) {
      const int begin = model.constraint_begin[comp], end = model.constraint_begin[comp + 1];
      std::vector<int> order(end - begin);
      std::iota(order.begin(), order.end(), begin);
      std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return colour[a] < colour[b]; });
      for (int c : order) ordered.push_back(model.constraints[c]);
    }
    model.constraints.swap(ordered);
  }
}

Model BuildModel(const MeshTopology& topology, const std::vector<double>& radii, const PbdLabelOptions& options,
                 PbdLabels* labels) {
  Model model;
  // Scale to a box of largest extent 1, centred.
  const Eigen::Vector3d size = topology.bounds.Size();
  const double extent = size.maxCoeff();
  if (!(extent > 0)) throw InputError("the part D has no extent");
  const double scale = 1.0 / extent;
  const Eigen::Vector3d centre = topology.bounds.Center();
  labels->scale = scale;

  // Glue separate components where they touch or overlap; glued components
  // are simulated together.
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  const std::vector<std::pair<int, int>> glue =
      options.glue ? FindGlue(topology, options.glue_tolerance * topology.diagonal, threads)
                   : std::vector<std::pair<int, int>>{};
  labels->glue_constraints = static_cast<std::int64_t>(glue.size());
  const int topology_components = topology.stats.components;
  std::vector<int> parent(topology_components);
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& [v, w] : glue) {
    const int a = FindRoot(parent, topology.component[v]), b = FindRoot(parent, topology.component[w]);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }

  const std::vector<int> sim_of_welded = OrderForSimulation(topology, glue, parent, &model, labels);
  const int n = model.n;

  SetRestAndMasses(topology, radii, scale, centre, options, &model, labels);
  BuildConstraints(topology, sim_of_welded, glue, options, &model);
  OrderConstraintsByColour(&model);
  labels->constraints = static_cast<std::int64_t>(model.constraints.size());

  // Load: f = -sigma n_i, as a velocity increment dt w_i f per step.
  model.load_dv.resize(3 * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d dv =
        -options.time_step / model.mass[i] * labels->sigma * topology.vertex_normals[model.welded[i]];
    for (int k = 0; k < 3; ++k) model.load_dv[3 * i + k] = static_cast<float>(dv[k]);
  }
  return model;
}

// Load cases under a budget ("sum" only, see pbd_label.h; BuildConstraintGraph
// and LoadCaseQuotas below, then SampleLoadCases). `loadable`: per
// simulation vertex (not: vertices inserted by refinement); `area`: the area
// it stands for as a load vertex. Sets `loaded` to the chosen load vertices
// and `cell` to the sample whose cell each simulation vertex lies in, and
// returns the samples' weights (the area they represent; 0 elsewhere).
//
// Quotas: every simulated component gets load cases in proportion to its
// loadable area, but at least kMinLoadCases (a SIMD batch costs the same
// for 1 or 8 lanes), or all its vertices when it has fewer; a component that
// got none would get no values at all (the load of one component does not
// reach another). Within a component: farthest-point sampling in graph
// distance over the constraints (edges, bending pairs and glue: geodesic on
// the surface, so both faces of a thin tongue and small parts glued on get
// samples as their area asks, whatever the mesh density), starting from the
// vertex farthest from the component's first one. Each sample represents its
// cell, the loadable vertices nearer to it than to any other sample.
// Everything is in a fixed order with ties to the lower index: deterministic.
constexpr int kMinLoadCases = kLanes;

// The simulation's vertices as a graph over the constraints (compressed
// rows: the neighbours of i are target[offset[i] .. offset[i + 1]), with
// the constraint's rest length).
struct ConstraintGraph {
  std::vector<int> offset, target;
  std::vector<float> length;
};

ConstraintGraph BuildConstraintGraph(const Model& model) {
  const int n = model.n;
  ConstraintGraph graph;
  std::vector<int>& offset = graph.offset;
  std::vector<int>& target = graph.target;
  std::vector<float>& length = graph.length;
  offset.assign(n + 1, 0);
  for (const Constraint& c : model.constraints) {
    ++offset[c.i + 1];
    ++offset[c.j + 1];
  }
  for (int i = 0; i < n; ++i) offset[i + 1] += offset[i];
  target.resize(offset[n]);
  length.resize(offset[n]);
  {
    std::vector<int> fill(offset.begin(), offset.end() - 1);
    for (const Constraint& c : model.constraints) {
      target[fill[c.i]] = c.j;
      length[fill[c.i]++] = c.rest;
      target[fill[c.j]] = c.i;
      length[fill[c.j]++] = c.rest;
    }
  }
  return graph;
}

// Load cases per simulated component (SampleLoadCases): in proportion to its
// loadable area, at least kMinLoadCases (or 1 where the budget is short) or
// all its loadable vertices; `count` gets the loadable vertices per
// component.
std::vector<std::int64_t> LoadCaseQuotas(const Model& model, const std::vector<std::uint8_t>& loadable,
                                         const std::vector<double>& area, std::int64_t budget,
                                         std::vector<std::int64_t>* count_out) {
  const int components = static_cast<int>(model.vertex_begin.size()) - 1;
  std::vector<std::int64_t>& count = *count_out;
  count.assign(components, 0);
  // Quotas: q_c(lambda) = min(count_c, max(minimum_c, floor(lambda area_c)))
  // grows with lambda; take the largest lambda within the budget, then hand
  // the rest out one by one, largest remainder first.
  std::vector<std::int64_t> minimum(components), quota(components);
  std::vector<double> component_area(components, 0.0);
  for (int c = 0; c < components; ++c) {
    for (int i = model.vertex_begin[c]; i < model.vertex_begin[c + 1]; ++i) {
      if (loadable[i]) {
        ++count[c];
        component_area[c] += area[i];
      }
    }
  }
  std::int64_t minimum_sum = 0;
  for (int c = 0; c < components; ++c) minimum_sum += minimum[c] = std::min<std::int64_t>(count[c], kMinLoadCases);
  if (minimum_sum > budget) {
    for (int c = 0; c < components; ++c) minimum[c] = std::min<std::int64_t>(count[c], 1);
  }
  const auto quotas = [&](double lambda, std::vector<std::int64_t>* out) {
    std::int64_t total = 0;
    for (int c = 0; c < components; ++c) {
      const double share = std::floor(std::min(lambda * component_area[c], 4e18));
      (*out)[c] = std::min(count[c], std::max(minimum[c], static_cast<std::int64_t>(share)));
      total += (*out)[c];
    }
    return total;
  };
  double lo = 0.0, hi = 1.0;
  while (quotas(hi, &quota) <= budget && hi < 1e300) hi *= 2;
  for (int k = 0; k < 200 && lo < hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (quotas(mid, &quota) <= budget ? lo : hi) = mid;
  }
  std::int64_t left = budget - quotas(lo, &quota);
  while (left > 0) {
    int best = -1;
    double best_remainder = -1.0;
    for (int c = 0; c < components; ++c) {
      const double remainder = lo * component_area[c] - static_cast<double>(quota[c]);
      if (quota[c] < count[c] && remainder > best_remainder) {
        best = c;
        best_remainder = remainder;
      }
    }
    if (best < 0) break;
    ++quota[best];
    --left;
  }

  return quota;
}

std::vector<double> SampleLoadCases(const Model& model, const std::vector<std::uint8_t>& loadable,
                                    const std::vector<double>& area, std::int64_t budget,
                                    std::vector<std::uint8_t>* loaded, std::vector<int>* cell) {
  const int n = model.n;
  const int components = static_cast<int>(model.vertex_begin.size()) - 1;
  const ConstraintGraph graph = BuildConstraintGraph(model);
  const std::vector<int>& offset = graph.offset;
  const std::vector<int>& target = graph.target;
  const std::vector<float>& length = graph.length;
  std::vector<std::int64_t> count;
  const std::vector<std::int64_t> quota = LoadCaseQuotas(model, loadable, area, budget, &count);

  // Farthest-point sampling, one component at a time; dist and owner are
  // updated incrementally (a Dijkstra from each new sample only visits the
  // vertices it is nearer to).
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  std::vector<int> owner(n, -1);
  std::vector<double> weight(n, 0.0);
  loaded->assign(n, 0);
  cell->assign(n, -1);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  const auto grow = [&](int source, int label) {
    dist[source] = 0.0;
    owner[source] = label;
    queue.push({0.0, source});
    while (!queue.empty()) {
      const auto [d, v] = queue.top();
      queue.pop();
      if (d > dist[v]) continue;
      for (int e = offset[v]; e < offset[v + 1]; ++e) {
        const double candidate = d + length[e];
        if (candidate < dist[target[e]]) {
          dist[target[e]] = candidate;
          owner[target[e]] = label;
          queue.push({candidate, target[e]});
        }
      }
    }
  };
  const auto farthest = [&](int begin, int end) {  // loadable, not yet a sample; -1 if none
    int best = -1;
    for (int i = begin; i < end; ++i) {
      if (loadable[i] && dist[i] > 0 && (best < 0 || dist[i] > dist[best])) best = i;
    }
    return best;
  };
  for (int c = 0; c < components; ++c) {
    const int begin = model.vertex_begin[c], end = model.vertex_begin[c + 1];
    if (quota[c] == 0) continue;
    std::vector<int> samples;
    if (quota[c] >= count[c]) {
      for (int i = begin; i < end; ++i) {
        if (loadable[i]) samples.push_back(i);
      }
      for (int i : samples) {
        weight[i] = area[i];
        (*loaded)[i] = 1;
        (*cell)[i] = i;
      }
      continue;
    }
    int next = -1;
    for (int i = begin; i < end && next < 0; ++i) {
      if (loadable[i]) next = i;
    }
    grow(next, 0);
    next = farthest(begin, end);
    std::fill(dist.begin() + begin, dist.begin() + end, std::numeric_limits<double>::infinity());
    while (next >= 0 && static_cast<std::int64_t>(samples.size()) < quota[c]) {
      grow(next, static_cast<int>(samples.size()));
      samples.push_back(next);
      next = farthest(begin, end);
    }
    for (int i = begin; i < end; ++i) {
      if (owner[i] < 0) continue;
      (*cell)[i] = samples[owner[i]];
      if (loadable[i]) weight[samples[owner[i]]] += area[i];
    }
    for (int i : samples) (*loaded)[i] = 1;
  }
  return weight;
}

// r_min over reliable spheres (referenced, positive, not a contact); every
// radius is raised to at least r_min, so that a contact's sliver of a
// sphere neither sets the load nor makes a vertex weightless.
std::vector<double> RadiiAtLeastRMin(const MeshTopology& topology, const std::vector<double>& given_radii,
                                     const std::vector<std::uint8_t>& contact) {
  double r_min = std::numeric_limits<double>::infinity();
  for (int v = 0; v < topology.VertexCount(); ++v) {
    if (topology.referenced[v] && given_radii[v] > 0 && (contact.empty() || !contact[v])) {
      r_min = std::min(r_min, given_radii[v]);
    }
  }
  if (!std::isfinite(r_min)) throw InputError("D has no medial sphere of positive radius (outside contacts)");
  std::vector<double> radii(given_radii.size());
  for (std::size_t v = 0; v < radii.size(); ++v) radii[v] = std::max(given_radii[v], r_min);
  return radii;
}

// Which simulated vertices are loaded, and with what weight.
struct LoadPlan {
  std::vector<int> sim_of_vertex;    // D's welded vertex -> simulation index (-1: none)
  std::vector<std::uint8_t> loaded;  // per simulation index
  std::vector<double> load_weight;   // per simulation index
  std::vector<double> represented;   // under a budget: area each vertex stands for
  std::vector<int> cell;             // under a budget: the load case whose cell a vertex is in
};

LoadPlan PlanLoadCases(const MeshTopology& topology, const MeshTopology& refined_topology, const Model& model,
                       const PbdLabelOptions& options) {
  const int n = model.n;
  const MeshTopology& simulated = options.refine > 0 ? refined_topology : topology;
  LoadPlan plan;
  std::vector<int>& sim_of_vertex = plan.sim_of_vertex;
  std::vector<std::uint8_t>& loaded = plan.loaded;
  std::vector<double>& load_weight = plan.load_weight;
  std::vector<double>& represented = plan.represented;
  std::vector<int>& cell = plan.cell;
  // Load cases: one per referenced vertex of D (inserted vertices only add
  // degrees of freedom). sim_of_vertex: D's welded vertex -> simulation index.
  std::vector<int> sim_of_simulated(simulated.VertexCount(), -1);
  for (int i = 0; i < n; ++i) sim_of_simulated[model.welded[i]] = i;
  sim_of_vertex.assign(topology.VertexCount(), -1);
  loaded.assign(n, 0);
  for (int w = 0; w < topology.VertexCount(); ++w) {
    if (!topology.referenced[w]) continue;
    const int s = sim_of_simulated[options.refine > 0 ? refined_topology.welded_of_original[w] : w];
    sim_of_vertex[w] = s;
    if (s >= 0) loaded[s] = 1;
  }
  // Weight of each load case in "sum": its vertex's share of D's area
  // relative to the mean (1 on a uniform mesh), so that the sum approximates
  // an integral over where the load is applied, whatever the sampling.
  load_weight.assign(n, 0.0);
  {
    double area = 0.0;
    int count = 0;
    for (int w = 0; w < topology.VertexCount(); ++w) {
      if (sim_of_vertex[w] >= 0) {
        area += topology.vertex_areas[w];
        ++count;
      }
    }
    if (options.measure == "sum" && options.max_load_cases > 0 && options.max_load_cases < count) {
      // Under a budget: a sample's weight is the area of its cell, in the
      // same units, so the sum stays an estimate of the full sum.
      represented.assign(n, 0.0);
      for (int w = 0; w < topology.VertexCount(); ++w) {
        if (sim_of_vertex[w] >= 0) {
          represented[sim_of_vertex[w]] = options.area_weighted ? topology.vertex_areas[w] * count / area : 1.0;
        }
      }
      const std::vector<std::uint8_t> loadable = loaded;
      load_weight = SampleLoadCases(model, loadable, represented, options.max_load_cases, &loaded, &cell);
    } else {
      for (int w = 0; w < topology.VertexCount(); ++w) {
        if (sim_of_vertex[w] >= 0) {
          load_weight[sim_of_vertex[w]] = options.area_weighted ? topology.vertex_areas[w] * count / area : 1.0;
        }
      }
    }
  }
  return plan;
}

// The load cases in batches of kLanes (one component per batch); the size
// of the largest component in *largest.
std::vector<Batch> MakeBatches(const Model& model, const std::vector<std::uint8_t>& loaded, int* largest_out,
                               std::int64_t* load_cases_out) {
  const int components = static_cast<int>(model.vertex_begin.size()) - 1;
  std::vector<Batch> batches;
  int& largest = *largest_out;
  largest = 0;
  std::int64_t& load_cases = *load_cases_out;
  load_cases = 0;
  for (int c = 0; c < components; ++c) {
    const int begin = model.vertex_begin[c], end = model.vertex_begin[c + 1];
    largest = std::max(largest, end - begin);
    Batch batch{c, 0, {}};
    for (int i = begin; i < end; ++i) {
      if (!loaded[i]) continue;
      batch.load[batch.count++] = i;
      ++load_cases;
      if (batch.count == kLanes) {
        batches.push_back(batch);
        batch.count = 0;
      }
    }
    if (batch.count > 0) batches.push_back(batch);
  }

  return batches;
}

}  // namespace

// Kept as one function (about 170 lines) on purpose: after the set-up
// (RadiiAtLeastRMin, PlanLoadCases, MakeBatches) it is one OpenMP region
// whose per-thread buffers, SIMD lanes and fixed-point sums are shared by
// the simulation and the accumulation; split, a dozen buffers would travel
// by reference through every call of the innermost loop.
PbdLabels ComputePbdLabels(const MeshTopology& topology, const std::vector<double>& given_radii,
                           const std::vector<std::uint8_t>& contact, const PbdLabelOptions& options) {
  options.Check();
  if (static_cast<int>(given_radii.size()) != topology.VertexCount() ||
      (!contact.empty() && contact.size() != given_radii.size())) {
    throw InputError("medial spheres: " + std::to_string(given_radii.size()) + " radii for " +
                     std::to_string(topology.VertexCount()) + " vertices");
  }
  const std::vector<double> radii = RadiiAtLeastRMin(topology, given_radii, contact);
  const auto started = std::chrono::steady_clock::now();
  PbdLabels labels;
  labels.steps = options.Steps();
  labels.solver_stiffness = options.SolverStiffness();
  // Refine long edges over thin places; the simulation runs on the refined
  // mesh and the labels are read off at the original vertices (which keep
  // their indices).
  MeshTopology refined_topology;
  std::vector<double> refined_radii;
  if (options.refine > 0) {
    const RefinedMesh refined = Refine(topology, radii, options.refine, options.refine_min_length * topology.diagonal);
    MeshTopologyOptions keep;
    keep.weld_tolerance = 0;
    keep.orient = false;
    refined_topology = BuildMeshTopology(refined.mesh, keep);
    refined_radii.assign(refined_topology.VertexCount(), 0.0);
    for (int i = static_cast<int>(refined.radii.size()) - 1; i >= 0; --i) {
      refined_radii[refined_topology.welded_of_original[i]] = refined.radii[i];
    }
  }
  const MeshTopology& simulated = options.refine > 0 ? refined_topology : topology;
  const Model model = BuildModel(simulated, options.refine > 0 ? refined_radii : radii, options, &labels);
  const int n = model.n;

  // Load cases: one per referenced vertex of D (inserted vertices only add
  // degrees of freedom); under a budget, a sample of them.
  const LoadPlan plan = PlanLoadCases(topology, refined_topology, model, options);
  const std::vector<int>& sim_of_vertex = plan.sim_of_vertex;
  const std::vector<std::uint8_t>& loaded = plan.loaded;
  const std::vector<double>& load_weight = plan.load_weight;
  const std::vector<double>& represented = plan.represented;
  const std::vector<int>& cell = plan.cell;
  int largest = 0;
  std::int64_t load_cases = 0;
  const std::vector<Batch> batches = MakeBatches(model, loaded, &largest, &load_cases);
  labels.load_cases = load_cases;

  const bool sum = options.measure == "sum";
  std::vector<double> self(n, 0.0);
  // Fixed point for "sum": integer addition is associative, so the result
  // does not depend on which thread added what first.
  constexpr double kFixed = 268435456.0;  // 2^28 units per scaled-mesh unit
  constexpr double kTermLimit = 1e15;     // fixed-point units per term: sums stay far from int64 overflow
  std::vector<std::int64_t> accumulated(sum ? n : 0, 0);
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  const float dt = static_cast<float>(options.time_step);
  const float inverse_dt = static_cast<float>(1.0 / options.time_step);
  const float damping = static_cast<float>(options.damping);
  std::atomic<std::int64_t> done{0};
  double thread_seconds = 0.0;

#pragma omp parallel num_threads(threads) reduction(+ : thread_seconds)
  {
    // Displacements decay to subnormal floats far from the load, which are
    // very slow to compute with; flush them to zero (deterministically).
    const unsigned int saved_csr = _mm_getcsr();
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
    // Per-thread state, allocated once.
    const std::size_t capacity = static_cast<std::size_t>(largest) * 3 * kLanes;
    std::vector<float> x(capacity), p(capacity), v(capacity);
    std::vector<double> residual(largest);
    std::vector<std::int64_t> local_sum(sum ? n : 0, 0);
#pragma omp for schedule(dynamic, 1)
    for (std::size_t b = 0; b < batches.size(); ++b) {
      if (CancelRequested()) continue;  // thrown after the region (core/cancel.h)
      const auto batch_started = std::chrono::steady_clock::now();
      const Batch& batch = batches[b];
      const int begin = model.vertex_begin[batch.component], end = model.vertex_begin[batch.component + 1];
      const int count = end - begin;
      const std::size_t values = static_cast<std::size_t>(count) * 3 * kLanes;
      for (int local = 0; local < count; ++local) {
        for (int k = 0; k < 3; ++k) {
          const float r = model.rest[3 * (begin + local) + k];
          float* xs = &x[(static_cast<std::size_t>(local) * 3 + k) * kLanes];
          float* ps = &p[(static_cast<std::size_t>(local) * 3 + k) * kLanes];
          for (int l = 0; l < kLanes; ++l) xs[l] = ps[l] = r;
        }
      }
      std::fill(v.begin(), v.begin() + values, 0.0f);
      const Constraint* constraints = model.constraints.data() + model.constraint_begin[batch.component];
      const int constraint_count =
          model.constraint_begin[batch.component + 1] - model.constraint_begin[batch.component];
      for (int step = 0; step < labels.steps; ++step) {
        for (int l = 0; l < batch.count; ++l) {
          const int g = batch.load[l];
          for (int k = 0; k < 3; ++k) {
            v[(static_cast<std::size_t>(g - begin) * 3 + k) * kLanes + l] += model.load_dv[3 * g + k];
          }
        }
        Predict(v.data(), p.data(), x.data(), values, damping, dt);
        for (int it = 0; it < options.solver_iterations; ++it) {
          ProjectConstraints(constraints, constraint_count, p.data(), begin);
        }
        UpdateVelocities(v.data(), p.data(), x.data(), values, inverse_dt);
      }
      for (int l = 0; l < batch.count; ++l) {
        RigidResiduals(model, begin, end, x.data(), l, residual.data());
        const int g = batch.load[l];
        self[g] = residual[g - begin];
        if (sum && cell.empty()) {
          for (int local = 0; local < count; ++local) {
            const double term = std::min(load_weight[g] * residual[local] * kFixed, kTermLimit);
            local_sum[begin + local] += static_cast<std::int64_t>(std::llround(term));
          }
        } else if (sum) {
          // Under a budget, the load case stands for the loads on every
          // vertex of its cell. Far from the cell that is its response times
          // the cell's area; inside the cell, its response peaks at the load
          // vertex, where loads on the other vertices of the cell would not
          // (each would peak at its own vertex). So the cell gets the total
          // of the response over the cell, sum_k area_k r_k, spread evenly:
          // the cell's share of the sum is kept, without a spike at every
          // sample.
          double near = 0.0;
          for (int local = 0; local < count; ++local) {
            if (cell[begin + local] == g) near += represented[begin + local] * residual[local];
          }
          for (int local = 0; local < count; ++local) {
            const double value = cell[begin + local] == g ? near : load_weight[g] * residual[local];
            const double term = std::min(value * kFixed, kTermLimit);
            local_sum[begin + local] += static_cast<std::int64_t>(std::llround(term));
          }
        }
      }
      thread_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - batch_started).count();
      const std::int64_t finished = done += batch.count;
      if (options.progress && omp_get_thread_num() == 0) options.progress(finished, load_cases);
    }
    if (sum) {
#pragma omp critical(ausbau_pbd_sum)
      for (int i = 0; i < n; ++i) accumulated[i] += local_sum[i];
    }
    _mm_setcsr(saved_csr);
  }
  ThrowIfCancelled();
  if (options.progress) options.progress(load_cases, load_cases);
  labels.thread_seconds = thread_seconds;

  // Values at D's vertices, normalized over them.
  labels.displacement.assign(topology.VertexCount(), 0.0);
  labels.deformability.assign(topology.VertexCount(), 0.0);
  labels.load_weight.assign(topology.VertexCount(), 0.0);
  for (int w = 0; w < topology.VertexCount(); ++w) {
    if (sim_of_vertex[w] >= 0 && loaded[sim_of_vertex[w]]) labels.load_weight[w] = load_weight[sim_of_vertex[w]];
  }
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int w = 0; w < topology.VertexCount(); ++w) {
    const int i = sim_of_vertex[w];
    if (i < 0) continue;
    const double value = sum ? static_cast<double>(accumulated[i]) / kFixed : self[i];
    labels.displacement[w] = value;
    lo = std::min(lo, value);
    hi = std::max(hi, value);
  }
  for (int w = 0; w < topology.VertexCount(); ++w) {
    if (sim_of_vertex[w] >= 0 && hi > lo) labels.deformability[w] = (labels.displacement[w] - lo) / (hi - lo);
  }
  labels.simulated_vertices = n;
  labels.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return labels;
}

void SpheresPerWeldedVertex(const MeshTopology& topology, const SpheresArtifact& spheres, const std::string& source,
                            std::vector<double>* radii_out, std::vector<std::uint8_t>* contact_out) {
  if (static_cast<int>(spheres.radii.size()) != topology.OriginalVertexCount()) {
    throw InputErrorAt(source, "holds " + std::to_string(spheres.radii.size()) + " spheres but D has " +
                                   std::to_string(topology.OriginalVertexCount()) +
                                   " vertices (computed for another part?)");
  }
  std::vector<double>& radii = *radii_out;
  std::vector<std::uint8_t>& contact = *contact_out;
  radii.assign(topology.VertexCount(), 0.0);
  contact.assign(topology.VertexCount(), 0);
  std::vector<std::uint8_t> set(topology.VertexCount(), 0);
  for (int i = 0; i < topology.OriginalVertexCount(); ++i) {
    const int w = topology.welded_of_original[i];
    if (set[w] || !spheres.valid[i]) continue;
    radii[w] = spheres.radii[i];
    contact[w] = spheres.contact[i];
    set[w] = 1;
  }
}

// ---------------------------------------------------------------- artifact

LabelsArtifact ToLabelsArtifact(const MeshTopology& topology, const PbdLabels& labels, const std::string& measure) {
  LabelsArtifact out;
  const int n = topology.OriginalVertexCount();
  out.deformability.resize(n);
  out.displacement.resize(n);
  for (int i = 0; i < n; ++i) {
    out.deformability[i] = labels.deformability[topology.welded_of_original[i]];
    out.displacement[i] = labels.displacement[topology.welded_of_original[i]];
  }
  out.r_min = labels.r_min;
  out.sigma = labels.sigma;
  out.scale = labels.scale;
  out.density = labels.density;
  out.measure = measure;
  out.load_cases = labels.load_cases;
  return out;
}

void WriteLabelsArtifact(const std::filesystem::path& path, const LabelsArtifact& labels,
                         const Provenance& provenance) {
  const std::size_t n = labels.deformability.size();
  ArtifactWriter writer(path, kLabelsSchema, kLabelsSchemaVersion, provenance);
  writer.WriteDoubles("deformability", labels.deformability, {n});
  writer.WriteDoubles("displacement", labels.displacement, {n});
  writer.SetAttribute("", "r_min", labels.r_min);
  writer.SetAttribute("", "sigma", labels.sigma);
  writer.SetAttribute("", "scale", labels.scale);
  writer.SetAttribute("", "density", labels.density);
  writer.SetAttribute("", "measure", labels.measure);
  writer.SetAttribute("", "load_cases", labels.load_cases);
  writer.SetAttribute("", "vertices", static_cast<std::int64_t>(n));
  writer.Commit();
}

LabelsArtifact ReadLabelsArtifact(const std::filesystem::path& path) {
  ArtifactReader reader(path, kLabelsSchema, kLabelsSchemaVersion);
  LabelsArtifact out;
  out.deformability = reader.ReadDoubles("deformability", 1).data;
  if (reader.Has("displacement")) {
    out.displacement = reader.ReadDoubles("displacement", 1).data;
    if (out.displacement.size() != out.deformability.size()) {
      throw InputErrorAt(path.string(), "dataset 'displacement' does not match 'deformability' in shape");
    }
  }
  for (std::size_t i = 0; i < out.deformability.size(); ++i) {
    if (!(out.deformability[i] >= 0 && out.deformability[i] <= 1)) {
      throw InputErrorAt(path.string(), "dataset 'deformability' holds a value outside [0, 1] at " + std::to_string(i));
    }
  }
  for (std::size_t i = 0; i < out.displacement.size(); ++i) {
    if (!std::isfinite(out.displacement[i])) {
      throw InputErrorAt(path.string(), "dataset 'displacement' holds a non-finite value at " + std::to_string(i));
    }
  }
  auto finite_attribute = [&](const char* name) {
    const double value = reader.ReadDoubleAttribute("", name);
    if (!std::isfinite(value))
      throw InputErrorAt(path.string(), std::string("root attribute '") + name + "' is not finite");
    return value;
  };
  out.r_min = finite_attribute("r_min");
  out.sigma = finite_attribute("sigma");
  out.scale = finite_attribute("scale");
  out.density = finite_attribute("density");
  out.measure = reader.ReadStringAttribute("", "measure");
  out.load_cases = reader.ReadIntAttribute("", "load_cases");
  return out;
}

void WriteLabelsCsv(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& vertices,
                    const std::vector<double>& deformability) {
  std::string text = "x,y,z,deformability\n";
  text.reserve(80 * vertices.size() + 24);
  char line[160];
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g\n", vertices[i].x(), vertices[i].y(), vertices[i].z(),
                  deformability[i]);
    text += line;
  }
  WriteTextFileAtomically(path, text);
}

}  // namespace ausbau
