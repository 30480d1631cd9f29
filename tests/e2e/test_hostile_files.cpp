// Issue 33: hostile file and folder names, and links around OUT. Each class
// end to end on the real executables and pipelines (the bad names and links
// are made here at run time), asserting the exit code, the message and that
// nothing outside OUT changed (testing::OutsideOut):
//   1. shell code or a space in a name given to a make target, a scene
//      folder's name (make batch, the Snakefile's config)
//   2. links under OUT where the pipeline writes its own files (inistate.mk,
//      batch.mk, the Snakefile, the C++ writers' temporaries)
//   3. links in a run folder that the report would embed
//   4. ausbau-scene-gen into a folder that holds a user's files
//   5. escape sequences in names (terminal), names as folders (ausbau-order)
//   6. unclear outcomes: VALIDITY=auto given, D already clear of S, BUDGET=1e308
// (The classes that fit one stage and one line, a units string with a
// formula or scene-gen over a user's meshes, are in test_bad_input.cpp.)
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "artifact/artifact.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;
using Outcome = testing::CommandOutcome;

// Runs `command` with bash in `dir` (stdout and stderr together), the stages
// first on PATH, killed after `timeout_s` (a hang fails the test, not the suite).
Outcome Shell(const fs::path& dir, const std::string& command, int timeout_s = 120) {
  return testing::RunInDir(dir, command, timeout_s);
}

std::string Quote(const std::string& text) { return testing::ShellQuote(text); }

void Write(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// The two-boxes scene (D starts clear of S, a goal pose on the other side)
// in dir/scene; without its goal, D is removable where it stands.
fs::path TwoBoxes(const fs::path& dir, bool with_goal = true) {
  const Outcome gen = Shell(dir, "ausbau-scene-gen --family two-boxes --seed 1 -o scene --log-level error");
  EXPECT_EQ(gen.exit_code, 0) << gen.output;
  if (!with_goal) {
    std::istringstream in(testing::ReadTextFile(dir / "scene/scene.yaml"));
    std::string line, text;
    while (std::getline(in, line)) {
      if (line.rfind("goal:", 0) != 0) text += line + "\n";
    }
    Write(dir / "scene/scene.yaml", text);
  }
  return dir / "scene/scene.yaml";
}

// make -f pipelines/inistate.mk on `scene` into `out`, rigid-exact unless
// the variables say otherwise, no report.
std::string Pipeline(const fs::path& scene, const std::string& out,
                     const std::string& variables = "VALIDITY=rigid-exact") {
  return "make --no-print-directory -f " + Quote((testing::SourceDir() / "pipelines/inistate.mk").string()) +
         " BIN=" + Quote(testing::BinDir().string()) + " SCENE=" + Quote(scene.string()) + " OUT=" + Quote(out) +
         " WITH_REPORT=0 THREADS=1 TIME_LIMIT=20 " + variables;
}

// The top Makefile's target in the source tree, without its `build`
// prerequisite (make -o build: the stages are built already), BUILD the
// folder of bin/.
std::string TopMake(const std::string& arguments) {
  return "make --no-print-directory -C " + Quote(testing::SourceDir().string()) +
         " -o build BUILD=" + Quote(testing::BinDir().parent_path().string()) + " " + arguments;
}

// No raw control character of an escape sequence (ESC, CSI, BEL) in a
// terminal's text.
bool HasRawControl(const std::string& text) {
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if ((u < 0x20 && c != '\n' && c != '\t') || u == 0x7f) return true;
  }
  return text.find("\xc2\x9b") != std::string::npos;
}

// ---- 1. shell code or a space in a name given to a make target

// The top Makefile passed SCENES, OUT and STEP to the sub-make unquoted:
// `make batch SCENES='s;touch PWNED'` ran touch. Every name now arrives as
// one word, and the pipeline refuses what it cannot pass on (exit 2).
TEST(HostileNames, ShellCodeInATopMakefileVariableNeverRuns) {
  const testing::ScopedTempDir dir("names-top");
  fs::create_directories(dir / "scenes/good");
  const testing::OutsideOut outside(dir.path(), dir / "out");
  // Snakemake keeps its records (.snakemake/) in the folder it runs in:
  // make snakemake runs it in OUT, never in the checkout.
  const bool records_in_checkout = fs::exists(testing::SourceDir() / ".snakemake");
  for (const std::string target : {"batch", "step", "snakemake", "run"}) {
    const std::string variable = target == "step" ? "STEP" : target == "run" ? "SCENE" : "SCENES";
    const Outcome outcome =
        Shell(dir.path(), TopMake(target + " " + variable + "=" +
                                  Quote((dir / "scenes").string() + ";touch " + (dir / "PWNED").string()) +
                                  " OUT=" + Quote((dir / "out").string())));
    EXPECT_NE(outcome.exit_code, 0) << target << ":\n" << outcome.output;
    EXPECT_FALSE(fs::exists(dir / "PWNED")) << target << ":\n" << outcome.output;
    if (target != "snakemake") {  // (snakemake may be missing: refused for that then)
      EXPECT_NE(outcome.output.find(variable + "=" + (dir / "scenes").string() + ";touch"), std::string::npos)
          << outcome.output;
      EXPECT_NE(outcome.output.find("(the name reaches a shell)"), std::string::npos) << outcome.output;
    }
  }
  // OUT with a space: refused as one value, never split into ./o and ./ut
  // (make batch, and make run through ausbau-run).
  for (const std::string& target : {"batch SCENES=" + Quote((dir / "scenes").string()),
                                    "run SCENE=" + Quote((dir / "scenes/good/scene.yaml").string())}) {
    const Outcome spaced = Shell(dir.path(), TopMake(target + " OUT=" + Quote((dir / "o ut").string())));
    EXPECT_EQ(spaced.exit_code, 2) << target << ":\n" << spaced.output;
    EXPECT_NE(spaced.output.find("OUT=" + (dir / "o ut").string() + ": only letters"), std::string::npos)
        << target << ":\n"
        << spaced.output;
  }
  EXPECT_EQ(outside.Changes(), "");
  EXPECT_EQ(fs::exists(testing::SourceDir() / ".snakemake"), records_in_checkout);
}

// A scene folder named like a command (from a data set or a CAD export):
// make batch stops before any recipe, naming it, and nothing is written.
TEST(HostileNames, ShellCodeInAFolderNameStopsTheBatch) {
  const testing::ScopedTempDir dir("names-batch");
  for (const std::string name : {"x$(touch${IFS}PWNED)", "y`touch${IFS}PWNED2`", "good"}) {
    fs::create_directories(dir / "scenes" / name);
    Write(dir / "scenes" / name / "scene.yaml", "format: ausbau-scene/1\n");
  }
  const testing::OutsideOut outside(dir.path(), dir / "out");
  const Outcome outcome = Shell(dir.path(), "make --no-print-directory -f " +
                                                Quote((testing::SourceDir() / "pipelines/batch.mk").string()) +
                                                " SCENES=scenes OUT=out BIN=" + Quote(testing::BinDir().string()));
  EXPECT_EQ(outcome.exit_code, 2) << outcome.output;
  EXPECT_NE(outcome.output.find("would reach a shell"), std::string::npos) << outcome.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
  EXPECT_EQ(outside.Changes(), "");
}

// The Snakefile's checks of its config (SCENES' folder names, OUT, links
// under OUT) are plain Python before its first rule. Where snakemake is not
// installed (tests/snakemake/run.sh, which runs it for real, is skipped),
// that part runs here on its own: python3 with a stand-in for the one
// snakemake module it imports, and the config as `--config` would give it.
void WriteSnakefileStandIn(const fs::path& dir) {
  fs::create_directories(dir / "stand-in/snakemake");
  Write(dir / "stand-in/snakemake/__init__.py", "");
  Write(dir / "stand-in/snakemake/common.py", "class Mode:\n    default = 0\n");
  Write(dir / "snakefile-config.py",
        "import sys, types\n"
        "sys.path.insert(0, 'stand-in')\n"
        "text = open(sys.argv[1]).read().split('\\nwildcard_constraints:')[0]\n"
        "assert '\\nrule ' not in text, 'the config part of the Snakefile now holds a rule'\n"
        "scope = {'workflow': types.SimpleNamespace(basedir=sys.argv[2]),\n"
        "         'config': dict(a.split('=', 1) for a in sys.argv[3:])}\n"
        "exec(compile(text, sys.argv[1], 'exec'), scope)\n"
        "print('accepted:', ' '.join(scope['NAMES']))\n");
}

Outcome SnakefileConfig(const fs::path& dir, const std::string& config) {
  const fs::path snakefile = testing::SourceDir() / "pipelines/Snakefile";
  return Shell(dir, "PYTHONDONTWRITEBYTECODE=1 python3 snakefile-config.py " + Quote(snakefile.string()) + " " +
                        Quote(snakefile.parent_path().string()) + " BIN=" + Quote(testing::BinDir().string()) + " " +
                        config);
}

TEST(HostileNames, SnakefileRefusesShellCodeAndLinksBeforeAnyJob) {
  const testing::ScopedTempDir dir("names-snakefile");
  if (Shell(dir.path(), "python3 -c 'import yaml'").exit_code != 0) GTEST_SKIP() << "python3 with yaml is missing";
  WriteSnakefileStandIn(dir.path());
  fs::create_directories(dir / "scenes");
  TwoBoxes(dir / "scenes");
  fs::create_directories(dir / "bad-scenes");
  fs::copy(dir / "scenes/scene", dir / "bad-scenes/x$(touch${IFS}PWNED)", fs::copy_options::recursive);
  Write(dir / "victim.txt", "the user's\n");
  fs::create_directories(dir / "out/scene/logs");
  fs::create_symlink(dir / "victim.txt", dir / "out/scene/logs/plan.log");
  const testing::OutsideOut outside(dir.path(), dir / "out");

  const Outcome named = SnakefileConfig(dir.path(), "SCENES=bad-scenes OUT=out");
  EXPECT_EQ(named.exit_code, 2) << named.output;
  EXPECT_NE(named.output.find("pipelines/Snakefile: error: SCENES: bad-scenes/x$(touch${IFS}PWNED)/scene.yaml: "
                              "the folder name 'x$(touch${IFS}PWNED)' names the scene's outputs"),
            std::string::npos)
      << named.output;
  const Outcome spaced = SnakefileConfig(dir.path(), Quote("OUT=o ut") + " SCENES=scenes");
  EXPECT_EQ(spaced.exit_code, 2) << spaced.output;
  EXPECT_NE(spaced.output.find("OUT=o ut: only letters"), std::string::npos) << spaced.output;
  const Outcome linked = SnakefileConfig(dir.path(), "SCENES=scenes OUT=out");
  EXPECT_EQ(linked.exit_code, 2) << linked.output;
  EXPECT_NE(linked.output.find("out/scene/logs/plan.log is a symbolic link; the pipeline writes only its own files"),
            std::string::npos)
      << linked.output;
  // With nothing wrong, a huge BUDGET and VALIDITY=auto are taken.
  fs::remove(dir / "out/scene/logs/plan.log");
  const Outcome good = SnakefileConfig(dir.path(), "SCENES=scenes OUT=out BUDGET=1e308 VALIDITY=auto");
  EXPECT_EQ(good.exit_code, 0) << good.output;
  EXPECT_NE(good.output.find("accepted: scene"), std::string::npos) << good.output;
  EXPECT_EQ(outside.Changes(), "");
}

// ---- 2. links under OUT where the pipeline writes its own files

struct LinkedOwnPath {
  std::string name;    // under OUT
  std::string target;  // outside OUT, under the test's folder
  bool folder;
};

// OUT/times, OUT/.ausbau-lock and OUT/.path.csv.tmp as links to files
// outside OUT: the pipeline had deleted *.seconds there, written its pid
// into the lock's target and the CSV into the temporary's. Now: exit 2, one
// line naming the link, and the targets unchanged.
TEST(HostileLinks, OwnPathsUnderOutThatAreLinksAreRefused) {
  const testing::ScopedTempDir dir("links-out");
  const fs::path scene = TwoBoxes(dir.path());
  for (const LinkedOwnPath& link :
       {LinkedOwnPath{"times", "victim-folder", true}, LinkedOwnPath{".ausbau-lock", "victim.txt", false},
        LinkedOwnPath{".path.csv.tmp", "victim.csv", false}, LinkedOwnPath{"path.csv", "victim-path-folder", true}}) {
    SCOPED_TRACE(link.name);
    const fs::path out = dir / ("out-" + link.target);
    fs::create_directories(out);
    if (link.folder) {
      fs::create_directories(dir / link.target);
      Write(dir / link.target / "precious.seconds", "the user's\n");
    } else {
      Write(dir / link.target, "the user's\n");
    }
    fs::create_symlink(dir / link.target, out / link.name);
    const testing::OutsideOut outside(dir.path(), out);
    const Outcome outcome = Shell(dir.path(), Pipeline(scene, out.string()));
    EXPECT_EQ(outcome.exit_code, 2) << outcome.output;
    EXPECT_TRUE(std::regex_search(
        outcome.output, std::regex("pipeline: [^\n]*" + std::regex_replace(link.name, std::regex("\\."), "\\.") +
                                   " is a symbolic link; the pipeline writes only its own "
                                   "files inside OUT")))
        << outcome.output;
    EXPECT_EQ(outside.Changes(), "");
    EXPECT_TRUE(fs::is_symlink(out / link.name)) << "the link itself is left to the user";
    EXPECT_FALSE(fs::exists(out / "verdict.json"));
  }
}

// make demo writes the oracle's answer, oracle.json, by shell redirection:
// a link there is refused, its target never written.
TEST(HostileLinks, DemoRefusesALinkedOracleAnswer) {
  const fs::path oracle = testing::SourceDir() / "../shared/benchmarks/inistate-external/oracle.py";
  if (!fs::exists(oracle) || std::system("/usr/bin/python3 -c 'import numpy' 2>/dev/null") != 0) {
    GTEST_SKIP() << "no oracle (" << oracle << ") or no numpy";
  }
  const testing::ScopedTempDir dir("links-demo");
  const fs::path out = dir / "out";
  fs::create_directories(out);
  Write(dir / "victim.txt", "the user's\n");
  fs::create_symlink(dir / "victim.txt", out / "oracle.json");
  const testing::OutsideOut outside(dir.path(), out);
  const Outcome outcome = Shell(dir.path(), TopMake("demo DEMO_OUT=" + Quote(out.string())));
  EXPECT_EQ(outcome.exit_code, 2) << outcome.output;
  EXPECT_NE(outcome.output.find("oracle.json is a symbolic link"), std::string::npos) << outcome.output;
  EXPECT_EQ(outside.Changes(), "");
  EXPECT_TRUE(fs::is_symlink(out / "oracle.json"));
  EXPECT_TRUE(fs::exists(out / "verdict.json")) << "the demo itself ran";
}

// make batch writes each scene's pipeline.log and pipeline.exit by shell
// redirection, which follows a link: a link there (or as the scene's
// folder) is refused before the scene's pipeline starts.
TEST(HostileLinks, BatchRefusesLinksWhereItWritesItsLogs) {
  const testing::ScopedTempDir dir("links-batch");
  fs::create_directories(dir / "scenes");
  TwoBoxes(dir / "scenes");
  Write(dir / "victim.txt", "the user's\n");
  fs::create_directories(dir / "victim-folder");
  for (const std::string name : {"pipeline.log", "pipeline.exit", ""}) {
    SCOPED_TRACE("OUT/scene/" + name);
    const fs::path out = dir / "out";
    fs::remove_all(out);
    fs::create_directories(out / "scene");
    if (name.empty()) {
      fs::remove(out / "scene");
      fs::create_directory_symlink(dir / "victim-folder", out / "scene");
    } else {
      fs::create_symlink(dir / "victim.txt", out / "scene" / name);
    }
    const testing::OutsideOut outside(dir.path(), out);
    const Outcome outcome =
        Shell(dir.path(),
              "make --no-print-directory -f " + Quote((testing::SourceDir() / "pipelines/batch.mk").string()) +
                  " SCENES=scenes OUT=out VALIDITY=rigid-exact WITH_REPORT=0 BIN=" + Quote(testing::BinDir().string()));
    EXPECT_EQ(outcome.exit_code, 2) << outcome.output;
    EXPECT_NE(outcome.output.find("pipeline: out/scene" + (name.empty() ? "" : "/" + name) +
                                  " is a symbolic link; the pipeline writes only its own files inside OUT"),
              std::string::npos)
        << outcome.output;
    EXPECT_EQ(outside.Changes(), "");
    EXPECT_TRUE(fs::is_empty(dir / "victim-folder"));
  }
}

// The C++ writers create their temporaries with O_EXCL | O_NOFOLLOW: a link
// planted under the next temporary's name is refused, not written through.
TEST(HostileLinks, AtomicWritersNeverWriteThroughALinkedTemporary) {
  const testing::ScopedTempDir dir("links-writers");
  Write(dir / "victim.txt", "the user's\n");
  const testing::OutsideOut outside(dir.path(), dir / "out");
  fs::create_directories(dir / "out");
  // The names the next writes use: TemporaryPathFor counts up per call.
  const fs::path text = dir / "out/verdict.json";
  const std::string probe = TemporaryPathFor(text).string();
  const std::string prefix = probe.substr(0, probe.rfind('-') + 1);
  const long next = std::stol(probe.substr(probe.rfind('-') + 1)) + 1;
  fs::create_symlink(dir / "victim.txt", prefix + std::to_string(next));
  try {
    WriteTextFileAtomically(text, "{}\n");
    ADD_FAILURE() << "wrote through a link at the temporary's name";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot create temporary file"), std::string::npos) << e.what();
  }
  const fs::path artifact = dir / "out/path.h5";
  const std::string artifact_probe = TemporaryPathFor(artifact).string();
  const long artifact_next = std::stol(artifact_probe.substr(artifact_probe.rfind('-') + 1)) + 1;
  fs::create_symlink(dir / "victim.txt",
                     artifact_probe.substr(0, artifact_probe.rfind('-') + 1) + std::to_string(artifact_next));
  EXPECT_THROW(ArtifactWriter(artifact, "ausbau-test", 1, Provenance{"test", "0", "", {}}), std::runtime_error);
  EXPECT_FALSE(fs::exists(text));
  EXPECT_FALSE(fs::exists(artifact));
  EXPECT_EQ(testing::ReadTextFile(dir / "victim.txt"), "the user's\n");
  EXPECT_EQ(outside.Changes(), "");
}

// ---- 3. links in a run folder that the report would embed

// stats.json (which no stage writes any more), verdict.json and path.csv as
// links to a file the user can read: not followed (a warning), and none of
// its bytes in report.html.
TEST(HostileLinks, ReportDoesNotFollowLinksInTheRunFolder) {
  const testing::ScopedTempDir dir("links-report");
  const fs::path scene = TwoBoxes(dir.path());
  Write(dir / "secret.txt", "TOP-SECRET-BYTES\n");
  const Outcome plan = Shell(dir.path(),
                             "ausbau-plan --scene scene/scene.yaml --time-limit 20 -o run/path.h5 "
                             "--log-level error");
  ASSERT_EQ(plan.exit_code, 0) << plan.output;
  for (const char* name : {"stats.json", "verdict.json", "path.csv", "profile.csv"}) {
    fs::create_symlink(dir / "secret.txt", dir / "run" / name);
  }
  const testing::OutsideOut outside(dir.path(), dir / "run");
  const Outcome report = Shell(dir.path(), "ausbau-report --scene scene/scene.yaml --run-dir run -o run/report.html");
  EXPECT_EQ(report.exit_code, 0) << report.output;
  EXPECT_TRUE(std::regex_search(report.output, std::regex("run/verdict\\.json: is a symbolic link; not followed")))
      << report.output;
  const std::string html = testing::ReadTextFile(dir / "run/report.html");
  EXPECT_FALSE(html.empty());
  EXPECT_EQ(html.find("TOP-SECRET"), std::string::npos) << "a linked file's bytes are in the report";
  EXPECT_EQ(html.find("stats.json"), std::string::npos) << "the report still looks for stats.json";
  EXPECT_EQ(outside.Changes(), "");
}

// ---- 4. ausbau-scene-gen into a folder that holds a user's files

TEST(HostileNames, SceneGenDoesNotWriteIntoAUsersFolder) {
  const testing::ScopedTempDir dir("scene-gen");
  fs::create_directories(dir / "mine");
  Write(dir / "mine/part.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");  // the user's, same name as the family's
  const testing::OutsideOut outside(dir.path(), dir / "elsewhere");
  const Outcome refused = Shell(dir.path(), "ausbau-scene-gen --family two-boxes -o mine");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_TRUE(std::regex_search(
      refused.output, std::regex("^ausbau-scene-gen: error: -o mine: the folder is not empty[^\n]*--force[^\n]*\n$")))
      << refused.output;
  EXPECT_EQ(outside.Changes(), "");
  // --force writes into it; an empty folder needs none.
  EXPECT_EQ(Shell(dir.path(), "ausbau-scene-gen --family two-boxes --force -o mine").exit_code, 0);
  EXPECT_TRUE(fs::exists(dir / "mine/scene.yaml"));
  fs::create_directories(dir / "empty");
  EXPECT_EQ(Shell(dir.path(), "ausbau-scene-gen --family two-boxes -o empty").exit_code, 0);
}

// ---- 5. escape sequences in names; names as folders

// A scene file named with an escape sequence (its name is its stem when
// scene.yaml gives none): the summaries show it escaped (\x1b), never raw.
TEST(HostileNames, EscapeSequencesInNamesAreShownEscaped) {
  const testing::ScopedTempDir dir("escape");
  TwoBoxes(dir.path(), /*with_goal=*/false);
  std::istringstream in(testing::ReadTextFile(dir / "scene/scene.yaml"));
  std::string line, text;
  while (std::getline(in, line)) {
    if (line.rfind("name:", 0) != 0) text += line + "\n";
  }
  const std::string evil =
      "evil\x1b]0;title\x07\x1b[2J\xc2\x9b"
      "31m";
  Write(dir / "scene" / (evil + ".yaml"), text);
  const testing::OutsideOut outside(dir.path(), dir / "out");
  const std::string scene = Quote("scene/" + evil + ".yaml");
  const Outcome check = Shell(dir.path(), "ausbau-scene-check --scene " + scene);
  EXPECT_EQ(check.exit_code, 0) << check.output;
  EXPECT_FALSE(HasRawControl(check.output)) << check.output;
  EXPECT_NE(check.output.find("evil\\x1b]0;title\\x07\\x1b[2J\\u009b31m"), std::string::npos) << check.output;
  // The verdict's summary and its log lines.
  const Outcome run = Shell(dir.path(), "ausbau-plan --scene " + scene + " -o out/path.h5 && ausbau-verdict --scene " +
                                            scene + " --path out/path.h5 -o out/verdict.json");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_FALSE(HasRawControl(run.output)) << run.output;
  EXPECT_NE(run.output.find("evil\\x1b]0;title"), std::string::npos) << run.output;
  // The report: the name escaped in the page's text (and as \u001b in its JSON).
  const Outcome report =
      Shell(dir.path(), "ausbau-report --scene " + scene + " --path out/path.h5 -o out/report.html --log-level warn");
  EXPECT_EQ(report.exit_code, 0) << report.output;
  const std::string html = testing::ReadTextFile(dir / "out/report.html");
  EXPECT_EQ(html.find('\x1b'), std::string::npos) << "a raw ESC in report.html";
  EXPECT_NE(html.find("<title>Ausbau report: evil\\x1b]0;title\\x07\\x1b[2J"), std::string::npos);
  // An error line naming such a file.
  const Outcome missing = Shell(dir.path(), "ausbau-scene-check --scene " + Quote("scene/gone\x1b[2J.yaml"));
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_FALSE(HasRawControl(missing.output)) << missing.output;
  EXPECT_NE(missing.output.find("gone\\x1b[2J.yaml"), std::string::npos) << missing.output;
  EXPECT_EQ(outside.Changes(), "");
}

// ausbau-order: a part's name names its folder. '/' and '..' are refused;
// control characters become '_' in the folder (the name itself stays, shown
// escaped); a part file whose name holds one is refused before any round.
TEST(HostileNames, OrderPartNamesMakeSafeFolders) {
  const testing::ScopedTempDir dir("order-names");
  TwoBoxes(dir.path(), /*with_goal=*/false);
  // A clip beside the body (the parts are where their files put them).
  Write(dir / "scene/clip.obj",
        "v 4 -0.5 -0.5\nv 5 -0.5 -0.5\nv 5 0.5 -0.5\nv 4 0.5 -0.5\nv 4 -0.5 0.5\nv 5 -0.5 0.5\nv 5 0.5 0.5\n"
        "v 4 0.5 0.5\nf 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\n"
        "f 3 8 7\nf 4 1 5\nf 4 5 8\n");
  const testing::OutsideOut outside(dir.path(), dir / "order");
  const std::string evil = "clip\x1b[2J";
  const Outcome order = Shell(dir.path(), "ausbau-order --part " + Quote(evil + "=scene/clip.obj") +
                                              " --part body=scene/environment.obj --fixed body --part-budget 20 "
                                              "--output-dir order");
  EXPECT_EQ(order.exit_code, 0) << order.output;
  EXPECT_FALSE(HasRawControl(order.output)) << order.output;
  EXPECT_NE(order.output.find("clip\\x1b[2J"), std::string::npos) << order.output;
  EXPECT_TRUE(fs::exists(dir / "order/round-1/clip_[2J/scene.yaml"));
  EXPECT_EQ(outside.Changes(), "");
  for (const std::string bad : {"../up=scene/part.obj", "a/b=scene/part.obj", "..=scene/part.obj"}) {
    const Outcome refused = Shell(
        dir.path(), "ausbau-order --part " + Quote(bad) + " --part body=scene/environment.obj --output-dir order2");
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_NE(refused.output.find("is empty or not a plain file name"), std::string::npos) << refused.output;
  }
  fs::copy_file(dir / "scene/part.obj", dir / ("scene/" + evil + ".obj"));
  const Outcome file = Shell(dir.path(), "ausbau-order --part " + Quote("scene/" + evil + ".obj") +
                                             " --part body=scene/environment.obj --output-dir order3");
  EXPECT_EQ(file.exit_code, 2) << file.output;
  EXPECT_FALSE(HasRawControl(file.output)) << file.output;
  EXPECT_NE(file.output.find("the file's name holds control characters"), std::string::npos) << file.output;
  EXPECT_FALSE(fs::exists(dir / "order3/round-1"));
}

// ---- 6. unclear outcomes

// VALIDITY=auto given on the command line resolves as the default does
// (it had reached tau-estimate as a mode named "auto").
TEST(UnclearOutcomes, ValidityAutoOnTheCommandLineIsResolved) {
  const testing::ScopedTempDir dir("validity-auto");
  const fs::path scene = TwoBoxes(dir.path());
  const testing::OutsideOut outside(dir.path(), dir / "out");
  const Outcome direct = Shell(dir.path(), Pipeline(scene, "out", "VALIDITY=auto"));
  EXPECT_EQ(direct.exit_code, 0) << direct.output;
  EXPECT_NE(direct.output.find("inistate: VALIDITY=auto: rigid-exact"), std::string::npos) << direct.output;
  EXPECT_EQ(direct.output.find("--validity auto"), std::string::npos) << direct.output;
  // Through the top Makefile's `make run`, as a user gives it.
  const Outcome run =
      Shell(dir.path(), TopMake("run SCENE=" + Quote(scene.string()) + " OUT=" + Quote((dir / "out").string()) +
                                " VALIDITY=auto WITH_REPORT=0"));
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.output.find("--validity auto"), std::string::npos) << run.output;
  EXPECT_NE(testing::ReadTextFile(dir / "out/verdict.json").find("\"validity\": \"rigid-exact\""), std::string::npos);
  EXPECT_EQ(outside.Changes(), "");
}

// A D already clear of S (the default goal met at the installed pose): the
// volume modes' planner returns that one pose as the path; the verdict says
// removable (already separated), exit 0, instead of "claims success with 1
// waypoint(s)" (exit 2).
TEST(UnclearOutcomes, APartAlreadyClearOfItsSurroundingsIsRemovable) {
  const testing::ScopedTempDir dir("already-clear");
  const fs::path scene = TwoBoxes(dir.path(), /*with_goal=*/false);
  // D far from S, in a box that holds both.
  std::string yaml = testing::ReadTextFile(scene);
  yaml = std::regex_replace(yaml, std::regex("t: \\[-3, 0, 0\\]"), "t: [-100, 0, 0]");
  yaml = std::regex_replace(yaml, std::regex("bounds: .*"), "bounds: {min: [-200, -200, -200], max: [200, 200, 200]}");
  Write(scene, yaml);
  const testing::OutsideOut outside(dir.path(), dir / "out");
  const Outcome outcome = Shell(dir.path(),
                                Pipeline(scene, "out",
                                         "VALIDITY=labeled-mliv VOXELIZE_FLAGS='--voxel-budget 20000' "
                                         "LABEL_FLAGS='--max-load-cases 50' DISTFIELD_FLAGS='--field-cells 32'"),
                                300);
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
  EXPECT_NE(outcome.output.find("REMOVABLE"), std::string::npos) << outcome.output;
  EXPECT_NE(outcome.output.find("already separated"), std::string::npos) << outcome.output;
  const std::string verdict = testing::ReadTextFile(dir / "out/verdict.json");
  EXPECT_NE(verdict.find("\"removable\": true"), std::string::npos) << verdict;
  EXPECT_NE(verdict.find("\"already_in_goal\": true"), std::string::npos) << verdict;
  EXPECT_EQ(outside.Changes(), "");
}

// BUDGET=1e308 (or 1e400, no double at all) is as good as none: taken as
// 1e9 s, documented, for the deadlines and the verdict; BUDGET=abc is named.
TEST(UnclearOutcomes, AHugeBudgetIsAcceptedAndABadOneNamed) {
  const testing::ScopedTempDir dir("budget");
  const fs::path scene = TwoBoxes(dir.path());
  const testing::OutsideOut outside(dir.path(), dir / "out");
  for (const char* budget : {"1e308", "1e400"}) {
    const Outcome huge =
        Shell(dir.path(), Pipeline(scene, "out", std::string("VALIDITY=rigid-exact BUDGET=") + budget));
    EXPECT_EQ(huge.exit_code, 0) << budget << ":\n" << huge.output;
    const std::string verdict = testing::ReadTextFile(dir / "out/verdict.json");
    EXPECT_NE(verdict.find("\"budget_seconds\": 1000000000"), std::string::npos) << verdict;
    EXPECT_NE(verdict.find("\"within_budget\": true"), std::string::npos) << verdict;
  }
  const Outcome bad = Shell(dir.path(), Pipeline(scene, "out", "VALIDITY=rigid-exact BUDGET=abc"));
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("BUDGET=abc"), std::string::npos) << bad.output;
  EXPECT_EQ(outside.Changes(), "");
}

}  // namespace
}  // namespace ausbau
