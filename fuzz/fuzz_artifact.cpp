// libFuzzer harness of one artifact reader, chosen at compile time by
// AUSBAU_FUZZ_READER (fuzz/CMakeLists.txt builds one executable per reader):
//   artifact  the low-level ArtifactReader (common/artifact)
//   path      ReadPathArtifact (planning/path_io)
//   tau       ReadTauArtifact (inistate/tau_estimate)
//   voxels    ReadVoxelArtifact (inistate/voxel_grid)
//   spheres   ReadSpheresArtifact (labeling/medial_spheres)
//   labels    ReadLabelsArtifact (labeling/pbd_label)
//   distfield ReadDistanceField (collision/distance_field)
// The input is a recipe (artifact_recipe.h) for an HDF5 file of the
// reader's schema; the harness writes that file and reads it.
#include <cstdint>
#include <cstring>
#include <string>

#include "artifact/artifact.h"
#include "artifact_recipe.h"
#include "fuzz_util.h"

#if AUSBAU_FUZZ_READER_PATH
#include "planning/path_io.h"
#elif AUSBAU_FUZZ_READER_TAU || AUSBAU_FUZZ_READER_VOXELS
#include "inistate/tau_estimate.h"
#include "inistate/voxel_grid.h"
#elif AUSBAU_FUZZ_READER_SPHERES || AUSBAU_FUZZ_READER_LABELS
#include "labeling/medial_spheres.h"
#include "labeling/pbd_label.h"
#elif AUSBAU_FUZZ_READER_DISTFIELD
#include "collision/distance_field.h"
#endif

namespace ausbau::fuzz {
namespace {

using K = Kind;
const std::vector<double> kPose = {0, 0, 0, 1, 0, 0, 0};
const std::vector<double> kIdentity = {1, 0, 0, 0, 1, 0, 0, 0, 1};

#if AUSBAU_FUZZ_READER_PATH
ArtifactSpec Spec() {
  return {kPathSchema,
          kPathSchemaVersion,
          {{"waypoints", K::kDouble, {-1, 7}, kPose},
           {"reference_point", K::kDouble, {3}, {0}},
           {"dynamic_origin", K::kDouble, {3}, {0}},
           {"stats/success", K::kInt64, {}, {1}},
           {"stats/time_s", K::kDouble, {}, {0.5}},
           {"stats/iterations", K::kInt64, {}, {10}},
           {"stats/nodes", K::kInt64, {}, {10}},
           {"stats/collision_checks", K::kInt64, {}, {10}},
           {"stats/invalid_checks", K::kInt64, {}, {1}},
           {"stats/length", K::kDouble, {}, {1}},
           {"stats/length_translation", K::kDouble, {}, {1}},
           {"stats/length_rotation", K::kDouble, {}, {0}},
           {"inistate/tau", K::kDouble, {}, {1}},
           {"inistate/psi", K::kDouble, {}, {1}},
           {"inistate/inter_index", K::kInt64, {}, {0}},
           {"inistate/volume", K::kDouble, {-1}, {0.5}},
           {"inistate/part", K::kInt64, {-1}, {0}},
           {"inistate/deformability", K::kDouble, {-1}, {0.5}}},
          {{"", "planner", K::kString, "rrt-connect", 0},
           {"", "scene", K::kString, "fuzz", 0},
           {"", "validity", K::kString, "iv", 0},
           {"waypoints", "columns", K::kString, "x,y,z,qw,qx,qy,qz", 0}}};
}
void Read(const std::filesystem::path& file) { ReadPathArtifact(file); }

#elif AUSBAU_FUZZ_READER_TAU
ArtifactSpec Spec() {
  return {kTauSchema,
          kTauSchemaVersion,
          {{"tau", K::kDouble, {}, {1}},
           {"psi", K::kDouble, {}, {1}},
           {"tau_lowest", K::kDouble, {}, {0.5}},
           {"speed_target", K::kDouble, {}, {10}},
           {"rounds", K::kInt64, {}, {2}},
           {"solved", K::kInt64, {}, {1}},
           {"seconds", K::kDouble, {}, {1}},
           {"sigma_1", K::kDouble, {-1, 7}, kPose},
           {"trace/round", K::kInt64, {-1}, {1}},
           {"trace/target_speed", K::kDouble, {-1}, {10}},
           {"trace/tau", K::kDouble, {-1}, {1}},
           {"trace/speed", K::kDouble, {-1}, {5}},
           {"trace/nodes", K::kInt64, {-1}, {100}},
           {"trace/attempts", K::kInt64, {-1}, {1}},
           {"trace/checks", K::kInt64, {-1}, {1000}},
           {"trace/planning_round", K::kInt64, {-1}, {0}},
           {"trace/solved", K::kInt64, {-1}, {1}},
           {"trace/seconds", K::kDouble, {-1}, {0.25}}},
          {{"", "validity", K::kString, "iv", 0},
           {"", "units", K::kString, "mm", 0},
           {"sigma_1", "seed", K::kInt64, "", 1},
           {"sigma_1", "planner", K::kString, "est", 0}}};
}
void Read(const std::filesystem::path& file) { ReadTauArtifact(file); }

#elif AUSBAU_FUZZ_READER_VOXELS
ArtifactSpec Spec() {
  ArtifactSpec spec{kVoxelsSchema, kVoxelsSchemaVersion, {}, {}};
  for (const std::string g : {"static", "dynamic"}) {
    spec.datasets.push_back({g + "/occupancy", K::kUint8, {-1, -1, -1}, {1, 2, 0}});
    spec.datasets.push_back({g + "/origin", K::kDouble, {3}, {0}});
    spec.datasets.push_back({g + "/spacing", K::kDouble, {}, {0.5}});
    spec.datasets.push_back({g + "/dims", K::kInt64, {3}, {2}});
    spec.datasets.push_back({g + "/axes", K::kDouble, {3, 3}, kIdentity});
  }
  spec.datasets.push_back({"dynamic/shrink", K::kDouble, {}, {0}});
  for (const char* s : {"stats/static_surface", "stats/static_inside", "stats/dynamic_surface", "stats/dynamic_inside"})
    spec.datasets.push_back({s, K::kInt64, {}, {1}});
  spec.attributes = {{"", "scene", K::kString, "fuzz", 0}, {"", "units", K::kString, "mm", 0}};
  return spec;
}
void Read(const std::filesystem::path& file) {
  VoxelArtifactInfo info;
  ReadVoxelArtifact(file, &info);
}

#elif AUSBAU_FUZZ_READER_SPHERES
ArtifactSpec Spec() {
  return {kSpheresSchema,
          kSpheresSchemaVersion,
          {{"centers", K::kDouble, {-1, 3}, {0, 1, 2}},
           {"radii", K::kDouble, {-1}, {0.5}},
           {"normals", K::kDouble, {-1, 3}, {0, 0, 1}},
           {"valid", K::kUint8, {-1}, {1}},
           {"contact", K::kUint8, {-1}, {0}}},
          {{"", "r_min", K::kDouble, "", 0.5},
           {"", "r_max", K::kDouble, "", 0.5},
           {"", "vertices", K::kInt64, "", 2},
           {"centers", "units", K::kString, "mm", 0}}};
}
void Read(const std::filesystem::path& file) { ReadSpheresArtifact(file); }

#elif AUSBAU_FUZZ_READER_LABELS
ArtifactSpec Spec() {
  return {kLabelsSchema,
          kLabelsSchemaVersion,
          {{"deformability", K::kDouble, {-1}, {0.5}}, {"displacement", K::kDouble, {-1}, {0.1}}},
          {{"", "r_min", K::kDouble, "", 0.5},
           {"", "sigma", K::kDouble, "", 1},
           {"", "scale", K::kDouble, "", 1},
           {"", "density", K::kDouble, "", 1},
           {"", "measure", K::kString, "mean", 0},
           {"", "load_cases", K::kInt64, "", 4},
           {"", "vertices", K::kInt64, "", 2}}};
}
void Read(const std::filesystem::path& file) { ReadLabelsArtifact(file); }

#elif AUSBAU_FUZZ_READER_DISTFIELD
ArtifactSpec Spec() {
  return {kDistanceFieldSchema,
          kDistanceFieldSchemaVersion,
          {{"class", K::kUint8, {-1, -1, -1}, {0, 1, 2}},
           {"triangle", K::kInt64, {-1, -1, -1}, {0}},
           {"nearest_point", K::kFloat, {-1, -1, -1, 3}, {0.5}},
           {"grid/origin", K::kDouble, {3}, {0}},
           {"grid/spacing", K::kDouble, {}, {1}},
           {"grid/dims", K::kInt64, {3}, {2}}},
          {{"", "resolution", K::kInt64, "", 2},
           {"", "padding", K::kDouble, "", 1.3},
           {"", "mesh_hash", K::kString, "00112233445566778899aabbccddeeff", 0},
           {"", "triangles", K::kInt64, "", 1},
           {"", "units", K::kString, "mm", 0}}};
}
void Read(const std::filesystem::path& file) {
  const auto field = ReadDistanceField(file);
  // What a query does with an accepted field: every cell's point and triangle.
  for (std::int64_t i = 0; i < field->size(); ++i) {
    const Eigen::Vector3d p = field->NearestPoint(i);
    const std::int64_t cell = field->Locate(p);
    if (cell < 0 || cell >= field->size() || field->cell(cell).triangle >= field->triangle_count()) __builtin_trap();
  }
}

#else  // the low-level reader on a schema of its own
ArtifactSpec Spec() {
  return {"ausbau-fuzz",
          1,
          {{"a", K::kDouble, {-1, -1}, {1.5}},
           {"g/b", K::kInt64, {-1}, {3}},
           {"c", K::kUint8, {-1, -1, -1}, {7}},
           {"d", K::kFloat, {-1}, {0.25}},
           {"s", K::kDouble, {}, {2}}},
          {{"", "text", K::kString, "hello", 0},
           {"", "number", K::kDouble, "", 2.5},
           {"", "count", K::kInt64, "", 3},
           {"a", "units", K::kString, "mm", 0},
           {"g", "note", K::kString, "group attribute", 0}}};
}
void Read(const std::filesystem::path& file) {
  const ArtifactReader reader(file, "ausbau-fuzz", 1);
  // Each read on its own: a rejected dataset must not hide the others.
  ExpectOnlyInputErrors([&] { reader.ReadDoubles("a", 2); });
  ExpectOnlyInputErrors([&] { reader.ReadDoubles("a"); });
  ExpectOnlyInputErrors([&] { reader.ReadInts("a"); });
  ExpectOnlyInputErrors([&] { reader.ReadInts("g/b", 1); });
  ExpectOnlyInputErrors([&] { reader.ReadDoubles("g/b"); });
  ExpectOnlyInputErrors([&] { reader.ReadBytes("c", 3); });
  ExpectOnlyInputErrors([&] { reader.ReadFloats("d", 1); });
  ExpectOnlyInputErrors([&] { reader.ReadDoubles("s", 0); });
  ExpectOnlyInputErrors([&] { reader.ReadDoubles("g"); });
  ExpectOnlyInputErrors([&] { reader.ReadStringAttribute("", "text"); });
  ExpectOnlyInputErrors([&] { reader.ReadDoubleAttribute("", "number"); });
  ExpectOnlyInputErrors([&] { reader.ReadIntAttribute("", "count"); });
  ExpectOnlyInputErrors([&] { reader.ReadStringAttribute("a", "units"); });
  ExpectOnlyInputErrors([&] { reader.ReadStringAttribute("g", "note"); });
  (void)reader.Has("g/b");
  (void)reader.Has("missing/x");
}
#endif

}  // namespace
}  // namespace ausbau::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ausbau::fuzz;
  static const ArtifactSpec spec = Spec();
  static const std::filesystem::path file = WorkDir() / "artifact.h5";
  WriteRecipeArtifact(spec, data, size, file);
  ExpectOnlyInputErrors([&] { Read(file); });
  return 0;
}
