// Issue 18, items 3 and 2: a time budget that ends the run with a verdict
// "not-removable (budget)" naming what blocks D, and the disassembly order
// of an assembly (ausbau-order), with a known precedence and with a cycle.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <regex>

#include "collision/part_contacts.h"
#include "fixtures/assembly_scenes.h"
#include "geometry/primitives.h"
#include "planning/path_io.h"
#include "test_scenes.h"
#include "workflow/disassembly_order.h"
#include "workflow/verdict.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;
using Outcome = testing::CommandOutcome;

bool Has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

// D a unit cube at the origin; part 0 a box 2 to its +x, part 1 a box
// overlapping its top by 0.25, part 2 far away.
TEST(PartContacts, NamesTheIntersectingPartFirstThenTheNearOnes) {
  const TriangleMesh robot = MakeBox({0, 0, 0}, {1, 1, 1});
  TriangleMesh environment = MakeBox({3, 0, 0}, {4, 1, 1});
  environment.Append(MakeBox({0.25, 0.25, 0.75}, {0.75, 0.75, 2}));
  environment.Append(MakeBox({50, 50, 50}, {51, 51, 51}));
  const std::vector<int> part_of_triangle = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1,
                                             1, 1, 1, 1, 1, 1, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2};
  const std::vector<PartContact> near =
      MeasurePartContacts(robot, Pose(), environment, part_of_triangle, {"side", "lid", "far"}, 5.0, 8);
  ASSERT_EQ(near.size(), 2u);  // "far" is beyond the reach of 5
  EXPECT_EQ(near[0].name, "lid");
  EXPECT_TRUE(near[0].intersects);
  EXPECT_TRUE(near[0].depth_exact);  // two boxes: the exact depth, 0.25 down
  EXPECT_NEAR(near[0].depth, 0.25, 1e-9);
  EXPECT_EQ(near[1].name, "side");
  EXPECT_FALSE(near[1].intersects);
  EXPECT_NEAR(near[1].distance, 2.0, 1e-9);
  EXPECT_NEAR(near[1].point.x(), 3.0, 1e-9);  // the closest point lies on the side box's face
  // Moved 10 up and 100 along x, D is near nothing: the nearest part alone.
  Pose away;
  away.t = Eigen::Vector3d(100, 0, 10);
  const std::vector<PartContact> alone =
      MeasurePartContacts(robot, away, environment, part_of_triangle, {"side", "lid", "far"}, 5.0, 8);
  ASSERT_EQ(alone.size(), 1u);
  EXPECT_EQ(alone[0].name, "far");
}

// A non-convex D (an L) standing on a block: the rigid check's surface
// depth, about 0 (FCL's deepest crossing triangle pair, the "local
// estimate" before, measures how far a vertex lies beyond another
// triangle's plane: for faces lying on one another, up to a part's size).
// Pressed 0.3 into the block: 0.3.
TEST(PartContacts, ANonConvexPartOnABlockHasTheSurfaceDepth) {
  const TriangleMesh robot = MakePrism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 5}, {0, 5}}, 0, 2);
  const TriangleMesh block = MakeBox({-10, -10, -30}, {10, 10, 0});
  const double resolution = 1e-4 * std::sqrt(4 * 4 + 5 * 5 + 2 * 2);
  const std::vector<PartContact> standing = MeasurePartContacts(robot, Pose(), block, {}, {"block"}, 5.0, 8);
  ASSERT_EQ(standing.size(), 1u);
  EXPECT_TRUE(standing[0].intersects);
  EXPECT_TRUE(standing[0].depth_exact);
  EXPECT_LE(standing[0].depth, resolution);
  Pose pressed;
  pressed.t = Eigen::Vector3d(0, 0, -0.3);
  const std::vector<PartContact> in = MeasurePartContacts(robot, pressed, block, {}, {"block"}, 5.0, 8);
  ASSERT_EQ(in.size(), 1u);
  EXPECT_TRUE(in[0].depth_exact);
  EXPECT_NEAR(in[0].depth, 0.3, 0.3 / 16);
}

// A post (1 x 1 x 10) held by three parts of S, each touching it within the
// tolerance: a sleeve round its middle (0.01 deep into it), a floor under
// it (0.005) and a cap over its top (walls and roof, 0.002). The sleeve is
// the deepest contact, but taken away it frees nothing (the cap and the
// floor still hold the post); the floor or the cap taken away lets it out
// along its axis. The parts that stop its motion come first.
TEST(PartContacts, ThePartsWhoseRemovalFreesDComeFirst) {
  Scene scene;
  scene.name = "post-held-three-ways";
  scene.units = "mm";
  scene.dynamic_mesh = MakeBox({0, 0, 0}, {1, 1, 10});
  const auto add = [&](const Eigen::Vector3d& min, const Eigen::Vector3d& max, int part) {
    scene.static_mesh.Append(MakeBox(min, max));
    scene.static_part_of_triangle.resize(scene.static_mesh.triangles.size(), part);
  };
  add({-1, -1, 2}, {0.01, 2, 6}, 0);  // sleeve: four walls
  add({0.99, -1, 2}, {2, 2, 6}, 0);
  add({0.01, -1, 2}, {0.99, 0.01, 6}, 0);
  add({0.01, 0.99, 2}, {0.99, 2, 6}, 0);
  add({-1, -1, -1}, {2, 2, 0.005}, 1);  // floor
  add({-1, -1, 9.999}, {2, 2, 11}, 2);  // cap: roof and four walls
  add({-1, -1, 7}, {0.002, 2, 9.999}, 2);
  add({0.998, -1, 7}, {2, 2, 9.999}, 2);
  add({0.002, -1, 7}, {0.998, 0.002, 9.999}, 2);
  add({0.002, 0.998, 7}, {0.998, 2, 9.999}, 2);
  scene.static_part_names = {"sleeve", "floor", "cap"};
  const std::vector<PartContact> found = FindBlockingParts(scene, scene.start, 0.05);
  ASSERT_EQ(found.size(), 3u);
  EXPECT_EQ(found[0].name, "floor");  // frees D, the deeper of the two that do
  EXPECT_TRUE(found[0].frees);
  EXPECT_EQ(found[1].name, "cap");
  EXPECT_TRUE(found[1].frees);
  EXPECT_EQ(found[2].name, "sleeve");  // the deepest contact, but holds nothing alone
  EXPECT_FALSE(found[2].frees);
  EXPECT_NEAR(found[2].depth, 0.01, 1e-9);
  // S of one part: nothing to take away, nothing tried.
  Scene one = scene;
  one.static_part_of_triangle.assign(one.static_mesh.triangles.size(), 0);
  one.static_part_names = {"all"};
  const std::vector<PartContact> whole = FindBlockingParts(one, one.start, 0.05);
  ASSERT_EQ(whole.size(), 1u);
  EXPECT_FALSE(whole[0].frees);
}

PartAttempt Blocked(const std::string& part, const std::vector<std::string>& by) {
  PartAttempt attempt;
  attempt.part = part;
  for (const std::string& name : by) {
    PartContact contact;
    contact.name = name;
    attempt.blocked_by.push_back(contact);
  }
  return attempt;
}

TEST(DisassemblyOrder, TheCycleFollowsEachPartsFirstBlockerStillIn) {
  // a is held by the fixed frame first, then by b; b by c; c by b.
  const std::vector<PartAttempt> round = {Blocked("a", {"frame", "b"}), Blocked("b", {"c", "a"}), Blocked("c", {"b"})};
  EXPECT_EQ(FindBlockingCycle({"a", "b", "c"}, round), (std::vector<std::string>{"b", "c", "b"}));
  EXPECT_TRUE(FindBlockingCycle({"a", "b", "c"}, {Blocked("a", {"frame"})}).empty());
}

class BudgetOrderTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { root_ = new fs::path(testing::MakeTempDir("budget-order")); }
  static fs::path* root_;
};
fs::path* BudgetOrderTest::root_ = nullptr;

// A post under a cap cannot come out: with BUDGET=20 the pipeline answers
// within the budget, not after its 60 s time limit, and says why.
TEST_F(BudgetOrderTest, ABlockedPartIsAnsweredWithinItsBudgetWithThePartThatBlocksIt) {
  const fs::path scene = WritePostUnderCapScene(*root_ / "post-under-cap");
  const fs::path out = *root_ / "post-under-cap-out";
  const auto begin = std::chrono::steady_clock::now();
  const Outcome run = testing::RunShellCommand(
      "make --no-print-directory -f " + (testing::SourceDir() / "pipelines/inistate.mk").string() +
      " BIN=" + testing::BinDir().string() + " SCENE=" + scene.string() + " OUT=" + out.string() +
      " VALIDITY=rigid-exact THREADS=1 WITH_REPORT=0 TIME_LIMIT=60 BUDGET=20 2>&1");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  EXPECT_NE(run.exit_code, 0) << run.output;
  const std::string json = testing::ReadTextFile(out / "verdict.json");
  EXPECT_TRUE(Has(json, "\"removable\": false")) << json << run.output;
  EXPECT_TRUE(Has(json, "\"status\": \"not-removable\"")) << json;
  EXPECT_TRUE(Has(json, "\"status_detail\": \"not-removable (budget)\"")) << json;
  EXPECT_TRUE(Has(json, "\"stopped_by_budget\": true")) << json;
  EXPECT_TRUE(Has(json, "\"budget_seconds\": 20")) << json;
  // The clock ended the search: what blocks the post is asked where it
  // stands, not where the search had got to in its seconds. There it
  // touches only its base; its pull up slides to the cover, and without
  // the cover it comes out.
  EXPECT_TRUE(Has(json, "\"at\": \"installed pose\"")) << json;
  EXPECT_TRUE(std::regex_search(json, std::regex(R"("pull_stopper": \{\s*"part": "cover.obj",\s*"frees": true\s*\})")))
      << json;
  const PathArtifact path = ReadPathArtifact(out / "path.h5");
  EXPECT_FALSE(path.success);
  EXPECT_TRUE(path.stopped_by_budget);
  ASSERT_GE(path.partial_waypoints.size(), 2u);
  // The partial path starts installed and stays under the cover (its top
  // at z = 22): every corner of the post (-15..-9, -3..3, 0.5..20) there.
  EXPECT_NEAR(path.partial_waypoints.front().t.norm(), 0.0, 1e-9);
  const Pose& last = path.partial_waypoints.back();
  for (const double x : {-15.0, -9.0}) {
    for (const double y : {-3.0, 3.0}) {
      for (const double z : {0.5, 20.0}) EXPECT_LT((last.q * Eigen::Vector3d(x, y, z) + last.t).z(), 22.0 + 0.05);
    }
  }
  // Generous: the run must end near its budget, not at the 60 s time limit.
  EXPECT_LT(seconds, 3 * 20.0) << run.output;
}

// A plan that the budget cut short is planned again by the next run, not
// reused from the cache (the deadline is not part of the cache key).
TEST_F(BudgetOrderTest, APlanCutShortByTheBudgetIsPlannedAgain) {
  const fs::path scene = WritePostUnderCapScene(*root_ / "replan");
  const std::string plan = "--scene " + scene.string() + " --validity rigid-exact --threads 1 --budget 1 -o " +
                           (*root_ / "replan" / "path.h5").string();
  const Outcome first = testing::RunStageCommand("plan", plan);
  EXPECT_EQ(first.exit_code, 3) << first.output;
  EXPECT_TRUE(Has(first.output, "time budget used up")) << first.output;
  const PathArtifact path = ReadPathArtifact(*root_ / "replan" / "path.h5");
  EXPECT_TRUE(path.stopped_by_budget);
  EXPECT_FALSE(path.partial_waypoints.empty());
  const Outcome again = testing::RunStageCommand("plan", plan);
  EXPECT_EQ(again.exit_code, 3) << again.output;
  EXPECT_TRUE(Has(again.output, "cut short by its time budget: planning again")) << again.output;
}

TEST_F(BudgetOrderTest, ABudgetThatIsNotANumberIsRefused) {
  const Outcome run = testing::RunShellCommand(
      "make --no-print-directory -f " + (testing::SourceDir() / "pipelines/inistate.mk").string() +
      " BIN=" + testing::BinDir().string() + " SCENE=x.yaml OUT=" + (*root_ / "bad-budget").string() +
      " VALIDITY=rigid-exact BUDGET=soon 2>&1");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_TRUE(Has(run.output, "BUDGET=soon: must be a positive number of seconds")) << run.output;
}

std::string PartFlags(const AssemblyFileList& parts) {
  std::string flags;
  for (const auto& [name, file] : parts) flags += " --part " + name + "=" + file.string();
  return flags;
}

// Cover over posts over base (fixed): the cover first, then both posts.
TEST_F(BudgetOrderTest, TheOrderOfCoverPostsAndBaseMatchesItsPrecedence) {
  const AssemblyFileList parts = WriteCapPostsAssembly(*root_ / "cap-posts");
  const fs::path out = *root_ / "cap-posts-order";
  const Outcome run = testing::RunStageCommand(
      "order", PartFlags(parts) + " --fixed base --part-budget 4 --output-dir " + out.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string json = testing::ReadTextFile(out / "order.json");
  EXPECT_TRUE(Has(json, "\"order_exists\": true")) << json;
  EXPECT_TRUE(Has(json, "\"steps\": [[\"cover\"], [\"post-a\", \"post-b\"]]")) << json;
  EXPECT_TRUE(Has(json, "\"sequence\": [\"cover\", \"post-a\", \"post-b\"]")) << json;
  EXPECT_TRUE(Has(json, "\"fixed\": [\"base\"]")) << json;
  // In round 1 the posts were blocked, the cover among what held them: it
  // is named as an attempt's part once and in a blocked_by at least once.
  std::size_t covers = 0;
  for (std::size_t at = json.find("\"part\": \"cover\""); at != std::string::npos;
       at = json.find("\"part\": \"cover\"", at + 1)) {
    ++covers;
  }
  EXPECT_GE(covers, 2u) << json;
  // ... and named there as the part whose removal frees the post.
  EXPECT_TRUE(Has(json, "\"frees\": true")) << json;
  EXPECT_TRUE(fs::exists(out / "round-1/post-a/scene.yaml"));
  EXPECT_TRUE(fs::exists(out / "round-2/post-b/path.csv"));
  EXPECT_TRUE(Has(run.output, "ORDER FOUND")) << run.output;
}

// A box in a closed shell: neither comes out first; the cycle is named.
TEST_F(BudgetOrderTest, AnInterlockedPairHasNoOrderAndTheCycleIsNamed) {
  const AssemblyFileList parts = WriteBoxInShellAssembly(*root_ / "box-in-shell");
  const fs::path out = *root_ / "box-in-shell-order";
  const Outcome run =
      testing::RunStageCommand("order", PartFlags(parts) + " --part-budget 3 --output-dir " + out.string());
  EXPECT_EQ(run.exit_code, 3) << run.output;
  const std::string json = testing::ReadTextFile(out / "order.json");
  EXPECT_TRUE(Has(json, "\"order_exists\": false")) << json;
  EXPECT_TRUE(Has(json, "\"cycle\": [\"inner\", \"shell\", \"inner\"]")) << json;
  EXPECT_TRUE(Has(json, "\"remaining\": [\"inner\", \"shell\"]")) << json;
  EXPECT_TRUE(Has(json, "\"status_detail\": \"not-removable (budget)\"")) << json;
  EXPECT_TRUE(Has(run.output, "NO ORDER EXISTS")) << run.output;
}

TEST_F(BudgetOrderTest, BadPartListsAreRefusedWithOneLine) {
  const AssemblyFileList parts = WriteBoxInShellAssembly(*root_ / "bad");
  const std::string out = " --output-dir " + (*root_ / "bad-out").string();
  Outcome run = testing::RunStageCommand("order", " --part " + parts[0].second.string() + out);
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_TRUE(Has(run.output, "at least two parts")) << run.output;
  run = testing::RunStageCommand("order", PartFlags(parts) + " --fixed nothing" + out);
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_TRUE(Has(run.output, "--fixed: no part is named 'nothing'")) << run.output;
  run = testing::RunStageCommand("order", PartFlags(parts) + " --part missing=/nonexistent/m.obj" + out);
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_TRUE(Has(run.output, "/nonexistent/m.obj")) << run.output;
  run = testing::RunStageCommand("order", PartFlags(parts) + " --output-dir " + parts[0].second.string());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_TRUE(Has(run.output, "not a folder")) << run.output;
}

}  // namespace
}  // namespace ausbau
