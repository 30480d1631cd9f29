// Clearance (planning/clearance.h) on hand-checkable boxes, the smoother's
// clearance guard, the path quality figures of the verdict, and the units
// and poses of the path artifacts and profile.csv.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "artifact/artifact.h"
#include "collision/fcl_checker.h"
#include "collision/scene_parts.h"
#include "generated_scene.h"
#include "geometry/primitives.h"
#include "planning/clearance.h"
#include "planning/path_io.h"
#include "planning/planner.h"
#include "planning/smoother.h"
#include "scene/scene.h"
#include "test_scenes.h"
#include "workflow/path_profile.h"
#include "workflow/path_quality.h"

namespace ausbau {
namespace {

// D: the unit cube about the origin; S: the box x in [2, 3], |y|, |z| <= 1.
// At t = (x, 0, 0), no rotation, the clearance is 1.5 - x (x <= 1.5).
Scene BoxScene() {
  Scene scene;
  scene.name = "boxes";
  scene.units = "mm";
  scene.dynamic_mesh = MakeBox({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5});
  scene.static_mesh = MakeBox({2, -1, -1}, {3, 1, 1});
  return scene;
}

Pose At(double x, double y = 0) {
  Pose pose;
  pose.t = {x, y, 0};
  return pose;
}

TEST(Clearance, MeasuresTheDistanceAndWhere) {
  const Scene scene = BoxScene();
  const PlanningProblem problem = MakePlanningProblem(scene);
  const ClearanceMeter meter(problem, problem.robot);
  const ClearanceSample here = meter.At(At(0));
  EXPECT_NEAR(here.clearance, 1.5, 1e-9);
  EXPECT_NEAR(here.on_robot.x(), 0.5, 1e-9);
  EXPECT_NEAR(here.on_static.x(), 2.0, 1e-9);
  // Moving towards S: the smallest clearance at the end, found whatever the floor.
  for (const double floor : {std::numeric_limits<double>::infinity(), 0.4, 0.0}) {
    const ClearanceSample along = meter.Along(At(0), At(1), floor, 0.01);
    EXPECT_NEAR(along.clearance, 0.5, 1e-9) << floor;
    EXPECT_NEAR(along.fraction, 1.0, 1e-12) << floor;
  }
  // In contact: 0, both points at the contact.
  const ClearanceSample touching = meter.At(At(2.0));
  EXPECT_EQ(touching.clearance, 0.0);
  EXPECT_TRUE(touching.on_robot.isApprox(touching.on_static));
  // A path: the closest segment is named.
  const ClearanceSample path = meter.AlongPath({At(0, -3), At(0), At(0.8), At(0.8, 3)}, 0.1, 0.01);
  EXPECT_EQ(path.segment, 1);
  EXPECT_NEAR(path.clearance, 0.7, 1e-9);
}

TEST(Clearance, DefaultIsHalfAMillimetreInTheSceneUnits) {
  EXPECT_DOUBLE_EQ(ClearanceInSceneUnits(-1, "mm"), 0.5);
  EXPECT_DOUBLE_EQ(ClearanceInSceneUnits(-1, "cm"), 0.05);
  EXPECT_DOUBLE_EQ(ClearanceInSceneUnits(-1, "m"), 0.0005);
  EXPECT_DOUBLE_EQ(ClearanceInSceneUnits(-1, ""), 0.5);  // unknown: taken as mm, like the rigid tolerance
  // Given: mm, as every length flag (README "Flags"), converted; without
  // units, scene units.
  EXPECT_DOUBLE_EQ(ClearanceInSceneUnits(2, "m"), 0.002);
  EXPECT_DOUBLE_EQ(ClearanceInSceneUnits(2.54, "in"), 0.1);
  EXPECT_DOUBLE_EQ(ClearanceInSceneUnits(2, "unitless"), 2);
  EXPECT_DOUBLE_EQ(ClearanceInSceneUnits(0, "mm"), 0);
}

TEST(Clearance, GuardRefusesOnlyWhatComesCloserBelowD) {
  const Scene scene = BoxScene();
  const PlanningProblem problem = MakePlanningProblem(scene);
  // The replaced detour keeps 1.5 (x = 0); the shortcut at x = 1.2 keeps
  // only 0.3 < d: refused. At x = 0.9 it keeps 0.6 >= d: accepted.
  const std::vector<Pose> detour = {At(0, -2), At(0, 2)};
  const ClearanceGuard guard(problem, problem.robot, 0.5, 0.01, detour);
  EXPECT_DOUBLE_EQ(guard.floor(), 0.5);
  EXPECT_FALSE(guard.Accepts(detour, {At(1.2, -2), At(1.2, 2)}));
  EXPECT_TRUE(guard.Accepts(detour, {At(0.9, -2), At(0.9, 2)}));
  // Where the replaced part came closer (0.1), a change to 0.3 is better: accepted.
  EXPECT_TRUE(guard.Accepts({At(1.4, -2), At(1.4, 2)}, {At(1.2, -2), At(1.2, 2)}));
  EXPECT_FALSE(guard.Accepts({At(1.2, -2), At(1.2, 2)}, {At(1.4, -2), At(1.4, 2)}));
  EXPECT_NEAR(guard.MinCapped({At(0), At(1.2)}), 0.3, 1e-9);
  EXPECT_DOUBLE_EQ(guard.MinCapped({At(0), At(0.5)}), 0.5);
  // d = 0: no condition.
  const ClearanceGuard none(problem, problem.robot, 0.0, 0.01, detour);
  EXPECT_TRUE(none.Accepts(detour, {At(1.49, -2), At(1.49, 2)}));
}

// The floor: where the path to be smoothed comes within 0.1 of S later on
// (x = 1.4), a shortcut may come that close anywhere, however far the part
// it replaces kept; D's way out of its seat does not count.
TEST(Clearance, GuardLetsShortcutsComeAsCloseAsThePathMust) {
  const Scene scene = BoxScene();
  const PlanningProblem problem = MakePlanningProblem(scene);
  const std::vector<Pose> detour = {At(0, -0.5), At(0, 0.5)};
  // Clear by 1.5 first, then 0.1 from S at x = 1.4: the floor is 0.1.
  const ClearanceGuard narrow_later(problem, problem.robot, 0.5, 0.01,
                                    {At(0, -0.5), At(0, 0.5), At(1.4, 0.5), At(1.4, 0)});
  EXPECT_NEAR(narrow_later.floor(), 0.1, 1e-9);
  EXPECT_TRUE(narrow_later.Accepts(detour, {At(1.2, -0.5), At(1.2, 0.5)}));     // 0.3 >= 0.1
  EXPECT_FALSE(narrow_later.Accepts(detour, {At(1.45, -0.5), At(1.45, 0.5)}));  // 0.05 < 0.1
  // Starting 0.05 from S (its seat), then clear by at least d: the seat
  // does not lower the floor, d is kept as before.
  const ClearanceGuard out_of_a_seat(problem, problem.robot, 0.5, 0.01, {At(1.45, -0.5), At(0, -0.5), At(0, 0.5)});
  EXPECT_DOUBLE_EQ(out_of_a_seat.floor(), 0.5);
  EXPECT_FALSE(out_of_a_seat.Accepts(detour, {At(1.2, -0.5), At(1.2, 0.5)}));
  // Never clear by d: the floor is the whole path's smallest clearance.
  const ClearanceGuard never_clear(problem, problem.robot, 0.5, 0.01, {At(1.45, -0.5), At(1.2, 0.5)});
  EXPECT_NEAR(never_clear.floor(), 0.05, 1e-9);
}

// A part that starts where D touches S (within `contact`, the rigid
// tolerance in rigid-exact: a screw 0.003 mm from its hole's wall) may be
// replaced by any motion: clearances below it are contact, not a clearance
// to keep (its straight pull ran 0.001 mm from the wall and was refused).
TEST(Clearance, GuardTakesAnyReplacementFromAPoseInContact) {
  const Scene scene = BoxScene();
  const PlanningProblem problem = MakePlanningProblem(scene);
  const std::vector<Pose> replaced = {At(1.46), At(0), At(0, 3)};   // from 0.04 of S, then clear by 1.5
  const std::vector<Pose> replacement = {At(1.46), At(1.48, 0.5)};  // to 0.02 from S
  const ClearanceGuard touching(problem, problem.robot, 0.5, 0.01, replaced, 0.05);
  EXPECT_TRUE(touching.Accepts(replaced, replacement));
  // Without it, 0.02 < 0.04: refused; and from 0.1 of S, more than the
  // contact, as well.
  const ClearanceGuard plain(problem, problem.robot, 0.5, 0.01, replaced);
  EXPECT_FALSE(plain.Accepts(replaced, replacement));
  EXPECT_FALSE(touching.Accepts({At(1.4), At(0), At(0, 3)}, {At(1.4), At(1.48, 0.5)}));
}

// A retreat along the replaced path's own first segment visits only poses
// of that segment: taken without walking it (its walk may sample closer than
// the replaced path's own walk did). Anything else is walked as before.
TEST(Clearance, GuardTakesARetraceOfTheFirstSegmentWithoutWalkingIt) {
  const Scene scene = BoxScene();
  const PlanningProblem problem = MakePlanningProblem(scene);
  // A step of 6.5: the walk of the replaced y = -3 .. 3 at x = 1.4 samples
  // only its ends (1.50 from S), the walk of y = -3 .. 0 its end too (0.1).
  const std::vector<Pose> replaced = {At(1.4, -3), At(1.4, 3)};
  const ClearanceGuard guard(problem, problem.robot, 0.5, 6.5, {At(0, -3), At(0, 3)});
  EXPECT_TRUE(guard.Accepts(replaced, {At(1.4, -3), At(1.4, 0)}));
  // Off its line, or turned: walked, and refused (0.05 and less < 0.5).
  EXPECT_FALSE(guard.Accepts(replaced, {At(1.4, -3), At(1.45, 0)}));
  Pose turned = At(1.4, 0);
  turned.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()));
  EXPECT_FALSE(guard.Accepts(replaced, {At(1.4, -3), turned}));
  // Beyond the segment's end: walked.
  EXPECT_FALSE(guard.Accepts({At(1.4, -3), At(1.4, -2)}, {At(1.4, -3), At(1.4, 0)}));
}

TEST(Clearance, WithClearanceIsStricterThanItsBase) {
  const Scene scene = BoxScene();
  const PlanningProblem problem = MakePlanningProblem(scene);
  const FclCollisionChecker fcl(problem.robot, problem.environment);
  const std::unique_ptr<PoseValidity> keeping = WithClearance(fcl, problem, problem.robot, 0.5);
  EXPECT_TRUE(keeping->IsValid(At(0.9)));   // 0.6 from S
  EXPECT_FALSE(keeping->IsValid(At(1.2)));  // 0.3: valid for FCL, not with the clearance
  EXPECT_TRUE(fcl.IsValid(At(1.2)));
  EXPECT_FALSE(keeping->IsValid(At(2.0)));  // in collision: invalid for both
}

TEST(Clearance, SmoothingKeepsItAndZeroChangesNothing) {
  const Scene scene = LoadScene(testing::MakeGeneratedScene("rod-in-cage"));
  const PlanningProblem problem = MakePlanningProblem(scene);
  const FclCollisionChecker checker(problem.robot, problem.environment);
  PlannerOptions options;
  options.seed = 3;
  const PlanResult plan = Plan(problem, checker, options);
  ASSERT_TRUE(plan.solved());
  SmoothOptions smooth;
  smooth.seed = 3;
  const SmoothResult plain = SmoothPath(problem, checker, plan.path, smooth);
  const ClearanceGuard zero(problem, problem.robot, 0.0, 0.01, plan.path);
  const SmoothResult with_zero = SmoothPath(problem, checker, plan.path, smooth, &zero);
  ASSERT_EQ(with_zero.path.size(), plain.path.size());
  for (std::size_t i = 0; i < plain.path.size(); ++i) {
    EXPECT_EQ(with_zero.path[i].t, plain.path[i].t);
    EXPECT_EQ(with_zero.path[i].q.coeffs(), plain.path[i].q.coeffs());
  }
  // A clearance of 2% of D's diagonal: the smoothed path comes no closer
  // below it than the planned one (measured at the guard's own step).
  const double d = 0.02 * problem.robot_diagonal;
  const ClearanceGuard guard(problem, problem.robot, d, ClearanceStep(problem, d), plan.path);
  const SmoothResult kept = SmoothPath(problem, checker, plan.path, smooth, &guard);
  EXPECT_GE(guard.MinCapped(kept.path), guard.MinCapped(plan.path) - ClearanceStep(problem, d));
  EXPECT_LE(kept.after.normalized, kept.before.normalized + 1e-12);
  EXPECT_TRUE(problem.InGoalRegion(kept.path.back()));
}

TEST(PathQuality, FiguresOfAStraightPath) {
  const std::filesystem::path file = testing::MakeGeneratedScene("rod-in-cage");
  const Scene scene = LoadScene(file);
  const PlanningProblem problem = MakePlanningProblem(scene);
  PathArtifact path;
  path.success = true;
  path.clearance = 1e9;  // every segment below it
  Pose end = problem.start;
  end.t.x() -= 0.5 * problem.robot_diagonal;
  Pose far = end;
  far.t.y() += 0.5 * problem.robot_diagonal;
  for (const Pose& p : {problem.start, end, far}) path.waypoints.push_back(problem.PlanningToScene(p));
  const PathQuality q = MeasurePathQuality(scene, path, 0.05);
  EXPECT_NEAR(q.translation, problem.robot_diagonal, 1e-9);
  EXPECT_NEAR(q.straight, std::sqrt(0.5) * problem.robot_diagonal, 1e-9);
  EXPECT_NEAR(q.ratio, std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(q.rotation, 0, 1e-12);
  ASSERT_EQ(q.segment_clearance.size(), 2u);
  EXPECT_EQ(q.min.clearance, std::min(q.segment_clearance[0], q.segment_clearance[1]));
  EXPECT_EQ(q.below, (std::vector<int>{0, 1}));
  // Where: the nearest points lie that far apart.
  EXPECT_NEAR((q.min.on_robot - q.min.on_static).norm(), q.min.clearance, 1e-6);
  EXPECT_NE(ClearanceWarning(q, scene.units).find("segment"), std::string::npos);
  const std::string json = PathQualityJson(q);
  for (const char* key : {"\"translation_ratio\"", "\"segment_clearance\"", "\"point_on_d\"", "\"point_on_s\"",
                          "\"segments_below_clearance\"", "\"clearance_kept\""}) {
    EXPECT_NE(json.find(key), std::string::npos) << key;
  }
  // As a rigid-exact path: the rigid shells' clearance. Given the parts
  // another check classified (the verdict's exact check; here no fastener),
  // the same figures without classifying D again.
  path.validity = ValidityMode::kRigidExact;
  const PathQuality rigid = MeasurePathQuality(scene, path, 0.05);
  const auto parts =
      ClassifySceneParts(scene, RigidToleranceInSceneUnits(0.05, scene, nullptr), UnmeasuredInterference::kRigid);
  ASSERT_EQ(parts->FastenerCount(), 0);
  const PathQuality reused = MeasurePathQuality(scene, path, 0.05, parts.get());
  EXPECT_EQ(reused.segment_clearance, rigid.segment_clearance);
  EXPECT_EQ(reused.min.clearance, rigid.min.clearance);
  EXPECT_EQ(reused.min.on_robot, rigid.min.on_robot);
}

TEST(PathQuality, ProfileHasPosesAndUnits) {
  const std::filesystem::path file = testing::MakeGeneratedScene("rod-in-cage");
  const Scene scene = LoadScene(file);
  const PlanningProblem problem = MakePlanningProblem(scene);
  Pose end = problem.start;
  end.t.x() -= problem.robot_diagonal;
  const std::filesystem::path csv = testing::MakeTempDir("profile") / "profile.csv";
  WritePathProfile(csv, problem, {problem.start, end}, nullptr, problem.robot, "mm");
  std::ifstream in(csv);
  std::string units, header, first;
  std::getline(in, units);
  std::getline(in, header);
  std::getline(in, first);
  EXPECT_EQ(units.rfind("# units: tx,ty,tz,clearance in mm", 0), 0u) << units;
  EXPECT_NE(units.find(kPoseConvention), std::string::npos);
  EXPECT_EQ(header, "segment,fraction,s,tx,ty,tz,qw,qx,qy,qz,volume,part,deformability,clearance");
  // The first row is the start in the scene convention, as path.csv writes it.
  std::vector<double> cells;
  std::stringstream row(first);
  for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell.empty() ? NAN : std::stod(cell));
  ASSERT_EQ(cells.size(), 14u);
  EXPECT_NEAR(cells[3], scene.start.t.x(), 1e-6);
  EXPECT_NEAR(cells[4], scene.start.t.y(), 1e-6);
  EXPECT_NEAR(cells[5], scene.start.t.z(), 1e-6);
  EXPECT_NEAR(std::abs(cells[6]), std::abs(scene.start.q.w()), 1e-6);
}

TEST(PathArtifact, DatasetsCarryUnits) {
  PathArtifact path;
  path.units = "cm";
  path.success = true;
  path.clearance = 0.05;
  path.waypoints = {At(0), At(1)};
  const std::filesystem::path file = testing::MakeTempDir("units") / "path.h5";
  WritePathArtifact(file, path, Provenance{"test", "0", "", {}});
  const ArtifactReader reader(file, kPathSchema, kPathSchemaVersion);
  EXPECT_EQ(reader.ReadStringAttribute("waypoints", "units"), "x,y,z: cm; qw,qx,qy,qz: unitless (unit quaternion)");
  EXPECT_EQ(reader.ReadStringAttribute("waypoints", "pose_convention"), kPoseConvention);
  EXPECT_EQ(reader.ReadStringAttribute("stats/length_translation", "units"), "cm");
  EXPECT_EQ(reader.ReadStringAttribute("stats/length_rotation", "units"), "rad");
  EXPECT_EQ(reader.ReadStringAttribute("stats/clearance", "units"), "cm");
  EXPECT_EQ(reader.ReadStringAttribute("", "units"), "cm");
  EXPECT_DOUBLE_EQ(ReadPathArtifact(file).clearance, 0.05);
}

}  // namespace
}  // namespace ausbau
