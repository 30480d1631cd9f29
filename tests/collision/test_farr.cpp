// Distance fields (inside/outside, nearest points, artifact, cache, memory
// guard) and the FARR checker: its answers against FCL's on generated and
// benchmark scenes, uniform and near-contact (planner-like) poses, with
// containment counted separately and confirmed by an independent test.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include "artifact/artifact.h"
#include "collision/distance_field.h"
#include "collision/farr_checker.h"
#include "collision/fcl_checker.h"
#include "core/cancel.h"
#include "core/error.h"
#include "core/random.h"
#include "fixtures/flange.h"
#include "generated_scene.h"
#include "geometry/closest_point.h"
#include "geometry/primitives.h"
#include "planning/planner.h"
#include "scene/scene.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

using Vec3 = Eigen::Vector3d;

// ---------------------------------------------------------------------------
// Independent references

// The closest point on a triangle as the distance field computes it.
Vec3 FieldClosestPoint(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return ClosestPointOnTriangle(p, a, b, c, DegenerateTriangles::kNearestEdgePoint, FaceWeights::kTimesReciprocalOfSum);
}

double BruteDistance(const TriangleMesh& mesh, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles) {
    const Vec3 q = FieldClosestPoint(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
    best = std::min(best, (q - p).norm());
  }
  return best;
}

// Point in solid by ray parity: the triangles deduplicated by their three
// positions (double-sided exports count once), five fixed oblique
// directions, majority vote. Independent of the field's six-ray winding.
class PointInSolid {
 public:
  explicit PointInSolid(const TriangleMesh& mesh) {
    std::set<std::array<double, 9>> seen;
    for (const auto& t : mesh.triangles) {
      std::array<std::array<double, 3>, 3> k;
      for (int i = 0; i < 3; ++i) k[i] = {mesh.vertices[t[i]].x(), mesh.vertices[t[i]].y(), mesh.vertices[t[i]].z()};
      std::sort(k.begin(), k.end());
      std::array<double, 9> key;
      for (int i = 0; i < 9; ++i) key[i] = k[i / 3][i % 3];
      if (seen.insert(key).second) tris_.push_back({mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]});
    }
  }
  bool Inside(const Vec3& p) const {
    static const Vec3 directions[5] = {
        Vec3(0.3171, 0.8123, -0.4892).normalized(), Vec3(-0.7013, 0.1234, 0.7020).normalized(),
        Vec3(0.5521, -0.6619, 0.5071).normalized(), Vec3(-0.2310, -0.4411, -0.8672).normalized(),
        Vec3(0.9121, 0.3012, 0.2781).normalized()};
    int votes = 0;
    for (const Vec3& d : directions) votes += Parity(p, d);
    return votes >= 3;
  }

 private:
  bool Parity(const Vec3& p, const Vec3& d) const {
    int crossings = 0;
    for (const auto& t : tris_) {
      const Vec3 e1 = t[1] - t[0], e2 = t[2] - t[0], h = d.cross(e2);
      const double a = e1.dot(h);
      if (std::abs(a) < 1e-15) continue;
      const double f = 1 / a;
      const Vec3 s = p - t[0];
      const double u = f * s.dot(h);
      if (u < 0 || u > 1) continue;
      const Vec3 q = s.cross(e1);
      const double v = f * d.dot(q);
      if (v < 0 || u + v > 1) continue;
      if (f * e2.dot(q) > 0) ++crossings;
    }
    return crossings % 2 == 1;
  }
  std::vector<std::array<Vec3, 3>> tris_;
};

// Two square rings (each a plate with a square hole, from four boxes),
// linked through each other: A in the xy-plane, B in the xz-plane.
TriangleMesh RingA() { return MakePlateWithRectHole(2, 2, 1, 1, 0, 0, -0.5, 0.5); }
TriangleMesh RingB() {
  TriangleMesh ring;
  const double c = 1.5;
  ring.Append(MakeBox({c - 2, -0.5, -2}, {c + 2, 0.5, -1}));
  ring.Append(MakeBox({c - 2, -0.5, 1}, {c + 2, 0.5, 2}));
  ring.Append(MakeBox({c - 2, -0.5, -1}, {c - 1, 0.5, 1}));
  ring.Append(MakeBox({c + 1, -0.5, -1}, {c + 2, 0.5, 1}));
  return ring;
}

std::shared_ptr<DistanceField> Field(const TriangleMesh& mesh, int resolution) {
  DistanceFieldOptions options;
  options.resolution = resolution;
  return BuildDistanceField(mesh, options);
}

// Checks a field against the references on a sample of cells: class of
// non-surface cells against PointInSolid (closed meshes), nearest points
// exact in the band (distance <= h), near-exact beyond.
void ExpectFieldMatchesReferences(const TriangleMesh& mesh, const DistanceField& field, int samples,
                                  bool check_classes = true) {
  const PointInSolid solid(mesh);
  Random random(11);
  const double h = field.spacing();
  const double scale = mesh.Bounds().max.cwiseAbs().maxCoeff() + mesh.Bounds().min.cwiseAbs().maxCoeff();
  int band = 0, far = 0, inside = 0, class_errors = 0;
  double worst_far = 0;
  for (int i = 0; i < samples; ++i) {
    const int x = static_cast<int>(random.Index(field.dims()[0]));
    const int y = static_cast<int>(random.Index(field.dims()[1]));
    const int z = static_cast<int>(random.Index(field.dims()[2]));
    const std::int64_t index = field.Index(x, y, z);
    const Vec3 center = field.CellCenter(x, y, z);
    const double truth = BruteDistance(mesh, center);
    const Vec3 nearest = field.NearestPoint(index);
    const double got = (nearest - center).norm();
    // The stored point lies on the stored triangle (to float precision).
    const auto& t = mesh.triangles[field.cell(index).triangle];
    const Vec3 on = FieldClosestPoint(nearest, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
    EXPECT_LT((on - nearest).norm(), 1e-5 * scale) << "cell " << x << " " << y << " " << z;
    EXPECT_GE(got, truth - 1e-5 * scale);
    if (truth <= h) {
      ++band;
      EXPECT_NEAR(got, truth, 1e-5 * scale) << "band cell " << x << " " << y << " " << z;
    } else {
      ++far;
      worst_far = std::max(worst_far, (got - truth) / truth);
    }
    const CellClass cls = field.cell_class(index);
    if (cls == CellClass::kSurface) {
      EXPECT_LE(truth, 0.5 * std::sqrt(3.0) * h + 4e-6 * h + 1e-9 * scale) << "a surface cell away from the surface";
    } else {
      EXPECT_GT(truth, 0.0);
      if (cls == CellClass::kInside) ++inside;
      if (check_classes && (cls == CellClass::kInside) != solid.Inside(center)) ++class_errors;
    }
  }
  EXPECT_EQ(class_errors, 0);
  EXPECT_LT(worst_far, 0.10) << "far-field nearest points more than 10% off";
  ::testing::Test::RecordProperty("band_cells", band);
  ::testing::Test::RecordProperty("far_cells", far);
  ::testing::Test::RecordProperty("inside_cells", inside);
}

// ---------------------------------------------------------------------------
// Distance field

TEST(DistanceField, CubeInsideOutsideAndNearestPoints) {
  const TriangleMesh cube = MakeBox({-1, -1, -1}, {1, 1, 1});
  const auto field = Field(cube, 64);
  EXPECT_EQ(field->dims()[0], 64);
  EXPECT_NEAR(field->spacing(), 1.3 * 2 / 64, 1e-12);
  ExpectFieldMatchesReferences(cube, *field, 3000);
  // Centre inside, corners of the grid outside, a face point surface.
  EXPECT_EQ(field->cell_class(field->Locate({0, 0, 0})), CellClass::kInside);
  EXPECT_EQ(field->cell_class(field->Locate({1.29, 1.29, 1.29})), CellClass::kOutside);
  EXPECT_EQ(field->cell_class(field->Locate({1.0, 0.1, 0.2})), CellClass::kSurface);
  // Points outside the grid use the cell of their projection.
  EXPECT_EQ(field->Locate({100, 0, 0}), field->Locate({1.299, 0, 0}));
  EXPECT_EQ(field->Locate({-100, -100, -100}), field->Index(0, 0, 0));
  // From the centre, the nearest point lies on a face at distance 1.
  EXPECT_NEAR((field->NearestPoint(field->Locate({0.01, 0.01, 0.01})) - field->CellCenter(32, 32, 32)).norm(),
              1.0 - 0.5 * field->spacing(), 1e-5);
}

TEST(DistanceField, PlateWithHole) {
  // Four boxes that share faces partly: the union's inside is the plate.
  const TriangleMesh plate = MakePlateWithHole(6, 1, -0.5, 0.5);
  const auto field = Field(plate, 96);
  ExpectFieldMatchesReferences(plate, *field, 3000);
  EXPECT_EQ(field->cell_class(field->Locate({0, 0, 0})), CellClass::kOutside);      // the hole
  EXPECT_EQ(field->cell_class(field->Locate({3, 3, 0})), CellClass::kInside);       // the plate
  EXPECT_EQ(field->cell_class(field->Locate({-3.5, 0.1, 0})), CellClass::kInside);  // across a shared face
}

TEST(DistanceField, InterlockedRings) {
  TriangleMesh rings = RingA();
  rings.Append(RingB());
  const auto field = Field(rings, 96);
  ExpectFieldMatchesReferences(rings, *field, 3000);
  EXPECT_EQ(field->cell_class(field->Locate({1.5, 0, 0})), CellClass::kInside);      // A's bar in B's hole
  EXPECT_EQ(field->cell_class(field->Locate({0, 0, 0})), CellClass::kInside);        // B's bar in A's hole
  EXPECT_EQ(field->cell_class(field->Locate({0, 1.5, 0})), CellClass::kInside);      // A's bar
  EXPECT_EQ(field->cell_class(field->Locate({0, 0, 1.5})), CellClass::kInside);      // B's top bar
  EXPECT_EQ(field->cell_class(field->Locate({1.5, 0, 0.75})), CellClass::kOutside);  // B's hole above A
  EXPECT_EQ(field->cell_class(field->Locate({-1.5, 0, 1.5})), CellClass::kOutside);
}

TEST(DistanceField, DoubleSidedAndDuplicatedTriangles) {
  // Like the OMPL.app exports: every face twice, once each way, plus
  // duplicates. A winding number of the raw soup is 0 everywhere; the field
  // still finds the inside.
  const TriangleMesh box = MakeBox({-1, -2, -1}, {1, 2, 1});
  TriangleMesh soup = box;
  for (auto t : box.triangles) soup.triangles.push_back({t[0], t[2], t[1]});
  soup.Append(box);
  const auto field = Field(soup, 48);
  EXPECT_EQ(field->cell_class(field->Locate({0, 0, 0})), CellClass::kInside);
  EXPECT_EQ(field->cell_class(field->Locate({0, 0, 1.25})), CellClass::kOutside);
  ExpectFieldMatchesReferences(soup, *field, 1500);
}

TEST(DistanceField, OpenBoxDocumentedClassification) {
  // A box with its top face (z = max) missing: not watertight. Documented
  // behaviour: cells inside the box are inside (five of six rays cross a
  // wall), cells outside are outside (at most one ray is fooled).
  TriangleMesh open = MakeBox({-1, -1, -1}, {1, 1, 1});
  open.triangles.erase(open.triangles.begin() + 2, open.triangles.begin() + 4);  // the two z = max triangles
  const auto field = Field(open, 64);
  int inside_wrong = 0, outside_wrong = 0;
  for (int z = 0; z < field->dims()[2]; ++z) {
    for (int y = 0; y < field->dims()[1]; ++y) {
      for (int x = 0; x < field->dims()[0]; ++x) {
        const std::int64_t index = field->Index(x, y, z);
        if (field->cell_class(index) == CellClass::kSurface) continue;
        const Vec3 c = field->CellCenter(x, y, z);
        const bool in_box = c.cwiseAbs().maxCoeff() < 1;
        if (in_box && field->cell_class(index) != CellClass::kInside) ++inside_wrong;
        if (!in_box && field->cell_class(index) != CellClass::kOutside) ++outside_wrong;
      }
    }
  }
  EXPECT_EQ(inside_wrong, 0);
  EXPECT_EQ(outside_wrong, 0);
  // The nearest points are unaffected: the missing face is simply not there.
  ExpectFieldMatchesReferences(open, *field, 1500, /*check_classes=*/false);
}

TEST(DistanceField, IndependentOfThreadCount) {
  TriangleMesh rings = RingA();
  rings.Append(RingB());
  DistanceFieldOptions options;
  options.resolution = 48;
  options.threads = 1;
  const auto one = BuildDistanceField(rings, options);
  options.threads = 2;
  const auto two = BuildDistanceField(rings, options);
  ASSERT_EQ(one->size(), two->size());
  EXPECT_EQ(0, std::memcmp(one->cells(), two->cells(), one->size() * sizeof(DistanceField::Cell)));
  EXPECT_EQ(0, std::memcmp(one->classes(), two->classes(), one->size()));
}

TEST(DistanceField, MemoryGuard) {
  const TriangleMesh cube = MakeBox({-1, -1, -1}, {1, 1, 1});
  DistanceFieldOptions options;
  options.resolution = 1025;
  EXPECT_THROW(PlanDistanceField(cube, options), InputError);
  options.resolution = 1024;  // 1024^3 cells: far more than 4 GiB
  try {
    BuildDistanceField(cube, options);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("memory budget"), std::string::npos) << e.what();
  }
  options.resolution = 64;
  options.memory_budget_bytes = 1 << 20;  // 1 MiB
  EXPECT_THROW(BuildDistanceField(cube, options), InputError);
  options.memory_budget_bytes = std::uint64_t{1} << 30;
  EXPECT_NO_THROW(PlanDistanceField(cube, options));
  EXPECT_THROW(PlanDistanceField(TriangleMesh{}, options), InputError);
}

// Cancelled between its steps (core/cancel.h), after reporting progress.
TEST(DistanceField, CancelStopsTheBuild) {
  const TriangleMesh cube = MakeBox({0, 0, 0}, {1, 1, 1});
  DistanceFieldOptions options;
  options.resolution = 16;
  std::int64_t last = -1;
  options.progress = [&last](std::int64_t done, std::int64_t total) {
    EXPECT_EQ(total, 1000);
    last = done;
  };
  EXPECT_NO_THROW(BuildDistanceField(cube, options));
  EXPECT_EQ(last, 1000);
  RequestCancel();
  EXPECT_THROW(BuildDistanceField(cube, options), Cancelled);
  ResetCancel();
}

TEST(DistanceField, ArtifactRoundTripAndCache) {
  const auto dir = testing::MakeTempDir("distfield");
  TriangleMesh rings = RingA();
  rings.Append(RingB());
  const auto field = Field(rings, 40);
  const auto file = dir / "rings.h5";
  WriteDistanceField(file, *field, "mm", "world");
  const auto read = ReadDistanceField(file);
  EXPECT_EQ(read->dims(), field->dims());
  EXPECT_EQ(read->origin(), field->origin());
  EXPECT_EQ(read->spacing(), field->spacing());
  EXPECT_EQ(read->mesh_hash(), field->mesh_hash());
  EXPECT_EQ(read->resolution(), 40);
  EXPECT_EQ(0, std::memcmp(read->cells(), field->cells(), field->size() * sizeof(DistanceField::Cell)));
  EXPECT_EQ(0, std::memcmp(read->classes(), field->classes(), field->size()));
  {
    ArtifactReader reader(file, kDistanceFieldSchema, kDistanceFieldSchemaVersion);
    EXPECT_EQ(reader.ReadStringAttribute("", "axis_order"), "z,y,x");
    EXPECT_EQ(reader.ReadStringAttribute("", "units"), "mm");
    EXPECT_EQ(reader.ReadIntAttribute("", "nx"), field->dims()[0]);
    EXPECT_EQ(reader.ReadDoubleAttribute("", "spacing"), field->spacing());
    EXPECT_EQ(reader.ReadStringAttribute("nearest_point", "units"), "mm");
    EXPECT_EQ(reader.provenance_hash(), DistanceFieldProvenanceHash({MeshContentHash(rings), 40, 1.3}));
  }
  // Wrong schema, missing and truncated files are input errors.
  {
    ArtifactWriter other(dir / "other.h5", "ausbau-other", 1, Provenance{"t", "0", "", {}});
    other.WriteDoubles("x", {1.0}, {1});
    other.Commit();
  }
  EXPECT_THROW(ReadDistanceField(dir / "other.h5"), InputError);
  EXPECT_THROW(ReadDistanceField(dir / "missing.h5"), InputError);
  {
    std::ifstream in(file, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream out(dir / "truncated.h5", std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  }
  EXPECT_THROW(ReadDistanceField(dir / "truncated.h5"), InputError);

  // The cache: built and written once, then reused; another resolution is
  // another file; a damaged file is rebuilt.
  const auto cache = dir / "cache";
  DistanceFieldOptions options;
  options.resolution = 40;
  CachedFieldInfo info;
  const auto first = LoadOrBuildDistanceField(rings, options, cache, "rings", "", "", &info);
  EXPECT_FALSE(info.reused);
  EXPECT_EQ(info.path, DistanceFieldCachePath(cache, MeshContentHash(rings), 40));
  EXPECT_TRUE(std::filesystem::exists(info.path));
  const auto second = LoadOrBuildDistanceField(rings, options, cache, "rings", "", "", &info);
  EXPECT_TRUE(info.reused);
  EXPECT_EQ(0, std::memcmp(first->cells(), second->cells(), first->size() * sizeof(DistanceField::Cell)));
  options.resolution = 32;
  LoadOrBuildDistanceField(rings, options, cache, "rings", "", "", &info);
  EXPECT_FALSE(info.reused);
  options.resolution = 40;
  std::filesystem::resize_file(DistanceFieldCachePath(cache, MeshContentHash(rings), 40), 100);
  LoadOrBuildDistanceField(rings, options, cache, "rings", "", "", &info);
  EXPECT_FALSE(info.reused);
  LoadOrBuildDistanceField(rings, options, cache, "rings", "", "", &info);
  EXPECT_TRUE(info.reused);

  // Default cache folder: $AUSBAU_CACHE_DIR, else beside the scene.
  const char* saved = std::getenv("AUSBAU_CACHE_DIR");
  const std::string saved_value = saved ? saved : "";
  unsetenv("AUSBAU_CACHE_DIR");
  EXPECT_EQ(DefaultDistanceFieldCacheDir("/a/b/scene.yaml"), std::filesystem::path("/a/b/.ausbau-cache"));
  // A read-only scene folder (shared benchmark data) is left alone.
  const auto readonly = dir / "readonly";
  std::filesystem::create_directories(readonly);
  std::filesystem::permissions(
      readonly,
      std::filesystem::perms::owner_write | std::filesystem::perms::group_write | std::filesystem::perms::others_write,
      std::filesystem::perm_options::remove);
  const char* saved_xdg = std::getenv("XDG_CACHE_HOME");
  const std::string saved_xdg_value = saved_xdg ? saved_xdg : "";
  setenv("XDG_CACHE_HOME", (dir / "xdg").c_str(), 1);
  EXPECT_EQ(DefaultDistanceFieldCacheDir(readonly / "scene.yaml"), dir / "xdg" / "ausbau");
  if (saved_xdg)
    setenv("XDG_CACHE_HOME", saved_xdg_value.c_str(), 1);
  else
    unsetenv("XDG_CACHE_HOME");
  std::filesystem::permissions(readonly, std::filesystem::perms::owner_write, std::filesystem::perm_options::add);
  setenv("AUSBAU_CACHE_DIR", "/tmp/x-cache", 1);
  EXPECT_EQ(DefaultDistanceFieldCacheDir("/a/b/scene.yaml"), std::filesystem::path("/tmp/x-cache"));
  if (saved)
    setenv("AUSBAU_CACHE_DIR", saved_value.c_str(), 1);
  else
    unsetenv("AUSBAU_CACHE_DIR");
  std::filesystem::remove_all(dir);
}

// ---------------------------------------------------------------------------
// The robust triangle-triangle test

TEST(Farr, RobustTriangleTest) {
  const Vec3 a[3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  const Vec3 crossing[3] = {{0.5, 0.5, -1}, {0.5, 0.5, 1}, {1.5, 0.2, 0.3}};
  EXPECT_TRUE(RobustTrianglesIntersect(a, crossing));
  EXPECT_TRUE(RobustTrianglesIntersect(crossing, a));
  const Vec3 above[3] = {{0.5, 0.5, 0.1}, {0.5, 0.5, 1}, {1.5, 0.2, 0.3}};
  EXPECT_FALSE(RobustTrianglesIntersect(a, above));
  const Vec3 touching[3] = {{0.5, 0.5, 0}, {0.5, 0.5, 1}, {1.5, 0.2, 0.3}};  // a vertex on a's plane
  EXPECT_FALSE(RobustTrianglesIntersect(a, touching));
  const Vec3 coplanar[3] = {{0.5, 0.5, 0}, {3, 0.5, 0}, {0.5, 3, 0}};
  EXPECT_FALSE(RobustTrianglesIntersect(a, coplanar));
  const Vec3 beside[3] = {{3, 3, -1}, {3, 3, 1}, {4, 3, 0}};  // crosses a's plane outside a
  EXPECT_FALSE(RobustTrianglesIntersect(a, beside));
  const Vec3 sliver[3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 1e-30}};
  EXPECT_FALSE(RobustTrianglesIntersect(a, sliver));
}

// ---------------------------------------------------------------------------
// FARR against FCL

struct Tally {
  std::int64_t poses = 0, invalid = 0, mismatches = 0, containment = 0, containment_confirmed = 0, witnesses = 0;
};

// Records the poses a planner checks.
class RecordingValidity : public PoseValidity {
 public:
  explicit RecordingValidity(const PoseValidity& inner) : inner_(inner) {}
  std::vector<Pose> poses;

 protected:
  bool CheckValid(const Pose& pose) const override {
    std::lock_guard<std::mutex> lock(mutex_);
    const_cast<RecordingValidity*>(this)->poses.push_back(pose);
    return inner_.IsValid(pose);
  }

 private:
  const PoseValidity& inner_;
  mutable std::mutex mutex_;
};

// Uniform poses, near-contact poses (both ends of a bisection between a free
// and a colliding pose, stopped at 1/1000 of the pair's distance, like a
// planner's edge step), and the poses a short CR-RRTC run checks.
std::vector<Pose> SamplePoses(const PlanningProblem& problem, const FclCollisionChecker& fcl, int uniform,
                              int near_contact, int planner_max, std::uint64_t seed) {
  Random random(seed);
  std::vector<Pose> poses;
  for (int i = 0; i < uniform; ++i) poses.push_back(problem.SampleUniform(random));
  // Near contact: pairs around the start pose (mostly narrow passages) and
  // uniform pairs.
  int attempts = 0;
  while (static_cast<int>(poses.size()) < uniform + near_contact && attempts++ < 50 * near_contact) {
    Pose a = problem.SampleUniform(random), b;
    if (attempts % 2 == 0) {
      a = problem.start;
      a.t += problem.robot_diagonal * 0.3 * Vec3(random.Normal(), random.Normal(), random.Normal());
      a.q = (problem.start.q *
             Eigen::Quaterniond(Eigen::AngleAxisd(
                 0.5 * random.Normal(), Vec3(random.Normal(), random.Normal(), random.Normal()).normalized())))
                .normalized();
    }
    b = problem.SampleUniform(random);
    bool ca = fcl.InCollision(a);
    if (ca == fcl.InCollision(b)) continue;
    for (int k = 0; k < 10; ++k) {
      const Pose m = Interpolate(a, b, 0.5);
      if (fcl.InCollision(m) == ca)
        a = m;
      else
        b = m;
    }
    poses.push_back(a);
    poses.push_back(b);
  }
  if (planner_max > 0) {
    RecordingValidity recorder(fcl);
    PlannerOptions options;
    options.seed = seed;
    options.max_iterations = 2000;
    options.time_limit_s = 20;
    Plan(problem, recorder, options);
    const std::size_t n = std::min<std::size_t>(recorder.poses.size(), planner_max);
    poses.insert(poses.end(), recorder.poses.begin(), recorder.poses.begin() + static_cast<std::ptrdiff_t>(n));
  }
  return poses;
}

// Compares FARR (thesis mode: 30 rays on every query; adaptive mode; and
// with containment reporting) with FCL on every pose.
Tally Compare(const PlanningProblem& problem, const std::vector<Pose>& poses, int resolution) {
  const auto robot_field = Field(problem.robot, resolution);
  const auto environment_field = Field(problem.environment, resolution);
  const FclCollisionChecker fcl(problem.robot, problem.environment);
  FarrOptions thesis;
  thesis.adaptive = false;
  const FarrCollisionChecker farr(problem.robot, problem.environment, robot_field, environment_field, 7, thesis);
  const FarrCollisionChecker adaptive(problem.robot, problem.environment, robot_field, environment_field, 7);
  FarrOptions report = thesis;
  report.report_containment = true;
  const FarrCollisionChecker containment(problem.robot, problem.environment, robot_field, environment_field, 7, report);
  const PointInSolid environment_solid(problem.environment), robot_solid(problem.robot);
  Tally tally;
  for (const Pose& pose : poses) {
    const bool truth = fcl.InCollision(pose);
    ++tally.poses;
    tally.invalid += truth;
    const bool a = farr.InCollision(pose), b = adaptive.InCollision(pose);
    if (a != truth || b != truth) {
      ++tally.mismatches;
      ADD_FAILURE() << "FARR differs from FCL (FCL " << truth << ", FARR " << a << ", adaptive " << b
                    << ") at t = " << pose.t.transpose() << ", q = " << pose.q.coeffs().transpose();
    }
    const bool c = containment.InCollision(pose);
    if (c == truth) continue;
    // Only containment may differ: FCL free, and one surface inside the
    // other's solid, confirmed independently.
    EXPECT_TRUE(c && !truth);
    ++tally.containment;
    bool confirmed = false;
    const Eigen::Matrix3d R = pose.q.toRotationMatrix();
    for (std::size_t i = 0; i < problem.robot.vertices.size() && i < 64 && !confirmed; ++i) {
      confirmed = environment_solid.Inside(R * problem.robot.vertices[i] + pose.t);
    }
    for (std::size_t i = 0; i < problem.environment.vertices.size() && i < 64 && !confirmed; ++i) {
      confirmed = robot_solid.Inside(R.transpose() * (problem.environment.vertices[i] - pose.t));
    }
    tally.containment_confirmed += confirmed;
    EXPECT_TRUE(confirmed) << "containment not confirmed at t = " << pose.t.transpose();
  }
  tally.witnesses = farr.stats().witnesses;
  EXPECT_EQ(farr.stats().pair_rejects, 0);
  return tally;
}

PlanningProblem ProblemFromMeshes(const TriangleMesh& robot, const TriangleMesh& environment, const Aabb& bounds) {
  PlanningProblem problem;
  problem.robot = robot;
  problem.environment = environment;
  problem.bounds = bounds;
  problem.robot_local_box = robot.Bounds();
  problem.robot_diagonal = problem.robot_local_box.Diagonal();
  for (const Vec3& v : robot.vertices) problem.robot_radius = std::max(problem.robot_radius, v.norm());
  problem.environment_box = environment.Bounds();
  problem.metric.nu = bounds.Diagonal();
  return problem;
}

// Each comparison asserts its number of poses; together (rod-in-cage 30,000,
// peg-in-plate 30,000, flange 9,000, rings 12,000, cube in cube 6,000,
// alpha-1.5 12,000 when present) at least 10^5 configurations.
void CompareOnScene(const std::filesystem::path& yaml, int uniform, int near_contact, int planner_max, int resolution,
                    std::int64_t at_least) {
  const Scene scene = LoadScene(yaml);
  const PlanningProblem problem = MakePlanningProblem(scene);
  const FclCollisionChecker fcl(problem.robot, problem.environment);
  const auto poses = SamplePoses(problem, fcl, uniform, near_contact, planner_max, 3);
  const Tally tally = Compare(problem, poses, resolution);
  EXPECT_GE(tally.poses, at_least);
  EXPECT_EQ(tally.mismatches, 0);
  EXPECT_GT(tally.invalid, tally.poses / 50) << "too few collisions to compare";
  EXPECT_GT(tally.witnesses, 0);
  std::printf(
      "[ farr     ] %s: %lld poses, %lld in collision, %lld proven by rays, %lld mismatches, "
      "%lld containment (%lld confirmed)\n",
      scene.name.c_str(), static_cast<long long>(tally.poses), static_cast<long long>(tally.invalid),
      static_cast<long long>(tally.witnesses), static_cast<long long>(tally.mismatches),
      static_cast<long long>(tally.containment), static_cast<long long>(tally.containment_confirmed));
}

TEST(Farr, EqualsFclOnRodInCage) {
  CompareOnScene(testing::MakeGeneratedScene("rod-in-cage", 2), 14000, 10000, 12000, 96, 30000);
}

TEST(Farr, EqualsFclOnPegInPlate) {
  CompareOnScene(testing::MakeGeneratedScene("peg-in-plate", 2), 14000, 10000, 12000, 96, 30000);
}

TEST(Farr, EqualsFclOnAlpha15) {
  const auto yaml = testing::OmplScene("alpha-1.5");
  if (yaml.empty()) GTEST_SKIP() << "../shared/benchmarks/ompl/alpha-1.5.yaml not present";
  CompareOnScene(yaml, 3000, 3000, 6000, 128, 12000);
}

TEST(Farr, EqualsFclOnFlange) {
  const auto dir = testing::MakeTempDir("flange");
  CompareOnScene(GenerateFlangeScene(1.0, dir), 3000, 3000, 6000, 96, 9000);
}

TEST(Farr, EqualsFclOnInterlockedRings) {
  // D = ring B, S = ring A: D can shift and turn a little before it hits A.
  Aabb bounds;
  bounds.min = Vec3::Constant(-3);
  bounds.max = Vec3::Constant(3);
  const PlanningProblem problem = ProblemFromMeshes(RingB(), RingA(), bounds);
  Random random(5);
  std::vector<Pose> poses;
  for (int i = 0; i < 12000; ++i) {
    Pose p;
    p.t = 0.8 * Vec3(random.Normal(), random.Normal(), random.Normal());
    p.q = Eigen::Quaterniond(
        Eigen::AngleAxisd(0.4 * random.Normal(), Vec3(random.Normal(), random.Normal(), random.Normal()).normalized()));
    poses.push_back(p);
  }
  const Tally tally = Compare(problem, poses, 96);
  EXPECT_EQ(tally.poses, 12000);
  EXPECT_EQ(tally.mismatches, 0);
  EXPECT_GT(tally.invalid, 1000);
  EXPECT_GT(tally.witnesses, tally.invalid / 2);
}

TEST(Farr, ContainmentCubeInCube) {
  // A small cube D inside a big closed cube S: no surface intersection, so
  // FCL (and FARR by default) say free; with report_containment FARR says
  // collision, counted as containment; the independent test confirms.
  Aabb bounds;
  bounds.min = Vec3::Constant(-4);
  bounds.max = Vec3::Constant(4);
  const PlanningProblem problem =
      ProblemFromMeshes(MakeBox({-0.3, -0.2, -0.25}, {0.3, 0.2, 0.25}), MakeBox({-2, -2, -2}, {2, 2, 2}), bounds);
  Random random(9);
  std::vector<Pose> poses;
  for (int i = 0; i < 6000; ++i) poses.push_back(problem.SampleUniform(random));
  const Tally tally = Compare(problem, poses, 64);
  EXPECT_EQ(tally.poses, 6000);
  EXPECT_EQ(tally.mismatches, 0);
  EXPECT_GT(tally.containment, 200);
  EXPECT_EQ(tally.containment, tally.containment_confirmed);
  std::printf("[ farr     ] cube in cube: %lld poses, %lld collisions, %lld containment (all confirmed)\n",
              static_cast<long long>(tally.poses), static_cast<long long>(tally.invalid),
              static_cast<long long>(tally.containment));

  // And the counters.
  const auto rf = Field(problem.robot, 32), ef = Field(problem.environment, 32);
  FarrOptions count;
  count.count_containment = true;
  const FarrCollisionChecker counting(problem.robot, problem.environment, rf, ef, 1, count);
  Pose inside;
  EXPECT_FALSE(counting.InCollision(inside));
  EXPECT_EQ(counting.stats().containments, 1);
  FarrOptions report;
  report.report_containment = true;
  const FarrCollisionChecker reporting(problem.robot, problem.environment, rf, ef, 1, report);
  EXPECT_TRUE(reporting.InCollision(inside));
  EXPECT_EQ(reporting.stats().containments, 1);
}

TEST(Farr, WorkIsAFunctionOfThePose) {
  const Scene scene = LoadScene(testing::MakeGeneratedScene("peg-in-plate", 1));
  const PlanningProblem problem = MakePlanningProblem(scene);
  const auto rf = Field(problem.robot, 48), ef = Field(problem.environment, 48);
  FarrOptions options;
  options.adaptive = false;
  const FarrCollisionChecker farr(problem.robot, problem.environment, rf, ef, 3, options);
  Random random(1);
  std::vector<Pose> poses;
  for (int i = 0; i < 200; ++i) poses.push_back(problem.SampleUniform(random));
  std::vector<FarrCollisionChecker::ProbeResult> first;
  for (const Pose& p : poses) first.push_back(farr.Probe(p, 30));
  for (int i = static_cast<int>(poses.size()) - 1; i >= 0; --i) {
    const auto again = farr.Probe(poses[i], 30);
    EXPECT_EQ(again.witness, first[i].witness);
    EXPECT_EQ(again.lookups, first[i].lookups);
  }
  // Complete probes report the lowest ray that finds a witness: fewer rays
  // find one exactly when that ray is among them.
  for (const Pose& p : poses) {
    const auto complete = farr.Probe(p, 30, true);
    if (!complete.witness) continue;
    EXPECT_TRUE(farr.Probe(p, complete.witness_ray + 1, true).witness);
    if (complete.witness_ray > 0) {
      EXPECT_FALSE(farr.Probe(p, complete.witness_ray, true).witness);
    }
  }
}

TEST(Farr, PlannerReturnsTheSamePathAsWithFcl) {
  const Scene scene = LoadScene(testing::MakeGeneratedScene("rod-in-cage", 1));
  const PlanningProblem problem = MakePlanningProblem(scene);
  const FclCollisionChecker fcl(problem.robot, problem.environment);
  const FarrCollisionChecker farr(problem.robot, problem.environment, Field(problem.robot, 64),
                                  Field(problem.environment, 64), 1);
  PlannerOptions options;
  options.seed = 4;
  options.time_limit_s = 120;
  const PlanResult a = Plan(problem, fcl, options);
  const PlanResult b = Plan(problem, farr, options);
  ASSERT_TRUE(a.solved());
  ASSERT_EQ(a.path.size(), b.path.size());
  for (std::size_t i = 0; i < a.path.size(); ++i) {
    EXPECT_EQ(a.path[i].t, b.path[i].t);
    EXPECT_EQ(a.path[i].q.coeffs(), b.path[i].q.coeffs());
  }
  EXPECT_EQ(a.stats.collision_checks, b.stats.collision_checks);
  EXPECT_GT(farr.stats().witnesses, 0);
}

TEST(Farr, FieldsMustMatchTheMeshes) {
  const TriangleMesh a = MakeBox({-1, -1, -1}, {1, 1, 1}), b = MakeBox({-2, -1, -1}, {1, 1, 1});
  const auto fa = Field(a, 16), fb = Field(b, 16);
  EXPECT_THROW(FarrCollisionChecker(a, b, fb, fb), std::invalid_argument);
  EXPECT_THROW(FarrCollisionChecker(a, b, fa, fa), std::invalid_argument);
  EXPECT_NO_THROW(FarrCollisionChecker(a, b, fa, fb));
  FarrOptions bad;
  bad.rays = FarrOptions::kMaxRays + 1;
  EXPECT_THROW(FarrCollisionChecker(a, b, fa, fb, 1, bad), InputError);
}

// ---------------------------------------------------------------------------
// The flange scene generator (common/fixtures/flange.h)

TEST(FlangeScene, ClosedMeshesAndAFreeStartInThreeClearances) {
  double previous = 0;
  for (double scale : {1.0, 0.95, 0.9}) {
    const FlangeScene flange = MakeFlangeScene(scale);
    auto volume = [](const TriangleMesh& m) {
      double v = 0;
      for (const auto& t : m.triangles) v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6;
      return v;
    };
    EXPECT_GT(volume(flange.part), 0);
    EXPECT_GT(volume(flange.environment), 0);
    const FclCollisionChecker fcl(flange.part, flange.environment);
    const double clearance = fcl.Distance(flange.start);
    EXPECT_GT(clearance, previous);  // the thinner the tube, the wider the passage
    previous = clearance;
    // Pushed sideways by 0.2 the tube hits the hole's rim.
    Pose moved = flange.start;
    moved.t.x() += 0.2;
    EXPECT_TRUE(fcl.InCollision(moved));
  }
  EXPECT_THROW(MakeFlangeScene(1.5), InputError);
  const auto dir = testing::MakeTempDir("flange-scene");
  const Scene scene = LoadScene(GenerateFlangeScene(0.95, dir));
  EXPECT_EQ(scene.name, "flange-0.95");
}

// ---------------------------------------------------------------------------
// The executables: ausbau-distfield-build and ausbau-plan --collision farr.

using Outcome = testing::CommandOutcome;

Outcome RunStage(const std::string& environment, const std::string& stage, const std::string& arguments) {
  return testing::RunStageCommand(stage, arguments, environment);
}

std::string ReadText(const std::filesystem::path& path) { return testing::ReadTextFile(path); }

TEST(FarrStages, DistfieldBuildThenPlanWithFarrGivesFclsPath) {
  if (!std::filesystem::exists(testing::BinDir() / "ausbau-distfield-build") ||
      !std::filesystem::exists(testing::BinDir() / "ausbau-plan")) {
    GTEST_SKIP() << "executables not built in " << testing::BinDir();
  }
  const auto yaml = testing::MakeGeneratedScene("peg-in-plate", 3);
  const auto dir = testing::MakeTempDir("farr-stages");
  const std::string env = "AUSBAU_CACHE_DIR=" + (dir / "cache").string();
  const std::string s = (dir / "df" / "distfield-static.h5").string(),
                    d = (dir / "df" / "distfield-dynamic.h5").string();

  Outcome built = RunStage(env, "distfield-build",
                           "--scene " + yaml.string() + " --field-cells 64 --output-dir " + (dir / "df").string());
  ASSERT_EQ(built.exit_code, 0) << built.output;
  EXPECT_NE(built.output.find(s + "," + d), std::string::npos) << built.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "cache"));  // also stored in the cache
  Outcome again = RunStage(env, "distfield-build",
                           "--scene " + yaml.string() + " --field-cells 64 --output-dir " + (dir / "df").string());
  EXPECT_EQ(again.exit_code, 0);
  EXPECT_NE(again.output.find("up to date"), std::string::npos) << again.output;

  const std::string common = "--scene " + yaml.string() + " --seed 2 --time-limit 120 ";
  Outcome fcl =
      RunStage(env, "plan", common + "-o " + (dir / "fcl.h5").string() + " --csv " + (dir / "fcl.csv").string());
  ASSERT_EQ(fcl.exit_code, 0) << fcl.output;
  Outcome given = RunStage(env, "plan",
                           common + "--collision farr --distfield " + s + "," + d + " -o " +
                               (dir / "farr.h5").string() + " --csv " + (dir / "farr.csv").string());
  ASSERT_EQ(given.exit_code, 0) << given.output;
  EXPECT_EQ(ReadText(dir / "fcl.csv"), ReadText(dir / "farr.csv"));
  // Without --distfield: built (256 cells) into the cache, then reused.
  Outcome cached = RunStage(
      env, "plan",
      common + "--collision farr -o " + (dir / "farr2.h5").string() + " --csv " + (dir / "farr2.csv").string());
  ASSERT_EQ(cached.exit_code, 0) << cached.output;
  EXPECT_EQ(ReadText(dir / "fcl.csv"), ReadText(dir / "farr2.csv"));
  Outcome reused = RunStage(env, "plan", common + "--collision farr --force -o " + (dir / "farr2.h5").string());
  EXPECT_EQ(reused.exit_code, 0);
  EXPECT_NE(reused.output.find("reused"), std::string::npos) << reused.output;

  // Errors: exit code 2 and one line naming the problem.
  Outcome one = RunStage(env, "plan", common + "--collision farr --distfield " + s + " -o " + (dir / "x.h5").string());
  EXPECT_EQ(one.exit_code, 2);
  EXPECT_NE(one.output.find("--distfield: expected two files"), std::string::npos) << one.output;
  Outcome swapped =
      RunStage(env, "plan", common + "--collision farr --distfield " + d + "," + s + " -o " + (dir / "x.h5").string());
  EXPECT_EQ(swapped.exit_code, 2);
  EXPECT_NE(swapped.output.find("another mesh"), std::string::npos) << swapped.output;
  Outcome bogus = RunStage(env, "plan", common + "--collision bvh -o " + (dir / "x.h5").string());
  EXPECT_EQ(bogus.exit_code, 2);
  Outcome huge = RunStage(env, "distfield-build", "--scene " + yaml.string() + " --field-cells 1024 --memory-limit 1");
  EXPECT_EQ(huge.exit_code, 2);
  EXPECT_NE(huge.output.find("memory budget"), std::string::npos) << huge.output;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ausbau
