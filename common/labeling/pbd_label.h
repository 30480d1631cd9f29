// Phase II of the deformability labeling (thesis 5.4.1, algorithm 10): a
// position based dynamics simulation (Mueller et al. 2007) of D's surface,
// one load case per vertex, gives every vertex a deformation value.
//
// Model (the thesis's values):
//  - D's welded mesh is scaled to an axis-aligned box of largest extent 1
//    (and centred, for float precision).
//  - Vertex masses: m_i = rho x (a third of the area of the incident
//    triangles) x (the local diameter: twice the medial-sphere radius).
//  - Constraints: a distance constraint per edge, and a bending constraint
//    per pair of triangles sharing an edge, realized as a distance constraint
//    between the two vertices opposite the edge. A pair of vertices is
//    constrained once (a bending pair that is also an edge, rare, adds
//    nothing). Gauss-Seidel projection in a fixed order.
//  - dt = 30 ms for 1 s: ceil(1 / 0.03) = 34 steps; N = 3 solver iterations;
//    linear velocity damping v <- 0.99 v every step.
//  - Stiffness k = 0.99 per iteration as k' = 1 - (1 - k)^N, as the thesis
//    writes it (k' = 0.999999, practically rigid constraints). Mueller et
//    al. 2007 write k' = 1 - (1 - k)^(1/N) (k' = 0.785, so that N iterations
//    together give k); `stiffness_formula = "mueller"` selects that form.
//  - Load case i: a constant external force f = -sigma n_i on vertex i only
//    (against its outward normal), sigma = kappa x r_min, kappa = 5.25, r_min
//    the smallest medial-sphere radius in the scaled mesh.
// Anchoring: D is free, so a load case also moves D rigidly. Deformation is
// measured relative to the best rigid motion: at the end of a load case the
// mass-weighted best-fit rigid transform (Kabsch) of the rest positions onto
// the simulated ones is computed, and a vertex's displacement is its
// distance from where that transform puts it. Only the load vertex's
// connected component is simulated (and fitted); other components do not
// feel the load.
// Deformation value (`measure`):
//  - "self" (default): vertex i's displacement at the end of its own load
//    case: how far a push on i moves i relative to the part;
//  - "sum": the thesis's wording (the displacements of all vertices are
//    "summed over all iterations" of the load-case loop): vertex j's value is
//    the sum over all load cases of j's displacement at their end.
// Normalization: deformability = (d - d_min) / (d_max - d_min) over the
// simulated vertices, so the stiffest vertex is 0 and the most deformable 1
// (all 0 when every value is equal); the raw values are kept too.
// Parallelism and determinism: load cases run 8 at a time in SIMD lanes (one
// simulation per lane over the same constraints) and batches of 8 in
// parallel over OpenMP threads, each thread with its own buffers (the inner
// loop allocates nothing). Lanes never interact and "sum" accumulates in
// fixed point (integers), so results are identical for any thread count.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "artifact/artifact.h"
#include "labeling/medial_spheres.h"
#include "labeling/mesh_topology.h"

namespace ausbau {

struct PbdLabelOptions {
  double time_step = 0.03;  // s
  double duration = 1.0;    // s; steps = ceil(duration / time_step)
  int solver_iterations = 3;
  double damping = 0.99;    // v <- damping x v every step
  double stiffness = 0.99;  // k
  std::string stiffness_formula = "thesis";  // thesis: 1 - (1 - k)^N; mueller: 1 - (1 - k)^(1/N)
  double kappa = 5.25;      // sigma = kappa x r_min
  double density = 1.0;     // rho, in the scaled mesh
  bool bending = true;      // bending constraints (thesis figure 42: needed)
  bool thickness = true;    // masses from the sphere diameters (false: a constant height, the mean diameter)
  std::string measure = "self";  // self | sum
  int threads = 0;          // 0 = all (OpenMP)
  // Called from one thread with the number of load cases done so far.
  std::function<void(std::int64_t done, std::int64_t total)> progress;

  void Check() const;  // throws InputError on values out of range
  int Steps() const;
  double SolverStiffness() const;  // k'
};

struct PbdLabels {
  // Per welded vertex of the topology; vertices in no triangle get 0.
  std::vector<double> deformability;  // [0, 1], higher = more deformable
  std::vector<double> displacement;   // raw deformation value, in the scaled mesh (largest extent 1)
  double scale = 1.0;                 // mesh units -> scaled mesh
  double r_min = 0.0;                 // smallest medial-sphere radius, scaled mesh
  double sigma = 0.0;                 // kappa x r_min
  int steps = 0;
  double solver_stiffness = 0.0;      // k'
  std::int64_t load_cases = 0;
  std::int64_t constraints = 0;
  double seconds = 0.0;         // wall-clock time of the labeling (set-up included)
  double thread_seconds = 0.0;  // time spent simulating, summed over threads
  double SecondsPerLoadCase() const { return load_cases > 0 ? thread_seconds / load_cases : 0.0; }
};

// `radii`: medial-sphere radius per welded vertex, in mesh units.
PbdLabels ComputePbdLabels(const MeshTopology& topology, const std::vector<double>& radii,
                           const PbdLabelOptions& options);

// Radius per welded vertex from a spheres artifact (per original vertex):
// the radius of the first valid original vertex of each welded vertex.
// Throws InputError naming `source` when the vertex counts differ.
std::vector<double> RadiiPerWeldedVertex(const MeshTopology& topology, const SpheresArtifact& spheres,
                                         const std::string& source);

// ---- the `ausbau-labels` artifact (schemas/labels.md)

inline constexpr const char* kLabelsSchema = "ausbau-labels";
inline constexpr int kLabelsSchemaVersion = 1;

// Per ORIGINAL vertex of D (as loaded by LoadScene).
struct LabelsArtifact {
  std::vector<double> deformability;
  std::vector<double> displacement;
  double r_min = 0.0;
  double sigma = 0.0;
  double scale = 1.0;
  std::string measure;
  std::int64_t load_cases = 0;
};

LabelsArtifact ToLabelsArtifact(const MeshTopology& topology, const PbdLabels& labels, const std::string& measure);
void WriteLabelsArtifact(const std::filesystem::path& path, const LabelsArtifact& labels,
                         const Provenance& provenance);
LabelsArtifact ReadLabelsArtifact(const std::filesystem::path& path);
// CSV `x,y,z,deformability`, one row per original vertex in D's mesh
// coordinates, 17 significant digits. Written atomically.
void WriteLabelsCsv(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& vertices,
                    const std::vector<double>& deformability);

// Area under the ROC curve of `score` separating positives (label 1) from
// negatives (label 0); ties count one half. Used by tests and benchmarks.
double RocAuc(const std::vector<double>& score, const std::vector<std::uint8_t>& positive);

}  // namespace ausbau
