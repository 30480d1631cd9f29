// End to end from an assembly file to a verdict (issue 32 item 1): the
// generated cover-over-posts assembly (fixtures/assembly_scenes.h) as one
// multi-object OBJ, ausbau-assembly writes a scene per part, a part is
// picked by its name in assembly.json, and the InIState pipeline
// (pipelines/inistate.mk, through make, the real executables) runs on that
// part's scene to ausbau-verdict. The answers are known by construction:
// the cover is clear of everything and comes off upwards; a post stands
// inside the cover (its walls reach to 0.5 above the base, the post is 6
// wide), so it cannot leave while the cover is on.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "fixtures/assembly_scenes.h"
#include "geometry/mesh.h"
#include "scene/mesh_io.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

class AssemblyPipeline : public ::testing::Test {
 protected:
  // The assembly as ausbau-assembly takes it: one file, an object per part.
  static void SetUpTestSuite() {
    dir_ = new testing::ScopedTempDir("assembly-pipeline");
    const AssemblyFileList files = WriteCapPostsAssembly(dir_->path() / "parts");
    std::vector<TriangleMesh> meshes;
    for (const auto& [name, file] : files) meshes.push_back(LoadMesh(file));
    std::vector<ObjPart> parts;
    for (std::size_t i = 0; i < files.size(); ++i) parts.push_back({files[i].first, &meshes[i]});
    SaveObjParts(parts, dir_->path() / "cap-posts.obj");
    split_ = testing::RunStageCommand("assembly", "--assembly " + (dir_->path() / "cap-posts.obj").string() +
                                                      " --units mm -o " + (dir_->path() / "scenes").string() + " 2>&1");
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }

  // The scene of the part named `name`, as assembly.json lists it (its
  // folder name is the assembly's business, not the test's).
  static fs::path SceneOf(const std::string& name) {
    const std::string json = testing::ReadTextFile(dir_->path() / "scenes" / "assembly.json");
    std::smatch match;
    const std::regex entry("\"name\": *\"" + name + "\"[^}]*\"scene\": *\"([^\"]+)\"");
    if (!std::regex_search(json, match, entry)) {
      ADD_FAILURE() << "no part named " << name << " in assembly.json:\n" << json;
      return fs::path();
    }
    return dir_->path() / "scenes" / match[1].str();
  }

  // pipelines/inistate.mk on one scene; returns verdict.json (empty when
  // none was written) and leaves make's output in `log`.
  static std::string RunPipeline(const fs::path& scene, const fs::path& out, const std::string& variables,
                                 std::string* log) {
    const std::string command = "make --no-print-directory -f " +
                                (testing::SourceDir() / "pipelines/inistate.mk").string() +
                                " BIN=" + testing::BinDir().string() + " SCENE=" + scene.string() +
                                " OUT=" + out.string() + " THREADS=1 WITH_REPORT=0 " + variables + " 2>&1";
    const testing::CommandOutcome run = testing::RunInDir(dir_->path(), command, 120);
    *log = run.output;
    return testing::ReadTextFile(out / "verdict.json");
  }

  static testing::ScopedTempDir* dir_;
  static testing::CommandOutcome split_;
};

testing::ScopedTempDir* AssemblyPipeline::dir_ = nullptr;
testing::CommandOutcome AssemblyPipeline::split_;

const std::regex kRemovable("\"removable\": *true");
const std::regex kNotRemovable("\"removable\": *false");

TEST_F(AssemblyPipeline, EveryPartGetsAScene) {
  ASSERT_EQ(split_.exit_code, 0) << split_.output;
  for (const char* name : {"base", "post-a", "post-b", "cover"}) {
    const fs::path scene = SceneOf(name);
    EXPECT_TRUE(fs::is_regular_file(scene)) << name << ": " << scene;
  }
}

// The cover, under --validity collision with the FARR distance fields: the
// chain distfield-build -> plan -> smooth -> verdict. Removable.
TEST_F(AssemblyPipeline, TheCoverComesOff) {
  ASSERT_EQ(split_.exit_code, 0) << split_.output;
  const fs::path scene = SceneOf("cover");
  ASSERT_FALSE(scene.empty());
  std::string log;
  const std::string verdict =
      RunPipeline(scene, dir_->path() / "run-cover",
                  "VALIDITY=collision COLLISION=farr TIME_LIMIT=20 DISTFIELD_FLAGS='--field-cells 32'", &log);
  ASSERT_FALSE(verdict.empty()) << log;
  EXPECT_TRUE(std::regex_search(verdict, kRemovable)) << verdict << "\n" << log;
  EXPECT_TRUE(fs::is_regular_file(dir_->path() / "run-cover" / "distfield-static.h5")) << log;
  EXPECT_TRUE(fs::is_regular_file(dir_->path() / "run-cover" / "path.csv")) << log;
}

// A post under the cover, with the pipeline's own choice (VALIDITY=auto:
// rigid-exact, plan -> smooth -> verdict) and a short time limit: no path,
// and the verdict says not removable and names the cover among what
// blocks it. make fails (the pipeline's exit 3).
TEST_F(AssemblyPipeline, APostUnderTheCoverStays) {
  ASSERT_EQ(split_.exit_code, 0) << split_.output;
  const fs::path scene = SceneOf("post-a");
  ASSERT_FALSE(scene.empty());
  std::string log;
  const std::string verdict = RunPipeline(scene, dir_->path() / "run-post-a", "TIME_LIMIT=3", &log);
  ASSERT_FALSE(verdict.empty()) << log;
  EXPECT_TRUE(std::regex_search(verdict, kNotRemovable)) << verdict << "\n" << log;
  EXPECT_TRUE(std::regex_search(verdict, std::regex(R"("blocked_by"[\s\S]*"part": *"cover")"))) << verdict;
  EXPECT_NE(log.find("not removable"), std::string::npos) << log;
}

}  // namespace
}  // namespace ausbau
