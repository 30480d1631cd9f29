// The bad-input suite (issue 16): every class of bad input, misuse and fault
// a hostile or careless user can produce, each an end-to-end run of a real
// executable (build/bin/ausbau-*) on a tiny scene, asserting the exit code
// and the message. The bad files are written here at run time.
//
// One table of cases {name, setup, command, exit code, message regex}, run
// as one parameterized test each, so that every class shows in ctest. Each
// case runs in a fresh folder holding a copy of a template: a small scene
// (two boxes), the artifacts of every stage for it, and the same artifacts
// for a second scene whose D has the same vertex count but other coordinates
// ("other/"). The template is built once per build of the stages (under a
// lock, so that parallel ctest processes share it). Every command runs under
// `timeout -s KILL`, so that a hang fails its case, not the suite.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>

#include "artifact/artifact.h"
#include "inistate/tau_estimate.h"
#include "inistate/voxel_grid.h"
#include "labeling/medial_spheres.h"
#include "labeling/pbd_label.h"
#include "planning/path_io.h"
#include "scene/scene.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

// Seconds a case may run before it counts as a hang (killed, exit 137).
constexpr int kCaseTimeoutSeconds = 20;

using Outcome = testing::CommandOutcome;  // stdout and stderr together

// Runs `command` with bash in `dir`, the stages first on PATH.
Outcome Shell(const fs::path& dir, const std::string& command, int timeout_s = kCaseTimeoutSeconds) {
  return testing::RunInDir(dir, command, timeout_s);
}

std::string Read(const fs::path& path) { return testing::ReadTextFile(path); }

void Write(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

// scene.yaml with the line of `key` replaced by "key: value" (or removed
// when value is empty).
void SetSceneKey(const fs::path& dir, const std::string& key, const std::string& value) {
  std::istringstream in(Read(dir / "scene.yaml"));
  std::string line, text;
  while (std::getline(in, line)) {
    if (line.rfind(key + ":", 0) == 0) {
      if (!value.empty()) text += key + ": " + value + "\n";
    } else {
      text += line + "\n";
    }
  }
  Write(dir / "scene.yaml", text);
}

// The first half of a file (a truncated download or a killed copy).
void Truncate(const fs::path& path) {
  const std::string text = Read(path);
  Write(path, text.substr(0, text.size() / 2));
}

// A path artifact with the given waypoints, built from the template's path.
void WritePath(const fs::path& file, const std::function<void(PathArtifact*)>& change) {
  PathArtifact path = ReadPathArtifact(file);
  change(&path);
  WritePathArtifact(file, path, Provenance{"test", "0", "", {}});
}

// ---------------------------------------------------------------- template

// The stages the template and the cases use; the template is rebuilt when
// any of them changed (their modification times form its stamp).
std::string BinariesStamp() {
  std::string stamp;
  for (const char* stage : {"scene-gen", "voxelize", "medial-spheres", "pbd-label", "plan", "tau-estimate"}) {
    std::error_code error;
    const auto time = fs::last_write_time(testing::BinDir() / (std::string("ausbau-") + stage), error);
    stamp += std::to_string(error ? 0 : time.time_since_epoch().count()) + "\n";
  }
  return stamp;
}

const char* const kTemplateCommands =
    "set -e\n"
    "ausbau-scene-gen --family two-boxes --seed 1 -o . > /dev/null\n"
    "ausbau-voxelize --scene scene.yaml --voxel-budget 20000 -o voxels.h5 --log-level error\n"
    "ausbau-medial-spheres --scene scene.yaml -o spheres.h5 --log-level error\n"
    "ausbau-pbd-label --scene scene.yaml --spheres spheres.h5 --max-load-cases 50 -o labels.h5 --log-level error\n"
    "ausbau-plan --scene scene.yaml --time-limit 20 -o path.h5 --csv path.csv --log-level error\n"
    "ausbau-tau-estimate --scene scene.yaml --voxels voxels.h5 --labels labels.h5 --rounds 1 --time-limit 5 "
    "-o tau.h5 --log-level error\n"
    // The other scene: D moved by 0.25 (same vertex count, other content),
    // everything made again for it.
    "mkdir other && cp scene.yaml environment.obj other/\n"
    "awk '$1 == \"v\" { print \"v\", $2 + 0.25, $3, $4; next } { print }' part.obj > other/part.obj\n"
    "cd other\n"
    "ausbau-voxelize --scene scene.yaml --voxel-budget 20000 -o voxels.h5 --log-level error\n"
    "ausbau-medial-spheres --scene scene.yaml -o spheres.h5 --log-level error\n"
    "ausbau-pbd-label --scene scene.yaml --spheres spheres.h5 --max-load-cases 50 -o labels.h5 --log-level error\n"
    "ausbau-plan --scene scene.yaml --time-limit 20 -o path.h5 --csv path.csv --log-level error\n"
    "ausbau-tau-estimate --scene scene.yaml --voxels voxels.h5 --labels labels.h5 --rounds 1 --time-limit 5 "
    "-o tau.h5 --log-level error\n";

fs::path Template() {
  static const fs::path ready = [] {
    const fs::path root = testing::BinDir().parent_path() / "tests" / "bad-input";
    fs::create_directories(root);
    const int lock = ::open((root / "lock").c_str(), O_CREAT | O_RDWR, 0644);
    ::flock(lock, LOCK_EX);
    const fs::path dir = root / "template";
    const std::string stamp = BinariesStamp();
    if (Read(root / "stamp") != stamp) {
      fs::remove_all(dir);
      const fs::path building = root / "building";
      fs::remove_all(building);
      fs::create_directories(building);
      const Outcome made = Shell(building, kTemplateCommands, 300);
      if (made.exit_code != 0) {
        ::close(lock);
        ADD_FAILURE() << "building the template failed:\n" << made.output;
        return fs::path();
      }
      fs::rename(building, dir);
      Write(root / "stamp", stamp);
    }
    ::close(lock);
    return dir;
  }();
  return ready;
}

// ---------------------------------------------------------------- the table

struct Case {
  std::string name;
  std::function<void(const fs::path&)> setup;  // writes the bad files into the case's folder
  std::string command;                         // bash, in that folder
  int exit_code;
  std::string message;                                          // regex, searched in the output
  std::function<void(const fs::path&, const Outcome&)> verify;  // more checks after the run
  std::string needs;  // "fuzz": passes once the reader fixes of branch fuzz are merged
};

std::ostream& operator<<(std::ostream& out, const Case& c) { return out << c.name; }

using Setup = std::function<void(const fs::path&)>;
const Setup kNothing = [](const fs::path&) {};

// The file must still hold what the template had (an input not overwritten).
std::function<void(const fs::path&, const Outcome&)> Unchanged(const std::string& file) {
  return [file](const fs::path& dir, const Outcome&) {
    EXPECT_TRUE(Read(dir / file) == Read(Template() / file)) << file << " was changed";
  };
}
std::function<void(const fs::path&, const Outcome&)> Absent(const std::string& file) {
  return [file](const fs::path& dir, const Outcome&) {
    std::error_code error;
    EXPECT_FALSE(fs::exists(fs::symlink_status(dir / file, error))) << file << " exists";
  };
}

std::vector<Case> SceneCases() {
  const std::string check = "ausbau-scene-check --scene scene.yaml";
  const auto key = [](const std::string& k, const std::string& v) {
    return [k, v](const fs::path& dir) { SetSceneKey(dir, k, v); };
  };
  return {
      {"SceneNameWithAnEscapeSequence", key("name", "\"panel\\e[2J\\e[31mred\""), check, 2,
       "name must not hold control characters"},
      {"SceneUnitsWithANewline", key("units", "\"mm\\n=HYPERLINK(1)\""), check, 2,
       "units must not hold control characters"},
      // Units reach profile.csv's header: a comma or a leading = would be a
      // cell holding a formula there.
      {"SceneUnitsWithAFormula", key("units", "\"mm,=HYPERLINK(\\\"http://x\\\")\""), check, 2,
       "units must be a unit's name"},
      {"SceneMissing", kNothing, "ausbau-scene-check --scene none.yaml", 2,
       "none\\.yaml: .*(not found|no such|cannot)"},
      {"SceneEmpty", [](const fs::path& d) { Write(d / "scene.yaml", ""); }, check, 2, "scene\\.yaml"},
      {"SceneBinaryGarbage", [](const fs::path& d) { Write(d / "scene.yaml", std::string("\x00\x01\xff\xfe{[", 6)); },
       check, 2, "scene\\.yaml"},
      {"SceneIsADirectory", kNothing, "ausbau-scene-check --scene .", 2, "\\.: .*(director|regular)"},
      {"SceneIsAFifo", [](const fs::path& d) { ::mkfifo((d / "fifo.yaml").c_str(), 0644); },
       "ausbau-scene-check --scene fifo.yaml", 2, "fifo\\.yaml: .*(regular|FIFO)", nullptr, "fuzz"},
      {"SceneIsDevZero", kNothing, "ausbau-scene-check --scene /dev/zero", 2, "/dev/zero: .*(regular|device)", nullptr,
       "fuzz"},
      {"SceneTopLevelList", [](const fs::path& d) { Write(d / "scene.yaml", "- a\n- b\n"); }, check, 2, "scene\\.yaml"},
      {"SceneUnterminated",
       [](const fs::path& d) { Write(d / "scene.yaml", "format: ausbau-scene/1\nstart: {t: [\n"); }, check, 2,
       "scene\\.yaml"},
      {"SceneWrongFormatVersion", key("format", "ausbau-scene/9"), check, 2, "scene\\.yaml.*(format|version)"},
      {"SceneNoFormat", key("format", ""), check, 2, "scene\\.yaml.*format"},
      {"SceneUnknownKey",
       [](const fs::path& d) { std::ofstream(d / "scene.yaml", std::ios::app) << "\ncolour: red\n"; }, check, 2,
       "colour"},
      {"SceneNoDynamic", key("dynamic", ""), check, 2, "dynamic"},
      {"SceneNoStatic", key("static", ""), check, 2, "static"},
      {"SceneDynamicFileMissing", key("dynamic", "\"gone.obj\""), check, 2, "gone\\.obj"},
      {"SceneStaticFileMissing", key("static", "[\"gone.obj\"]"), check, 2, "gone\\.obj"},
      {"SceneStaticListEmpty", key("static", "[]"), check, 2, "static"},
      // Unknown units are a warning (tolerances then taken as mm), not an error.
      {"SceneUnknownUnitsWarns", key("units", "\"furlongs\""), check, 0, "warning units-unknown"},
      {"SceneStartNaN", key("start", "{t: [.nan, 0, 0], q: [1, 0, 0, 0]}"), check, 2, "start"},
      {"SceneStartInfinite", key("start", "{t: [.inf, 0, 0], q: [1, 0, 0, 0]}"), check, 2, "start"},
      {"SceneStartZeroQuaternion", key("start", "{t: [-3, 0, 0], q: [0, 0, 0, 0]}"), check, 2, "start"},
      {"SceneStartShortVector", key("start", "{t: [-3, 0], q: [1, 0, 0, 0]}"), check, 2, "start"},
      {"SceneStartText", key("start", "{t: [a, b, c], q: [1, 0, 0, 0]}"), check, 2, "start"},
      {"SceneGoalNaN", key("goal", "{t: [.nan, 0, 0], q: [1, 0, 0, 0]}"), check, 2, "goal"},
      // Issue 33: a goal region narrower than the planner resolves was
      // accepted and never reached (the planner's inset emptied it).
      {"SceneGoalRegionTooSmallToReach", key("goal", "{region: {min: [3, 0, 0], max: [3.000000001, 1, 1]}}"),
       "ausbau-plan --scene scene.yaml --time-limit 5 -o p.h5", 2,
       "scene\\.yaml: goal\\.region is 1e-09 wide on axis x, narrower than the planner resolves", Absent("p.h5")},
      {"SceneBoundsInverted", key("bounds", "{min: [5, 5, 5], max: [-5, -5, -5]}"), check, 2, "bounds"},
      {"SceneBoundsNaN", key("bounds", "{min: [.nan, -5, -5], max: [5, 5, 5]}"), check, 2, "bounds"},
      {"SceneDynamicOriginHuge", key("dynamic_origin", "[1e300, 0, 0]"), "ausbau-plan --scene scene.yaml -o p.h5", 2,
       "dynamic_origin", Absent("p.h5"), "fuzz"},
      {"SceneDynamicOriginNaN", key("dynamic_origin", "[.nan, 0, 0]"), check, 2, "dynamic_origin"},
      {"SceneMeshIsADirectory",
       [](const fs::path& d) {
         fs::create_directory(d / "meshdir");
         SetSceneKey(d, "dynamic", "\"meshdir\"");
       },
       check, 2, "meshdir"},
      {"SceneMeshIsTheSceneFile", key("dynamic", "\"scene.yaml\""), check, 2, "scene\\.yaml"},
      {"SceneMeshIsAFifo",
       [](const fs::path& d) {
         ::mkfifo((d / "fifo.obj").c_str(), 0644);
         SetSceneKey(d, "dynamic", "\"fifo.obj\"");
       },
       check, 2, "fifo\\.obj: .*(regular|FIFO)", nullptr, "fuzz"},
      {"ScenePathWithSpacesWorks",
       [](const fs::path& d) {
         fs::create_directory(d / "my scene");
         for (const char* f : {"scene.yaml", "part.obj", "environment.obj"}) fs::copy(d / f, d / "my scene" / f);
       },
       "ausbau-scene-check --scene \"my scene/scene.yaml\"", 0, "two-boxes"},
  };
}

std::vector<Case> MeshCases() {
  const std::string check = "ausbau-scene-check --scene scene.yaml";
  const auto part = [](const std::string& text) { return [text](const fs::path& d) { Write(d / "part.obj", text); }; };
  const auto ply = [](const std::string& faces) {
    return [faces](const fs::path& d) {
      Write(d / "part.ply",
            "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n" +
                faces);
      SetSceneKey(d, "dynamic", "\"part.ply\"");
    };
  };
  const std::string tetra = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  // Both meshes moved 1e7 along x: single precision stores them 1 apart.
  const Setup far_away = [](const fs::path& d) {
    for (const char* file : {"part.obj", "environment.obj"}) {
      std::istringstream in(Read(d / file));
      std::string line, text;
      while (std::getline(in, line)) {
        if (line.rfind("v ", 0) == 0) {
          std::istringstream v(line.substr(2));
          double x = 0, y = 0, z = 0;
          v >> x >> y >> z;
          std::ostringstream moved;
          moved.precision(17);
          moved << "v " << x + 1e7 << " " << y << " " << z;
          line = moved.str();
        }
        text += line + "\n";
      }
      Write(d / file, text);
    }
  };
  return {
      {"MeshesFarFromTheOriginLosePrecision", far_away, "ausbau-plan --scene scene.yaml --validity rigid-exact -o p.h5",
       2, "coordinates reach 1e\\+07.*single precision"},
      {"MeshEmptyObj", part(""), check, 2, "part\\.obj"},
      {"MeshBinaryGarbage",
       part(std::string("\x7f"
                        "ELF\x00\x01\x02\xff",
                        8)),
       check, 2, "part\\.obj"},
      {"MeshOnlyVertices", part("v 0 0 0\nv 1 0 0\nv 0 1 0\n"), check, 2, "part\\.obj"},
      {"MeshFaceIndexOutOfRangeObj", part("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), check, 2, "part\\.obj"},
      {"MeshFaceIndexOutOfRangePly", ply("3 0 1 9\n3 0 2 3\n"), check, 2, "part\\.ply.*(index|range)", nullptr, "fuzz"},
      {"MeshNegativeFaceIndexPly", ply("3 0 1 -7\n3 0 2 3\n"), check, 2, "part\\.ply.*(index|range)", nullptr, "fuzz"},
      {"MeshFaceIndexOutOfRangePlyInVoxelize", ply("3 0 1 9\n3 0 2 3\n"), "ausbau-voxelize --scene scene.yaml", 2,
       "part\\.ply", nullptr, "fuzz"},
      {"MeshFaceIndexOutOfRangePlyInPlan", ply("3 0 1 9\n3 0 2 3\n"), "ausbau-plan --scene scene.yaml", 2, "part\\.ply",
       nullptr, "fuzz"},
      // OBJ that assimp 5.2 reads as another mesh without an error
      // (scene/obj_check.h), and a COLLADA file that crashes its importer.
      {"MeshObjNumberStartingWithDot", part("v .5 0 0\n" + tetra), check, 2, "part\\.obj: malformed OBJ file"},
      {"MeshObjVertexOfFiveNumbers", part("v 0 0 0 1 2\n" + tetra), check, 2,
       "part\\.obj: malformed OBJ file \\(line 1: a vertex of 5 numbers"},
      {"MeshObjIndexWithLeadingZero", part(tetra + "f 01 2 3\n"), check, 2, "part\\.obj: .*line 9: '01'"},
      {"MeshObjWordTakenForAFace", part(tetra + "foo 1 2 3\n"), check, 2, "part\\.obj: .*unknown statement 'foo'"},
      {"MeshObjIndentedStatement", part(tetra + " f 1 2 3\n"), check, 2, "part\\.obj: .*after leading blanks"},
      {"MeshObjNulInFace", part(tetra + std::string("f 1 2\0 3\n", 10)), check, 2, "part\\.obj: .*control character"},
      {"MeshColladaCrashingTheImporter",
       [](const fs::path& d) {
         Write(d / "part.dae",
               "<?xml version=\"1.0\"?>\n<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" "
               "version=\"1.4.1\"><library_geometries><geometry id=\"g\"><mesh><source id=\"p\"><float_array "
               "id=\"a\" count=\"0\">0 0 0 1 0 0 0 1 0</float_array><technique_common><accessor source=\"#a\" "
               "count=\"3\" stride=\"3\"><param name=\"X\" type=\"float\"/><param name=\"Y\" type=\"float\"/><param "
               "name=\"Z\" type=\"float\"/></accessor></technique_common></source><vertices id=\"v\"><input "
               "semantic=\"POSITION\" source=\"#p\"/></vertices><triangles count=\"1\"><input semantic=\"VERTEX\" "
               "source=\"#v\" offset=\"0\"/><p>0 1 2</p></triangles></mesh></geometry></library_geometries>"
               "<library_visual_scenes><visual_scene id=\"s\"><node id=\"n\"><instance_geometry url=\"#g\"/></node>"
               "</visual_scene></library_visual_scenes><scene><instance_visual_scene url=\"#s\"/></scene></COLLADA>\n");
         SetSceneKey(d, "dynamic", "\"part.dae\"");
       },
       "ausbau-plan --scene scene.yaml", 2, "part\\.dae: the dae importer of assimp crashed \\(signal 11, SIGSEGV\\)"},
      {"MeshNaNVertex", part("v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), check, 2, "part\\.obj"},
      {"MeshInfiniteVertex", part("v inf 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), check, 2, "part\\.obj"},
      {"MeshHugeCoordinates", part("v 1e300 0 0\nv -1e300 0 0\nv 0 1e300 0\nf 1 2 3\n"),
       "ausbau-voxelize --scene scene.yaml", 2, "part\\.obj|voxel"},
      {"MeshAllDegenerate", part("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 3 2\n"), "ausbau-plan --scene scene.yaml", 2,
       "part\\.obj.*(area|degenerate)", nullptr, "fuzz"},
      {"MeshTxtExtension",
       [](const fs::path& d) {
         Write(d / "part.txt", "just some words\n");
         SetSceneKey(d, "dynamic", "\"part.txt\"");
       },
       "ausbau-voxelize --scene scene.yaml", 2, "part\\.txt", nullptr, "fuzz"},
      {"MeshTruncatedBinaryStl",
       [](const fs::path& d) {
         Write(d / "part.stl", std::string(80, ' ') + std::string("\x10\x00\x00\x00", 4) + std::string(20, '\0'));
         SetSceneKey(d, "dynamic", "\"part.stl\"");
       },
       check, 2, "part\\.stl"},
      {"MeshAsciiStlGarbage",
       [](const fs::path& d) {
         Write(d / "part.stl", "solid x\nfacet normal oops\nendsolid\n");
         SetSceneKey(d, "dynamic", "\"part.stl\"");
       },
       check, 2, "part\\.stl"},
      {"MeshSingleTriangleVoxelize", part("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
       "ausbau-voxelize --scene scene.yaml -o v.h5", 0, "voxel size"},
      {"MeshFlatPartVoxelize", part("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"),
       "ausbau-voxelize --scene scene.yaml -o v.h5", 0, "voxel size"},
      {"MeshFlatPartVoxelizeTinyMemoryLimit", part("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"),
       "ausbau-voxelize --scene scene.yaml -o v.h5 --voxel-size 1e-3 --memory-limit 0.001", 2,
       "memory-limit|voxel-size", Absent("v.h5")},
      {"MeshTetraOk", part(tetra), check, 0, ""},
      {"MeshTooLargeForVoxelizeIsRefusedUpFront", part(tetra),
       "ausbau-voxelize --scene scene.yaml -o v.h5 --voxel-size 1e-5", 2, "memory-limit|voxel-size", Absent("v.h5")},
  };
}

// A numeric flag given a bad value: exit 2 and a line naming the flag.
Case Flag(const std::string& stage, const std::string& arguments, const std::string& flag, const std::string& value) {
  std::string name = stage + flag + "_" + value;
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return {name,
          kNothing,
          "ausbau-" + stage + " " + arguments + " " + flag + " " + value,
          2,
          std::regex_replace(flag, std::regex("-"), "\\-"),
          Absent("out.h5")};
}

std::vector<Case> CliCases() {
  std::vector<Case> cases;
  const std::string scene = "--scene scene.yaml -o out.h5";
  const std::string labels = "--scene scene.yaml --spheres spheres.h5 -o out.h5";
  const std::string smooth = "--scene scene.yaml --path path.h5 -o out.h5";
  const std::string verdict = "--scene scene.yaml --path path.h5 -o out.json";
  // Unknown flags are named first (verdict had said "--scene is required").
  for (const char* stage : {"voxelize", "medial-spheres", "pbd-label", "distfield-build", "tau-estimate", "plan",
                            "smooth", "verdict", "report", "scene-check", "scene-gen", "order"}) {
    cases.push_back(
        {std::string("UnknownFlag_") + stage, kNothing, std::string("ausbau-") + stage + " --bogus 1", 2, "--bogus"});
  }
  cases.push_back({"VerdictMissingPathNamesPath", kNothing, "ausbau-verdict --scene scene.yaml", 2, "--path"});
  cases.push_back({"PlanMissingScene", kNothing, "ausbau-plan", 2, "--scene"});
  cases.push_back({"PlanNegativeBudget", kNothing, "ausbau-plan --scene scene.yaml --budget -5", 2, "--budget"});
  cases.push_back(
      {"SmoothDeadlineNotANumber", kNothing, "ausbau-smooth " + smooth + " --deadline soon", 2, "--deadline"});
  cases.push_back({"BadLogLevel", kNothing, "ausbau-plan --scene scene.yaml --log-level loud", 2, "loud|log"});
  // --threads: 0..1024 (libgomp crashed on -1 and 100000).
  for (const auto& [stage, args] :
       std::vector<std::pair<std::string, std::string>>{{"voxelize", scene},
                                                        {"pbd-label", labels},
                                                        {"medial-spheres", scene},
                                                        {"plan", scene},
                                                        {"tau-estimate", scene},
                                                        {"distfield-build", "--scene scene.yaml --output-dir out"}}) {
    for (const char* value : {"-1", "100000", "two"}) cases.push_back(Flag(stage, args, "--threads", value));
  }
  // --seed: unsigned (-1 had become 2^64-1).
  for (const auto& [stage, args] : std::vector<std::pair<std::string, std::string>>{
           {"plan", scene}, {"smooth", smooth}, {"tau-estimate", scene}, {"scene-gen", "-o out"}}) {
    cases.push_back(Flag(stage, args, "--seed", "-1"));
  }
  // --time-limit: (0, a week] (1e308 had overflowed to an instant "no path").
  for (const auto& [stage, args] :
       std::vector<std::pair<std::string, std::string>>{{"plan", scene}, {"smooth", smooth}, {"tau-estimate", scene}}) {
    for (const char* value : {"1e308", "0", "-5", "nan"}) cases.push_back(Flag(stage, args, "--time-limit", value));
  }
  // --memory-limit (1e30 had been "must be > 0").
  for (const auto& [stage, args] : std::vector<std::pair<std::string, std::string>>{
           {"voxelize", scene}, {"distfield-build", "--scene scene.yaml --output-dir out"}}) {
    for (const char* value : {"1e30", "0", "-1", "nan"}) cases.push_back(Flag(stage, args, "--memory-limit", value));
  }
  // Iteration counts are bounded (10^9 hung).
  for (const char* value : {"1e9", "-1"}) {
    cases.push_back(Flag("pbd-label", labels, "--solver-iterations", value));
    cases.push_back(Flag("medial-spheres", scene, "--cooling-iterations", value));
    cases.push_back(Flag("medial-spheres", scene, "--growth-iterations", value));
  }
  cases.push_back(Flag("plan", scene, "--max-iterations", "-1"));
  // -1 is automatic (the default); below it, or above 10^6, is refused.
  for (const char* value : {"1e9", "-2"}) cases.push_back(Flag("plan", scene, "--coarse-iterations", value));
  // --tau: a number >= 0 (-5 had meant "estimate").
  for (const char* value : {"-5", "nan"}) cases.push_back(Flag("plan", scene, "--tau", value));
  // Every other numeric flag: out of its range, NaN.
  const std::vector<std::tuple<std::string, std::string, std::string, std::vector<std::string>>> numeric = {
      {"voxelize", scene, "--voxel-size", {"-1", "nan"}},
      {"voxelize", scene, "--voxel-budget", {"0"}},
      {"voxelize", scene, "--shrink", {"-1"}},
      {"distfield-build", "--scene scene.yaml --output-dir out", "--field-cells", {"0"}},
      {"medial-spheres", scene, "--delta", {"-1", "nan"}},
      {"medial-spheres", scene, "--push-factor", {"2"}},
      {"medial-spheres", scene, "--weld-tolerance", {"-1"}},
      {"pbd-label", labels, "--kappa", {"-1", "nan"}},
      {"pbd-label", labels, "--time-step", {"0"}},
      {"pbd-label", labels, "--duration", {"-1"}},
      {"pbd-label", labels, "--stiffness", {"2"}},
      {"pbd-label", labels, "--damping", {"nan"}},
      {"pbd-label", labels, "--max-load-cases", {"-1"}},
      {"pbd-label", labels, "--refine", {"-1"}},
      {"pbd-label", labels, "--density", {"-1"}},
      {"pbd-label", labels, "--glue-tolerance", {"-1"}},
      {"pbd-label", labels, "--rigid-tolerance", {"-1"}},
      {"plan", scene, "--u", {"2"}},
      {"plan", scene, "--range-max", {"0"}},
      {"plan", scene, "--resolution", {"0", "nan"}},
      {"plan", scene, "--rigid-tolerance", {"-1"}},
      {"plan", scene, "--sigma", {"-1"}},
      {"smooth", smooth, "--attempts", {"-1"}},
      {"smooth", smooth, "--resolution", {"0"}},
      {"tau-estimate", scene, "--rounds", {"0"}},
      {"tau-estimate", scene, "--initial-speed", {"-1"}},
      {"tau-estimate", scene, "--speed-step", {"nan"}},
      {"tau-estimate", scene, "--probe-attempts", {"-1"}},
      {"tau-estimate", scene, "--psi", {"-1"}},
      {"verdict", verdict, "--budget", {"nan", "-1"}},
      {"verdict", verdict, "--rigid-tolerance", {"-1"}},
      {"report", "--scene scene.yaml --path path.h5 -o out.html", "--clearance-samples", {"-1"}},
      {"scene-gen", "-o out", "--triangles", {"-1"}},
  };
  for (const auto& [stage, args, flag, values] : numeric) {
    for (const std::string& value : values) cases.push_back(Flag(stage, args, flag, value));
  }
  // Words from a fixed set.
  for (const auto& [stage, args, flag] :
       std::vector<std::tuple<std::string, std::string, std::string>>{{"plan", scene, "--planner"},
                                                                      {"plan", scene, "--sampler"},
                                                                      {"plan", scene, "--validity"},
                                                                      {"plan", scene, "--collision"},
                                                                      {"tau-estimate", scene, "--planner"},
                                                                      {"pbd-label", labels, "--rule"},
                                                                      {"pbd-label", labels, "--measure"},
                                                                      {"pbd-label", labels, "--stiffness-formula"},
                                                                      {"scene-gen", "-o out", "--family"}}) {
    cases.push_back(Flag(stage, args, flag, "bogus"));
  }
  // Renamed flags answer with the new name.
  cases.push_back(
      {"RenamedIterations", kNothing, "ausbau-pbd-label " + labels + " --iterations 3", 2, "--solver-iterations"});
  return cases;
}

std::vector<Case> FileSystemCases() {
  const auto link = [](const std::string& target, const std::string& name) {
    return [target, name](const fs::path& d) { fs::create_symlink(target, d / name); };
  };
  return {
      // Outputs that are inputs (also by another spelling or a link).
      {"OutputIsTheScene", kNothing, "ausbau-plan --scene scene.yaml -o scene.yaml", 2,
       "scene\\.yaml: .*same file as the input --scene", Unchanged("scene.yaml")},
      {"OutputIsTheSceneOtherSpelling", [](const fs::path& d) { fs::create_directory(d / "sub"); },
       "ausbau-voxelize --scene scene.yaml -o ./sub/../scene.yaml", 2, "same file as the input --scene",
       Unchanged("scene.yaml")},
      {"OutputIsTheSceneThroughAHardLink",
       [](const fs::path& d) { fs::create_hard_link(d / "scene.yaml", d / "h.h5"); },
       "ausbau-plan --scene scene.yaml -o h.h5", 2, "same file as the input --scene", Unchanged("scene.yaml")},
      {"CsvIsDsMesh", kNothing, "ausbau-plan --scene scene.yaml -o p.h5 --csv part.obj", 2,
       "part\\.obj: .*same file as the input scene's dynamic mesh", Unchanged("part.obj")},
      {"CsvIsSsMesh", kNothing, "ausbau-smooth --scene scene.yaml --path path.h5 -o s.h5 --csv environment.obj", 2,
       "environment\\.obj: .*static", Unchanged("environment.obj")},
      {"PlyIsDsMesh", kNothing, "ausbau-medial-spheres --scene scene.yaml -o s.h5 --ply part.obj", 2,
       "part\\.obj: .*dynamic mesh", Unchanged("part.obj")},
      {"OutputIsTheSpheres", kNothing, "ausbau-pbd-label --scene scene.yaml --spheres spheres.h5 -o spheres.h5", 2,
       "spheres\\.h5: .*same file as the input --spheres", Unchanged("spheres.h5")},
      {"OutputIsThePathInSmooth", kNothing, "ausbau-smooth --scene scene.yaml --path path.h5 -o path.h5", 2,
       "same file as the input --path", Unchanged("path.h5")},
      {"OutputIsThePathInVerdict", kNothing, "ausbau-verdict --scene scene.yaml --path path.h5 -o path.h5", 2,
       "same file as the input --path", Unchanged("path.h5")},
      {"CsvIsThePathCsvInVerdictsInput", kNothing,
       "ausbau-verdict --scene scene.yaml --path path.h5 --csv-name path.csv -o path.csv", 2,
       "same file as the input --csv-name", Unchanged("path.csv")},
      {"OutputIsTheVoxels", kNothing,
       "ausbau-tau-estimate --scene scene.yaml --voxels voxels.h5 --labels labels.h5 -o voxels.h5", 2,
       "same file as the input --voxels", Unchanged("voxels.h5")},
      {"ProfileIsTheLabels", kNothing,
       "ausbau-smooth --scene scene.yaml --path path.h5 -o s.h5 --labels labels.h5 --profile labels.h5", 2,
       "same file as the input --labels", Unchanged("labels.h5")},
      {"OmplPathIsTheScene", kNothing, "ausbau-plan --scene scene.yaml -o p.h5 --ompl-path scene.yaml", 2,
       "same file as the input --scene", Unchanged("scene.yaml")},
      {"JsonIsTheScene", kNothing, "ausbau-scene-check --scene scene.yaml --json scene.yaml", 2,
       "same file as the input --scene", Unchanged("scene.yaml")},
      {"CsvEqualsOutput", kNothing, "ausbau-plan --scene scene.yaml -o p.h5 --csv p.h5", 2, "name the same file",
       Absent("p.h5")},
      // The stages moved onto the runner (issue 32 item 1): their files are
      // declared, so the same checks hold for them.
      {"DistfieldStaticOutIsDsMesh", kNothing,
       "ausbau-distfield-build --scene scene.yaml --static-out part.obj --dynamic-out d.h5", 2,
       "part\\.obj: .*same file as the input scene's dynamic mesh", Unchanged("part.obj")},
      {"DistfieldOutputDirIsAFile", kNothing, "ausbau-distfield-build --scene scene.yaml --output-dir scene.yaml", 2,
       "scene\\.yaml: --output-dir: not a folder", Unchanged("scene.yaml")},
      {"ReportOutputIsThePath", kNothing, "ausbau-report --scene scene.yaml --path path.h5 -o path.h5", 2,
       "same file as the input --path", Unchanged("path.h5")},
      {"OrderOutputDirIsAPart", kNothing, "ausbau-order --part part.obj --part environment.obj --output-dir part.obj",
       2, "part\\.obj: --output-dir: not a folder", Unchanged("part.obj")},
      // --validate of a stage without an artifact: checks, prints, writes nothing.
      {"SceneGenValidateWritesNothing", kNothing, "ausbau-scene-gen --family two-boxes -o new --validate", 0,
       "ausbau-scene-gen: the options and inputs are valid", Absent("new")},
      {"SceneGenValidateChecksTheFamilysFlags", kNothing,
       "ausbau-scene-gen --family two-boxes --parts 3 -o new --validate", 2,
       "--parts, --cell: apply only to the vehicle", Absent("new")},
      {"ReportValidateNeedsTheFiles", kNothing, "ausbau-report --scene scene.yaml --path gone.h5 --validate", 2,
       "gone\\.h5: file not found", Absent("report.html")},
      // Outputs that are not regular files: never replaced.
      {"CsvIsDevFull", kNothing, "ausbau-plan --scene scene.yaml -o p.h5 --csv /dev/full", 2, "/dev/full: is a device",
       Absent("p.h5")},
      {"OutputIsDevNull", kNothing, "ausbau-voxelize --scene scene.yaml -o /dev/null", 2, "/dev/null: is a device"},
      {"OutputIsACharDeviceNode",
       [](const fs::path& d) { ::mknod((d / "dev").c_str(), S_IFCHR | 0666, makedev(1, 3)); },
       "ausbau-plan --scene scene.yaml -o dev", 2, "dev: is a device",
       [](const fs::path& d, const Outcome&) {
         struct stat info;
         ASSERT_EQ(::lstat((d / "dev").c_str(), &info), 0);
         EXPECT_TRUE(S_ISCHR(info.st_mode)) << "the device node was replaced";
       }},
      {"OutputIsASymlink", link("spheres.h5", "out.h5"), "ausbau-plan --scene scene.yaml -o out.h5", 2,
       "out\\.h5: is a symbolic link", Unchanged("spheres.h5")},
      {"OutputIsADanglingSymlink", link("nowhere.h5", "out.h5"), "ausbau-plan --scene scene.yaml -o out.h5", 2,
       "out\\.h5: is a symbolic link", Absent("nowhere.h5")},
      {"OutputIsAFifo", [](const fs::path& d) { ::mkfifo((d / "out.csv").c_str(), 0644); },
       "ausbau-plan --scene scene.yaml -o p.h5 --csv out.csv", 2, "out\\.csv: is a FIFO", Absent("p.h5")},
      {"OutputIsADirectory", [](const fs::path& d) { fs::create_directory(d / "out.h5"); },
       "ausbau-plan --scene scene.yaml -o out.h5", 2, "out\\.h5: is a directory"},
      {"VerdictOutputIsASymlink", link("scene.yaml", "v.json"),
       "ausbau-verdict --scene scene.yaml --path path.h5 -o v.json", 2, "v\\.json: is a symbolic link",
       Unchanged("scene.yaml")},
      {"ReportOutputIsADirectory", kNothing, "ausbau-report --scene scene.yaml --path path.h5 -o .", 2,
       "is a directory"},
      {"SceneGenOutputIsAFile", kNothing, "ausbau-scene-gen --family two-boxes -o scene.yaml", 2, "scene\\.yaml"},
      {"SceneGenOverAUsersScene", kNothing, "ausbau-scene-gen --family rod-in-cage -o .", 2,
       "already holds a scene.*--force", Unchanged("part.obj")},
      {"SceneGenOverAUsersMeshes",
       [](const fs::path& d) {
         fs::create_directory(d / "meshes");
         fs::copy_file(d / "part.obj", d / "meshes/part.obj");
       },
       "ausbau-scene-gen --family two-boxes -o meshes", 2, "meshes: the folder is not empty.*--force",
       [](const fs::path& d, const Outcome&) {
         EXPECT_TRUE(Read(d / "meshes/part.obj") == Read(Template() / "part.obj")) << "the user's mesh was replaced";
       }},
      {"OutputInAMissingFolderIsCreated", kNothing, "ausbau-plan --scene scene.yaml -o new/deeper/p.h5", 0, "",
       [](const fs::path& d, const Outcome&) { EXPECT_TRUE(fs::exists(d / "new/deeper/p.h5")); }},
      {"OutputFolderCannotBeCreated", kNothing, "ausbau-plan --scene scene.yaml -o /proc/no/such/p.h5", 1,
       "/proc/no/such/p\\.h5: cannot create directory"},
      {"OutputWithSpaces", kNothing, "ausbau-plan --scene scene.yaml -o \"my path.h5\" --csv \"my path.csv\"", 0, "",
       [](const fs::path& d, const Outcome&) { EXPECT_TRUE(fs::exists(d / "my path.csv")); }},
      // Inputs missing or of the wrong kind.
      {"SpheresMissing", kNothing, "ausbau-pbd-label --scene scene.yaml --spheres none.h5 -o l.h5", 2,
       "none\\.h5: file not found"},
      {"PathMissing", kNothing, "ausbau-smooth --scene scene.yaml --path none.h5 -o s.h5", 2,
       "none\\.h5: file not found"},
      {"PathIsADirectory", kNothing, "ausbau-verdict --scene scene.yaml --path . -o v.json", 2,
       "\\.: not a regular file"},
      {"VoxelsMissing", kNothing, "ausbau-tau-estimate --scene scene.yaml --voxels none.h5 --labels labels.h5", 2,
       "none\\.h5: file not found"},
      {"LabelsMissing", kNothing, "ausbau-tau-estimate --scene scene.yaml --voxels voxels.h5 --labels none.h5", 2,
       "none\\.h5: file not found"},
      {"TauFileMissing", kNothing, "ausbau-verdict --scene scene.yaml --path path.h5 --tau-file none.h5 -o v.json", 2,
       "none\\.h5: file not found"},
      {"TimesIsAFile", kNothing, "ausbau-verdict --scene scene.yaml --path path.h5 --times scene.yaml -o v.json", 2,
       "scene\\.yaml: --times: not a folder"},
      {"TimesHoldsGarbage",
       [](const fs::path& d) {
         fs::create_directory(d / "times");
         Write(d / "times/plan.seconds", "fast\n");
       },
       "ausbau-verdict --scene scene.yaml --path path.h5 --times times -o v.json", 2, "plan\\.seconds"},
      {"SameFileAsTwoInputs", kNothing,
       "ausbau-tau-estimate --scene scene.yaml --voxels voxels.h5 --labels voxels.h5 -o t.h5", 2,
       "voxels\\.h5.*(schema|ausbau-labels)"},
      {"DistfieldNotTwoFiles", kNothing, "ausbau-plan --scene scene.yaml --collision farr --distfield one.h5 -o p.h5",
       2, "distfield"},
      // Temporary files of a killed writer (a pid that no longer runs) are
      // removed on the next write of that output; a live writer's and other
      // names stay.
      {"StaleTemporaryFilesAreRemoved",
       [](const fs::path& d) {
         Write(d / "p.h5.tmp-999999999-0", "half an artifact");
         Write(d / "p.csv.tmp-999999999-3", "half a csv");
         Write(d / ("p.h5.tmp-" + std::to_string(::getpid()) + "-0"), "a live writer's");
         Write(d / "p.h5.tmp-notapid", "someone else's");
       },
       "ausbau-plan --scene scene.yaml -o p.h5 --csv p.csv", 0, "",
       [](const fs::path& d, const Outcome&) {
         EXPECT_FALSE(fs::exists(d / "p.h5.tmp-999999999-0"));
         EXPECT_FALSE(fs::exists(d / "p.csv.tmp-999999999-3"));
         EXPECT_TRUE(fs::exists(d / ("p.h5.tmp-" + std::to_string(::getpid()) + "-0")));
         EXPECT_TRUE(fs::exists(d / "p.h5.tmp-notapid"));
       }},
  };
}

// Artifact consumers: (stage command with {} for the artifact, schema word).
struct Consumer {
  std::string name, command, file, schema;
  int version;
};

std::vector<Case> ArtifactCases() {
  const std::vector<Consumer> consumers = {
      {"Spheres", "ausbau-pbd-label --scene scene.yaml --spheres spheres.h5 -o out.h5", "spheres.h5", kSpheresSchema,
       kSpheresSchemaVersion},
      {"Labels", "ausbau-tau-estimate --scene scene.yaml --voxels voxels.h5 --labels labels.h5 -o out.h5", "labels.h5",
       kLabelsSchema, kLabelsSchemaVersion},
      {"Voxels", "ausbau-tau-estimate --scene scene.yaml --voxels voxels.h5 --labels labels.h5 -o out.h5", "voxels.h5",
       kVoxelsSchema, kVoxelsSchemaVersion},
      {"Path", "ausbau-smooth --scene scene.yaml --path path.h5 -o out.h5", "path.h5", kPathSchema, kPathSchemaVersion},
      {"PathInVerdict", "ausbau-verdict --scene scene.yaml --path path.h5 -o out.json", "path.h5", kPathSchema,
       kPathSchemaVersion},
      {"Tau", "ausbau-verdict --scene scene.yaml --path path.h5 --tau-file tau.h5 -o out.json", "tau.h5", kTauSchema,
       kTauSchemaVersion},
  };
  std::vector<Case> cases;
  for (const Consumer& c : consumers) {
    const std::string file = c.file, pattern = std::regex_replace(c.file, std::regex("\\."), "\\.");
    cases.push_back({c.name + "Empty", [file](const fs::path& d) { Write(d / file, ""); }, c.command, 2, pattern});
    cases.push_back(
        {c.name + "Text", [file](const fs::path& d) { Write(d / file, "not hdf5 at all\n"); }, c.command, 2, pattern});
    cases.push_back({c.name + "Truncated", [file](const fs::path& d) { Truncate(d / file); }, c.command, 2, pattern});
    cases.push_back(
        {c.name + "OfAnotherSchema",
         [file](const fs::path& d) { fs::copy_file(d / "spheres.h5", d / file, fs::copy_options::overwrite_existing); },
         c.command, c.name == "Spheres" ? 0 : 2, c.name == "Spheres" ? "" : pattern + ".*schema"});
    const std::string schema = c.schema;
    const int version = c.version;
    cases.push_back({c.name + "UnsupportedVersion",
                     [file, schema](const fs::path& d) {
                       ArtifactWriter writer(d / file, schema, 99, Provenance{"test", "0", "", {}});
                       writer.Commit();
                     },
                     c.command, 2, pattern + ".*version"});
    cases.push_back({c.name + "NoDatasets",
                     [file, schema, version](const fs::path& d) {
                       ArtifactWriter writer(d / file, schema, version, Provenance{"t", "0", "", {}});
                       writer.Commit();
                     },
                     c.command, 2, pattern + ".*(dataset|missing)"});
  }
  // The "OfAnotherSchema" of spheres is a copy of itself: valid, removed
  // again below so that it does not pose as a class.
  cases.erase(
      std::remove_if(cases.begin(), cases.end(), [](const Case& c) { return c.name == "SpheresOfAnotherSchema"; }),
      cases.end());
  const std::string verdict = "ausbau-verdict --scene scene.yaml --path path.h5 -o v.json";
  const std::string smooth = "ausbau-smooth --scene scene.yaml --path path.h5 -o s.h5";
  std::vector<Case> more = {
      // Artifacts of another scene or part (content hashes in their provenance).
      {"LabelsOfAnotherPartSameVertexCount",
       [](const fs::path& d) { fs::copy_file(d / "other/labels.h5", d / "l.h5"); },
       "ausbau-tau-estimate --scene scene.yaml --voxels voxels.h5 --labels l.h5 -o t.h5", 2,
       "l\\.h5: was made from another D than this scene's .*part\\.obj", Absent("t.h5")},
      {"LabelsOfAnotherPartInPlan", [](const fs::path& d) { fs::copy_file(d / "other/labels.h5", d / "l.h5"); },
       "ausbau-plan --scene scene.yaml --validity labeled-mliv --tau 1 --psi 0.1 --voxels voxels.h5 --labels l.h5 "
       "-o p.h5",
       2, "l\\.h5: was made from another D", Absent("p.h5")},
      {"VoxelsOfAnotherScene", [](const fs::path& d) { fs::copy_file(d / "other/voxels.h5", d / "v.h5"); },
       "ausbau-tau-estimate --scene scene.yaml --voxels v.h5 --labels labels.h5 -o t.h5", 2,
       "v\\.h5: was made from another D", Absent("t.h5")},
      {"PathOfAnotherSceneSmoothed", [](const fs::path& d) { fs::copy_file(d / "other/path.h5", d / "p.h5"); },
       "ausbau-smooth --scene scene.yaml --path p.h5 -o s.h5", 2, "p\\.h5: was made from another D", Absent("s.h5")},
      {"PathOfAnotherSceneJudged", [](const fs::path& d) { fs::copy_file(d / "other/path.h5", d / "p.h5"); },
       "ausbau-verdict --scene scene.yaml --path p.h5 -o v.json", 2, "p\\.h5: was made from another D",
       Absent("v.json")},
      {"TauOfAnotherScene", [](const fs::path& d) { fs::copy_file(d / "other/tau.h5", d / "t.h5"); },
       "ausbau-verdict --scene scene.yaml --path path.h5 --tau-file t.h5 -o v.json", 2,
       "t\\.h5: was made from another D"},
      {"SpheresOfAnotherPart", [](const fs::path& d) { fs::copy_file(d / "other/spheres.h5", d / "s.h5"); },
       "ausbau-pbd-label --scene scene.yaml --spheres s.h5 -o l.h5", 2, "s\\.h5: computed for another part D"},
      {"LabelsWrongVertexCount",
       [](const fs::path& d) {
         LabelsArtifact labels = ReadLabelsArtifact(d / "labels.h5");
         labels.deformability.push_back(0.5);
         labels.displacement.push_back(0.0);
         WriteLabelsArtifact(d / "labels.h5", labels, Provenance{"t", "0", "", {}});
       },
       "ausbau-tau-estimate --scene scene.yaml --voxels voxels.h5 --labels labels.h5 -o t.h5", 2,
       "labels\\.h5.*vertices"},
      {"LabelsNaN",
       [](const fs::path& d) {
         LabelsArtifact labels = ReadLabelsArtifact(d / "labels.h5");
         labels.deformability[0] = std::nan("");
         WriteLabelsArtifact(d / "labels.h5", labels, Provenance{"t", "0", "", {}});
       },
       "ausbau-tau-estimate --scene scene.yaml --voxels voxels.h5 --labels labels.h5 -o t.h5", 2, "labels\\.h5"},
      // Paths a verdict must not call removable.
      {"PathEndsAtTheInstalledPose",
       [](const fs::path& d) {
         WritePath(d / "path.h5", [](PathArtifact* p) { p->waypoints.push_back(p->waypoints.front()); });
       },
       verdict, 3, "NOT REMOVABLE",
       [](const fs::path& d, const Outcome&) {
         EXPECT_NE(Read(d / "v.json").find("\"removable\": false"), std::string::npos) << Read(d / "v.json");
       }},
      // One waypoint is a D already in its goal at the installed pose (judged
      // as staying there); here the goal is elsewhere: not removable, said so.
      {"PathOfOneWaypointNotInTheGoal",
       [](const fs::path& d) { WritePath(d / "path.h5", [](PathArtifact* p) { p->waypoints.resize(1); }); }, verdict, 3,
       "NOT REMOVABLE"},
      {"PathOfNoWaypointClaimingSuccess",
       [](const fs::path& d) { WritePath(d / "path.h5", [](PathArtifact* p) { p->waypoints.clear(); }); }, verdict, 2,
       "path\\.h5: (claims success with 0 waypoints|.*waypoints)", Absent("v.json")},
      {"PathNotStartingAtTheInstalledPose",
       [](const fs::path& d) {
         WritePath(d / "path.h5", [](PathArtifact* p) { p->waypoints.erase(p->waypoints.begin()); });
       },
       verdict, 3, "NOT REMOVABLE"},
      {"PathWithNaNVolumes",
       [](const fs::path& d) {
         WritePath(d / "path.h5", [](PathArtifact* p) {
           p->validity = ValidityMode::kMliv;
           p->waypoint_volume.assign(p->waypoints.size(), std::nan(""));
           p->waypoint_part.assign(p->waypoints.size(), 0);
           p->waypoint_deformability.assign(p->waypoints.size(), 0.5);
         });
       },
       verdict, 2, "path\\.h5: .*(volume|finite)", Absent("v.json")},
      {"PathWithNaNLength",
       [](const fs::path& d) {
         WritePath(d / "path.h5", [](PathArtifact* p) { p->length_normalized = std::nan(""); });
       },
       verdict, 2, "path\\.h5: .*length", Absent("v.json")},
      {"PathFailedIsNotRemovable",
       [](const fs::path& d) { WritePath(d / "path.h5", [](PathArtifact* p) { p->success = false; }); }, verdict, 3,
       "NOT REMOVABLE"},
      {"PathFailedIsNotSmoothed",
       [](const fs::path& d) { WritePath(d / "path.h5", [](PathArtifact* p) { p->success = false; }); }, smooth, 2,
       "path\\.h5: holds no path"},
      {"PathCsvNaN",
       [](const fs::path& d) { Write(d / "bad.csv", "x,y,z,qw,qx,qy,qz\nnan,0,0,1,0,0,0\n1,0,0,1,0,0,0\n"); },
       "ausbau-verdict --scene scene.yaml --path path.h5 --csv-name bad.csv -o v.json", 2, "bad\\.csv"},
      {"PathCsvWrongColumns", [](const fs::path& d) { Write(d / "bad.csv", "x,y,z\n1,2,3\n"); },
       "ausbau-verdict --scene scene.yaml --path path.h5 --csv-name bad.csv -o v.json", 2, "bad\\.csv"},
      {"PathCsvEmpty", [](const fs::path& d) { Write(d / "bad.csv", ""); },
       "ausbau-verdict --scene scene.yaml --path path.h5 --csv-name bad.csv -o v.json", 2, "bad\\.csv"},
      // Issue 33: links out of an artifact. HDF5 follows them on reading,
      // while the provenance and every content hash see only this file.
      {"ArtifactWithAnExternalLink",
       [](const fs::path& d) {
         const hid_t other = H5Fcreate((d / "other.h5").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
         ASSERT_GE(other, 0);
         const hsize_t dims[2] = {2, 7};
         const std::vector<double> poses = {0, 0, 0, 1, 0, 0, 0, 100, 0, 0, 1, 0, 0, 0};
         const hid_t space = H5Screate_simple(2, dims, nullptr);
         const hid_t set = H5Dcreate2(other, "w", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
         H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, poses.data());
         H5Dclose(set);
         H5Sclose(space);
         H5Fclose(other);
         const hid_t h5 = H5Fopen((d / "path.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
         ASSERT_GE(h5, 0);
         H5Ldelete(h5, "waypoints", H5P_DEFAULT);
         ASSERT_GE(H5Lcreate_external("other.h5", "/w", h5, "waypoints", H5P_DEFAULT, H5P_DEFAULT), 0);
         H5Fclose(h5);
       },
       smooth, 2, "path\\.h5: 'waypoints' is an external link to other\\.h5:/w: an artifact must hold all its data",
       Absent("s.h5")},
      {"ArtifactWithASoftLink",
       [](const fs::path& d) {
         const hid_t h5 = H5Fopen((d / "path.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
         ASSERT_GE(h5, 0);
         H5Ldelete(h5, "waypoints", H5P_DEFAULT);
         ASSERT_GE(H5Lcreate_soft("/elsewhere/waypoints", h5, "waypoints", H5P_DEFAULT, H5P_DEFAULT), 0);
         H5Fclose(h5);
       },
       verdict, 2, "path\\.h5: 'waypoints' is a soft link", Absent("v.json")},
      // Reader classes (branch fuzz): a dataset far larger than its file.
      {"ArtifactDeclaringAHugeDataset",
       [](const fs::path& d) {
         // The path artifact's waypoints replaced by a 2^33 x 7 dataset of
         // which nothing is written: a few KB on disk, 448 GB to read.
         const std::string file = (d / "path.h5").string();
         const hid_t h5 = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
         ASSERT_GE(h5, 0);
         H5Ldelete(h5, "waypoints", H5P_DEFAULT);
         const hsize_t dims[2] = {hsize_t{1} << 33, 7}, chunk[2] = {1024, 7};
         const hid_t space = H5Screate_simple(2, dims, nullptr);
         const hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
         H5Pset_chunk(plist, 2, chunk);
         const hid_t set = H5Dcreate2(h5, "waypoints", H5T_IEEE_F64LE, space, H5P_DEFAULT, plist, H5P_DEFAULT);
         ASSERT_GE(set, 0);
         H5Dclose(set);
         H5Pclose(plist);
         H5Sclose(space);
         H5Fclose(h5);
       },
       verdict, 2, "path\\.h5: .*waypoints", Absent("v.json"), "fuzz"},
  };
  cases.insert(cases.end(), more.begin(), more.end());
  return cases;
}

std::vector<Case> AllCases() {
  std::vector<Case> all;
  for (auto part : {SceneCases(), MeshCases(), CliCases(), FileSystemCases(), ArtifactCases()}) {
    all.insert(all.end(), part.begin(), part.end());
  }
  return all;
}

class BadInput : public ::testing::TestWithParam<Case> {};

TEST_P(BadInput, ExitCodeAndMessage) {
  const Case& c = GetParam();
  const fs::path source = Template();
  ASSERT_FALSE(source.empty());
  const fs::path dir = testing::MakeTempDir("bad-" + c.name);
  fs::copy(source, dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  c.setup(dir);
  const Outcome outcome = Shell(dir, c.command);
  SCOPED_TRACE(c.command + (c.needs.empty() ? "" : "  [needs branch " + c.needs + "]"));
  EXPECT_EQ(outcome.exit_code, c.exit_code) << outcome.output;
  EXPECT_TRUE(std::regex_search(outcome.output, std::regex(c.message))) << "expected /" << c.message << "/ in:\n"
                                                                        << outcome.output;
  if (c.exit_code == 2) {
    // One line: "ausbau-<stage>: error: <file or flag>: <problem>".
    const std::regex error_line("(^|\n)ausbau-[a-z-]+: error: [^\n]+\n");
    const auto begin = std::sregex_iterator(outcome.output.begin(), outcome.output.end(), error_line);
    EXPECT_EQ(std::distance(begin, std::sregex_iterator()), 1) << outcome.output;
  }
  if (c.verify) c.verify(dir, outcome);
  std::error_code ignored;
  fs::remove_all(dir, ignored);
}

INSTANTIATE_TEST_SUITE_P(Classes, BadInput, ::testing::ValuesIn(AllCases()),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           std::string name = info.param.name;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace ausbau

namespace ausbau {
namespace {

// ---------------------------------------------------------------- faults

// A fresh copy of the template for a fault test.
fs::path FaultDir(const std::string& name) {
  const fs::path source = Template();
  if (source.empty()) return fs::path();
  const fs::path dir = testing::MakeTempDir("fault-" + name);
  fs::copy(source, dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  return dir;
}

// Names of the temporary files atomic writes use ("<file>.tmp-<pid>-<n>").
std::vector<std::string> TemporaryFiles(const fs::path& dir) {
  std::vector<std::string> found;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().filename().string().find(".tmp-") != std::string::npos) {
      found.push_back(entry.path().filename().string());
    }
  }
  return found;
}

// OMP_NUM_THREADS far beyond the cores (with the default --threads 0) once
// crashed voxelize and medial-spheres inside libgomp: clamped to the
// cores, with a warning.
TEST(Faults, AHugeOmpNumThreadsIsClampedToTheCores) {
  const fs::path dir = FaultDir("omp-threads");
  ASSERT_FALSE(dir.empty());
  const Outcome outcome = Shell(dir,
                                "export OMP_NUM_THREADS=100000; "
                                "ausbau-voxelize --scene scene.yaml --voxel-budget 20000 -o v2.h5 && "
                                "ausbau-medial-spheres --scene scene.yaml -o s2.h5");
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
  EXPECT_TRUE(std::regex_search(outcome.output, std::regex("100000 threads .* more than the"))) << outcome.output;
  EXPECT_TRUE(fs::exists(dir / "v2.h5"));
  EXPECT_TRUE(fs::exists(dir / "s2.h5"));
  std::error_code ignored;
  fs::remove_all(dir, ignored);
}

// A full disk (the file size limit, ulimit -f, in the stage's shell): the
// stage fails naming its output, leaves no temporary file, and the output of
// an earlier run stays as it was.
TEST(Faults, FullDiskLeavesNoTemporaryFileAndTheOldOutput) {
  const fs::path dir = FaultDir("full-disk");
  ASSERT_FALSE(dir.empty());
  const std::string before = Read(dir / "voxels.h5");
  ASSERT_FALSE(before.empty());
  // voxels.h5 is about 70 KB: 8 KB (ulimit -f counts 1024-byte blocks) is
  // not enough.
  const Outcome full = Shell(dir, "ulimit -f 8; ausbau-voxelize --scene scene.yaml --voxel-budget 30000 -o voxels.h5");
  EXPECT_NE(full.exit_code, 0) << full.output;
  EXPECT_TRUE(std::regex_search(full.output, std::regex("voxels\\.h5: cannot"))) << full.output;
  EXPECT_TRUE(TemporaryFiles(dir).empty()) << full.output;
  EXPECT_TRUE(Read(dir / "voxels.h5") == before) << "the old output was changed";
  // The same for a text output (the verdict's JSON, a few KB, at 1 KB).
  const Outcome verdict = Shell(dir, "ulimit -f 1; ausbau-verdict --scene scene.yaml --path path.h5 -o v.json");
  EXPECT_NE(verdict.exit_code, 0) << verdict.output;
  EXPECT_EQ(verdict.exit_code == 0 || verdict.exit_code == 3, false) << verdict.output;
  EXPECT_TRUE(std::regex_search(verdict.output, std::regex("v\\.json: cannot write file"))) << verdict.output;
  EXPECT_TRUE(TemporaryFiles(dir).empty()) << verdict.output;
  EXPECT_FALSE(fs::exists(dir / "v.json"));
}

// Two pipelines on one OUT: the second is refused while the first runs (its
// plan stage waits for a file the test creates), the first completes.
TEST(Faults, TwoPipelinesOnOneOutTheSecondIsRefused) {
  const fs::path dir = FaultDir("two-pipelines");
  ASSERT_FALSE(dir.empty());
  Write(dir / "slow-plan",
        "#!/bin/sh\ntouch \"$(dirname \"$0\")/plan-started\"\n"
        "while [ ! -e \"$(dirname \"$0\")/release\" ]; do sleep 0.05; done\nexec ausbau-plan \"$@\"\n");
  fs::permissions(dir / "slow-plan", fs::perms::owner_all);
  const std::string make = "make --no-print-directory -f '" + (testing::SourceDir() / "pipelines/plan.mk").string() +
                           "' BIN='" + testing::BinDir().string() + "' SCENE=scene.yaml OUT=out TIME_LIMIT=20 ";
  const Outcome both = Shell(dir,
                             // The first in the background, stopped in its plan stage.
                             make +
                                 "PLAN=./slow-plan > first.log 2>&1 & first=$!\n"
                                 "while [ ! -e plan-started ]; do sleep 0.05; done\n" +
                                 make +
                                 "> second.log 2>&1; echo \"second: $?\"\n"
                                 "touch release; wait $first; echo \"first: $?\"\n");
  EXPECT_NE(both.output.find("second: 2"), std::string::npos) << both.output << Read(dir / "second.log");
  EXPECT_TRUE(std::regex_search(Read(dir / "second.log"), std::regex("OUT out is in use by pid [0-9]+")))
      << Read(dir / "second.log");
  EXPECT_NE(both.output.find("first: 0"), std::string::npos) << both.output << Read(dir / "first.log");
  EXPECT_TRUE(fs::exists(dir / "out/path-smooth.csv"));
}

// kill -9 in the middle of a stage, then the same command again: nothing the
// killed run left is trusted (a half-written output under the output's name
// is recomputed, not reused), its temporary files go, and the rerun writes
// the same bytes as an undisturbed run.
TEST(Faults, KillNineThenResumeGivesTheSameOutput) {
  const fs::path dir = FaultDir("kill");
  ASSERT_FALSE(dir.empty());
  const std::string voxelize = "ausbau-voxelize --scene scene.yaml --voxel-budget 3000000 --threads 1 -o v.h5";
  ASSERT_EQ(Shell(dir, voxelize + " && mv v.h5 clean.h5").exit_code, 0);
  // Killed once its grids are sized (it is then voxelizing).
  const Outcome killed = Shell(dir, voxelize +
                                        " > log 2>&1 & pid=$!\n"
                                        "until grep -q 'voxel size' log || ! kill -0 $pid 2>/dev/null; do "
                                        "sleep 0.02; done\nkill -9 $pid; wait $pid; echo \"status $?\"\n");
  EXPECT_NE(killed.output.find("status 137"), std::string::npos) << killed.output << Read(dir / "log");
  EXPECT_FALSE(fs::exists(dir / "v.h5"));
  // What a kill during the write (without the atomic rename) would leave:
  // half the file under its name, and a temporary file of a dead writer.
  Write(dir / "v.h5", Read(dir / "clean.h5").substr(0, Read(dir / "clean.h5").size() / 2));
  Write(dir / "v.h5.tmp-999999999-0", "half");
  const Outcome resumed = Shell(dir, voxelize);
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(resumed.output.find("up to date"), std::string::npos) << resumed.output;
  // The same provenance and the same voxels as the undisturbed run.
  EXPECT_EQ(ArtifactReader(dir / "v.h5", kVoxelsSchema, kVoxelsSchemaVersion).provenance_hash(),
            ArtifactReader(dir / "clean.h5", kVoxelsSchema, kVoxelsSchemaVersion).provenance_hash());
  const SceneVoxels resumed_voxels = ReadVoxelArtifact(dir / "v.h5"),
                    clean_voxels = ReadVoxelArtifact(dir / "clean.h5");
  EXPECT_TRUE(resumed_voxels.static_grid.cells == clean_voxels.static_grid.cells);
  EXPECT_TRUE(resumed_voxels.dynamic_grid.cells == clean_voxels.dynamic_grid.cells);
  EXPECT_TRUE(TemporaryFiles(dir).empty());
  // And now it is up to date.
  EXPECT_NE(Shell(dir, voxelize).output.find("up to date"), std::string::npos);
}

// An input changed while the stage runs: the output is not left as up to
// date for the new input (it is removed, exit 2 naming the file), and the
// next run computes it for the new content.
TEST(Faults, InputChangedWhileTheStageRuns) {
  const fs::path dir = FaultDir("changed");
  ASSERT_FALSE(dir.empty());
  const std::string voxelize = "ausbau-voxelize --scene scene.yaml --voxel-budget 3000000 --threads 1 -o v.h5";
  const Outcome changed = Shell(dir, voxelize +
                                         " > log 2>&1 & pid=$!\n"
                                         "until grep -q 'voxel size' log || ! kill -0 $pid 2>/dev/null; do "
                                         "sleep 0.02; done\necho '# edited' >> part.obj\n"
                                         "wait $pid; echo \"status $?\"; cat log\n");
  EXPECT_NE(changed.output.find("status 2"), std::string::npos) << changed.output;
  EXPECT_TRUE(std::regex_search(changed.output, std::regex("part\\.obj: changed while ausbau-voxelize ran")))
      << changed.output;
  EXPECT_FALSE(fs::exists(dir / "v.h5"));
  const Outcome again = Shell(dir, voxelize);
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(again.output.find("up to date"), std::string::npos) << again.output;
}

}  // namespace
}  // namespace ausbau
