// InIState planning: validity modes, psi, shrink, the two-part planner, the
// tau estimate, the ground-truth check and the path artifact's InIState
// datasets. Planner cases use generated clip scenes with the generator's
// ground-truth labels (clips deformable, the rest rigid), so they test the
// planner, not the labeling.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>

#include "collision/fcl_checker.h"
#include "core/error.h"
#include "fixtures/clip_scenes.h"
#include "fixtures/ground_truth_check.h"
#include "geometry/primitives.h"
#include "inistate/inistate_planner.h"
#include "inistate/tau_estimate.h"
#include "inistate/volume_model.h"
#include "inistate/volume_smoother.h"
#include "planning/path_io.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

using Vec3 = Eigen::Vector3d;

// A scene from two meshes, written to a temporary folder and loaded back.
Scene MakeScene(const std::string& name, const TriangleMesh& s, const TriangleMesh& d) {
  const auto dir = testing::MakeTempDir(name);
  SaveObj(s, dir / "s.obj");
  SaveObj(d, dir / "d.obj");
  Scene scene;
  scene.name = name;
  scene.units = "mm";
  scene.static_files = {dir / "s.obj"};
  scene.dynamic_file = dir / "d.obj";
  SaveSceneYaml(scene, dir / "scene.yaml");
  return LoadScene(dir / "scene.yaml");
}

TEST(ValidityModes, NamesRoundTripAndUnknownNamesAreRefused) {
  for (const std::string& name : ValidityModeNames()) EXPECT_EQ(ValidityModeName(ParseValidityMode(name)), name);
  EXPECT_EQ(MeasureOf(ValidityMode::kShrink), VolumeMeasure::kIv);
  EXPECT_EQ(MeasureOf(ValidityMode::kLabeledMliv), VolumeMeasure::kLabeledMliv);
  EXPECT_EQ(MeasureOf(ValidityMode::kLabeledMlivUnguarded), VolumeMeasure::kLabeledMliv);
  EXPECT_TRUE(NeedsLabels(ValidityMode::kLabeledMlivUnguarded));
  EXPECT_FALSE(NeedsLabels(ValidityMode::kMliv));
  EXPECT_THROW(ParseValidityMode("labelled-mliv"), InputError);
}

// Every mode has one spelling (the flag's and the artifacts'); rigid-exact
// and collision are no volume modes; ausbau-tau-estimate's list leaves out
// rigid-exact; a wrong name's error lists the right ones.
TEST(ValidityModes, EachModeHasOneSpellingAndAWrongOneListsThem) {
  EXPECT_EQ(ValidityModeNames().size(), 7u);
  EXPECT_EQ(ValidityModeName(ValidityMode::kRigidExact), "rigid-exact");
  EXPECT_EQ(ValidityModeName(ValidityMode::kCollision), "collision");
  EXPECT_EQ(ValidityModeName(ValidityMode::kLabeledMlivUnguarded), "labeled-mliv-unguarded");
  EXPECT_EQ(ParseValidityMode("rigid-exact"), ValidityMode::kRigidExact);
  EXPECT_EQ(ParseValidityMode("shrink"), ValidityMode::kShrink);
  EXPECT_FALSE(IsVolumeValidity(ValidityMode::kRigidExact));
  EXPECT_FALSE(IsVolumeValidity(ValidityMode::kCollision));
  EXPECT_TRUE(IsVolumeValidity(ValidityMode::kShrink));
  EXPECT_TRUE(IsVolumeValidity(ValidityMode::kLabeledMlivUnguarded));
  const std::vector<std::string> inistate = {"collision", "shrink",       "iv",
                                             "mliv",      "labeled-mliv", "labeled-mliv-unguarded"};
  EXPECT_EQ(InIStateValidityNames(), inistate);
  try {
    ParseValidityMode("exact", "run/path.h5: attribute 'validity'");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "run/path.h5: attribute 'validity': unknown mode 'exact' (expected rigid-exact, collision, shrink, "
                 "iv, mliv, labeled-mliv or labeled-mliv-unguarded)");
  }
}

// A box-soup panel: a rigid key (its own solid) 2 mm above a 2 mm plate,
// near a long clip whose tip sits in the plate at the start (so the key is
// within the fasteners' reach psi and the voxel fastener guard lets it be).
// Pushing the key 1.5 mm into the plate costs a volume far under a generous
// tau: Labeled-MLIV cannot forbid it. The rigid guard refuses it whatever
// tau is, and leaves the clip's own overlap to the volume.
TEST(VolumeModel, ARigidKeyCrossingA2mmPlateIsRefusedWhateverTauIs) {
  TriangleMesh d = MakeBox({0, 0, 10}, {60, 40, 13});  // the panel
  d.Append(MakeBox({10, 10, 4}, {14, 30, 10}));        // the rigid key, 2 mm above the plate
  d.Append(MakeBox({20, 18, 0.5}, {52, 22, 10}));      // the clip, its tip in the plate
  const Scene scene = MakeScene("key-over-plate", MakeBox({-20, -20, 0}, {80, 60, 2}), d);
  const PlanningProblem problem = MakePlanningProblem(scene);
  VoxelizeOptions voxelize;
  voxelize.voxel_size = 0.5;
  const SceneVoxels voxels = VoxelizeScene(scene, voxelize);
  std::vector<double> deformability(scene.dynamic_mesh.vertices.size(), 0.0);
  for (const auto& tri : scene.dynamic_mesh.triangles) {
    bool clip = true;
    for (int v : tri)
      clip = clip && scene.dynamic_mesh.vertices[v].x() > 19 && scene.dynamic_mesh.vertices[v].z() < 10.5;
    if (clip)
      for (int v : tri) deformability[v] = 1.0;
  }
  VolumeModel model(problem, scene.dynamic_mesh, voxels, deformability, ValidityMode::kLabeledMliv);
  Pose pushed = problem.start;
  pushed.t.z() -= 3.5;  // the key 1.5 mm into the plate (the clip deeper too)
  const double unguarded = model.Measure(pushed);
  EXPECT_TRUE(std::isfinite(unguarded));
  const double tau = 1e6;
  EXPECT_TRUE(VolumeValidity(model.volume(), model.measure(), tau).IsValid(pushed));
  EXPECT_EQ(model.GuardRigidParts(problem, 0.05), 2);  // the panel and the key; the clip is a fastener
  EXPECT_TRUE(std::isinf(model.Measure(pushed)));
  EXPECT_FALSE(VolumeValidity(model.volume(), model.measure(), tau).IsValid(pushed));
  // The start (only the clip in the plate) and a pose with the key just
  // touching stay as they were.
  EXPECT_TRUE(std::isfinite(model.Measure(problem.start)));
  Pose touching = problem.start;
  touching.t.z() -= 1.99;
  EXPECT_TRUE(std::isfinite(model.Measure(touching)));
}

// S: a 10 mm cube; D: a 10 x 10 x 4 slab overlapping its top by 1 mm at the
// start (a 10 x 10 x 1 = 100 mm^3 overlap, plus the voxels' surface margin).
TEST(VolumeModel, ModesMeasureTheOverlapAndShrinkFreesTheStart) {
  const Scene scene = MakeScene("slab-on-cube", MakeBox({0, 0, 0}, {10, 10, 10}), MakeBox({0, 0, 9}, {10, 10, 13}));
  const PlanningProblem problem = MakePlanningProblem(scene);
  VoxelizeOptions voxelize;
  voxelize.voxel_size = 0.25;
  const SceneVoxels voxels = VoxelizeScene(scene, voxelize);
  VolumeModel iv(problem, scene.dynamic_mesh, voxels, {}, ValidityMode::kIv);
  const double start = iv.Measure(problem.start);
  EXPECT_GT(start, 100.0);
  EXPECT_LT(start, 100.0 + 2 * 100 * 0.5);  // at most ~2 voxel layers of margin
  // Lifted clear, nothing.
  Pose lifted = problem.start;
  lifted.t.z() += 5;
  EXPECT_EQ(iv.Measure(lifted), 0.0);
  // The validity thresholds the same number.
  const VolumeValidity tight(iv.volume(), VolumeMeasure::kIv, start - 1), loose(iv.volume(), VolumeMeasure::kIv, start);
  EXPECT_FALSE(tight.IsValid(problem.start));
  EXPECT_TRUE(loose.IsValid(problem.start));
  // Labeled-MLIV needs labels.
  EXPECT_THROW(VolumeModel(problem, scene.dynamic_mesh, voxels, {}, ValidityMode::kLabeledMliv), InputError);
  // Shrink: the smallest whole-voxel erosion that frees the start is a bit
  // more than the 1 mm overlap (plus the margin), far less than D's 4 mm.
  VolumeModel shrink(problem, scene.dynamic_mesh, voxels, {}, ValidityMode::kShrink);
  EXPECT_GE(shrink.shrink(), 1.0);
  EXPECT_LE(shrink.shrink(), 1.0 + 3 * 0.25);
  EXPECT_EQ(shrink.Measure(problem.start), 0.0);
  // A D buried 3 mm deep in a 4 mm slab cannot be freed by shrinking.
  const Scene buried = MakeScene("buried", MakeBox({0, 0, 0}, {10, 10, 10}), MakeBox({0, 0, 7}, {10, 10, 11}));
  EXPECT_THROW(VolumeModel(MakePlanningProblem(buried), buried.dynamic_mesh, VoxelizeScene(buried, voxelize), {},
                           ValidityMode::kShrink),
               InputError);
}

// D: a 20 x 20 x 2 plate with a 2 x 2 x 8 tongue below; the tongue's
// vertices are labelled deformable. psi = the tongue's 8 mm + 2 voxels,
// give or take the voxels at its root that take the tongue's colour; far
// from the plate's 20 mm.
TEST(VolumeModel, PsiIsTheLargestDeformableComponentsExtent) {
  TriangleMesh d = MakeBox({0, 0, 8}, {20, 20, 10});
  const int tongue_first_vertex = static_cast<int>(d.vertices.size());
  d.Append(MakeBox({9, 9, 0}, {11, 11, 8}));
  const Scene scene = MakeScene("tongue", MakeBox({40, 40, 0}, {50, 50, 10}), d);
  std::vector<double> deformability(scene.dynamic_mesh.vertices.size(), 0.0);
  for (std::size_t v = tongue_first_vertex; v < deformability.size(); ++v) deformability[v] = 1.0;
  VoxelizeOptions voxelize;
  voxelize.voxel_size = 0.25;
  const PlanningProblem problem = MakePlanningProblem(scene);
  VolumeModel model(problem, scene.dynamic_mesh, VoxelizeScene(scene, voxelize), deformability,
                    ValidityMode::kLabeledMliv);
  EXPECT_GE(model.EstimatePsi(), 8.0);
  EXPECT_LE(model.EstimatePsi(), 8.0 + 2 * 0.25 + 1.5);
  VolumeModel rigid(problem, scene.dynamic_mesh, VoxelizeScene(scene, voxelize), {}, ValidityMode::kMliv);
  EXPECT_DOUBLE_EQ(rigid.EstimatePsi(), 2 * 0.25);  // no labels: two voxels
}

// The fastener guard. S: a 55 x 40 x 2 plate. D: a 40 mm bar 1 mm above it
// with a deformable 2 x 4 mm tongue at one end that reaches 0.5 mm into the
// plate at the start (a relaxed clip). Pushing the tongue deeper stays
// within its reach; lowering the whole bar into the plate puts voxels up to
// 37 mm from the tongue into S: refused by labeled-mliv at any tau, a finite
// volume for labeled-mliv-unguarded.
TEST(VolumeModel, FastenerGuardRefusesIntersectionsBeyondTheFastenersReach) {
  TriangleMesh d = MakeBox({0, 18, 3}, {40, 22, 5});
  const int tongue_first_vertex = static_cast<int>(d.vertices.size());
  d.Append(MakeBox({1, 18, 1.5}, {3, 22, 5}));
  const Scene scene = MakeScene("bar-with-tongue", MakeBox({-5, 0, 0}, {50, 40, 2}), d);
  std::vector<double> deformability(scene.dynamic_mesh.vertices.size(), 0.0);
  for (std::size_t v = tongue_first_vertex; v < deformability.size(); ++v) deformability[v] = 1.0;
  VoxelizeOptions voxelize;
  voxelize.voxel_size = 0.25;
  const SceneVoxels voxels = VoxelizeScene(scene, voxelize);
  const PlanningProblem problem = MakePlanningProblem(scene);
  VolumeModel guarded(problem, scene.dynamic_mesh, voxels, deformability, ValidityMode::kLabeledMliv);
  VolumeModel unguarded(problem, scene.dynamic_mesh, voxels, deformability, ValidityMode::kLabeledMlivUnguarded);
  ASSERT_TRUE(guarded.guarded());
  EXPECT_FALSE(unguarded.guarded());
  // psi: the tongue below the bar (1.5 mm) plus two voxels, give or take the
  // interpolated colours at its root; the reach is the tongue's end of D.
  EXPECT_GT(guarded.start_voxels(), 0);
  EXPECT_GT(guarded.reach_voxels(), guarded.start_voxels());
  EXPECT_LT(guarded.reach_voxels(), voxels.dynamic_grid.CountOccupied() / 3);

  // At the start both measure the tongue's overlap (its colour is ~0, so
  // little of it counts), the same number.
  EXPECT_TRUE(std::isfinite(guarded.Measure(problem.start)));
  EXPECT_DOUBLE_EQ(guarded.Measure(problem.start), unguarded.Measure(problem.start));
  // The tongue 0.4 mm deeper (the bar still 0.6 mm above the plate, more
  // than the voxels' surface margin): within reach.
  Pose deeper = problem.start;
  deeper.t.z() -= 0.4;
  EXPECT_TRUE(std::isfinite(guarded.Measure(deeper)));
  EXPECT_DOUBLE_EQ(guarded.Measure(deeper), unguarded.Measure(deeper));
  // The bar 0.5 mm into the plate along its whole length: the rigid bar's
  // overlap, at least 37 x 4 x 0.5 = 74 mm^3 beyond the tongue, counts fully
  // when unguarded; guarded, nothing allows it.
  Pose lowered = problem.start;
  lowered.t.z() -= 1.5;
  EXPECT_GT(unguarded.Measure(lowered), 74.0);
  EXPECT_TRUE(std::isfinite(unguarded.Measure(lowered)));
  EXPECT_EQ(guarded.Measure(lowered), std::numeric_limits<double>::infinity());
  EXPECT_FALSE(VolumeValidity(guarded.volume(), VolumeMeasure::kLabeledMliv, 1e9).IsValid(lowered));
  EXPECT_TRUE(VolumeValidity(unguarded.volume(), VolumeMeasure::kLabeledMliv, 1e9).IsValid(lowered));
  // Reports keep the labels' deformability (no infinities).
  const VolumeReport report = guarded.Describe(lowered);
  EXPECT_GE(report.deformability, 0.0);
  EXPECT_LE(report.deformability, 1.0);

  // A start clear of S has no reach: any intersection is refused.
  PlanningProblem lifted_start = problem;
  lifted_start.start.t.z() += 5;
  VolumeModel no_reach(lifted_start, scene.dynamic_mesh, voxels, deformability, ValidityMode::kLabeledMliv);
  EXPECT_EQ(no_reach.start_voxels(), 0);
  EXPECT_EQ(no_reach.reach_voxels(), 0);
  EXPECT_EQ(no_reach.Measure(lifted_start.start), 0.0);
  EXPECT_EQ(no_reach.Measure(problem.start), std::numeric_limits<double>::infinity());
}

// S a 10-unit cube, D a 2-unit cube, and the MLIV model on 0.25 voxels:
// the volume smoother's hand-checkable case.
struct CubeBesideCube {
  explicit CubeBesideCube(const std::string& name)
      : scene(MakeScene(name, MakeBox({0, 0, 0}, {10, 10, 10}), MakeBox({-1, -1, -1}, {1, 1, 1}))),
        problem(MakePlanningProblem(scene)),
        model(problem, scene.dynamic_mesh, VoxelizeScene(scene, Voxels(0.25)), {}, ValidityMode::kMliv) {}
  static VoxelizeOptions Voxels(double size) {
    VoxelizeOptions options;
    options.voxel_size = size;
    return options;
  }
  // D's reference point at (x, 5, z).
  Pose At(double x, double z) const {
    Pose p = problem.start;
    p.t = Eigen::Vector3d(x, 5, z);
    return p;
  }
  Scene scene;
  PlanningProblem problem;
  VolumeModel model;
};

// A detour around a cube (no intersection anywhere) is shortened, but never
// through the cube, although the straight line start -> end would be shorter.
TEST(VolumeSmoother, ShortcutsNeverDeepenTheIntersection) {
  const CubeBesideCube cubes("detour");
  const PlanningProblem& problem = cubes.problem;
  auto at = [&](double x, double z) { return cubes.At(x, z); };
  // Left of the cube, up, over in small steps, down on the right.
  std::vector<Pose> path = {at(-5, 5), at(-5, 15)};
  for (double x = -3; x <= 15; x += 2) path.push_back(at(x, 15));
  path.push_back(at(15, 5));
  IntersectionVolume volume = cubes.model.volume().Clone();
  const double step = 0.01 * problem.robot_diagonal / 4;
  ASSERT_EQ(MaxVolumeAlong(problem, volume, VolumeMeasure::kMliv, path, step), 0.0);
  ASSERT_GT(MaxVolumeAlong(problem, volume, VolumeMeasure::kMliv, {path.front(), path.back()}, step), 0.0);
  SmoothOptions options;
  options.attempts = 500;
  const VolumeSmoothResult result = SmoothUnderVolume(problem, volume, VolumeMeasure::kMliv, path, options);
  EXPECT_LT(result.path.size(), path.size());
  EXPECT_GT(result.shortcuts, 0);
  EXPECT_EQ(result.path.front().t, path.front().t);
  EXPECT_EQ(result.path.back().t, path.back().t);
  EXPECT_EQ(result.max_after, 0.0);
  EXPECT_EQ(MaxVolumeAlong(problem, volume, VolumeMeasure::kMliv, result.path, step), 0.0);
  EXPECT_LT(MeasurePath(problem, result.path).normalized, MeasurePath(problem, path).normalized);
}

// The guard compares a replacement with the section it replaces, both
// including the pose they start from: leaving a partial intersection at its
// own depth is accepted (a section that starts there reaches it too), going
// deeper is not.
TEST(VolumeSmoother, GuardComparesWithTheReplacedSectionFromItsStart) {
  const CubeBesideCube cubes("guard");
  const PlanningProblem& problem = cubes.problem;
  auto at = [&](double x) { return cubes.At(x, 5); };
  IntersectionVolume volume = cubes.model.volume().Clone();
  const VolumeGuard guard(problem, volume, VolumeMeasure::kMliv, 0.01 * problem.robot_diagonal / 4);
  const Pose partly_in = at(-0.5), out = at(-5), deep = at(3);
  const double start_volume = volume.Measure(VolumeMeasure::kMliv, partly_in);
  ASSERT_GT(start_volume, 0.0);
  ASSERT_GT(volume.Measure(VolumeMeasure::kMliv, deep), start_volume);
  ASSERT_EQ(volume.Measure(VolumeMeasure::kMliv, out), 0.0);
  EXPECT_TRUE(guard.Accepts({partly_in, out}, {partly_in, partly_in}));  // stays at the start's depth
  EXPECT_FALSE(guard.Accepts({partly_in, out}, {partly_in, deep}));
  EXPECT_TRUE(guard.Accepts({partly_in, deep}, {partly_in, out}));
}

// The straight retreat of an InIState path may leave only from the part
// that may be replaced (from waypoint `first` on); what comes before stays.
TEST(Smoother, StraightRetreatLeavesFromTheReplaceablePartOnly) {
  TriangleMesh walls = MakeBox({0, 0, 0}, {1, 10, 10});
  walls.Append(MakeBox({9, 0, 0}, {10, 10, 10}));
  const Scene scene = MakeScene("retreat", walls, MakeBox({4.5, 4.5, 4.5}, {5.5, 5.5, 5.5}));
  const PlanningProblem problem = MakePlanningProblem(scene);
  const FclCollisionChecker checker(problem.robot, problem.environment);
  auto at = [&](double dx, double dz) {
    Pose p = problem.start;
    p.t += Eigen::Vector3d(dx, 0, dz);
    return p;
  };
  const std::vector<Pose> input = {at(0, 0), at(0, 3), at(1, 3), at(1, 7), at(1, 20)};
  ASSERT_TRUE(problem.InGoalRegion(input.back()));
  SmoothOptions options;
  std::vector<Pose> anywhere = input;
  // Anywhere: straight up from the first segment (any point of it makes the
  // same length), D's AABB just clear of S's (plus 1% of D's diagonal).
  const Pose top = at(0, 5.5 + 0.01 * problem.robot_diagonal);
  const int from_anywhere = StraightRetreatFrom(problem, checker, options, nullptr, 0, &anywhere);
  EXPECT_LE(from_anywhere, 1);
  ASSERT_EQ(static_cast<int>(anywhere.size()), from_anywhere + 2);
  for (const Pose& pose : anywhere) EXPECT_NEAR(pose.t.x(), top.t.x(), 1e-9);
  EXPECT_NEAR(anywhere.back().t.z(), top.t.z(), 1e-9);
  // From waypoint 2 on only: the first two segments stay, then up from at(1, 3).
  std::vector<Pose> later = input;
  const int from_later = StraightRetreatFrom(problem, checker, options, nullptr, 2, &later);
  EXPECT_GE(from_later, 2);
  ASSERT_EQ(static_cast<int>(later.size()), from_later + 2);
  for (int i = 0; i <= 2; ++i) EXPECT_EQ(later[i].t, input[i].t);
  EXPECT_NEAR(later.back().t.x(), at(1, 0).t.x(), 1e-9);
  EXPECT_NEAR(later.back().t.z(), top.t.z(), 1e-9);
  // No point of the part to replace: unchanged.
  std::vector<Pose> none = input;
  EXPECT_EQ(StraightRetreatFrom(problem, checker, options, nullptr, input.size() - 1, &none), -1);
  EXPECT_EQ(none.size(), input.size());
}

// ------------------------------------------------------------ clip scenes

struct ClipCase {
  Scene scene;
  ClipGroundTruth truth;
  SceneVoxels voxels;
};

const ClipCase& Clip(const std::string& family) {
  static std::map<std::string, ClipCase> cache;
  auto it = cache.find(family);
  if (it == cache.end()) {
    ClipSceneOptions options;
    options.seed = 3;
    options.triangles = 2000;
    const ClipSceneFiles files = GenerateClipScene(family, options, testing::MakeTempDir(family));
    ClipCase c;
    c.scene = LoadScene(files.scene_yaml);
    c.truth = LoadClipGroundTruth(files.ground_truth_yaml);
    c.voxels = VoxelizeScene(c.scene, VoxelizeOptions{});
    it = cache.emplace(family, std::move(c)).first;
  }
  return it->second;
}

std::vector<double> TruthLabels(const ClipCase& c) {
  std::vector<double> labels = c.truth.VertexDeformability();
  for (double& value : labels) value = value > 0 ? 1.0 : 0.0;
  return labels;
}

TEST(GroundTruthCheck, KnownPathIsCorrectStraightLiftIsNot) {
  for (const std::string family : {"clips-ds1", "clips-ds3"}) {
    SCOPED_TRACE(family);
    const ClipCase& c = Clip(family);
    const GroundTruthCheck known =
        CheckPathAgainstGroundTruth(c.scene, c.truth, c.voxels, c.scene.dynamic_origin, c.truth.path);
    EXPECT_TRUE(known.correct) << known.reason;
    // Lifting straight up, without sliding the rails out first, drags them
    // through their lips.
    Pose up = c.truth.path.front();
    up.t.z() += 100;
    const GroundTruthCheck lift =
        CheckPathAgainstGroundTruth(c.scene, c.truth, c.voxels, c.scene.dynamic_origin, {c.truth.path.front(), up});
    EXPECT_TRUE(lift.ends_disassembled);
    EXPECT_FALSE(lift.correct);
    EXPECT_EQ(lift.worst_part.rfind("rail", 0), 0u) << lift.worst_part;
  }
}

struct Planned {
  InIStateResult result;
  double tau = 0, psi = 0;
};

// A clip scene's planning problem, Labeled-MLIV model with ground-truth
// labels, FCL checker and psi.
struct TruthLabelled {
  explicit TruthLabelled(const ClipCase& c)
      : problem(MakePlanningProblem(c.scene)),
        model(problem, c.scene.dynamic_mesh, c.voxels, TruthLabels(c), ValidityMode::kLabeledMliv),
        fcl(problem.robot, problem.environment),
        psi(model.EstimatePsi()) {}
  const PlanningProblem problem;
  VolumeModel model;
  const FclCollisionChecker fcl;
  const double psi;
};

// tau estimate + InIState planning with ground-truth labels.
Planned PlanClip(const ClipCase& c, std::uint64_t seed, int threads = 0) {
  TruthLabelled t(c);
  const PlanningProblem& problem = t.problem;
  VolumeModel& model = t.model;
  const FclCollisionChecker& fcl = t.fcl;
  Planned out;
  out.psi = t.psi;
  TauEstimateOptions tau_options;
  tau_options.planner.seed = seed;
  tau_options.threads = threads;
  const TauEstimate estimate =
      EstimateTau(FastenerProblem(problem, fcl, out.psi), model.volume(), model.measure(), out.psi, tau_options);
  EXPECT_TRUE(estimate.solved);
  EXPECT_GE(estimate.tau, estimate.tau_lowest);
  out.tau = estimate.tau;
  const VolumeValidity validity(model.volume(), model.measure(), out.tau);
  InIStateOptions options;
  options.local.seed = options.rigid.seed = seed;
  options.local.time_limit_s = options.rigid.time_limit_s = 30;
  options.psi = out.psi;
  out.result = PlanInIState(problem, validity, fcl, fcl, options);
  return out;
}

TEST(InIStatePlanner, PlansCorrectPathsOnClipScenesWithTrueLabels) {
  for (const std::string family : {"clips-ds1", "clips-ds2", "clips-ds3", "clips-ds4", "clips-ds5"}) {
    SCOPED_TRACE(family);
    const ClipCase& c = Clip(family);
    const Planned planned = PlanClip(c, 1);
    ASSERT_TRUE(planned.result.solved());
    const PlanningProblem problem = MakePlanningProblem(c.scene);
    const auto& path = planned.result.path;
    ASSERT_GT(planned.result.inter_index, 0);
    // c_inter: collision-free and more than psi from S.
    const FclCollisionChecker fcl(problem.robot, problem.environment);
    const Pose& inter = path[planned.result.inter_index];
    EXPECT_FALSE(fcl.InCollision(inter));
    EXPECT_GT(fcl.Distance(inter), planned.psi);
    EXPECT_EQ(path.front().t, problem.start.t);
    EXPECT_TRUE(problem.InGoalRegion(path.back()));
    std::vector<Pose> scene_path;
    for (const Pose& p : path) scene_path.push_back(problem.PlanningToScene(p));
    const GroundTruthCheck check =
        CheckPathAgainstGroundTruth(c.scene, c.truth, c.voxels, problem.reference_point, scene_path);
    EXPECT_TRUE(check.correct) << check.reason;
  }
}

// ausbau-plan hands the tau estimate's sigma_1 to PlanInIState instead of
// planning it again: the result is the same path, without the planning; a
// path that does not hold is re-planned.
TEST(InIStatePlanner, ReusesAKnownSigma1OnlyWhenItHolds) {
  TruthLabelled t(Clip("clips-ds4"));
  const PlanningProblem& problem = t.problem;
  VolumeModel& model = t.model;
  const FclCollisionChecker& fcl = t.fcl;
  const double psi = t.psi;
  TauEstimateOptions tau_options;
  tau_options.planner.seed = 3;
  const TauEstimate estimate =
      EstimateTau(FastenerProblem(problem, fcl, psi), model.volume(), model.measure(), psi, tau_options);
  ASSERT_TRUE(estimate.solved);
  ASSERT_GE(estimate.local_path.size(), 2u);
  EXPECT_EQ(estimate.local_seed, 3u);
  EXPECT_EQ(estimate.local_planner, "est");
  const VolumeValidity validity(model.volume(), model.measure(), estimate.tau);
  InIStateOptions options;
  options.local.seed = options.rigid.seed = 3;
  options.psi = psi;

  const InIStateResult planned = PlanInIState(problem, validity, fcl, fcl, options);
  options.known_local_path = estimate.local_path;
  const InIStateResult reused = PlanInIState(problem, validity, fcl, fcl, options);
  ASSERT_TRUE(planned.solved() && reused.solved());
  EXPECT_EQ(reused.local.stats.nodes, 0);             // not planned
  EXPECT_GT(reused.local.stats.collision_checks, 0);  // but re-checked
  EXPECT_GT(planned.local.stats.nodes, 0);
  // Same seed, tau and planner: the round's sigma_1 is the one planning finds.
  ASSERT_EQ(planned.path.size(), reused.path.size());
  for (std::size_t i = 0; i < planned.path.size(); ++i) EXPECT_EQ(planned.path[i].t, reused.path[i].t) << i;

  // Not from the start: planned anew.
  options.known_local_path.front().t.x() += 1.0;
  const InIStateResult off = PlanInIState(problem, validity, fcl, fcl, options);
  ASSERT_TRUE(off.solved());
  EXPECT_GT(off.local.stats.nodes, 0);
  EXPECT_EQ(off.path.front().t, problem.start.t);
  // Through S (a straight lift drags the clips' barbs through the plate,
  // far above the start's volume): not used, planned anew.
  const VolumeValidity tight(model.volume(), model.measure(), model.Measure(problem.start));
  options.known_local_path = {problem.start, problem.start};
  options.known_local_path.back().t.z() += 3 * problem.robot_diagonal;
  options.local.time_limit_s = 0.5;
  const InIStateResult through = PlanInIState(problem, tight, fcl, fcl, options);
  const std::vector<Pose>& got = through.local.path;
  EXPECT_TRUE(got.size() != 2 || got[1].t != options.known_local_path[1].t);
  EXPECT_GT(through.local.stats.nodes, 0);
}

TEST(TauEstimate, DeterministicAndIndependentOfThreads) {
  const ClipCase& c = Clip("clips-ds4");
  const Planned one = PlanClip(c, 5, 1), two = PlanClip(c, 5, 2);
  EXPECT_EQ(one.tau, two.tau);
  ASSERT_TRUE(one.result.solved() && two.result.solved());
  ASSERT_EQ(one.result.path.size(), two.result.path.size());
  for (std::size_t i = 0; i < one.result.path.size(); ++i) EXPECT_EQ(one.result.path[i].t, two.result.path[i].t);
}

// With more than one thread, round r + 1 is searched and planned alongside
// round r, on a tau found as if r had failed: the trace must be the
// one-round-at-a-time trace. Rounds limited by iterations, so that they fail
// deterministically (DeterministicAndIndependentOfThreads covers a first
// round that succeeds while the second is cancelled).
TEST(TauEstimate, SpeculativeRoundsGiveTheSequentialTrace) {
  TruthLabelled t(Clip("clips-ds4"));
  const PlanningProblem fastener = FastenerProblem(t.problem, t.fcl, t.psi);
  VolumeModel& model = t.model;
  const double psi = t.psi;
  auto run = [&](int threads) {
    TauEstimateOptions options;
    options.planner.seed = 2;
    options.planner.max_iterations = 3;
    options.max_rounds = 3;
    options.threads = threads;
    return EstimateTau(fastener, model.volume(), model.measure(), psi, options);
  };
  const TauEstimate one = run(1);
  EXPECT_FALSE(one.solved);
  EXPECT_EQ(one.rounds, 3);
  EXPECT_GT(one.trace.size(), 3u);  // probes and rounds
  for (int threads : {2, 3}) {
    SCOPED_TRACE(threads);
    const TauEstimate many = run(threads);
    EXPECT_EQ(many.tau, one.tau);
    EXPECT_EQ(many.rounds, one.rounds);
    EXPECT_EQ(many.speed_target, one.speed_target);
    ASSERT_EQ(many.trace.size(), one.trace.size());
    for (std::size_t i = 0; i < one.trace.size(); ++i) {
      EXPECT_EQ(many.trace[i].round, one.trace[i].round) << i;
      EXPECT_EQ(many.trace[i].tau, one.trace[i].tau) << i;
      EXPECT_EQ(many.trace[i].planning_round, one.trace[i].planning_round) << i;
      EXPECT_EQ(many.trace[i].nodes, one.trace[i].nodes) << i;
      EXPECT_EQ(many.trace[i].checks, one.trace[i].checks) << i;
    }
  }
}

TEST(TauEstimate, StartAboveTauIsRefusedAndArtifactRoundTrips) {
  const ClipCase& c = Clip("clips-ds4");
  const PlanningProblem problem = MakePlanningProblem(c.scene);
  VolumeModel model(problem, c.scene.dynamic_mesh, c.voxels, {}, ValidityMode::kIv);
  const double start = model.Measure(problem.start);
  ASSERT_GT(start, 0);
  const FclCollisionChecker fcl(problem.robot, problem.environment);
  const VolumeValidity below(model.volume(), VolumeMeasure::kIv, 0.5 * start);
  InIStateOptions options;
  options.psi = 1;
  EXPECT_THROW(PlanInIState(
                   problem, below, fcl, [](const Pose&) { return true; }, [](const Pose&) { return 0.0; }, options),
               InputError);

  TauArtifact artifact;
  artifact.validity = ValidityMode::kIv;
  artifact.units = "mm";
  artifact.estimate.tau = 12.5;
  artifact.estimate.psi = 3.0;
  artifact.estimate.tau_lowest = 10;
  artifact.estimate.rounds = 1;
  artifact.estimate.solved = true;
  TauProbe probe;
  probe.tau = 12.5;
  probe.speed = std::numeric_limits<double>::infinity();
  probe.nodes = 7;
  artifact.estimate.trace = {probe};
  Pose moved;
  moved.t = {1, 2, 3};
  artifact.estimate.local_path = {Pose{}, moved};
  artifact.estimate.local_seed = 9;
  artifact.estimate.local_planner = "est";
  const auto file = testing::MakeTempDir("tau") / "tau.h5";
  WriteTauArtifact(file, artifact, Provenance{"test", "0", "", {}});
  const TauArtifact back = ReadTauArtifact(file);
  EXPECT_EQ(back.validity, ValidityMode::kIv);
  EXPECT_EQ(back.estimate.tau, 12.5);
  EXPECT_EQ(back.estimate.psi, 3.0);
  ASSERT_EQ(back.estimate.trace.size(), 1u);
  EXPECT_TRUE(std::isinf(back.estimate.trace[0].speed));
  EXPECT_EQ(back.estimate.trace[0].nodes, 7);
  ASSERT_EQ(back.estimate.local_path.size(), 2u);
  EXPECT_EQ(back.estimate.local_path[1].t, moved.t);
  EXPECT_EQ(back.estimate.local_seed, 9u);
  EXPECT_EQ(back.estimate.local_planner, "est");
  EXPECT_THROW(ReadPathArtifact(file), InputError);  // wrong schema
}

TEST(PathArtifact, InIStateDatasetsRoundTrip) {
  PathArtifact path;
  path.success = true;
  path.waypoints = {Pose{}, Pose{}};
  path.waypoints[1].t = {1, 2, 3};
  path.validity = ValidityMode::kLabeledMliv;
  path.tau = 4.5;
  path.psi = 2.0;
  path.inter_index = 1;
  path.waypoint_volume = {3.0, 0.0};
  path.waypoint_part = {2, -1};
  path.waypoint_deformability = {0.75, 0.0};
  const auto file = testing::MakeTempDir("path") / "path.h5";
  WritePathArtifact(file, path, Provenance{"test", "0", "", {}});
  const PathArtifact back = ReadPathArtifact(file);
  EXPECT_EQ(back.validity, ValidityMode::kLabeledMliv);
  EXPECT_EQ(back.tau, 4.5);
  EXPECT_EQ(back.inter_index, 1);
  EXPECT_EQ(back.waypoint_part, (std::vector<int>{2, -1}));
  EXPECT_EQ(back.waypoint_deformability, (std::vector<double>{0.75, 0.0}));
  // A rigid path has none of it.
  PathArtifact rigid;
  rigid.waypoints = {Pose{}};
  WritePathArtifact(file, rigid, Provenance{"test", "0", "", {}});
  EXPECT_EQ(ReadPathArtifact(file).validity, ValidityMode::kCollision);
  EXPECT_TRUE(ReadPathArtifact(file).waypoint_volume.empty());
}

}  // namespace
}  // namespace ausbau
