// cli/stage.h: the stage runner in process. A made-up stage with one option
// in the cache key (--size) and one not (--note) parses an argv; --validate
// prints the resolved options and the provenance hash and does no work.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "cli/stage.h"
#include "core/error.h"
#include "geometry/primitives.h"
#include "scene/mesh_io.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

constexpr StageSpec kTestStage{
    "ausbau-test-stage", "A stage for the runner's test", SceneHash::kWholeScene, {"out.h5", "ausbau-test-out", 1}, {}};

struct TestOptions {
  double size = 1.0;
  std::string note;
  int threads = 0;
};

// What one run of the made-up stage did: its exit code, stdout, whether the
// work ran, and the options the work saw.
struct Outcome {
  int exit_code = -1;
  std::string out;
  bool worked = false;
  TestOptions seen;
  std::string options_text;
};

class StageRunnerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    SaveObj(MakeBox({-2, -2, -1}, {2, 2, 0}), dir_ / "floor.obj");
    SaveObj(MakeBox({-0.5, -0.5, 0.5}, {0.5, 0.5, 1.5}), dir_ / "cube.obj");
    std::ofstream(dir_ / "scene.yaml") << "format: ausbau-scene/1\nstatic: [floor.obj]\ndynamic: cube.obj\nunits: mm\n";
  }

  Outcome Run(const std::vector<std::string>& flags) {
    std::vector<std::string> words = {"ausbau-test-stage", "--scene", (dir_ / "scene.yaml").string(), "-o",
                                      (dir_ / "out.h5").string()};
    words.insert(words.end(), flags.begin(), flags.end());
    std::vector<char*> argv;
    for (std::string& word : words) argv.push_back(word.data());
    Outcome outcome;
    TestOptions options;
    StageDefinition stage(kTestStage);
    stage.Option("--size", &options.size, "a length", CacheKey::kYes);
    stage.Option("--note", &options.note, "a remark", CacheKey::kNo);
    stage.Threads(&options.threads);
    StageWork work;
    work.compute = [&](const StageRun&) {
      outcome.worked = true;
      outcome.seen = options;
      return static_cast<int>(kExitOk);
    };
    ::testing::internal::CaptureStdout();
    outcome.exit_code = stage.Run(static_cast<int>(argv.size()), argv.data(), work);
    outcome.out = ::testing::internal::GetCapturedStdout();
    outcome.options_text = stage.OptionsText();
    return outcome;
  }

  // The "provenance hash: ..." line of a --validate run.
  static std::string HashLine(const Outcome& outcome) {
    const auto at = outcome.out.find("provenance hash: ");
    if (at == std::string::npos) return "";
    return outcome.out.substr(at, outcome.out.find('\n', at) - at);
  }

  testing::ScopedTempDir dir_{"stage_runner"};
};

TEST_F(StageRunnerTest, ValidatePrintsTheResolvedOptionsAndDoesNoWork) {
  const Outcome o = Run({"--size", "2.5", "--note", "first", "--validate"});
  EXPECT_EQ(o.exit_code, kExitOk);
  EXPECT_FALSE(o.worked);
  EXPECT_NE(o.out.find("ausbau-test-stage: the options and inputs are valid\n"), std::string::npos) << o.out;
  // Only --size is in the cache key: not --note, --threads, --scene, -o.
  EXPECT_NE(o.out.find("options (cache key):\nsize: \"2.5\"\ninputs:\n"), std::string::npos) << o.out;
  EXPECT_EQ(o.out.find("first"), std::string::npos) << "--note is not in the cache key: " << o.out;
  EXPECT_NE(o.out.find("out.h5: would be computed"), std::string::npos) << o.out;
  EXPECT_FALSE(HashLine(o).empty()) << o.out;
  EXPECT_EQ(o.options_text, "size: \"2.5\"\n");
}

TEST_F(StageRunnerTest, WithoutValidateTheWorkSeesTheParsedOptions) {
  const Outcome o = Run({"--size", "2.5", "--note", "first"});
  EXPECT_EQ(o.exit_code, kExitOk);
  EXPECT_TRUE(o.worked);
  EXPECT_EQ(o.seen.size, 2.5);
  EXPECT_EQ(o.seen.note, "first");
}

TEST_F(StageRunnerTest, OnlyCacheKeyOptionsChangeTheProvenanceHash) {
  const std::string first = HashLine(Run({"--size", "2.5", "--note", "first", "--validate"}));
  const std::string other_note = HashLine(Run({"--size", "2.5", "--note", "second", "--validate"}));
  const std::string other_size = HashLine(Run({"--size", "3", "--note", "first", "--validate"}));
  ASSERT_FALSE(first.empty());
  EXPECT_EQ(first, other_note);
  EXPECT_NE(first, other_size);
}

TEST_F(StageRunnerTest, AValueThatIsNoNumberIsBadInputAndNoWork) {
  ::testing::internal::CaptureStderr();
  const Outcome o = Run({"--size", "wide"});
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(o.exit_code, kExitBadInput);
  EXPECT_FALSE(o.worked);
  EXPECT_NE(err.find("ausbau-test-stage: error:"), std::string::npos) << err;
  EXPECT_NE(err.find("--size"), std::string::npos) << err;
}

}  // namespace
}  // namespace ausbau
