#include "test_scenes.h"

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "fixtures/generators.h"

namespace ausbau::testing {

namespace {

// Every folder MakeTempDir made, removed when the test process ends (a
// `make test` left about a thousand behind). AUSBAU_KEEP_TEST_DIRS=1 keeps
// them, for a look after a failure. Only the process that made them
// removes them (a forked child ends with _exit anyway).
class TempDirs {
 public:
  void Add(const std::filesystem::path& dir) {
    const std::lock_guard<std::mutex> lock(mutex_);
    dirs_.push_back(dir);
  }
  ~TempDirs() {
    const char* keep = std::getenv("AUSBAU_KEEP_TEST_DIRS");
    if ((keep != nullptr && *keep != '\0' && std::string(keep) != "0") || ::getpid() != owner_) return;
    std::error_code ignored;
    for (const auto& dir : dirs_) std::filesystem::remove_all(dir, ignored);
  }

 private:
  std::mutex mutex_;
  std::vector<std::filesystem::path> dirs_;
  pid_t owner_ = ::getpid();
};

TempDirs& MadeTempDirs() {
  static TempDirs dirs;
  return dirs;
}

}  // namespace

std::filesystem::path MakeTempDir(const std::string& prefix) {
  static std::atomic<int> counter{0};
  const auto dir = std::filesystem::temp_directory_path() /
                   ("ausbau-test-" + prefix + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  MadeTempDirs().Add(dir);
  return dir;
}

std::filesystem::path MakeGeneratedScene(const std::string& family, std::uint64_t seed) {
  return GenerateScene(family, seed, MakeTempDir(family));
}

std::filesystem::path SourceDir() {
  const char* dir = std::getenv("AUSBAU_SOURCE_DIR");
  return dir ? std::filesystem::path(dir) : std::filesystem::current_path();
}

std::filesystem::path BinDir() {
  const char* dir = std::getenv("AUSBAU_BIN_DIR");
  return dir ? std::filesystem::path(dir) : std::filesystem::current_path();
}

CommandOutcome RunStageCommand(const std::string& stage, const std::string& arguments, const std::string& environment) {
  return RunShellCommand((environment.empty() ? "" : environment + " ") + (BinDir() / ("ausbau-" + stage)).string() +
                         " " + arguments + " 2>&1");
}

CommandOutcome RunShellCommand(const std::string& command) {
  CommandOutcome outcome;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return outcome;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) outcome.output += buffer;
  const int status = pclose(pipe);
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return outcome;
}

std::string ReadTextFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::filesystem::path OmplScene(const std::string& name) {
  const auto path = SourceDir() / ".." / "shared" / "benchmarks" / "ompl" / (name + ".yaml");
  return std::filesystem::exists(path) ? path : std::filesystem::path();
}

}  // namespace ausbau::testing
