// ausbau-inistate-bench: the reproduction of thesis table 16 (5.5.2). For
// each generated clip family clips-ds1 .. clips-ds5 and a few seeds (scene
// seed = planner seed) it runs the whole InIState pipeline in process:
//
//   voxelize S and D (VoxelizeScene, defaults)
//   label D (medial spheres + PBD labels, library defaults)
//   for each validity mode shrink / iv / mliv / labeled-mliv (with the
//   fastener guard, volume_model.h) / labeled-mliv-unguarded (alg. 12 alone):
//     VolumeModel, psi (EstimatePsi), tau (EstimateTau with the goal
//     ClearOfFasteners; shrink: tau 0), PlanInIState (sigma_1 EST under the
//     volume validity, sigma_2 CR-RRTC under FCL), and the path checked
//     against the generator's ground truth (CheckPathAgainstGroundTruth: the
//     rigid parts never penetrate S beyond the installed pose, the path ends
//     disassembled).
//
// --truth-labels adds a column labeled-mliv-gt: Labeled-MLIV with the
// generator's nominal labels instead of the PBD labels, which separates the
// labels' quality from the method.
//
// A cell of the table is "k/n": the runs that found a path and whose path is
// correct, out of the seeds; "+" when k >= 0.8 n (4/5), else "-". A failure
// of one run (an InputError such as shrink not freeing the start, or any
// other exception) is recorded as a failed run with its reason.
//
// Output (--output-dir DIR): inistate-results.csv (one row per family, seed and
// mode), inistate-scenes.csv (per scene: sizes, times, labels per part kind)
// and inistate-summary.md (the table, times per scene, labels); both are
// rewritten after every scene, so an interrupted run keeps what it measured.
#include <omp.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cli/stage_main.h"
#include "collision/fcl_checker.h"
#include "core/error.h"
#include "core/format.h"
#include "core/log.h"
#include "fixtures/clip_scenes.h"
#include "fixtures/ground_truth_check.h"
#include "inistate/inistate_planner.h"
#include "inistate/intersection_volume.h"
#include "inistate/tau_estimate.h"
#include "inistate/volume_model.h"
#include "inistate/volume_smoother.h"
#include "inistate/voxel_grid.h"
#include "inistate_end_to_end.h"
#include "labeling/medial_spheres.h"
#include "labeling/mesh_topology.h"
#include "labeling/pbd_label.h"
#include "machine.h"
#include "parse_args.h"
#include "planning/path_io.h"
#include "planning/planner.h"
#include "planning/state_space.h"
#include "scene/scene.h"
#include "split_list.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

struct BenchOptions {
  std::vector<std::string> families;
  int seeds = 5;
  int first_seed = 1;
  std::vector<ValidityMode> modes{ValidityMode::kShrink, ValidityMode::kIv, ValidityMode::kMliv,
                                  ValidityMode::kLabeledMliv, ValidityMode::kLabeledMlivUnguarded};
  double time_limit_s = 20.0;  // per part of the path, and per planning round of the tau estimate
  std::int64_t triangles = 0;  // 0 = the families' defaults (thesis table 14)
  std::string out = "out/bench-inistate";
  int threads = 0;                                  // 0 = all cores
  double resolution = PlannerOptions{}.resolution;  // edge check step, fraction of D's diagonal
  bool keep_scenes = false;
  // The stages' knobs that decide how well D's parts are told apart (see
  // docs/results/inistate-ds3-2026-11-22.md): library defaults.
  std::int64_t voxel_budget = VoxelizeOptions{}.voxel_budget;
  double label_refine = PbdLabelOptions{}.refine;
  // Also Labeled-MLIV with the generator's nominal labels (clips 1, ds5's
  // thick clips 0.35, rigid parts 0) instead of the PBD labels.
  bool truth_labels = false;

  // The table's columns: (name, mode).
  std::vector<std::pair<std::string, ValidityMode>> Columns() const {
    std::vector<std::pair<std::string, ValidityMode>> columns;
    for (ValidityMode mode : modes) columns.emplace_back(ValidityModeName(mode), mode);
    if (truth_labels) columns.emplace_back("labeled-mliv-gt", ValidityMode::kLabeledMliv);
    return columns;
  }
};

// One (family, seed, mode) run.
struct RunResult {
  std::string family;
  std::uint64_t seed = 0;
  ValidityMode mode = ValidityMode::kLabeledMliv;
  std::string name;  // the table's column: the mode, "labeled-mliv-gt" with the ground-truth labels
  double tau = std::nan(""), tau_lowest = std::nan(""), psi = std::nan(""), start_volume = std::nan("");
  double shrink = 0;
  int tau_rounds = 0;
  bool tau_solved = false;
  bool solved = false, correct = false;
  std::string reason;  // why not solved-and-correct; empty otherwise
  double model_s = 0, tau_s = 0, plan_s = 0, check_s = 0;
  double local_s = 0, rigid_s = 0;
  std::int64_t nodes = 0, checks = 0;
  int waypoints = 0, inter_index = -1;
  double start_rigid_volume = std::nan(""), max_rigid_volume = std::nan("");
  bool ends_disassembled = false;
  // The mode's largest volume along the generator's known (correct) path:
  // a tau below it rules that path out.
  double truth_volume = std::nan("");
  // The mode's largest volume along the planned sigma_1, densely (0.25% of
  // D's diagonal): above tau where the planner's edge checks (--resolution)
  // stepped over a thin wall.
  double path_volume = std::nan("");
};

// Per part kind (clip, rail, rim, panel): the median of the labels.
struct KindLabels {
  std::string kind;
  double median = 0, p10 = 0, p90 = 0;
  std::int64_t vertices = 0;
};

struct SceneResult {
  std::string family;
  std::uint64_t seed = 0;
  std::int64_t dynamic_triangles = 0, static_triangles = 0;
  std::int64_t dynamic_voxels = 0;
  double voxel_size = 0;
  double generate_s = 0, voxelize_s = 0, spheres_s = 0, labels_s = 0;
  std::int64_t load_cases = 0;
  bool labeled = false;
  std::vector<KindLabels> kinds;
  std::string error;  // the scene itself failed (generation, voxelization, labeling)
  std::vector<RunResult> runs;

  const RunResult* Run(const std::string& name) const {
    for (const RunResult& run : runs) {
      if (run.name == name) return &run;
    }
    return nullptr;
  }
  // Voxelize + labels + tau + planning of labeled-mliv (the project's
  // end-to-end target); negative when labeled-mliv did not run.
  double EndToEnd() const {
    const RunResult* run = Run("labeled-mliv");
    if (run == nullptr) return -1;
    return voxelize_s + spheres_s + labels_s + run->model_s + run->tau_s + run->plan_s;
  }
};

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const double at = q * (values.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(at));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (at - lo) * (values[hi] - values[lo]);
}

std::vector<KindLabels> LabelsByKind(const ClipGroundTruth& truth, const std::vector<double>& deformability) {
  std::map<std::string, std::vector<double>> by_kind;
  for (const ClipScenePart& part : truth.parts) {
    for (const IndexRange& range : part.vertices) {
      for (std::int64_t v = range.begin; v < range.end && v < static_cast<std::int64_t>(deformability.size()); ++v) {
        by_kind[part.kind].push_back(deformability[v]);
      }
    }
  }
  std::vector<KindLabels> out;
  for (const char* kind : {"clip", "rail", "rim", "panel"}) {
    const auto it = by_kind.find(kind);
    if (it == by_kind.end()) continue;
    out.push_back({kind, Quantile(it->second, 0.5), Quantile(it->second, 0.1), Quantile(it->second, 0.9),
                   static_cast<std::int64_t>(it->second.size())});
  }
  return out;
}

// Densely checked volumes (MaxVolumeAlong): no vertex of D moves more than
// 0.25% of D's diagonal between measured poses.
double DenseStep(const PlanningProblem& problem) { return 0.0025 * problem.robot_diagonal; }

// The largest volume of the model's mode along the ground-truth path.
double TruthPathVolume(const PlanningProblem& problem, const ClipGroundTruth& truth, VolumeModel* model) {
  std::vector<Pose> path;
  for (const Pose& pose : truth.path) path.push_back(problem.SceneToPlanning(pose));
  return MaxVolumeAlong(problem, model->volume(), model->measure(), path, DenseStep(problem));
}

// The largest volume of the model's mode along path[0..last] (sigma_1).
double DensePathVolume(const PlanningProblem& problem, const std::vector<Pose>& path, int last, VolumeModel* model) {
  const std::vector<Pose> part(path.begin(), path.begin() + std::min<std::size_t>(last + 1, path.size()));
  return MaxVolumeAlong(problem, model->volume(), model->measure(), part, DenseStep(problem));
}

// One validity mode on one scene. Never throws: a failure is the run's reason.
RunResult RunMode(const Scene& scene, const ClipGroundTruth& truth, const PlanningProblem& problem,
                  const SceneVoxels& voxels, const std::vector<double>& deformability, const FclCollisionChecker& fcl,
                  ValidityMode mode, const std::string& column, std::uint64_t seed, const BenchOptions& options) {
  RunResult run;
  run.name = column;
  run.family = truth.family;
  run.seed = seed;
  run.mode = mode;
  try {
    auto start = Clock::now();
    VolumeModel model(problem, scene.dynamic_mesh, voxels, deformability, mode);
    run.shrink = model.shrink();
    run.psi = model.EstimatePsi();
    run.start_volume = model.Measure(problem.start);
    run.model_s = SecondsSince(start);
    run.truth_volume = TruthPathVolume(problem, truth, &model);

    PlannerOptions local;
    local.planner = "est";
    local.seed = seed;
    local.time_limit_s = options.time_limit_s;
    local.threads = options.threads;
    local.resolution = options.resolution;
    std::vector<Pose> known_local_path;  // the tau estimate's sigma_1, as ausbau-plan reuses it
    if (mode == ValidityMode::kShrink) {
      run.tau = 0;
      run.tau_lowest = run.start_volume;
    } else {
      const PlanningProblem local_problem = FastenerProblem(problem, fcl, run.psi);
      TauEstimateOptions tau_options;
      tau_options.planner = local;
      tau_options.threads = options.threads;
      start = Clock::now();
      const TauEstimate estimate = EstimateTau(local_problem, model.volume(), model.measure(), run.psi, tau_options);
      run.tau_s = SecondsSince(start);
      run.tau = estimate.tau;
      run.tau_lowest = estimate.tau_lowest;
      run.tau_rounds = estimate.rounds;
      run.tau_solved = estimate.solved;
      if (estimate.solved) known_local_path = estimate.local_path;
    }
    if (run.start_volume > run.tau) {
      run.reason = Fmt("start invalid: volume %.6g > tau %.6g", run.start_volume, run.tau);
      return run;
    }
    const VolumeValidity volume_validity(model.volume(), model.measure(), run.tau);
    InIStateOptions inistate;
    inistate.local = local;
    inistate.rigid = local;
    inistate.rigid.planner = "cr-rrtc";
    inistate.psi = run.psi;
    inistate.known_local_path = known_local_path;
    start = Clock::now();
    const InIStateResult result = PlanInIState(problem, volume_validity, fcl, fcl, inistate);
    run.plan_s = SecondsSince(start);
    run.local_s = result.local.stats.time_s;
    run.rigid_s = result.rigid.stats.time_s;
    const PlanStats stats = result.Stats();
    run.nodes = stats.nodes;
    run.checks = stats.collision_checks;
    run.solved = result.solved();
    if (!run.solved) {
      run.reason = result.inter_index < 0 && !result.local.solved()
                       ? Fmt("no sigma_1 within %.0f s (volume validity, tau %.6g)", options.time_limit_s, run.tau)
                       : Fmt("no sigma_2 within %.0f s (rigid, FCL)", options.time_limit_s);
      return run;
    }
    run.inter_index = result.inter_index;
    run.path_volume = DensePathVolume(problem, result.path, result.inter_index, &model);
    run.waypoints = static_cast<int>(result.path.size());
    std::vector<Pose> waypoints;
    waypoints.reserve(result.path.size());
    for (const Pose& pose : result.path) waypoints.push_back(problem.PlanningToScene(pose));
    AlignQuaternionSigns(&waypoints);
    start = Clock::now();
    const GroundTruthCheck check =
        CheckPathAgainstGroundTruth(scene, truth, voxels, problem.reference_point, waypoints);
    run.check_s = SecondsSince(start);
    run.correct = check.correct;
    run.start_rigid_volume = check.start_rigid_volume;
    run.max_rigid_volume = check.max_rigid_volume;
    run.ends_disassembled = check.ends_disassembled;
    if (!check.correct) run.reason = "incorrect path: " + check.reason;
  } catch (const InputError& e) {
    run.reason = std::string("input error: ") + e.what();
  } catch (const std::exception& e) {
    run.reason = std::string("error: ") + e.what();
  }
  return run;
}

SceneResult RunScene(const std::string& family, std::uint64_t seed, const BenchOptions& options) {
  SceneResult result;
  result.family = family;
  result.seed = seed;
  const fs::path dir =
      fs::path(options.out) / "scenes" / Fmt("%s-seed%llu", family.c_str(), static_cast<unsigned long long>(seed));
  try {
    auto start = Clock::now();
    ClipSceneOptions scene_options;
    scene_options.seed = seed;
    scene_options.triangles = options.triangles;
    const ClipSceneFiles files = GenerateClipScene(family, scene_options, dir);
    const Scene scene = LoadScene(files.scene_yaml);
    const ClipGroundTruth truth = LoadClipGroundTruth(files.ground_truth_yaml);
    const PlanningProblem problem = MakePlanningProblem(scene);
    result.generate_s = SecondsSince(start);
    result.dynamic_triangles = static_cast<std::int64_t>(scene.dynamic_mesh.triangles.size());
    result.static_triangles = static_cast<std::int64_t>(scene.static_mesh.triangles.size());

    start = Clock::now();
    VoxelizeOptions voxelize_options;
    voxelize_options.voxel_budget = options.voxel_budget;
    voxelize_options.whole_static = true;  // the ground-truth check below judges whole paths by these voxels
    const SceneVoxels voxels = VoxelizeScene(scene, voxelize_options);
    result.voxelize_s = SecondsSince(start);
    result.voxel_size = voxels.dynamic_grid.geometry.spacing;
    result.dynamic_voxels = voxels.dynamic_grid.CountOccupied();
    std::printf("  %s seed %llu: D %lld triangles, S %lld; voxels %.3g mm, %lld of D; voxelized in %.1f s\n",
                family.c_str(), static_cast<unsigned long long>(seed), static_cast<long long>(result.dynamic_triangles),
                static_cast<long long>(result.static_triangles), result.voxel_size,
                static_cast<long long>(result.dynamic_voxels), result.voxelize_s);
    std::fflush(stdout);

    // Labels (library defaults) when a labeled mode runs; the other modes get
    // them too, for psi (the extent of the largest deformable component), so
    // that every mode hands over to the rigid planner at the same distance.
    std::vector<double> deformability;
    if (std::any_of(options.modes.begin(), options.modes.end(), NeedsLabels)) {
      start = Clock::now();
      const MeshTopology topology = BuildMeshTopology(scene.dynamic_mesh);
      MedialSphereOptions sphere_options;
      sphere_options.threads = options.threads;
      const MedialSpheres spheres = ComputeMedialSpheres(topology, sphere_options);
      result.spheres_s = SecondsSince(start);
      start = Clock::now();
      PbdLabelOptions label_options;
      label_options.threads = options.threads;
      label_options.refine = options.label_refine;
      const PbdLabels labels = ComputePbdLabels(topology, spheres, label_options);
      result.labels_s = SecondsSince(start);
      result.load_cases = labels.load_cases;
      deformability = ToLabelsArtifact(topology, labels, label_options.measure).deformability;
      result.labeled = true;
      result.kinds = LabelsByKind(truth, deformability);
      std::string kinds;
      for (const KindLabels& k : result.kinds) kinds += Fmt(" %s %.2f", k.kind.c_str(), k.median);
      std::printf("    labels: spheres %.1f s, PBD %.1f s (%lld load cases); median label:%s\n", result.spheres_s,
                  result.labels_s, static_cast<long long>(result.load_cases), kinds.c_str());
      std::fflush(stdout);
    }

    const FclCollisionChecker fcl(problem.robot, problem.environment);
    const std::vector<double> nominal = truth.VertexDeformability();
    for (const auto& [column, mode] : options.Columns()) {
      const bool gt = column == "labeled-mliv-gt";
      RunResult run =
          RunMode(scene, truth, problem, voxels, gt ? nominal : deformability, fcl, mode, column, seed, options);
      std::printf(
          "    %-12s tau %-9.5g truth path %-9.5g psi %-6.3g start %-9.5g model %4.1f s, tau %5.1f s, "
          "plan %5.1f s, sigma_1 dense %.5g: %s%s%s\n",
          column.c_str(), run.tau, run.truth_volume, run.psi, run.start_volume, run.model_s, run.tau_s, run.plan_s,
          run.path_volume, run.solved && run.correct ? "solved, correct" : (run.solved ? "solved" : "FAILED"),
          run.reason.empty() ? "" : ": ", run.reason.c_str());
      std::fflush(stdout);
      result.runs.push_back(std::move(run));
    }
    if (result.EndToEnd() >= 0) {
      std::printf("    end to end (voxelize + labels + labeled-mliv tau + planning): %.1f s\n", result.EndToEnd());
    }
  } catch (const std::exception& e) {
    result.error = e.what();
    std::printf("    scene failed: %s\n", e.what());
    for (const auto& [column, mode] : options.Columns()) {
      if (result.Run(column) != nullptr) continue;
      RunResult run;
      run.family = family;
      run.seed = seed;
      run.mode = mode;
      run.name = column;
      run.reason = std::string("scene failed: ") + e.what();
      result.runs.push_back(run);
    }
  }
  if (!options.keep_scenes) {
    std::error_code ignored;
    fs::remove_all(dir, ignored);
  }
  return result;
}

// ---- output

std::string CsvField(std::string text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c == '\n' ? ' ' : c;
  }
  return out + "\"";
}

std::string Num(double value) { return std::isfinite(value) ? Fmt("%.6g", value) : ""; }

void WriteResultsCsv(const fs::path& file, const std::vector<SceneResult>& scenes) {
  std::ofstream csv(file);
  csv << "family,seed,mode,tau,tau_lowest,tau_rounds,tau_solved,psi,start_volume,shrink,solved,correct,reason,"
         "voxelize_s,labels_s,model_s,tau_s,plan_s,local_s,rigid_s,check_s,nodes,checks,waypoints,inter_index,"
         "start_rigid_volume,max_rigid_volume,ends_disassembled,truth_path_volume,sigma1_dense_volume\n";
  for (const SceneResult& scene : scenes) {
    for (const RunResult& r : scene.runs) {
      csv << r.family << "," << r.seed << "," << r.name << "," << Num(r.tau) << "," << Num(r.tau_lowest) << ","
          << r.tau_rounds << "," << r.tau_solved << "," << Num(r.psi) << "," << Num(r.start_volume) << ","
          << Num(r.shrink) << "," << r.solved << "," << r.correct << "," << CsvField(r.reason) << ","
          << Num(scene.voxelize_s) << "," << Num(scene.spheres_s + scene.labels_s) << "," << Num(r.model_s) << ","
          << Num(r.tau_s) << "," << Num(r.plan_s) << "," << Num(r.local_s) << "," << Num(r.rigid_s) << ","
          << Num(r.check_s) << "," << r.nodes << "," << r.checks << "," << r.waypoints << "," << r.inter_index << ","
          << Num(r.start_rigid_volume) << "," << Num(r.max_rigid_volume) << "," << r.ends_disassembled << ","
          << Num(r.truth_volume) << "," << Num(r.path_volume) << "\n";
    }
  }
}

void WriteScenesCsv(const fs::path& file, const std::vector<SceneResult>& scenes) {
  std::ofstream csv(file);
  csv << "family,seed,dynamic_triangles,static_triangles,voxel_size,dynamic_voxels,generate_s,voxelize_s,spheres_s,"
         "labels_s,load_cases,end_to_end_s,label_clip,label_rail,label_rim,label_panel,error\n";
  for (const SceneResult& s : scenes) {
    auto label = [&s](const char* kind) {
      for (const KindLabels& k : s.kinds) {
        if (k.kind == kind) return Num(k.median);
      }
      return std::string();
    };
    csv << s.family << "," << s.seed << "," << s.dynamic_triangles << "," << s.static_triangles << ","
        << Num(s.voxel_size) << "," << s.dynamic_voxels << "," << Num(s.generate_s) << "," << Num(s.voxelize_s) << ","
        << Num(s.spheres_s) << "," << Num(s.labels_s) << "," << s.load_cases << ","
        << (s.EndToEnd() >= 0 ? Num(s.EndToEnd()) : "") << "," << label("clip") << "," << label("rail") << ","
        << label("rim") << "," << label("panel") << "," << CsvField(s.error) << "\n";
  }
}

// Thesis table 16.
const char* ThesisCell(const std::string& family, ValidityMode mode) {
  static const std::map<std::string, std::string> rows = {{"clips-ds1", "--++"},
                                                          {"clips-ds2", "-+++"},
                                                          {"clips-ds3", "---+"},
                                                          {"clips-ds4", "---+"},
                                                          {"clips-ds5", "-+++"}};
  const auto it = rows.find(family);
  if (it == rows.end()) return "?";
  // Both labeled modes stand for the thesis's Labeled-MLIV column.
  const int column = mode == ValidityMode::kShrink ? 0
                     : mode == ValidityMode::kIv   ? 1
                     : mode == ValidityMode::kMliv ? 2
                                                   : 3;
  return it->second[column] == '+' ? "+" : "-";
}

std::string Summary(const std::vector<SceneResult>& scenes, const BenchOptions& options, const std::string& date,
                    const std::string& command) {
  std::ostringstream md;
  md << "# ausbau-inistate-bench: thesis table 16 on the generated clip scenes\n\n";
  md << "- Machine: " << bench::MachineLine(bench::DescribeMachine()) << "\n";
  md << "- Date: " << date << " (UTC), load average at the end " << bench::LoadAverage() << "\n";
  md << "- Command: `" << command << "`\n";
  md << "- Seeds " << options.first_seed << ".." << options.first_seed + options.seeds - 1
     << " (scene seed = planner seed); D triangles "
     << (options.triangles > 0 ? std::to_string(options.triangles) : std::string("default (thesis table 14)"))
     << "; time limit " << options.time_limit_s
     << " s for sigma_1 (EST), for sigma_2 (CR-RRTC, FCL) and for each planning round of the tau estimate; "
     << "edge resolution " << options.resolution << " of D's diagonal; threads "
     << (options.threads > 0 ? std::to_string(options.threads) : std::string("all")) << "\n";
  md << "- Cell: solved and correct (ground truth: rigid parts never penetrate S beyond the installed pose, "
        "ends disassembled) out of the seeds; + when at least 4/5 of them, else -. In brackets: the thesis.\n\n";

  md << "| family |";
  const auto columns = options.Columns();
  for (const auto& column : columns) md << " " << column.first << " |";
  md << "\n|---|";
  for (std::size_t i = 0; i < columns.size(); ++i) md << "---|";
  md << "\n";
  std::vector<std::string> families = options.families;
  std::sort(families.begin(), families.end());
  for (const std::string& family : families) {
    bool any = false;
    for (const SceneResult& s : scenes) any |= s.family == family;
    if (!any) continue;
    md << "| " << family << " |";
    for (const auto& [column, mode] : columns) {
      int good = 0, total = 0;
      for (const SceneResult& s : scenes) {
        if (s.family != family) continue;
        const RunResult* run = s.Run(column);
        if (run == nullptr) continue;
        ++total;
        good += run->solved && run->correct;
      }
      const bool plus = total > 0 && 5 * good >= 4 * total;
      md << " " << good << "/" << total << " " << (plus ? "+" : "-") << " (" << ThesisCell(family, mode) << ") |";
    }
    md << "\n";
  }

  md << "\n## Runs\n\n";
  md << "tau: the estimate; truth path: the mode's largest volume along the generator's known path (a tau below it "
        "excludes that path); sigma_1 dense: the mode's largest volume along the planned sigma_1 checked every "
        "0.25% of D's diagonal (above tau where the planner's edge checks stepped over a thin wall); max rigid: the "
        "rigid parts' largest MLIV along the planned path (ground-truth check).\n\n";
  md << "| family | seed | mode | tau | truth path | sigma_1 dense | psi | start volume | max rigid | tau s | plan s | "
        "nodes | result |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const SceneResult& s : scenes) {
    for (const RunResult& r : s.runs) {
      md << "| " << r.family << " | " << r.seed << " | " << r.name << " | " << Num(r.tau) << " | "
         << Num(r.truth_volume) << " | " << Num(r.path_volume) << " | " << Num(r.psi) << " | " << Num(r.start_volume)
         << " | " << Num(r.max_rigid_volume) << " | " << Fmt("%.1f", r.tau_s) << " | " << Fmt("%.1f", r.plan_s) << " | "
         << r.nodes << " | " << (r.solved && r.correct ? std::string("correct") : r.reason) << " |\n";
    }
  }

  md << "\n## Times per scene (seconds)\n\n";
  md << "End to end = voxelize + labels (spheres + PBD) + the labeled-mliv run (model, tau estimate, planning); "
        "the project's target is <= 60 s per scene on the 2-core machine.\n\n";
  md << "| family | seed | D / S triangles | voxel mm | voxelize | spheres | PBD labels (load cases) | "
        "labeled-mliv tau | labeled-mliv plan | end to end |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const SceneResult& s : scenes) {
    const RunResult* run = s.Run("labeled-mliv");
    md << "| " << s.family << " | " << s.seed << " | " << s.dynamic_triangles << " / " << s.static_triangles << " | "
       << Fmt("%.3g", s.voxel_size) << " | " << Fmt("%.1f", s.voxelize_s) << " | " << Fmt("%.1f", s.spheres_s) << " | "
       << Fmt("%.1f (%lld)", s.labels_s, static_cast<long long>(s.load_cases)) << " | "
       << (run ? Fmt("%.1f", run->tau_s) : std::string("")) << " | "
       << (run ? Fmt("%.1f", run->plan_s) : std::string("")) << " | "
       << (s.EndToEnd() >= 0 ? Fmt("%.1f", s.EndToEnd()) : std::string("")) << " |\n";
  }

  md << "\n## Labels per part kind (median, 10%-90%)\n\n| family | seed | clip | rail | rim | panel |\n"
        "|---|---|---|---|---|---|\n";
  for (const SceneResult& s : scenes) {
    if (!s.labeled) continue;
    md << "| " << s.family << " | " << s.seed << " |";
    for (const char* kind : {"clip", "rail", "rim", "panel"}) {
      std::string cell;
      for (const KindLabels& k : s.kinds) {
        if (k.kind == kind) cell = Fmt("%.2f (%.2f-%.2f)", k.median, k.p10, k.p90);
      }
      md << " " << cell << " |";
    }
    md << "\n";
  }
  for (const SceneResult& s : scenes) {
    if (!s.error.empty()) md << "\n- " << s.family << " seed " << s.seed << " failed: " << s.error << "\n";
  }
  return md.str();
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  BenchOptions options;
  options.families = ClipSceneFamilies();
  std::string families, modes;
  CLI::App app(
      "Thesis table 16 on the generated clip scenes: shrink, IV, MLIV and Labeled-MLIV (guarded and not) "
      "InIState planning, "
      "paths checked against the ground truth",
      "ausbau-inistate-bench");
  app.set_version_flag("--version", std::string(AUSBAU_VERSION));
  app.add_option("--families", families, "comma-separated, default all: clips-ds1,...,clips-ds5");
  app.add_option("--seeds", options.seeds, "number of seeds per family (scene seed = planner seed)")
      ->capture_default_str();
  app.add_option("--first-seed", options.first_seed, "first seed")->capture_default_str();
  app.add_option("--modes", modes,
                 "comma-separated validity modes, default shrink,iv,mliv,labeled-mliv,labeled-mliv-unguarded");
  app.add_option("--time-limit", options.time_limit_s,
                 "seconds for sigma_1, for sigma_2 and for each planning round of the tau estimate")
      ->capture_default_str();
  app.add_option("--triangles", options.triangles, "target triangle count of D; 0 = the families' defaults")
      ->capture_default_str();
  app.add_option("--output-dir", options.out, "output folder")->capture_default_str();
  AddRenamedFlag(app, "--out", "--output-dir");
  app.add_option("--threads", options.threads, "threads for voxelization, labels and tau probes; 0 = all cores")
      ->capture_default_str()
      ->check(ThreadCount());
  app.add_option("--resolution", options.resolution,
                 "edge check step of every planner (fraction of D's diagonal; library default)")
      ->capture_default_str();
  app.add_option("--voxel-budget", options.voxel_budget,
                 "automatic voxel size: about this many voxels in D's AABB (ausbau-voxelize --voxel-budget)")
      ->capture_default_str();
  app.add_option("--label-refine", options.label_refine,
                 "split D's edges longer than this x the local diameter before labeling (ausbau-pbd-label --refine); "
                 "0 = off")
      ->capture_default_str();
  app.add_flag("--truth-labels", options.truth_labels,
               "also run Labeled-MLIV with the generator's nominal labels (column labeled-mliv-gt)");
  app.add_flag("--keep-scenes", options.keep_scenes, "keep the generated scenes under OUT/scenes");
  // --end-to-end (inistate_end_to_end.h).
  bool end_to_end = false;
  bench::EndToEndOptions e2e;
  std::string external = "../shared/benchmarks/inistate-external";
  e2e.bin = fs::absolute(argv[0]).parent_path();
  app.add_flag("--end-to-end", end_to_end,
               "run the whole pipeline (pipelines/inistate.mk) on every family, clips-ds* and panel-* (coarse, "
               "fine and moulded, turned and metres out), and on the external set (box soup and moulded); paths judged "
               "by oracle.py or the ground "
               "truth; --seeds defaults to 3, --output-dir to out/inistate-end-to-end");
  app.add_option("--external", external, "end-to-end: folder with scenes/ and oracle.py; 'none' for no external set")
      ->capture_default_str();
  bool skip_external = false;
  app.add_flag("--skip-external-scenes", skip_external,
               "end-to-end: use the external folder's oracle.py only, not its scenes");
  app.add_option("--validity", e2e.validity, "end-to-end: the pipeline's VALIDITY (default: its default, auto)");
  app.add_option("--bin", e2e.bin, "end-to-end: the stages' folder (default: this program's)");
  app.add_option("--pipeline", e2e.pipeline, "end-to-end: the pipeline Makefile")->capture_default_str();
  app.add_option("--python", e2e.python, "end-to-end: python with numpy, for oracle.py")->capture_default_str();
  if (const int code = ausbau::bench::ParseArguments(app, argc, argv); code >= 0) return code;
  std::string command = "ausbau-inistate-bench";
  for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];
  SetLogProgramName("ausbau-inistate-bench");
  SetLogLevel(LogLevel::kWarn);
  if (end_to_end) {
    try {
      if (!families.empty()) e2e.families = bench::SplitList(families);
      const int seeds = app.count("--seeds") > 0 ? options.seeds : 3;
      if (seeds < 1) throw InputError("--seeds: must be >= 1");
      e2e.seeds.clear();
      for (int s = 0; s < seeds; ++s) e2e.seeds.push_back(options.first_seed + s);
      e2e.out = app.count("--output-dir") > 0 ? options.out : "out/inistate-end-to-end";
      if (external != "none") e2e.external = external;
      e2e.external_scenes = !skip_external;
      e2e.command = command;
      fs::create_directories(e2e.out);
      return bench::RunEndToEnd(e2e);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "ausbau-inistate-bench: error: %s\n", e.what());
      return 2;
    }
  }
  try {
    if (!families.empty()) options.families = bench::SplitList(families);
    for (const std::string& family : options.families) {
      if (!IsClipSceneFamily(family)) throw InputError("--families: unknown family '" + family + "'");
    }
    if (!modes.empty()) {
      options.modes.clear();
      for (const std::string& name : bench::SplitList(modes)) {
        const ValidityMode mode = ParseValidityMode(name, "--modes");
        if (!IsVolumeValidity(mode)) throw InputError("--modes: " + name + " is not an InIState mode");
        options.modes.push_back(mode);
      }
    }
    if (options.seeds < 1) throw InputError("--seeds: must be >= 1");
    if (options.first_seed < 0) throw InputError("--first-seed: must be >= 0");
    if (!(options.time_limit_s > 0)) throw InputError("--time-limit: must be > 0");
    if (options.threads < 0) throw InputError("--threads: must be >= 0");
    if (!(options.resolution > 0)) throw InputError("--resolution: must be > 0");
    if (options.triangles < 0) throw InputError("--triangles: must be >= 0");
    if (options.voxel_budget < 1) throw InputError("--voxel-budget: must be >= 1");
    if (options.label_refine < 0) throw InputError("--label-refine: must be >= 0 (0 = off)");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ausbau-inistate-bench: error: %s\n", e.what());
    return 2;
  }
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const std::string date = bench::NowIsoUtc();
  const fs::path out = options.out;
  std::vector<SceneResult> scenes;
  try {
    fs::create_directories(out);
    for (const std::string& family : options.families) {
      for (int s = 0; s < options.seeds; ++s) {
        scenes.push_back(RunScene(family, static_cast<std::uint64_t>(options.first_seed + s), options));
        WriteResultsCsv(out / "inistate-results.csv", scenes);
        WriteScenesCsv(out / "inistate-scenes.csv", scenes);
        std::ofstream(out / "inistate-summary.md") << Summary(scenes, options, date, command);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ausbau-inistate-bench: error: %s\n", e.what());
    return 1;
  }
  const std::string summary = Summary(scenes, options, date, command);
  std::ofstream(out / "inistate-summary.md") << summary;
  std::fputs(summary.c_str(), stdout);
  return 0;
}
