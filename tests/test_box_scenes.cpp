// The panel-* box scenes (fixtures/box_scenes.h): the box shells, the exact
// separating-axis test, and per family and tessellation the written files
// (deterministic, counts, labels), the installed state (clips and only clips
// in S, rigid parts clear by the family's minimum), the known path against a
// wrong one, and the random world placement as a rigid transform of the
// identity one; the welded union and the moulded twins (one closed solid
// whose surface lies on the boxes, labels where it lies on a clip). oracle.py's
// own verdict is scripts/check-generated-scenes.sh.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "fixtures/box_scenes.h"
#include "fixtures/welded_union.h"
#include "geometry/weld.h"
#include "planning/exact_check.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"
#include "test_scenes.h"
#include "workflow/plan_scene.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;
using Vec3 = Eigen::Vector3d;

const BoxTessellation kTessellations[] = {BoxTessellation::kCoarse, BoxTessellation::kFine};

std::string Name(BoxTessellation t) { return t == BoxTessellation::kFine ? "fine" : "coarse"; }

OrientedBox Obb(const Vec3& center, const Vec3& half, const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity()) {
  OrientedBox b;
  b.center = center;
  b.half_extents = half;
  b.rotation = rotation;
  return b;
}

double SignedVolume(const TriangleMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles) v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]]));
  return v / 6.0;
}

// One vertex per position (an STL repeats each corner per triangle).
TriangleMesh WeldMesh(const TriangleMesh& m) {
  const std::vector<int> index = WeldExactPositions(m.vertices);
  TriangleMesh out;
  out.vertices.resize(*std::max_element(index.begin(), index.end()) + 1);
  for (size_t v = 0; v < index.size(); ++v) out.vertices[index[v]] = m.vertices[v];
  for (const auto& t : m.triangles) out.triangles.push_back({index[t[0]], index[t[1]], index[t[2]]});
  return out;
}

std::vector<int> ReadLabels(const fs::path& file) {
  std::ifstream in(file);
  std::vector<int> out;
  int v;
  while (in >> v) out.push_back(v);
  return out;
}

// ---------------------------------------------------------------- boxes

TEST(BoxShell, IsAClosedOutwardConvexShell) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const OrientedBox box = Obb({3000, -1200, 800}, {11.3, 0.6, 2.5}, R);
  for (BoxTessellation t : kTessellations) {
    SCOPED_TRACE(Name(t));
    const TriangleMesh m = BoxShell(box, t);
    if (t == BoxTessellation::kCoarse) {
      EXPECT_EQ(m.triangles.size(), 12u);
      EXPECT_EQ(m.vertices.size(), 8u);
    } else {
      // >= 4 x 4 cells per face: x: 12 cells (2 mm), y: 4 (minimum), z: 4 (minimum).
      EXPECT_EQ(m.triangles.size(), 2u * 2 * (12 * 4 + 4 * 4 + 4 * 12));
    }
    // Closed and consistently oriented: every directed edge once, its reverse once.
    std::map<std::pair<int, int>, int> directed;
    for (const auto& tri : m.triangles) {
      for (int k = 0; k < 3; ++k) ++directed[{tri[k], tri[(k + 1) % 3]}];
    }
    for (const auto& [edge, count] : directed) {
      EXPECT_EQ(count, 1);
      EXPECT_EQ(directed.count({edge.second, edge.first}), 1u);
    }
    EXPECT_NEAR(SignedVolume(m), 8 * 11.3 * 0.6 * 2.5, 1e-6 * 3000 * 3000);
    // Convex: every vertex on the box's surface, every face normal outwards.
    double longest = 0;
    for (const auto& tri : m.triangles) {
      const Vec3 &a = m.vertices[tri[0]], &b = m.vertices[tri[1]], &c = m.vertices[tri[2]];
      EXPECT_GT((b - a).cross(c - a).dot((a + b + c) / 3 - box.center), 0);
      for (const Vec3* e : {&a, &b, &c}) {
        const Vec3 u = R.transpose() * (*e - box.center);
        EXPECT_NEAR(((u.cwiseAbs() - box.half_extents).maxCoeff()), 0.0, 1e-9);
      }
      longest = std::max({longest, (b - a).norm(), (c - b).norm(), (a - c).norm()});
    }
    if (t == BoxTessellation::kFine) {
      EXPECT_LE(longest, kFineEdge * std::sqrt(2.0) + 1e-9);  // a cell's diagonal
    }
  }
}

TEST(BoxPenetration, IsTheExactSeparatingAxisDepth) {
  const OrientedBox a = Obb({0, 0, 0}, {1, 1, 1});
  // Faces 0.3 apart, then 0.4 into each other.
  EXPECT_NEAR(BoxPenetration(a, Obb({2.3, 0.5, 0}, {1, 1, 1})), -0.3, 1e-12);
  EXPECT_NEAR(BoxDistance(a, Obb({2.3, 0.5, 0}, {1, 1, 1})), 0.3, 1e-9);
  EXPECT_NEAR(BoxPenetration(a, Obb({1.6, 0.2, 0.1}, {1, 1, 1})), 0.4, 1e-12);
  EXPECT_EQ(BoxDistance(a, Obb({1.6, 0.2, 0.1}, {1, 1, 1})), 0.0);
  // A cube turned by 45 degrees about z points an edge at a's face.
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_NEAR(BoxPenetration(a, Obb({3, 0, 0}, {1, 1, 1}, turn)), -(2 - std::sqrt(2.0)), 1e-12);
  EXPECT_NEAR(BoxPenetration(a, Obb({2.2, 0, 0}, {1, 1, 1}, turn)), 1 + std::sqrt(2.0) - 2.2, 1e-12);
  // Diagonal neighbours: the separating axes give a lower bound, the distance is exact.
  const OrientedBox diagonal = Obb({3, 3, 0}, {1, 1, 1});
  EXPECT_NEAR(BoxPenetration(a, diagonal), -1.0, 1e-12);
  EXPECT_NEAR(BoxDistance(a, diagonal), std::sqrt(2.0), 1e-9);
  // Edge against edge, crossed: only a cross-product axis separates them.
  const Eigen::Matrix3d tilt_x = Eigen::AngleAxisd(M_PI / 4, Vec3::UnitX()).toRotationMatrix();
  const Eigen::Matrix3d tilt_y = Eigen::AngleAxisd(M_PI / 4, Vec3::UnitY()).toRotationMatrix();
  const OrientedBox e1 = Obb({0, 0, 0}, {5, 1, 1}, tilt_x);                          // top edge along x at z = sqrt(2)
  const OrientedBox e2 = Obb({0, 0, 2 * std::sqrt(2.0) + 0.25}, {1, 5, 1}, tilt_y);  // bottom edge along y
  EXPECT_NEAR(BoxPenetration(e1, e2), -0.25, 1e-9);
  EXPECT_NEAR(BoxDistance(e1, e2), 0.25, 1e-6);
}

// ---------------------------------------------------------------- scenes

struct Generated {
  BoxScene scene;
  BoxSceneFiles files;
  fs::path dir;
};

Generated Generate(const std::string& family, BoxTessellation t, BoxWorld w, std::uint64_t seed = 1) {
  BoxSceneOptions options;
  options.seed = seed;
  options.tessellation = t;
  options.world = w;
  Generated g;
  g.dir = testing::MakeTempDir(family + "-" + Name(t));
  g.scene = BuildBoxScene(family, options);
  g.files = WriteBoxScene(g.scene, g.dir);
  return g;
}

std::vector<std::string> FilesUnder(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) out.push_back(fs::relative(e.path(), dir).string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(BoxScenes, AreDeterministicForASeed) {
  for (const std::string& family : BoxSceneFamilies()) {
    for (BoxTessellation t : kTessellations) {
      SCOPED_TRACE(family + " " + Name(t));
      const Generated a = Generate(family, t, BoxWorld::kRandom, 4), b = Generate(family, t, BoxWorld::kRandom, 4);
      const auto files = FilesUnder(a.dir);
      ASSERT_EQ(files, FilesUnder(b.dir));
      for (const std::string& f : files) {
        EXPECT_TRUE(testing::ReadTextFile(a.dir / f) == testing::ReadTextFile(b.dir / f)) << f;
      }
      const Generated c = Generate(family, t, BoxWorld::kRandom, 5);
      EXPECT_NE(testing::ReadTextFile(a.files.boxes_json), testing::ReadTextFile(c.files.boxes_json));
      fs::remove_all(a.dir);
      fs::remove_all(b.dir);
      fs::remove_all(c.dir);
    }
  }
}

TEST(BoxScenes, FilesMatchTheBoxesAndLabels) {
  for (const std::string& family : BoxSceneFamilies()) {
    for (BoxTessellation t : kTessellations) {
      SCOPED_TRACE(family + " " + Name(t));
      const Generated g = Generate(family, t, BoxWorld::kRandom, 2);
      const BoxScene& s = g.scene;
      const TriangleMesh d = LoadMesh(g.dir / "dynamic.stl"), st = LoadMesh(g.dir / "static.stl");
      const std::vector<int> labels = ReadLabels(g.files.labels);
      ASSERT_EQ(labels.size(), d.triangles.size());
      if (t == BoxTessellation::kCoarse) {
        EXPECT_EQ(d.triangles.size(), 12 * (s.rigid_boxes.size() + s.clip_boxes.size()));
        EXPECT_EQ(st.triangles.size(), 12 * s.static_boxes.size());
      }
      // dynamic.stl holds the boxes in dynamic_box_order, each box's
      // triangles labelled alike and lying on that box.
      const size_t n_rigid = s.rigid_boxes.size();
      ASSERT_EQ(s.dynamic_box_order.size(), n_rigid + s.clip_boxes.size());
      size_t next = 0;
      for (int k : s.dynamic_box_order) {
        const bool clip = static_cast<size_t>(k) >= n_rigid;
        const OrientedBox& box = clip ? s.clip_boxes[k - n_rigid] : s.rigid_boxes[k];
        const size_t n = BoxShell(box, t).triangles.size();
        ASSERT_LE(next + n, d.triangles.size());
        for (size_t i = next; i < next + n; ++i) {
          ASSERT_EQ(labels[i], clip ? 1 : 0) << "triangle " << i;
          for (int v : d.triangles[i]) {
            const Vec3 u = box.rotation.transpose() * (d.vertices[v] - box.center);
            ASSERT_LE((u.cwiseAbs() - box.half_extents).maxCoeff(), 2e-3);  // float32 at metres from the origin
          }
        }
        next += n;
      }
      EXPECT_EQ(next, d.triangles.size());
      // scene.yaml as the external set writes it, and as the stages read it.
      const Scene loaded = LoadScene(g.files.scene_yaml);
      EXPECT_EQ(loaded.dynamic_mesh.triangles.size(), d.triangles.size());
      EXPECT_EQ(loaded.static_mesh.triangles.size(), st.triangles.size());
      EXPECT_FALSE(loaded.dynamic_origin_given);
      EXPECT_EQ(
          testing::ReadTextFile(g.files.scene_yaml),
          "format: ausbau-scene/1\nname: " + family + "-s2\nunits: mm\nstatic: [static.stl]\ndynamic: dynamic.stl\n");
      EXPECT_EQ(testing::ReadTextFile(g.files.known_path).rfind("x,y,z,qw,qx,qy,qz\n0,0,0,1,0,0,0\n", 0), 0u);
      fs::remove_all(g.dir);
    }
  }
}

TEST(BoxScenes, OnlyClipsIntersectSAtTheInstalledPose) {
  for (const std::string& family : BoxSceneFamilies()) {
    for (std::uint64_t seed : {1, 2, 3, 4, 5, 6}) {
      for (BoxWorld w : {BoxWorld::kIdentity, BoxWorld::kRandom}) {
        SCOPED_TRACE(family + " seed " + std::to_string(seed));
        BoxSceneOptions options;
        options.seed = seed;
        options.world = w;
        const BoxScene s = BuildBoxScene(family, options);
        for (const OrientedBox& d : s.rigid_boxes) {
          for (const OrientedBox& e : s.static_boxes) {
            ASSERT_LE(BoxPenetration(d, e), -(s.min_clearance - 1e-6)) << d.tag << " / " << e.tag;
          }
        }
        std::vector<bool> hit(s.clips, false);
        for (size_t k = 0; k < s.clip_boxes.size(); ++k) {
          for (const OrientedBox& e : s.static_boxes) {
            if (BoxPenetration(s.clip_boxes[k], e) > 0.05) hit[s.clip_of_box[k]] = true;
          }
        }
        for (int c = 0; c < s.clips; ++c) EXPECT_TRUE(hit[c]) << "clip " << c;
        EXPECT_EQ(s.clips == 0, family == "panel-channel");
        const BoxSceneContacts contacts = InstalledContacts(s);
        EXPECT_GE(contacts.rigid_min_clearance, contacts.rigid_min_separation - 1e-9);
        EXPECT_GE(contacts.rigid_min_separation, s.min_clearance - 1e-6);
      }
    }
  }
}

TEST(BoxScenes, KnownPathIsFreeAndAStraightLiftIsNot) {
  for (const std::string& family : BoxSceneFamilies()) {
    for (std::uint64_t seed : {1, 2, 3}) {
      SCOPED_TRACE(family + " seed " + std::to_string(seed));
      BoxSceneOptions options;
      options.seed = seed;
      const BoxScene s = BuildBoxScene(family, options);
      ASSERT_GE(s.path.size(), 2u);
      EXPECT_EQ(s.path.front().t, Vec3::Zero());
      EXPECT_LE(MaxRigidPenetration(s, s.path), 0.0);
      // The last pose: D's world AABB clear of S's.
      Aabb d_box, s_box;
      for (const auto* list : {&s.rigid_boxes, &s.clip_boxes}) {
        for (const OrientedBox& b : *list) {
          for (const Vec3& c : Corners(b)) d_box.Extend(s.path.back().Apply(c));
        }
      }
      for (const OrientedBox& b : s.static_boxes) {
        for (const Vec3& c : Corners(b)) s_box.Extend(c);
      }
      EXPECT_TRUE(d_box.SeparatedFrom(s_box));
      // Wrong: straight out along S's normal (for panel-straight-pull: 3
      // degrees off it, towards the design frame's x + 22.5 degrees).
      Vec3 direction = s.pull_direction;
      if (family == "panel-straight-pull") {
        const Vec3 side = s.world.q * Vec3(std::cos(M_PI / 8), std::sin(M_PI / 8), 0);
        direction = std::cos(3 * M_PI / 180) * s.pull_direction + std::sin(3 * M_PI / 180) * side;
      }
      Pose out;
      out.t = 100 * direction;
      EXPECT_GT(MaxRigidPenetration(s, {Pose{}, out}), 0.05);
    }
  }
}

TEST(BoxScenes, RandomWorldIsARigidTransformOfTheIdentity) {
  for (const std::string& family : BoxSceneFamilies()) {
    SCOPED_TRACE(family);
    const Generated id = Generate(family, BoxTessellation::kCoarse, BoxWorld::kIdentity, 3);
    const Generated rnd = Generate(family, BoxTessellation::kCoarse, BoxWorld::kRandom, 3);
    const Pose& w = rnd.scene.world;
    EXPECT_NEAR(w.q.norm(), 1.0, 1e-12);
    EXPECT_GE(w.t.norm(), 2000.0);
    EXPECT_LE(w.t.norm(), 4000.0);
    EXPECT_EQ(id.scene.world.t, Vec3::Zero());
    auto same = [&](const std::vector<OrientedBox>& a, const std::vector<OrientedBox>& b) {
      ASSERT_EQ(a.size(), b.size());
      for (size_t k = 0; k < a.size(); ++k) {
        const OrientedBox moved = Transformed(a[k], w);
        EXPECT_LT((moved.center - b[k].center).norm(), 1e-9);
        EXPECT_LT((moved.rotation - b[k].rotation).norm(), 1e-12);
        EXPECT_EQ(a[k].half_extents, b[k].half_extents);
        EXPECT_EQ(a[k].tag, b[k].tag);
      }
    };
    same(id.scene.static_boxes, rnd.scene.static_boxes);
    same(id.scene.rigid_boxes, rnd.scene.rigid_boxes);
    same(id.scene.clip_boxes, rnd.scene.clip_boxes);
    EXPECT_EQ(id.scene.dynamic_box_order, rnd.scene.dynamic_box_order);
    EXPECT_LT((w.q * id.scene.pull_direction - rnd.scene.pull_direction).norm(), 1e-12);
    // The paths: W P W^-1, waypoint by waypoint (the last pull's length
    // depends on the placement: it ends where the world AABBs part).
    ASSERT_EQ(id.scene.path.size(), rnd.scene.path.size());
    for (size_t k = 0; k + 1 < id.scene.path.size(); ++k) {
      const Pose& p = id.scene.path[k];
      const Pose& q = rnd.scene.path[k];
      for (const Vec3& x : {Vec3(0, 0, 0), Vec3(100, 0, 0), Vec3(0, 100, 50)}) {
        const Vec3 expected = w.Apply(p.Apply(x));
        EXPECT_LT((q.Apply(w.Apply(x)) - expected).norm(), 1e-8) << "waypoint " << k;
      }
    }
    // The meshes too (float32 STL: about 0.5 micrometres at 4 m).
    const TriangleMesh a = LoadMesh(id.dir / "dynamic.stl"), b = LoadMesh(rnd.dir / "dynamic.stl");
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    for (size_t t = 0; t < a.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        ASSERT_LT((w.Apply(a.vertices[a.triangles[t][k]]) - b.vertices[b.triangles[t][k]]).norm(), 2e-3);
      }
    }
    fs::remove_all(id.dir);
    fs::remove_all(rnd.dir);
  }
}

// ausbau-plan's default validity (collision) on a part placed metres from its
// mesh origin: the path as written must hold for a reader that interpolates
// the plain way (about the mesh origin; README "What the verdict promises"),
// not only about D's reference point as the planner moved it. Before the
// written path was split for that, such a reader saw the tongue sweep
// millimetres through the channel's roof on turning segments.
TEST(BoxScenes, CollisionPlanHoldsUnderPlainInterpolation) {
  const Generated g = Generate("panel-channel", BoxTessellation::kCoarse, BoxWorld::kRandom);
  const Scene scene = LoadScene(g.files.scene_yaml);
  PlanSceneOptions options;
  options.validity = ValidityMode::kCollision;
  options.planner.time_limit_s = 60;
  options.planner.seed = 1;
  const PlannedPath planned = PlanScene(scene, options);
  ASSERT_TRUE(planned.artifact.success);
  const ExactCheckReport check = ExactCheckPath(scene, planned.artifact.waypoints, 0.05);
  EXPECT_TRUE(check.valid) << check.reason;
  EXPECT_LE(check.max_rigid_depth, 0.05);
}

// ---------------------------------------------------------------- moulded

// A plate 10 x 10 x 1 with a rib on top, a leg through its bottom, a foot
// beside the leg (sharing the leg's face x = 3 exactly) and a block that
// sticks out of the plate's side: the union's volume by hand is
// 100 + 24 (rib above z = 1) + 18 (leg below z = 0) + 12 (foot) + 20 (the
// block's part beyond x = 10) = 174.
TEST(WeldedUnion, IsOneClosedSolidOfTheHandComputedVolume) {
  auto box = [](const Vec3& lo, const Vec3& hi) {
    return BoxShell(Obb((lo + hi) / 2, (hi - lo) / 2), BoxTessellation::kCoarse);
  };
  const std::vector<TriangleMesh> shells = {box({0, 0, 0}, {10, 10, 1}), box({2, 2, 1}, {3, 8, 5}),
                                            box({2, 2, -3}, {3, 8, 0.5}), box({3, 2, -3}, {5, 8, -2}),
                                            box({9, 0, 0}, {12, 10, 1})};
  const TriangleMesh u = WeldedUnion(shells);
  const ClosedMeshFacts facts = DescribeClosedMesh(u);
  EXPECT_TRUE(facts.closed_manifold);
  EXPECT_EQ(facts.components, 1);
  EXPECT_NEAR(facts.volume, 174.0, 1e-9);
}

// Two boxes that share only an edge have no manifold union.
TEST(WeldedUnion, RefusesShellsThatMeetAlongAnEdgeOnly) {
  auto box = [](const Vec3& lo, const Vec3& hi) {
    return BoxShell(Obb((lo + hi) / 2, (hi - lo) / 2), BoxTessellation::kCoarse);
  };
  EXPECT_THROW(WeldedUnion({box({0, 0, 0}, {1, 1, 1}), box({1, 1, 0}, {2, 2, 1})}), std::logic_error);
  // An open shell is refused too.
  TriangleMesh open = box({0, 0, 0}, {1, 1, 1});
  open.triangles.pop_back();
  EXPECT_THROW(WeldedUnion({open, box({0.5, 0, 0}, {2, 1, 1})}), std::logic_error);
  EXPECT_FALSE(DescribeClosedMesh(open).closed_manifold);
}

// The moulded twin: one closed solid whose every vertex lies on the surface
// of D's boxes (within float32 at metres from the origin) and inside none,
// the same S, boxes.json and known path as the box soup, labels 1 exactly on
// the clips' outer surface.
TEST(BoxScenes, MouldedTwinIsOneSolidOnTheBoxes) {
  for (const std::string& family : BoxSceneFamilies()) {
    SCOPED_TRACE(family);
    BoxSceneOptions options;
    options.seed = 2;
    const fs::path soup_dir = testing::MakeTempDir(family + "-soup");
    const BoxScene soup = BuildBoxScene(family, options);
    const BoxSceneFiles soup_files = WriteBoxScene(soup, soup_dir);
    options.molded = true;
    const fs::path dir = testing::MakeTempDir(family + "-molded");
    const BoxScene molded = BuildBoxScene(family, options);
    const BoxSceneFiles files = WriteBoxScene(molded, dir);
    for (const char* same : {"static.stl", "boxes.json", "truth/known_path.csv"}) {
      EXPECT_EQ(testing::ReadTextFile(dir / same), testing::ReadTextFile(soup_dir / same)) << same;
    }
    const TriangleMesh d = LoadMesh(dir / "dynamic.stl");
    const ClosedMeshFacts facts = DescribeClosedMesh(WeldMesh(d));
    EXPECT_TRUE(facts.closed_manifold);
    EXPECT_EQ(facts.components, 1);
    std::vector<OrientedBox> boxes = molded.rigid_boxes;
    boxes.insert(boxes.end(), molded.clip_boxes.begin(), molded.clip_boxes.end());
    for (const Vec3& v : d.vertices) {
      double outside = std::numeric_limits<double>::infinity(), inside = 0;
      for (const OrientedBox& b : boxes) {
        const double signed_distance = BoxSignedDistance(b, v);
        outside = std::min(outside, std::max(signed_distance, 0.0));
        inside = std::min(inside, signed_distance);
      }
      ASSERT_LE(outside, 2e-3);  // on some box
      ASSERT_GE(inside, -2e-3);  // deep in none
    }
    const std::vector<int> labels = ReadLabels(files.labels);
    ASSERT_EQ(labels.size(), d.triangles.size());
    const long clip_triangles = std::count(labels.begin(), labels.end(), 1);
    if (molded.clips > 0) {
      EXPECT_GT(clip_triangles, 4 * molded.clips);  // each clip's hook shows several faces
    } else {
      EXPECT_EQ(clip_triangles, 0);
    }
    EXPECT_NE(testing::ReadTextFile(dir / "scene.json").find("\"molded\": true"), std::string::npos);
    EXPECT_TRUE(fs::is_regular_file(dir / "truth" / "molded_check.json"));
    fs::remove_all(dir);
    fs::remove_all(soup_dir);
  }
}

TEST(BoxScenes, RejectsUnknownOptions) {
  EXPECT_THROW(BuildBoxScene("panel-nothing", {}), InputError);
  EXPECT_THROW(ParseBoxTessellation("medium"), InputError);
  EXPECT_THROW(ParseBoxWorld("car"), InputError);
  EXPECT_EQ(ParseBoxTessellation("fine"), BoxTessellation::kFine);
  EXPECT_EQ(ParseBoxWorld("identity"), BoxWorld::kIdentity);
  BoxSceneOptions fine_molded;
  fine_molded.tessellation = BoxTessellation::kFine;
  fine_molded.molded = true;
  EXPECT_THROW(BuildBoxScene("panel-channel", fine_molded), InputError);
}

}  // namespace
}  // namespace ausbau
