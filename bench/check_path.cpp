// ausbau-check-path: checks a path on a generated clip scene against the
// generator's ground truth (fixtures/ground_truth_check.h). Exit 0 correct,
// 3 incorrect, 2 bad input.
#include <cstdio>

#include "cli/stage_main.h"
#include "fixtures/ground_truth_check.h"
#include "inistate/intersection_volume.h"
#include "labeling/pbd_label.h"
#include "planning/path_io.h"
#include "scene/scene.h"

namespace {

// The check judges the whole path by its voxels: all of S, not only S near
// D's installed pose.
ausbau::VoxelizeOptions WholeStatic() {
  ausbau::VoxelizeOptions options;
  options.whole_static = true;
  return options;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ausbau;
  std::string scene_file, truth_file, path_file, voxels_file, labels_file;
  bool truth_path = false;
  double step = 0.0025, tolerance = 8;
  return RunStage(
      {"ausbau-check-path", "Checks a path on a clips-ds* scene against the ground truth (rigid parts, disassembly)."},
      argc, argv,
      [&](CLI::App& app) {
        app.add_option("--scene", scene_file, "scene.yaml")->required();
        app.add_option("--ground-truth", truth_file, "ground_truth.yaml")->required();
        app.add_option("--path", path_file, "path artifact");
        app.add_flag("--truth-path", truth_path, "check the ground truth's own path instead");
        app.add_option("--labels", labels_file, "also print the path's largest Labeled-MLIV under these labels");
        app.add_option("--voxels", voxels_file, "voxels artifact; default: voxelized here");
        app.add_option("--resolution", step, "check step as a fraction of D's diagonal")->capture_default_str();
        AddRenamedFlag(app, "--step", "--resolution");
        app.add_option("--tolerance", tolerance, "voxels")->capture_default_str();
      },
      [&] {
        const Scene scene = LoadScene(scene_file);
        const ClipGroundTruth truth = LoadClipGroundTruth(truth_file);
        PathArtifact path;
        if (truth_path) {
          path.waypoints = truth.path;
          path.reference_point = scene.dynamic_origin;
        } else {
          path = ReadPathArtifact(path_file);
        }
        const SceneVoxels voxels =
            voxels_file.empty() ? VoxelizeScene(scene, WholeStatic()) : ReadVoxelArtifact(voxels_file);
        const GroundTruthCheck check =
            CheckPathAgainstGroundTruth(scene, truth, voxels, path.reference_point, path.waypoints, step, tolerance);
        std::printf("%s: rigid volume start %.4g max %.4g (segment %d), ends disassembled %s, %lld poses%s%s\n",
                    check.correct ? "correct" : "INCORRECT", check.start_rigid_volume, check.max_rigid_volume,
                    check.worst_segment, check.ends_disassembled ? "yes" : "no",
                    static_cast<long long>(check.poses_checked), check.reason.empty() ? "" : ": ",
                    check.reason.c_str());
        if (!labels_file.empty()) {
          const std::vector<float> colors =
              ColorValues(voxels.dynamic_grid, scene.dynamic_mesh, ReadLabelsArtifact(labels_file).deformability);
          IntersectionVolume volume(voxels.static_grid, voxels.dynamic_grid, scene.dynamic_origin, colors);
          double worst = 0, worst_raw = 0, worst_iv = 0;
          std::size_t at = 0;
          for (std::size_t i = 0; i + 1 < path.waypoints.size(); ++i) {
            for (int s = 0; s < 50; ++s) {
              const Pose pose = Interpolate(path.waypoints[i], path.waypoints[i + 1], s / 50.0);
              const double v = volume.LabeledMliv(pose);
              if (v > worst) worst = v, at = i;
              worst_raw = std::max(worst_raw, volume.Mliv(pose));
              worst_iv = std::max(worst_iv, volume.Iv(pose));
            }
          }
          std::printf("largest along the path: Labeled-MLIV %.4g on segment %zu (start %.4g), MLIV %.4g, IV %.4g\n",
                      worst, at, volume.LabeledMliv(path.waypoints.front()), worst_raw, worst_iv);
        }
        return check.correct ? kExitOk : kExitNoPath;
      });
}
