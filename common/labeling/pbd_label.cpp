#include "labeling/pbd_label.h"

#include <omp.h>
#if defined(__SSE2__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#endif

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "core/atomic_file.h"
#include "core/error.h"

namespace ausbau {

void PbdLabelOptions::Check() const {
  if (!(time_step > 0)) throw InputError("--time-step: must be positive");
  if (!(duration > 0)) throw InputError("--duration: must be positive");
  if (Steps() > 100000) throw InputError("--duration: more than 100000 steps of --time-step");
  if (solver_iterations < 1) throw InputError("--iterations: must be at least 1");
  if (!(damping >= 0 && damping <= 1)) throw InputError("--damping: must lie in [0, 1]");
  if (!(stiffness >= 0 && stiffness <= 1)) throw InputError("--stiffness: must lie in [0, 1]");
  if (stiffness_formula != "thesis" && stiffness_formula != "mueller") {
    throw InputError("--stiffness-formula: expected thesis or mueller, got '" + stiffness_formula + "'");
  }
  if (!(kappa > 0)) throw InputError("--kappa: must be positive");
  if (!(density > 0)) throw InputError("--density: must be positive");
  if (measure != "self" && measure != "sum") throw InputError("--measure: expected self or sum, got '" + measure + "'");
  if (threads < 0) throw InputError("--threads: must be at least 0");
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

constexpr int kLanes = 8;  // load cases simulated together (SIMD lanes)

struct Constraint {
  int i, j;    // simulation vertex indices, i < j
  float rest;  // rest length
  float wi, wj;  // k' w_i / (w_i + w_j), k' w_j / (w_i + w_j)
};

// One Gauss-Seidel sweep over `count` constraints for kLanes simulations.
// p: positions of the component, [vertex][coordinate][lane], vertex indices
// relative to the component's first vertex `base`.
__attribute__((target_clones("avx2", "default"))) void ProjectConstraints(const Constraint* constraints, int count,
                                                                          float* p, int base) {
  constexpr float kTiny = 1e-20f;
  for (int c = 0; c < count; ++c) {
    const Constraint& k = constraints[c];
    float* __restrict pi = p + static_cast<std::size_t>(k.i - base) * 3 * kLanes;
    float* __restrict pj = p + static_cast<std::size_t>(k.j - base) * 3 * kLanes;
    float dx[kLanes], dy[kLanes], dz[kLanes], s[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      dx[l] = pj[l] - pi[l];
      dy[l] = pj[kLanes + l] - pi[kLanes + l];
      dz[l] = pj[2 * kLanes + l] - pi[2 * kLanes + l];
    }
    for (int l = 0; l < kLanes; ++l) {
      const float length = std::sqrt(dx[l] * dx[l] + dy[l] * dy[l] + dz[l] * dz[l]);
      s[l] = (length - k.rest) / std::max(length, kTiny);
    }
    for (int l = 0; l < kLanes; ++l) {
      pi[l] += k.wi * s[l] * dx[l];
      pi[kLanes + l] += k.wi * s[l] * dy[l];
      pi[2 * kLanes + l] += k.wi * s[l] * dz[l];
      pj[l] -= k.wj * s[l] * dx[l];
      pj[kLanes + l] -= k.wj * s[l] * dy[l];
      pj[2 * kLanes + l] -= k.wj * s[l] * dz[l];
    }
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
  int n = 0;                     // simulated vertices
  std::vector<int> welded;       // simulation index -> welded vertex
  std::vector<float> rest;       // [n][3], scaled and centred
  std::vector<double> mass;      // [n]
  std::vector<float> load_dv;    // [n][3]: velocity increment per step of the load case on that vertex
  std::vector<Constraint> constraints;
  std::vector<int> vertex_begin;      // per component, size components + 1
  std::vector<int> constraint_begin;  // per component, size components + 1
};

struct Batch {
  int component;
  int first;  // first load vertex (simulation index)
  int count;  // load cases in the batch, <= kLanes
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

Model BuildModel(const MeshTopology& topology, const std::vector<double>& radii, const PbdLabelOptions& options,
                 PbdLabels* labels) {
  Model model;
  const int welded_count = topology.VertexCount();
  // Scale to a box of largest extent 1, centred.
  const Eigen::Vector3d size = topology.bounds.Size();
  const double extent = size.maxCoeff();
  if (!(extent > 0)) throw InputError("the part D has no extent");
  const double scale = 1.0 / extent;
  const Eigen::Vector3d centre = topology.bounds.Center();
  labels->scale = scale;

  // Simulation order: component by component; within one, breadth first from
  // its lowest vertex (neighbours in increasing order), for memory locality.
  std::vector<std::vector<int>> neighbours(welded_count);
  for (const auto& e : topology.edges) {
    neighbours[e[0]].push_back(e[1]);
    neighbours[e[1]].push_back(e[0]);
  }
  for (auto& list : neighbours) std::sort(list.begin(), list.end());
  std::vector<int> sim_of_welded(welded_count, -1);
  const int components = topology.stats.components;
  std::vector<int> component_seed(components, -1);
  for (int v = 0; v < welded_count; ++v) {
    if (topology.referenced[v] && component_seed[topology.component[v]] < 0) component_seed[topology.component[v]] = v;
  }
  model.vertex_begin.push_back(0);
  for (int c = 0; c < components; ++c) {
    const int seed = component_seed[c];
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
  const int n = model.n;

  // Radii, r_min, sigma.
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
    model.mass[i] = options.density * topology.vertex_areas[w] * scale * scale * height;
    mass_sum += model.mass[i];
  }
  const double mass_floor = 1e-6 * mass_sum / n;
  for (double& m : model.mass) m = std::max(m, mass_floor);

  // Constraints: edges and bending pairs, once per vertex pair.
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
  labels->constraints = static_cast<std::int64_t>(model.constraints.size());

  // Load: f = -sigma n_i, as a velocity increment dt w_i f per step.
  model.load_dv.resize(3 * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d dv = -options.time_step / model.mass[i] * labels->sigma * topology.vertex_normals[model.welded[i]];
    for (int k = 0; k < 3; ++k) model.load_dv[3 * i + k] = static_cast<float>(dv[k]);
  }
  return model;
}

}  // namespace

PbdLabels ComputePbdLabels(const MeshTopology& topology, const std::vector<double>& radii,
                           const PbdLabelOptions& options) {
  options.Check();
  if (static_cast<int>(radii.size()) != topology.VertexCount()) {
    throw InputError("medial-sphere radii: " + std::to_string(radii.size()) + " values for " +
                     std::to_string(topology.VertexCount()) + " vertices");
  }
  const auto started = std::chrono::steady_clock::now();
  PbdLabels labels;
  labels.steps = options.Steps();
  labels.solver_stiffness = options.SolverStiffness();
  const Model model = BuildModel(topology, radii, options, &labels);
  const int n = model.n;
  const int components = static_cast<int>(model.vertex_begin.size()) - 1;

  std::vector<Batch> batches;
  int largest = 0;
  for (int c = 0; c < components; ++c) {
    const int begin = model.vertex_begin[c], end = model.vertex_begin[c + 1];
    largest = std::max(largest, end - begin);
    for (int first = begin; first < end; first += kLanes) batches.push_back({c, first, std::min(kLanes, end - first)});
  }
  labels.load_cases = n;

  const bool sum = options.measure == "sum";
  std::vector<double> self(n, 0.0);
  // Fixed point for "sum": integer addition is associative, so the result
  // does not depend on which thread added what first.
  constexpr double kFixed = 4294967296.0;  // 2^32 units per scaled-mesh unit
  std::vector<std::int64_t> accumulated(sum ? n : 0, 0);
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  const float dt = static_cast<float>(options.time_step);
  const float inverse_dt = static_cast<float>(1.0 / options.time_step);
  const float damping = static_cast<float>(options.damping);
  std::atomic<std::int64_t> done{0};
  double thread_seconds = 0.0;

#pragma omp parallel num_threads(threads) reduction(+ : thread_seconds)
  {
#if defined(__SSE2__)
    // Displacements decay to subnormal floats far from the load, which are
    // very slow to compute with; flush them to zero (deterministically).
    const unsigned int saved_csr = _mm_getcsr();
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
#endif
    // Per-thread state, allocated once.
    const std::size_t capacity = static_cast<std::size_t>(largest) * 3 * kLanes;
    std::vector<float> x(capacity), p(capacity), v(capacity);
    std::vector<double> residual(largest);
    std::vector<std::int64_t> local_sum(sum ? n : 0, 0);
#pragma omp for schedule(dynamic, 1)
    for (std::size_t b = 0; b < batches.size(); ++b) {
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
          const int g = batch.first + l;
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
        const int g = batch.first + l;
        self[g] = residual[g - begin];
        if (sum) {
          for (int local = 0; local < count; ++local) {
            local_sum[begin + local] += static_cast<std::int64_t>(std::llround(residual[local] * kFixed));
          }
        }
      }
      thread_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - batch_started).count();
      const std::int64_t finished = done += batch.count;
      if (options.progress && omp_get_thread_num() == 0) options.progress(finished, n);
    }
    if (sum) {
#pragma omp critical(ausbau_pbd_sum)
      for (int i = 0; i < n; ++i) accumulated[i] += local_sum[i];
    }
#if defined(__SSE2__)
    _mm_setcsr(saved_csr);
#endif
  }
  if (options.progress) options.progress(n, n);
  labels.thread_seconds = thread_seconds;

  std::vector<double> value(n);
  for (int i = 0; i < n; ++i) value[i] = sum ? static_cast<double>(accumulated[i]) / kFixed : self[i];
  const double lo = n > 0 ? *std::min_element(value.begin(), value.end()) : 0.0;
  const double hi = n > 0 ? *std::max_element(value.begin(), value.end()) : 0.0;
  labels.displacement.assign(topology.VertexCount(), 0.0);
  labels.deformability.assign(topology.VertexCount(), 0.0);
  for (int i = 0; i < n; ++i) {
    const int w = model.welded[i];
    labels.displacement[w] = value[i];
    labels.deformability[w] = hi > lo ? (value[i] - lo) / (hi - lo) : 0.0;
  }
  labels.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return labels;
}

std::vector<double> RadiiPerWeldedVertex(const MeshTopology& topology, const SpheresArtifact& spheres,
                                         const std::string& source) {
  if (static_cast<int>(spheres.radii.size()) != topology.OriginalVertexCount()) {
    throw InputErrorAt(source, "holds " + std::to_string(spheres.radii.size()) + " spheres but D has " +
                                   std::to_string(topology.OriginalVertexCount()) +
                                   " vertices (computed for another part?)");
  }
  std::vector<double> radii(topology.VertexCount(), 0.0);
  std::vector<std::uint8_t> set(topology.VertexCount(), 0);
  for (int i = 0; i < topology.OriginalVertexCount(); ++i) {
    const int w = topology.welded_of_original[i];
    if (set[w] || !spheres.valid[i]) continue;
    radii[w] = spheres.radii[i];
    set[w] = 1;
  }
  return radii;
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
  out.r_min = reader.ReadDoubleAttribute("", "r_min");
  out.sigma = reader.ReadDoubleAttribute("", "sigma");
  out.scale = reader.ReadDoubleAttribute("", "scale");
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

double RocAuc(const std::vector<double>& score, const std::vector<std::uint8_t>& positive) {
  std::vector<int> order(score.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return score[a] < score[b]; });
  // Mann-Whitney U with average ranks for ties.
  double rank_sum = 0.0;
  std::int64_t positives = 0, negatives = 0;
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j < order.size() && score[order[j]] == score[order[i]]) ++j;
    const double average_rank = 0.5 * (static_cast<double>(i + 1) + static_cast<double>(j));
    for (std::size_t k = i; k < j; ++k) {
      if (positive[order[k]]) {
        rank_sum += average_rank;
        ++positives;
      } else {
        ++negatives;
      }
    }
    i = j;
  }
  if (positives == 0 || negatives == 0) return 0.5;
  return (rank_sum - 0.5 * static_cast<double>(positives) * (positives + 1)) /
         (static_cast<double>(positives) * negatives);
}

}  // namespace ausbau
