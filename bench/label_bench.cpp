// ausbau-label-bench: time of the deformability labeling (thesis 5.4.1) on a
// generated panel with thin tongues (snap-fit clips) of about 6,500 triangles,
// or on a mesh file. Prints the medial-sphere time, the labeling time with
// one thread and with all threads, the time per load case, and (generated
// panel) how well the labels separate the tongues (ROC AUC).
// With --family: the generated clip scenes (fixtures/clip_scenes.h) instead,
// labelled once per --max-load-cases budget with --threads, printing the time
// and the ROC AUC of clip vertices against rigid ones (over the exposed
// vertices, as tests/labeling/test_labeling.cpp measures it, and over all).
//
//   build/bin/ausbau-label-bench [--mesh FILE] [--panel-cells N] [--threads N] [--skip-single]
//   build/bin/ausbau-label-bench --family clips-ds1 [--family ...|all] [--triangles N]
//                                [--max-load-cases N ...] [--threads N]
//   build/bin/ausbau-label-bench --scene DIR [--scene DIR ...] [--threads N]
// With --scene: a scene folder holding scene.yaml and
// truth/labels_per_triangle.txt (1 clip, 0 rigid per triangle of D, as
// ausbau-scene-gen's box families and the inistate-external set write it);
// prints the ROC AUC of each triangle's mean vertex deformability against
// that truth, and the largest label on a rigid triangle, for the PBD labels
// and for the solid rule (labeling/solid_labels.h) where it applies.
#include <omp.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cli/stage_main.h"
#include "core/error.h"
#include "parse_args.h"

#include "collision/scene_parts.h"
#include "fixtures/clip_scenes.h"
#include "fixtures/roc.h"
#include "labeling/medial_spheres.h"
#include "labeling/mesh_topology.h"
#include "labeling/pbd_label.h"
#include "labeling/solid_labels.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"

namespace {

using namespace ausbau;

std::vector<double> Steps(double from, double to, int count) {
  std::vector<double> out;
  for (int i = 0; i <= count; ++i) out.push_back(from + (to - from) * i / count);
  return out;
}

std::vector<double> Lines(std::vector<std::vector<double>> parts) {
  std::vector<double> out;
  for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end(), [](double a, double b) { return std::abs(a - b) < 1e-12; }), out.end());
  return out;
}

// A 1.0 x 0.6 x 0.03 panel with four tongues 0.006 thick, 0.05 wide and 0.2
// long sticking out of its +x edge. `cells`: grid cells along the panel's x.
struct Part {
  TriangleMesh mesh;
  std::vector<std::uint8_t> tongue;
};

Part MakePanel(int cells) {
  const double tz0 = 0.012, tz1 = 0.018;
  std::vector<std::vector<double>> ylines = {Steps(0, 0.6, cells * 6 / 10)};
  for (int k = 0; k < 4; ++k) ylines.push_back({0.1 + 0.13 * k, 0.15 + 0.13 * k});
  const auto xs = Lines({Steps(0, 1, cells), Steps(1, 1.2, std::max(2, cells / 5))});
  const auto ys = Lines(ylines);
  const auto zs = Lines({{0, 0.03, tz0, tz1}});
  const auto centre = [](const std::vector<double>& lines, int i) { return 0.5 * (lines[i] + lines[i + 1]); };
  Part part;
  part.mesh = MakeGridSolidMesh(xs, ys, zs, [&](int i, int j, int k) {
    const double x = centre(xs, i), y = centre(ys, j), z = centre(zs, k);
    if (x < 1) return true;
    for (int t = 0; t < 4; ++t) {
      if (y > 0.1 + 0.13 * t && y < 0.15 + 0.13 * t && z > tz0 && z < tz1) return true;
    }
    return false;
  });
  for (const auto& v : part.mesh.vertices) part.tongue.push_back(v.x() > 1 + 1e-9 ? 1 : 0);
  return part;
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Labels one generated clip scene once per budget; prints time and AUCs.
void BenchClipScene(const std::string& family, std::int64_t triangles, const std::vector<int>& budgets, int threads) {
  ClipSceneOptions scene_options;
  scene_options.triangles = triangles;
  const auto dir = std::filesystem::temp_directory_path() / ("ausbau-label-bench-" + family);
  const ClipSceneFiles files = GenerateClipScene(family, scene_options, dir);
  const Scene scene = LoadScene(files.scene_yaml);
  const ClipGroundTruth truth = LoadClipGroundTruth(files.ground_truth_yaml);
  const MeshTopology topology = BuildMeshTopology(scene.dynamic_mesh);
  MedialSphereOptions sphere_options;
  sphere_options.threads = threads;
  const MedialSpheres spheres = ComputeMedialSpheres(topology, sphere_options);
  const std::vector<double> nominal = truth.VertexDeformability();
  const std::vector<std::uint8_t> exposed = ExposedVertices(topology);
  std::printf("%s: %zu triangles, %d welded vertices, %d components; medial spheres %.2f s (%d threads)\n",
              family.c_str(), scene.dynamic_mesh.triangles.size(), topology.VertexCount(), topology.stats.components,
              spheres.seconds, threads);
  for (int budget : budgets) {
    PbdLabelOptions options;
    options.threads = threads;
    options.max_load_cases = budget;
    const PbdLabels labels = ComputePbdLabels(topology, spheres, options);
    std::vector<double> all_score, exposed_score;
    std::vector<std::uint8_t> all_clip, exposed_clip;
    for (std::size_t i = 0; i < nominal.size(); ++i) {
      const double d = labels.deformability[topology.welded_of_original[i]];
      const std::uint8_t clip = nominal[i] > 0.2 ? 1 : 0;
      all_score.push_back(d);
      all_clip.push_back(clip);
      if (!exposed[i]) continue;
      exposed_score.push_back(d);
      exposed_clip.push_back(clip);
    }
    std::printf(
        "  budget %6d: %6lld load cases in %7.2f s (%.2f ms thread time each, %d glued components): "
        "ROC AUC %.4f exposed, %.4f all\n",
        budget, static_cast<long long>(labels.load_cases), labels.seconds, 1e3 * labels.SecondsPerLoadCase(),
        labels.components, RocAuc(exposed_score, exposed_clip), RocAuc(all_score, all_clip));
    std::fflush(stdout);
  }
  std::filesystem::remove_all(dir);
}

// Labels the part D of a scene folder and compares with its per-triangle truth.
void BenchSceneFolder(const std::filesystem::path& dir, int threads, const PbdLabelOptions& base) {
  const Scene scene = LoadScene(dir / "scene.yaml");
  const auto truth_file = dir / "truth" / "labels_per_triangle.txt";
  std::ifstream in(truth_file);
  if (!in) throw InputErrorAt(truth_file, "cannot read the per-triangle truth");
  std::vector<std::uint8_t> clip;
  for (int v; in >> v;) clip.push_back(v != 0 ? 1 : 0);
  if (clip.size() != scene.dynamic_mesh.triangles.size()) {
    throw InputErrorAt(truth_file, "has " + std::to_string(clip.size()) + " labels for " +
                                       std::to_string(scene.dynamic_mesh.triangles.size()) + " triangles of D");
  }
  // Per triangle: the mean of its vertices' deformability.
  const auto auc = [&](const std::vector<double>& per_vertex, double* rigid_max, double* clip_min) {
    std::vector<double> score;
    *rigid_max = 0.0;
    *clip_min = 1.0;
    for (std::size_t t = 0; t < clip.size(); ++t) {
      double sum = 0.0;
      for (int v : scene.dynamic_mesh.triangles[t]) sum += per_vertex[v];
      score.push_back(sum / 3.0);
      double& bound = clip[t] ? *clip_min : *rigid_max;
      bound = clip[t] ? std::min(bound, score.back()) : std::max(bound, score.back());
    }
    return RocAuc(score, clip);
  };
  double rigid_max = 0.0, clip_min = 0.0;
  auto started = std::chrono::steady_clock::now();
  const MeshTopology topology = BuildMeshTopology(scene.dynamic_mesh);
  MedialSphereOptions sphere_options;
  sphere_options.threads = threads;
  const MedialSpheres spheres = ComputeMedialSpheres(topology, sphere_options);
  PbdLabelOptions options = base;
  options.threads = threads;
  const PbdLabels labels = ComputePbdLabels(topology, spheres, options);
  std::vector<double> pbd(scene.dynamic_mesh.vertices.size());
  for (std::size_t i = 0; i < pbd.size(); ++i) pbd[i] = labels.deformability[topology.welded_of_original[i]];
  const double pbd_auc = auc(pbd, &rigid_max, &clip_min);
  std::printf("%s: %zu triangles of D (%d components, %lld sphere walks escaped)\n", dir.filename().c_str(),
              clip.size(), topology.stats.components, static_cast<long long>(spheres.escaped));
  std::printf("  pbd:    ROC AUC %.4f per triangle; rigid triangles up to %.3f, clip triangles from %.3f; %.2f s\n",
              pbd_auc, rigid_max, clip_min, Seconds(started));
  started = std::chrono::steady_clock::now();
  const SolidLabels solids = LabelBySolids(scene, RigidToleranceInSceneUnits(0.05, scene.units, nullptr));
  const bool any_clip = std::find(clip.begin(), clip.end(), 1) != clip.end();
  if (solids.applies && !any_clip) {
    std::printf("  solids: no clip in the truth; %d of %d solids labelled deformable\n", solids.fasteners,
                solids.solids);
  } else if (solids.applies) {
    const double solid_auc = auc(solids.deformability, &rigid_max, &clip_min);
    std::printf("  solids: ROC AUC %.4f per triangle; rigid triangles up to %.3f, clip triangles from %.3f; %.2f s\n",
                solid_auc, rigid_max, clip_min, Seconds(started));
  } else {
    std::printf("  solids: does not apply: %s\n", solids.reason.c_str());
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Times the deformability labeling (medial spheres + PBD load cases).", "ausbau-label-bench");
  app.set_version_flag("--version", std::string(AUSBAU_VERSION));
  std::string mesh_file;
  int cells = 42;
  int threads = 0;
  bool skip_single = false;
  app.add_option("--mesh", mesh_file, "label this mesh instead of the generated panel");
  AddRenamedFlag(app, "--cells", "--panel-cells");
  app.add_option("--panel-cells", cells, "generated panel: grid cells along x (42: about 6,500 triangles)")
      ->capture_default_str();
  app.add_option("--threads", threads, "threads for the parallel run; 0 = all")
      ->capture_default_str()
      ->check(ThreadCount());
  app.add_flag("--skip-single", skip_single, "skip the single-thread run");
  std::vector<std::string> families;
  std::int64_t triangles = 0;
  std::vector<int> budgets;
  app.add_option("--family", families, "clip scene family (clips-ds1 .. clips-ds5, or all); repeatable");
  app.add_option("--triangles", triangles, "clip scenes: D's triangle target; 0 = the family's default")
      ->capture_default_str();
  app.add_option("--max-load-cases", budgets, "clip scenes: load-case budgets to run (0 = every vertex); repeatable");
  std::vector<std::string> scene_dirs;
  app.add_option("--scene", scene_dirs, "scene folder with truth/labels_per_triangle.txt; repeatable");
  PbdLabelOptions scene_label_options;
  app.add_option("--refine", scene_label_options.refine, "scenes: PbdLabelOptions::refine")->capture_default_str();
  app.add_option("--refine-min-length", scene_label_options.refine_min_length,
                 "scenes: PbdLabelOptions::refine_min_length")
      ->capture_default_str();
  if (const int code = ausbau::bench::ParseArguments(app, argc, argv); code >= 0) return code;
  if (threads <= 0) threads = omp_get_max_threads();
  if (!scene_dirs.empty()) {
    for (const auto& dir : scene_dirs) BenchSceneFolder(dir, threads, scene_label_options);
    return 0;
  }
  if (!families.empty()) {
    if (budgets.empty()) budgets.push_back(PbdLabelOptions{}.max_load_cases);
    if (families.size() == 1 && families[0] == "all") families = ClipSceneFamilies();
    for (const auto& family : families) BenchClipScene(family, triangles, budgets, threads);
    return 0;
  }

  Part part;
  if (mesh_file.empty()) {
    part = MakePanel(cells);
  } else {
    part.mesh = LoadMesh(mesh_file);
  }
  auto started = std::chrono::steady_clock::now();
  const MeshTopology topology = BuildMeshTopology(part.mesh);
  const double topology_s = Seconds(started);
  std::printf("D: %s, %zu triangles, %zu vertices -> %d welded, %d components, %zu edges\n",
              mesh_file.empty() ? "generated panel with 4 tongues" : mesh_file.c_str(), part.mesh.triangles.size(),
              part.mesh.vertices.size(), topology.VertexCount(), topology.stats.components, topology.edges.size());
  std::printf("topology (weld, orient, normals): %.3f s\n", topology_s);

  MedialSphereOptions sphere_options;
  sphere_options.threads = threads;
  const MedialSpheres spheres = ComputeMedialSpheres(topology, sphere_options);
  std::printf("medial spheres (%d threads): %.3f s, %lld nearest-point queries (%.2f us each), r %.4g .. %.4g\n",
              threads, spheres.seconds, static_cast<long long>(spheres.nearest_queries),
              1e6 * spheres.seconds * threads / std::max<std::int64_t>(1, spheres.nearest_queries), spheres.MinRadius(),
              spheres.MaxRadius());

  std::vector<std::pair<int, PbdLabels>> runs;
  std::vector<int> thread_counts;
  if (!skip_single) thread_counts.push_back(1);
  if (threads != 1 || skip_single) thread_counts.push_back(threads);
  for (int t : thread_counts) {
    PbdLabelOptions options;
    options.threads = t;
    const PbdLabels labels = ComputePbdLabels(topology, spheres, options);
    std::printf(
        "PBD labels (%d thread%s): %.3f s for %lld load cases on %lld vertices, %lld constraints; "
        "%.3f ms per load case (thread time / load cases), rho %.4g, sigma %.4g\n",
        t, t == 1 ? "" : "s", labels.seconds, static_cast<long long>(labels.load_cases),
        static_cast<long long>(labels.simulated_vertices), static_cast<long long>(labels.constraints),
        1e3 * labels.SecondsPerLoadCase(), labels.density, labels.sigma);
    runs.emplace_back(t, labels);
  }
  if (runs.size() == 2) {
    std::printf("same labels with 1 and %d threads: %s; speed-up %.2f\n", runs[1].first,
                runs[0].second.deformability == runs[1].second.deformability ? "yes" : "NO",
                runs[0].second.seconds / runs[1].second.seconds);
  }
  std::printf("whole labeling (topology + spheres + labels, %d threads): %.3f s\n", runs.back().first,
              topology_s + spheres.seconds + runs.back().second.seconds);
  if (mesh_file.empty()) {
    std::vector<double> d(part.mesh.vertices.size());
    for (std::size_t i = 0; i < d.size(); ++i) d[i] = runs.back().second.deformability[topology.welded_of_original[i]];
    std::printf("tongue vertices vs panel vertices: ROC AUC %.4f\n", RocAuc(d, part.tongue));
  }
  return 0;
}
