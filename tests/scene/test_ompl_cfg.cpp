// ausbau-scene-import (scene/ompl_cfg.h): the .cfg reader and the scene it
// makes on hand-made problems, its errors, and, end to end, every .cfg of
// ../shared/benchmarks/ompl against the shipped scene.yaml (skipped where
// that folder is absent).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "geometry/primitives.h"
#include "scene/mesh_io.h"
#include "scene/ompl_cfg.h"
#include "scene/scene.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

// A tetrahedron with corners (0,0,0), (3,0,0), (0,6,0), (0,0,9): the mean of
// its corners is (0.75, 1.5, 2.25), however often each corner is counted
// (every corner lies on exactly three faces, so face normals triple each).
TriangleMesh Tetrahedron() {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {3, 0, 0}, {0, 6, 0}, {0, 0, 9}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

const char* kProblem =
    "[problem]\n"
    "name = tetra\n"
    "robot = robot.obj\n"
    "world = world.obj\n"
    "start.x = 1\nstart.y = 2\nstart.z = 3\n"
    "start.theta = 0\nstart.axis.x = 1\nstart.axis.y = 0\nstart.axis.z = 0\n"
    "goal.x = 4 # a comment\ngoal.y = 5\ngoal.z = 6\n"
    "goal.theta = 3.14159265358979\ngoal.axis.x = 0\ngoal.axis.y = 0\ngoal.axis.z = 2\n"
    "volume.min.x = -10\nvolume.min.y = -10\nvolume.min.z = -10\n"
    "volume.max.x = 10\nvolume.max.y = 10\nvolume.max.z = 10\n"
    "sampler = obstacle_based\n"
    "\n[benchmark]\ntime_limit=1.0\n\n[planner]\nrrt=\nrrt.range=5\n";

// A folder with robot.obj (the tetrahedron), world.obj (a box) and
// problem.cfg holding `text`.
fs::path WriteProblem(const std::string& text) {
  const fs::path dir = testing::MakeTempDir("scene-import");
  SaveObj(Tetrahedron(), dir / "robot.obj");
  SaveObj(MakeBox(Eigen::Vector3d(-5, -5, -5), Eigen::Vector3d(5, 5, -4)), dir / "world.obj");
  std::ofstream(dir / "problem.cfg") << text;
  return dir / "problem.cfg";
}

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::string ErrorOf(const std::string& text) {
  try {
    const fs::path cfg = WriteProblem(text);
    SceneFromOmplProblem(ReadOmplCfg(cfg));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(OmplCfg, ReadsPosesVolumeAndTheRobotCentre) {
  const fs::path cfg = WriteProblem(kProblem);
  const OmplProblem problem = ReadOmplCfg(cfg);
  EXPECT_EQ(problem.name, "tetra");
  EXPECT_EQ(problem.robot, cfg.parent_path() / "robot.obj");
  EXPECT_TRUE(problem.start.t.isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_NEAR(problem.start.q.w(), 1.0, 1e-15);
  // pi about z (the axis is normalized): q = (0, 0, 0, 1) up to the rounding of pi.
  EXPECT_NEAR(std::abs(problem.goal.q.z()), 1.0, 1e-12);
  EXPECT_NEAR(problem.goal.q.w(), 0.0, 1e-12);
  ASSERT_TRUE(problem.volume.has_value());
  EXPECT_EQ(problem.volume->min, Eigen::Vector3d(-10, -10, -10));
  // sampler: only how OMPL.app plans; then [benchmark] and [planner], kept
  // as notes (comments in the scene, warnings of ausbau-scene-import).
  ASSERT_EQ(problem.notes.size(), 4u);
  EXPECT_EQ(problem.notes[1], "[benchmark] time_limit = 1.0");
  EXPECT_EQ(problem.notes[2], "[planner] rrt = ");
  EXPECT_EQ(problem.notes[3], "[planner] rrt.range = 5");
  EXPECT_TRUE(OmplRobotCenter(problem.robot).isApprox(Eigen::Vector3d(0.75, 1.5, 2.25), 1e-6));

  const Scene scene = SceneFromOmplProblem(problem);
  EXPECT_TRUE(scene.dynamic_origin_given);
  EXPECT_TRUE(scene.dynamic_origin.isApprox(Eigen::Vector3d(0.75, 1.5, 2.25), 1e-6));
  // The centre of D lies at start.t: the corner (0,0,0) at (1,2,3) - (0.75,1.5,2.25).
  EXPECT_TRUE(scene.start.Apply(Eigen::Vector3d::Zero() - scene.dynamic_origin)
                  .isApprox(Eigen::Vector3d(0.25, 0.5, 0.75), 1e-6));
  // At the goal D is turned by pi about z around its centre: (0,0,0) -> (4,5,6) + (0.75,1.5,-2.25).
  EXPECT_TRUE(scene.goal->Apply(Eigen::Vector3d::Zero() - scene.dynamic_origin)
                  .isApprox(Eigen::Vector3d(4.75, 6.5, 3.75), 1e-6));
  EXPECT_EQ(scene.bounds->max, Eigen::Vector3d(10, 10, 10));
}

TEST(OmplCfg, WithoutVolumeTheBoundsAreTheWorldBoxGrownToStartAndGoal) {
  std::string text = kProblem;
  for (const char* key : {"volume.min.x = -10\n", "volume.min.y = -10\n", "volume.min.z = -10\n", "volume.max.x = 10\n",
                          "volume.max.y = 10\n", "volume.max.z = 10\n"}) {
    text = Replace(text, key, "");
  }
  const OmplProblem problem = ReadOmplCfg(WriteProblem(text));
  EXPECT_FALSE(problem.volume.has_value());
  bool grown = false;
  const Aabb box = OmplBounds(problem, &grown);
  EXPECT_TRUE(grown);  // the goal (4, 5, 6) lies above the world box
  EXPECT_TRUE(box.min.isApprox(Eigen::Vector3d(-5, -5, -5)));
  EXPECT_TRUE(box.max.isApprox(Eigen::Vector3d(5, 5, 6)));
}

TEST(OmplCfg, BadInputNamesTheFileAndTheKey) {
  EXPECT_NE(ErrorOf(Replace(kProblem, "start.y = 2\n", "")).find("problem.start.y: missing required key"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kProblem, "goal.z = 6", "goal.z = six")).find("problem.goal.z: 'six' is not a finite"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kProblem, "goal.z = 6", "goal.z = nan")).find("problem.goal.z"), std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kProblem, "[benchmark]", "[benchmarks]")).find("unknown section [benchmarks]"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kProblem, "robot = robot.obj", "robot = gone.obj")).find("problem.robot: "),
            std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kProblem, "robot = robot.obj", "robot = gone.obj")).find("gone.obj: file not found"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kProblem, "start.theta = 0", "start.thetta = 0")).find("problem.start.thetta: unknown key"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kProblem, "start.theta = 0", "start.thetta = 0")).find("did you mean problem.start.theta?"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kProblem, "goal.y = 5", "goal.y = 5\ngoal.y = 5")).find("problem.goal.y: given twice"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kProblem, "volume.max.z = 10\n", "")).find("problem.volume.max.z: missing"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kProblem, "volume.max.y = 10", "volume.max.y = -20")).find("problem.volume.min.y"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kProblem, "goal.axis.z = 2", "goal.axis.z = 0")).find("problem.goal.axis: the rotation"),
            std::string::npos);
  EXPECT_NE(ErrorOf(std::string("robot = x.obj\n") + kProblem).find("outside any section"), std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kProblem, "sampler", "control = car\nsampler")).find("problem.control"), std::string::npos);
  // Every message starts with the .cfg's path.
  EXPECT_NE(ErrorOf(Replace(kProblem, "start.y = 2\n", "")).find("problem.cfg: problem.start.y"), std::string::npos);
}

// The world positions of D's vertices at a pose of `scene`.
std::vector<Eigen::Vector3d> Placed(const Scene& scene, const Pose& pose) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& v : scene.dynamic_mesh.vertices) out.push_back(pose.Apply(v - scene.dynamic_origin));
  return out;
}

double MaxDeviation(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  double worst = a.size() == b.size() ? 0.0 : INFINITY;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) worst = std::max(worst, (a[i] - b[i]).norm());
  return worst;
}

TEST(SceneImportStage, WritesPathsRelativeToTheOutputAndRefusesToOverwrite) {
  const fs::path cfg = WriteProblem(kProblem);
  const fs::path out = testing::MakeTempDir("scene-import-out") / "deeper" / "scene.yaml";
  const std::string args = "--ompl-cfg " + cfg.string() + " -o " + out.string();
  auto run = testing::RunStageCommand("scene-import", args);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const Scene scene = LoadScene(out);  // the meshes resolve from the other folder
  EXPECT_TRUE(fs::equivalent(scene.dynamic_file, cfg.parent_path() / "robot.obj"));
  EXPECT_TRUE(scene.dynamic_origin.isApprox(Eigen::Vector3d(0.75, 1.5, 2.25), 1e-6));
  EXPECT_EQ(scene.name, "problem");
  const std::string written = testing::ReadTextFile(out);
  EXPECT_NE(written.find("OMPL.app name: tetra"), std::string::npos);

  // The same import again: up to date, untouched.
  run = testing::RunStageCommand("scene-import", args);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  // A scene edited by hand is not replaced without --force.
  std::ofstream(out, std::ios::app) << "# edited\n";
  run = testing::RunStageCommand("scene-import", args);
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("refusing to replace it (use --force)"), std::string::npos) << run.output;
  run = testing::RunStageCommand("scene-import", args + " --force");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(testing::ReadTextFile(out), written);

  // An output that is an input.
  for (const fs::path& input : {cfg, cfg.parent_path() / "robot.obj"}) {
    run = testing::RunStageCommand("scene-import", "--ompl-cfg " + cfg.string() + " -o " + input.string() + " --force");
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_NE(run.output.find("refusing to overwrite an input"), std::string::npos) << run.output;
  }
  EXPECT_NE(testing::ReadTextFile(cfg).find("[problem]"), std::string::npos);
  // Bad input: one line, exit 2.
  std::ofstream(cfg) << Replace(kProblem, "goal.x = 4", "goal.x = four");
  run = testing::RunStageCommand("scene-import", args + " --force");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("problem.goal.x: 'four' is not a finite number"), std::string::npos) << run.output;
  EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
}

// Every .cfg shipped with the OMPL.app scenes gives the scene shipped beside
// it: D's vertices at the same places at start and goal, the same bounds.
TEST(SceneImportStage, EveryShippedCfgGivesTheShippedScene) {
  const fs::path folder = testing::SourceDir() / ".." / "shared" / "benchmarks" / "ompl";
  if (!fs::is_directory(folder)) GTEST_SKIP() << folder << " not found";
  std::vector<fs::path> cfgs;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() == ".cfg") cfgs.push_back(entry.path());
  }
  std::sort(cfgs.begin(), cfgs.end());
  ASSERT_FALSE(cfgs.empty());
  const fs::path out_dir = testing::MakeTempDir("scene-import-ompl");
  for (const fs::path& cfg : cfgs) {
    SCOPED_TRACE(cfg.filename().string());
    const fs::path shipped = folder / (cfg.stem().string() + ".yaml");
    ASSERT_TRUE(fs::exists(shipped)) << shipped;
    const fs::path out = out_dir / (cfg.stem().string() + ".yaml");
    const auto run = testing::RunStageCommand("scene-import", "--ompl-cfg " + cfg.string() + " -o " + out.string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const Scene ours = LoadScene(out);
    const Scene theirs = LoadScene(shipped);
    EXPECT_EQ(ours.name, theirs.name);
    ASSERT_EQ(ours.static_files.size(), 1u);
    EXPECT_TRUE(fs::equivalent(ours.static_files[0], theirs.static_files[0]));
    EXPECT_TRUE(fs::equivalent(ours.dynamic_file, theirs.dynamic_file));
    // Tolerance: the shipped numbers are floats written with 17 digits, ours the same computation; 1e-9 of the
    // world's size leaves room for the last bit of a float and nothing more.
    const double size = theirs.static_mesh.Bounds().Diagonal();
    EXPECT_LE((ours.dynamic_origin - theirs.dynamic_origin).norm(), 1e-9 * size);
    EXPECT_LE(MaxDeviation(Placed(ours, ours.start), Placed(theirs, theirs.start)), 1e-9 * size);
    ASSERT_TRUE(ours.goal && theirs.goal);
    EXPECT_LE(MaxDeviation(Placed(ours, *ours.goal), Placed(theirs, *theirs.goal)), 1e-9 * size);
    ASSERT_TRUE(ours.bounds && theirs.bounds);
    EXPECT_LE((ours.bounds->min - theirs.bounds->min).norm(), 1e-9 * size);
    EXPECT_LE((ours.bounds->max - theirs.bounds->max).norm(), 1e-9 * size);
  }
}

}  // namespace
}  // namespace ausbau
