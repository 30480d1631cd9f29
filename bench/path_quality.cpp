// ausbau-path-quality: how direct a path is, against a known path of the
// same scene (issue "paths an engineer accepts on sight"). Both paths are
// measured at D's reference point (the centre of D's AABB, or the scene's
// dynamic_origin), so that a scene placed metres from the origin does not
// turn rotation into translation. The known path is extended to the same
// goal: from its last pose, straight along its last motion until D's AABB
// is clear of S's (the disassembly goal the planner's path ends in). One CSV
// row on stdout (with --header, the header first):
//   scene,translation,rotation,straight,ratio,known_translation,known_rotation,translation_ok,rotation_ok
#include <cstdio>

#include "cli/stage_main.h"
#include "planning/path_io.h"
#include "planning/smoother.h"
#include "scene/scene.h"

namespace {

using namespace ausbau;

std::vector<Pose> ToPlanning(const PlanningProblem& problem, const std::vector<Pose>& scene_path) {
  std::vector<Pose> out;
  for (const Pose& pose : scene_path) out.push_back(problem.SceneToPlanning(pose));
  return out;
}

// The known path, continued straight out of S's box where it ends inside.
std::vector<Pose> ExtendToGoal(const PlanningProblem& problem, std::vector<Pose> path) {
  if (path.size() < 2 || problem.InGoalRegion(path.back())) return path;
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();
  for (std::size_t i = path.size() - 1; i > 0 && direction.norm() < 1e-9; --i) direction = path[i].t - path[i - 1].t;
  const std::optional<Pose> end = StraightExitPose(problem, path.back(), direction);
  if (!end) throw InputError("--known: its last motion does not lead out of S's box; cannot extend it to the goal");
  path.push_back(*end);
  return path;
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene_file, path_file, known_file;
  bool header = false;
  double translation_factor = 1.25, rotation_margin = 0.1;
  return RunStage(
      {"ausbau-path-quality", "Measures a path's translation and rotation against a known path of the same scene."},
      argc, argv,
      [&](CLI::App& app) {
        app.add_option("--scene", scene_file, "scene.yaml")->required();
        app.add_option("--path-csv", path_file, "the path to judge (CSV, x,y,z,qw,qx,qy,qz, scene convention)")
            ->required();
        app.add_option("--known", known_file, "the known path (CSV, same convention as --path-csv)")->required();
        app.add_option("--translation-factor", translation_factor, "translation_ok: at most this times the known")
            ->capture_default_str();
        app.add_option("--rotation-margin", rotation_margin, "rotation_ok: at most the known's plus this, rad")
            ->capture_default_str();
        app.add_flag("--header", header, "print the CSV header first");
      },
      [&] {
        const Scene scene = LoadScene(scene_file);
        const PlanningProblem problem = MakePlanningProblem(scene);
        const std::vector<Pose> path = ToPlanning(problem, ReadPathCsv(path_file));
        const std::vector<Pose> known = ExtendToGoal(problem, ToPlanning(problem, ReadPathCsv(known_file)));
        if (path.size() < 2) throw InputErrorAt(path_file, "needs at least two waypoints");
        const PathLength ours = MeasurePath(problem, path), theirs = MeasurePath(problem, known);
        const double straight = (path.back().t - path.front().t).norm();
        if (header) {
          std::printf(
              "scene,translation,rotation,straight,ratio,known_translation,known_rotation,translation_ok,rotation_"
              "ok\n");
        }
        std::printf("%s,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%d,%d\n", scene.name.c_str(), ours.translation, ours.rotation,
                    straight, straight > 0 ? ours.translation / straight : 0.0, theirs.translation, theirs.rotation,
                    ours.translation <= translation_factor * theirs.translation ? 1 : 0,
                    ours.rotation <= theirs.rotation + rotation_margin ? 1 : 0);
        return kExitOk;
      });
}
