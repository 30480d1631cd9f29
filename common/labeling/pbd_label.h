// Phase II of the deformability labeling (thesis 5.4.1, algorithm 10): a
// position based dynamics simulation (Mueller et al. 2007) of D's surface,
// one load case per vertex (or per vertex of a well-spread subset: the
// load-case budget below), gives every vertex a deformation value.
//
// Model (the thesis's values):
//  - D's welded mesh is scaled to an axis-aligned box of largest extent 1
//    (and centred, for float precision).
//  - Vertex masses: m_i = rho x (a third of the area of the incident
//    triangles) x (the local diameter: twice the medial-sphere radius, at
//    least 2 r_min).
//  - Constraints: a distance constraint per edge, and a bending constraint
//    per pair of triangles sharing an edge, realized as a distance constraint
//    between the two vertices opposite the edge. A pair of vertices is
//    constrained once (a bending pair that is also an edge, rare, adds
//    nothing). Gauss-Seidel projection in a fixed order (by colour, see
//    pbd_label.cpp).
//  - dt = 30 ms for 1 s: ceil(1 / 0.03) = 34 steps; N = 3 solver iterations;
//    linear velocity damping v <- 0.99 v every step.
//  - Stiffness k = 0.99 per iteration as k' = 1 - (1 - k)^N, as the thesis
//    writes it (k' = 0.999999, practically rigid constraints). Mueller et
//    al. 2007 write k' = 1 - (1 - k)^(1/N) (k' = 0.785, so that N iterations
//    together give k); `stiffness_formula = "mueller"` selects that form.
//  - Load case i: a constant external force f = -sigma n_i on vertex i only
//    (against its outward normal), sigma = kappa x r_min, kappa = 5.25, r_min
//    the smallest medial-sphere radius in the scaled mesh (spheres flagged as
//    contacts, see medial_spheres.h, left out).
// Density: the thesis gives none, and it matters: the dynamics depend on
// the force only through sigma / rho (accelerations; constraint projection
// uses mass ratios only), so kappa and rho are one knob. Too light a mesh
// (rho = 1 on a mesh of a few thousand vertices) is thrown about by the load
// (a free vertex would move tens of edge lengths per step) and the labels
// turn to noise; and the per-vertex masses shrink with the mesh resolution.
// So by default rho is chosen per mesh so that the load's effect is the
// same fraction of the mesh's edge length at any resolution: a free vertex of
// area h^2 at the thinnest place (diameter 2 r_min) moves lambda h in one
// step, h the mean edge length of the scaled mesh, lambda = 0.1:
//   rho = dt^2 kappa / (2 lambda h^3).
// On the box with a thin tongue (tests/labeling/test_labeling.cpp) the labels separate
// the tongue for rho from 10 to 10^5 at two resolutions (ROC AUC >= 0.998);
// rho = 1 gives 0.85-1.0 (and "self" 0.27-0.85). `density` > 0 sets rho
// directly.
// Anchoring: D is free, so a load case also moves D rigidly. Deformation is
// measured relative to the best rigid motion: at the end of a load case the
// mass-weighted best-fit rigid transform (Kabsch) of the rest positions onto
// the simulated ones is computed, and a vertex's displacement is its
// distance from where that transform puts it. Only the load vertex's
// (glued) component is simulated and fitted; other components do not feel
// the load.
// Separate solids (`glue`): CAD parts often model a clip, a rim or a rail as
// its own closed solid overlapping (or touching) the panel. Simulated alone,
// such a solid can only move rigidly, and the rigid fit removes all of it. So
// a vertex that lies inside another closed component (ray parity) or within
// glue_tolerance x D's diagonal of another component is tied by distance
// constraints to the three vertices of that component's nearest triangle,
// and glued components are simulated as one.
// Deformation value (`measure`):
//  - "sum" (default): the thesis's wording (the displacements of all
//    vertices are "summed over all iterations" of the load-case loop):
//    vertex j's value is the sum over all load cases i of j's displacement
//    at their end, each load case weighted by its vertex's share of D's area
//    (area_i / mean area: 1 on a uniform mesh), so that the sum does not
//    depend on where the mesh happens to be fine. A cantilever moves when it
//    is pushed and lags behind when the rest of the part is pushed, so it
//    collects from every load case;
//  - "self": vertex i's displacement at the end of its own load case only
//    (a driving-point compliance). Measured: on the clip scenes as good as
//    "sum" (ROC AUC 0.98-1.0), on the thick-tongue test worse (0.85-0.92 for
//    tongues a third as thick as the box, against 0.96-1.0).
// Load-case budget (`max_load_cases`, "sum" only): a load case costs a
// simulation of the whole component, so loading every vertex is quadratic in
// the mesh size (clips-ds1, 34k vertices: 442 s with 2 threads). Under a
// budget, loads are applied at most at max_load_cases vertices and every
// vertex is still simulated and valued. The sum over load cases is an
// integral over where the load is applied, so a subset estimates it: every
// simulated component gets load cases in proportion to its area (at least
// 8, a SIMD batch, or all its vertices when it has fewer), placed by
// farthest-point sampling in distance along the constraints (geodesic: both
// faces of a thin tongue count), and each sample is weighted by the area of
// its cell (the vertices nearer to it than to any other sample). Inside its
// own cell a load case's response peaks at the load vertex, as the loads it
// stands for would not; there the cell's total response is spread evenly
// over the cell instead. Measured (bench/label_bench.cpp --family all, ROC
// AUC over exposed vertices, default triangle counts): see
// stages/pbd-label/README.md. 0, or a budget of at least the vertex count,
// loads every vertex (bit-identical to no budget); "self" always does.
// Normalization: deformability = (d - d_min) / (d_max - d_min) over D's
// vertices, so the stiffest vertex is 0 and the most deformable 1 (all 0 when
// every value is equal); the raw values are kept too.
// Refinement (`refine` > 0, off by default): edges longer than refine x the
// local diameter (and than refine_min_length x D's diagonal) are split before
// simulating (longest-edge bisection, radii interpolated), so that a clip
// modelled as one long box gets vertices along its length; load cases stay
// one per vertex of D and labels are read at D's vertices. On the clip scenes
// it did not help (it adds light vertices at panel corners) and costs time.
// Parallelism and determinism: load cases run 8 at a time in SIMD lanes (one
// simulation per lane over the same constraints) and batches of 8 in
// parallel over OpenMP threads, each thread with its own buffers (the inner
// loop allocates nothing). Lanes never interact and "sum" accumulates in
// fixed point (integers), so results are identical for any thread count.
// The budget's sampling runs before, on one thread, in a fixed order.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "artifact/artifact.h"
#include "core/log.h"
#include "labeling/medial_spheres.h"
#include "labeling/mesh_topology.h"

namespace ausbau {

struct PbdLabelOptions {
  double time_step = 0.03;  // s
  double duration = 1.0;    // s; steps = ceil(duration / time_step)
  int solver_iterations = 3;
  double damping = 0.99;                     // v <- damping x v every step
  double stiffness = 0.99;                   // k
  std::string stiffness_formula = "thesis";  // thesis: 1 - (1 - k)^N; mueller: 1 - (1 - k)^(1/N)
  double kappa = 5.25;                       // sigma = kappa x r_min
  double density = 0.0;                      // rho, in the scaled mesh; 0 = automatic (see above)
  bool bending = true;                       // bending constraints (thesis figure 42: needed)
  bool thickness = true;        // masses from the sphere diameters (false: a constant height, the mean diameter)
  std::string measure = "sum";  // sum | self
  // "sum": load only a well-spread subset of at most this many vertices, each
  // weighted by the area it stands for (see above); 0 = every vertex.
  int max_load_cases = 1024;
  double refine = 0.0;              // split edges longer than refine x local diameter; 0 = off
  double refine_min_length = 0.02;  // never split below this fraction of D's AABB diagonal
  bool area_weighted = true;        // "sum": weight load cases by their vertex's area
  bool glue = true;                 // tie separate components where they touch or overlap
  double glue_tolerance = 1e-4;     // "touch": closer than this fraction of D's AABB diagonal
  int threads = 0;                  // 0 = all (OpenMP)
  // Called from one thread with the number of load cases done so far.
  ProgressCallback progress;  // core/log.h; empty = silent

  void Check() const;  // throws InputError on values out of range
  int Steps() const;
  double SolverStiffness() const;  // k'
};

struct PbdLabels {
  // Per welded vertex of the topology; vertices in no triangle get 0.
  std::vector<double> deformability;  // [0, 1], higher = more deformable
  std::vector<double> displacement;   // raw deformation value, in the scaled mesh (largest extent 1)
  // "sum": the weight of the load case on each vertex (the area it stands
  // for, 1 = the mean vertex area); 0 where no load was applied.
  std::vector<double> load_weight;
  double scale = 1.0;      // mesh units -> scaled mesh
  double r_min = 0.0;      // smallest medial-sphere radius, scaled mesh
  double sigma = 0.0;      // kappa x r_min
  double density = 0.0;    // rho used
  double mean_edge = 0.0;  // mean edge length, scaled mesh
  int steps = 0;
  double solver_stiffness = 0.0;        // k'
  std::int64_t load_cases = 0;          // = simulated vertices
  std::int64_t simulated_vertices = 0;  // after refinement
  std::int64_t constraints = 0;
  std::int64_t glue_constraints = 0;  // vertex pairs tied across components
  int components = 0;                 // simulated components (after gluing)
  double seconds = 0.0;               // wall-clock time of the labeling (set-up included)
  double thread_seconds = 0.0;        // time spent simulating, summed over threads
  double SecondsPerLoadCase() const { return load_cases > 0 ? thread_seconds / load_cases : 0.0; }
};

// `radii`: medial-sphere radius per welded vertex, in mesh units; `contact`
// (empty, or per welded vertex): spheres left out of r_min (see
// medial_spheres.h). Masses use max(radius, r_min).
PbdLabels ComputePbdLabels(const MeshTopology& topology, const std::vector<double>& radii,
                           const std::vector<std::uint8_t>& contact, const PbdLabelOptions& options);
inline PbdLabels ComputePbdLabels(const MeshTopology& topology, const MedialSpheres& spheres,
                                  const PbdLabelOptions& options) {
  return ComputePbdLabels(topology, spheres.radii, spheres.contact, options);
}

// Radius and contact flag per welded vertex from a spheres artifact (per
// original vertex): those of the first valid original vertex of each welded
// vertex. Throws InputError naming `source` when the vertex counts differ.
void SpheresPerWeldedVertex(const MeshTopology& topology, const SpheresArtifact& spheres, const std::string& source,
                            std::vector<double>* radii, std::vector<std::uint8_t>* contact);

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
  double density = 0.0;
  std::string measure;
  std::int64_t load_cases = 0;
  std::size_t VertexCount() const { return deformability.size(); }
};

LabelsArtifact ToLabelsArtifact(const MeshTopology& topology, const PbdLabels& labels, const std::string& measure);
void WriteLabelsArtifact(const std::filesystem::path& path, const LabelsArtifact& labels, const Provenance& provenance);
LabelsArtifact ReadLabelsArtifact(const std::filesystem::path& path);
// CSV `x,y,z,deformability`, one row per original vertex in D's mesh
// coordinates, 17 significant digits. Written atomically.
void WriteLabelsCsv(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& vertices,
                    const std::vector<double>& deformability);

}  // namespace ausbau
