// Phase I of the deformability labeling (thesis 5.4.1, algorithm 9, after
// Weller and Zachmann 2010): one sphere per vertex of D, near the vertex and
// centred approximately on the medial axis, whose radius is half the local
// thickness of D there.
//
// For each (welded) vertex v with outward normal n:
//   p = v - delta n                                   (start just inside)
//   repeat: p_near = nearest point of D to p          (exact, BVH)
//           p = p + eps (p - p_near)                  (push away from the surface)
//   sphere: centre p, radius |p - p_near|
// eps is a factor, as in the thesis: each step moves p by eps times its
// distance to the surface. With eps < 1 the step stays inside the empty ball
// around p, so p can never cross the surface, whatever the geometry.
// Schedule: the thesis cools eps linearly from the first iteration. A start
// delta small enough for thin clips then needs many iterations to grow a
// sphere in thick regions (each step multiplies the distance by at most
// 1 + eps, and at a corner only every third step does), so eps is held at
// `step` while the distance keeps growing (by more than a factor
// 1 + step / 4 over three iterations; at most `growth_iterations`), and then
// cools linearly from `step` to step / cooling_iterations over
// `cooling_iterations` iterations, as in the thesis. growth_iterations = 0
// gives the thesis's pure cooling schedule.
// Contacts: a vertex where another surface of D (a triangle not incident to
// it) passes closer than delta gets a sphere that measures the gap between
// the surfaces (internal faces of overlapping solids, T-junctions in CAD
// meshes, touching parts): it is flagged (`contact`) and left out of r_min.
// Defaults relative to D's size: delta = 1e-4 x D's AABB diagonal (well under
// half the thickness of a 1 mm clip on a 1 m part), step 0.75, 30 cooling
// iterations, at most 200 growth iterations. On a 2 x 2 x 2 box every vertex
// (corners included: the centre walks up the corner's diagonal) ends near the
// box's centre with radius 1; on a plate every vertex's radius is half the
// thickness.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "artifact/artifact.h"
#include "core/log.h"
#include "labeling/mesh_topology.h"

namespace ausbau {

struct MedialSphereOptions {
  double delta = 1e-4;  // start offset along -n, fraction of D's AABB diagonal
  double step = 0.75;   // eps while growing and at the start of cooling, in (0, 1)
  int cooling_iterations = 30;
  int growth_iterations = 200;  // cap on the growth phase; 0 = cool from the start (thesis)
  int threads = 0;              // 0 = all (OpenMP)
  // Called from one thread with the number of vertices done so far.
  ProgressCallback progress;  // core/log.h; empty = silent

  // Throws InputError on values out of range.
  void Check() const;
};

struct MedialSpheres {
  // Per welded vertex of the topology. Vertices in no triangle have no sphere:
  // centre = the vertex, radius 0, valid 0.
  std::vector<Eigen::Vector3d> centers;
  std::vector<double> radii;
  std::vector<std::uint8_t> valid;
  // 1 where another surface of D passes closer to the vertex than delta (a
  // triangle not incident to it): internal faces of overlapping solids,
  // T-junctions, touching parts. Such a sphere measures the gap between the
  // two surfaces, not a thickness; it is kept but left out of MinRadius().
  std::vector<std::uint8_t> contact;
  // Walks that left D's bounding box (the vertex's normal points out of its
  // solid: a vertex shared by overlapping solids, an open or inverted
  // surface): such a vertex gets no sphere (valid 0, radius 0).
  std::int64_t escaped = 0;
  std::int64_t nearest_queries = 0;
  double seconds = 0.0;  // wall-clock time of the computation

  // Smallest and largest radius over valid spheres that are not contacts (0
  // when there is none).
  double MinRadius() const;
  double MaxRadius() const;
};

MedialSpheres ComputeMedialSpheres(const MeshTopology& topology, const MedialSphereOptions& options);

// ---- the `ausbau-spheres` artifact (schemas/spheres.md)

inline constexpr const char* kSpheresSchema = "ausbau-spheres";
inline constexpr int kSpheresSchemaVersion = 1;

// Per ORIGINAL vertex of D (as loaded by LoadScene), in D's mesh coordinates.
struct SpheresArtifact {
  std::vector<Eigen::Vector3d> centers;
  std::vector<double> radii;
  std::vector<Eigen::Vector3d> normals;  // the consistent outward vertex normals used
  std::vector<std::uint8_t> valid;
  std::vector<std::uint8_t> contact;
  std::string units;  // the scene's units, informative ("" if not given)
  std::size_t VertexCount() const { return radii.size(); }
};

// Expands per-welded-vertex results to the original vertices.
SpheresArtifact ToSpheresArtifact(const MeshTopology& topology, const MedialSpheres& spheres);
void WriteSpheresArtifact(const std::filesystem::path& path, const SpheresArtifact& spheres,
                          const Provenance& provenance);
// Throws InputError on a missing, malformed or wrong-schema file.
SpheresArtifact ReadSpheresArtifact(const std::filesystem::path& path);
// CSV `x,y,z,radius`, one row per original vertex (its position in D's mesh
// coordinates), 17 significant digits. Written atomically.
void WriteSpheresCsv(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& vertices,
                     const std::vector<double>& radii);

}  // namespace ausbau
