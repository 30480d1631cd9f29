#include "inistate_end_to_end.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "fixtures/box_scenes.h"
#include "fixtures/clip_scenes.h"
#include "machine.h"

namespace ausbau::bench {
namespace {

namespace fs = std::filesystem;

enum class Checker { kOracle, kGroundTruth };

struct SceneRun {
  std::string family, name;
  fs::path dir;  // the scene folder (scene.yaml, and boxes.json or ground_truth.yaml)
  Checker checker = Checker::kOracle;
  // Filled by Run.
  bool removable = false;
  std::string result;  // correct | WRONG | not-removable
  double rigid_penetration = std::nan("");
  double seconds = 0;
};

SceneRun MakeRun(const std::string& family, const std::string& name, const fs::path& dir, Checker checker) {
  SceneRun run;
  run.family = family;
  run.name = name;
  run.dir = dir;
  run.checker = checker;
  return run;
}

// Paths go into a shell command between single quotes.
std::string Quoted(const fs::path& path) {
  const std::string text = path.string();
  if (text.find('\'') != std::string::npos) throw InputError("path with a single quote: " + text);
  return "'" + text + "'";
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The value after `"key":` in a JSON text (the first occurrence), as written
// by ausbau-verdict; "" when absent.
std::string JsonValue(const std::string& json, const std::string& key) {
  const std::size_t at = json.find("\"" + key + "\"");
  if (at == std::string::npos) return "";
  std::size_t begin = json.find(':', at);
  if (begin == std::string::npos) return "";
  ++begin;
  while (begin < json.size() && (json[begin] == ' ' || json[begin] == '\n')) ++begin;
  std::size_t end = begin;
  while (end < json.size() && json[end] != ',' && json[end] != '\n' && json[end] != '}') ++end;
  return json.substr(begin, end - begin);
}

void Run(SceneRun& scene, const EndToEndOptions& options) {
  const fs::path run = options.out / "runs" / scene.name;
  fs::remove_all(run);
  fs::create_directories(run.parent_path());
  const fs::path log = run.string() + ".log";
  std::string command = "make --no-print-directory -f " + Quoted(options.pipeline) + " BIN=" + Quoted(options.bin) +
                        " SCENE=" + Quoted(scene.dir / "scene.yaml") + " OUT=" + Quoted(run) + " WITH_REPORT=0";
  if (!options.validity.empty()) command += " VALIDITY=" + Quoted(options.validity);
  command += " > " + Quoted(log) + " 2>&1";
  const auto started = std::chrono::steady_clock::now();
  const int status = std::system(command.c_str());
  scene.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  (void)status;  // exit 3 is "not removable"; the verdict file decides
  const std::string verdict = ReadText(run / "verdict.json");
  scene.removable = JsonValue(verdict, "removable") == "true";
  const std::string depth = JsonValue(verdict, "max_rigid_penetration");
  // Where every solid of D is a fastener (one welded mesh whose installed
  // intersection is not measured, left to the volume model), the exact
  // check had no rigid part to measure: no number.
  const bool rigid_part = JsonValue(verdict, "fastener_shells") != JsonValue(verdict, "shells");
  if (rigid_part && !depth.empty() && depth != "null") scene.rigid_penetration = std::strtod(depth.c_str(), nullptr);
  scene.result = "not-removable";
  if (!scene.removable) return;
  std::string check;
  if (scene.checker == Checker::kOracle) {
    check = Quoted(options.python) + " " + Quoted(options.external / "oracle.py") + " " + Quoted(scene.dir) + " " +
            Quoted(run / "path.csv") + " > " + Quoted(run / "oracle.json") + " 2>&1";
  } else {
    check = Quoted(options.bin / "ausbau-check-path") + " --scene " + Quoted(scene.dir / "scene.yaml") +
            " --ground-truth " + Quoted(scene.dir / "ground_truth.yaml") + " --path " + Quoted(run / "path-smooth.h5") +
            " > " + Quoted(run / "check.txt") + " 2>&1";
  }
  scene.result = std::system(check.c_str()) == 0 ? "correct" : "WRONG";
}

std::string Number(double value, const char* format) {
  if (!std::isfinite(value)) return "";
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

void WriteResults(const fs::path& path, const std::vector<SceneRun>& runs) {
  std::string csv = "family,scene,verdict,checker,result,rigid_penetration,seconds\n";
  for (const SceneRun& r : runs) {
    if (r.result.empty()) continue;
    csv += r.family + "," + r.name + "," + (r.removable ? "removable" : "not-removable") + "," +
           (r.checker == Checker::kOracle ? "oracle" : "truth") + "," + r.result + "," +
           Number(r.rigid_penetration, "%.6g") + "," + Number(r.seconds, "%.1f") + "\n";
  }
  WriteTextFileAtomically(path, csv);
}

double Median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::string Summary(const std::vector<SceneRun>& runs, const EndToEndOptions& options, const MachineInfo& machine) {
  std::ostringstream md;
  md << "# ausbau-inistate-bench --end-to-end\n\n"
     << "Command: `" << options.command << "`  \n"
     << "Machine: " << MachineLine(machine) << "; load at start " << machine.load_start << "  \n"
     << "Date: " << machine.date_utc << "  \n"
     << "Pipeline: `" << options.pipeline.string() << "`, VALIDITY "
     << (options.validity.empty() ? "default" : options.validity) << "; seeds";
  for (int seed : options.seeds) md << " " << seed;
  md << "\n\nCorrect: removable and the checker (oracle.py, or the clip generator's ground truth) accepts "
        "path.csv; WRONG: removable and rejected. Rigid penetration: the deepest the verdict's exact check "
        "measured along path.csv (mm, tolerance 0.05; removable scenes; empty where D had no rigid solid to measure: "
        "one welded mesh, left to the volume model and judged by the ground truth).\n\n"
     << "| family | scenes | correct | wrongly removable | not removable | max rigid penetration | median s | max s "
        "|\n|---|---|---|---|---|---|---|---|\n";
  std::vector<std::string> families;
  for (const SceneRun& r : runs) {
    if (!r.result.empty() && std::find(families.begin(), families.end(), r.family) == families.end()) {
      families.push_back(r.family);
    }
  }
  families.push_back("all");
  for (const std::string& family : families) {
    int scenes = 0, correct = 0, wrong = 0, refused = 0;
    double depth = -std::numeric_limits<double>::infinity();
    std::vector<double> seconds;
    for (const SceneRun& r : runs) {
      if (r.result.empty() || (family != "all" && r.family != family)) continue;
      ++scenes;
      correct += r.result == "correct";
      wrong += r.result == "WRONG";
      refused += r.result == "not-removable";
      if (r.removable && std::isfinite(r.rigid_penetration)) depth = std::max(depth, r.rigid_penetration);
      seconds.push_back(r.seconds);
    }
    if (seconds.empty()) continue;
    md << "| " << family << " | " << scenes << " | " << correct << " | " << wrong << " | " << refused << " | "
       << Number(depth, "%.4f") << " | " << Number(Median(seconds), "%.1f") << " | "
       << Number(*std::max_element(seconds.begin(), seconds.end()), "%.1f") << " |\n";
  }
  md << "\nPer scene: `end-to-end-results.csv`; each run's artifacts and log under `runs/`.\n";
  return md.str();
}

}  // namespace

int RunEndToEnd(const EndToEndOptions& options) {
  if (!fs::is_regular_file(options.pipeline)) {
    throw InputError("--pipeline: " + options.pipeline.string() + " not found (run from the repository root)");
  }
  if (!fs::is_regular_file(options.bin / "ausbau-plan")) {
    throw InputError("--bin: " + options.bin.string() + " holds no ausbau-plan (build first)");
  }
  std::vector<std::string> families = options.families;
  if (families.empty()) {
    families = ClipSceneFamilies();
    for (const auto& f : BoxSceneFamilies()) families.push_back(f);
  }
  for (const std::string& family : families) {
    if (!IsClipSceneFamily(family) && !IsBoxSceneFamily(family)) {
      throw InputError("--families: unknown family '" + family + "' (clips-ds1 .. clips-ds5, panel-*)");
    }
  }
  const bool needs_oracle =
      (options.external_scenes && !options.external.empty()) ||
      std::any_of(families.begin(), families.end(), [](const std::string& f) { return IsBoxSceneFamily(f); });
  if (needs_oracle) {
    if (options.external.empty() || !fs::is_regular_file(options.external / "oracle.py")) {
      throw InputError(
          "--external: the panel-* families and the external set are judged by its oracle.py, not found "
          "in '" +
          options.external.string() + "'");
    }
    const std::string numpy = Quoted(options.python) + " -c 'import numpy' > /dev/null 2>&1";
    if (std::system(numpy.c_str()) != 0) {
      throw InputError("--python: " + options.python + " cannot import numpy (apt-get install python3-numpy)");
    }
  }

  std::vector<SceneRun> runs;
  const fs::path scenes = options.out / "scenes";
  for (const std::string& family : families) {
    for (int seed : options.seeds) {
      if (IsClipSceneFamily(family)) {
        SceneRun r = MakeRun(family, family + "-" + std::to_string(seed),
                             scenes / (family + "-" + std::to_string(seed)), Checker::kGroundTruth);
        if (!fs::exists(r.dir / "scene.yaml")) {
          ClipSceneOptions clip;
          clip.seed = static_cast<std::uint64_t>(seed);
          clip.triangles = 2000;  // the pipeline's scale for a benchmark of many scenes
          GenerateClipScene(family, clip, r.dir);
        }
        runs.push_back(r);
      } else if (IsBoxSceneFamily(family)) {
        // The box soup, coarse and fine, and its moulded twin (D one welded
        // solid, made from the coarse boxes).
        for (const char* variant : {"coarse", "fine", "molded"}) {
          const std::string name = family + "-" + variant + "-" + std::to_string(seed);
          SceneRun r = MakeRun(family + "-" + variant, name, scenes / name, Checker::kOracle);
          if (!fs::exists(r.dir / "scene.yaml")) {
            BoxSceneOptions box;
            box.seed = static_cast<std::uint64_t>(seed);
            box.molded = std::string(variant) == "molded";
            box.tessellation = ParseBoxTessellation(box.molded ? "coarse" : variant);
            box.world = BoxWorld::kRandom;
            GenerateBoxScene(family, box, r.dir);
          }
          runs.push_back(r);
        }
      }
    }
  }
  // The external set's box soups, then their moulded twins.
  for (const char* set : {"scenes", "scenes-molded"}) {
    if (!options.external_scenes || options.external.empty() || !fs::is_directory(options.external / set)) continue;
    const std::string family = std::string(set) == "scenes" ? "external" : "external-molded";
    std::vector<fs::path> dirs;
    for (const auto& entry : fs::directory_iterator(options.external / set)) {
      if (fs::is_regular_file(entry.path() / "scene.yaml")) dirs.push_back(entry.path());
    }
    std::sort(dirs.begin(), dirs.end());
    for (const fs::path& dir : dirs) {
      runs.push_back(MakeRun(family, family + "-" + dir.filename().string(), dir, Checker::kOracle));
    }
  }

  if (runs.empty()) throw InputError("no scene to run (no --families and no external scenes)");
  MachineInfo machine = DescribeMachine();
  int wrong = 0;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    Run(runs[i], options);
    wrong += runs[i].result == "WRONG";
    std::printf("[%zu/%zu] %-40s %-14s %-14s rigid %-10s %7.1f s\n", i + 1, runs.size(), runs[i].name.c_str(),
                runs[i].removable ? "removable" : "not-removable", runs[i].result.c_str(),
                Number(runs[i].rigid_penetration, "%.4f").c_str(), runs[i].seconds);
    std::fflush(stdout);
    WriteResults(options.out / "end-to-end-results.csv", runs);
  }
  const std::string summary = Summary(runs, options, machine);
  WriteTextFileAtomically(options.out / "end-to-end-summary.md", summary);
  std::fputs(summary.c_str(), stdout);
  return wrong == 0 ? 0 : 1;
}

}  // namespace ausbau::bench
