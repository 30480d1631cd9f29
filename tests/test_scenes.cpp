#include "test_scenes.h"

#include <sys/stat.h>
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

namespace {
bool KeepTestDirs() {
  const char* keep = std::getenv("AUSBAU_KEEP_TEST_DIRS");
  return keep != nullptr && *keep != '\0' && std::string(keep) != "0";
}
}  // namespace

ScopedTempDir::ScopedTempDir(const std::string& prefix) {
  static std::atomic<int> counter{0};
  path_ = std::filesystem::temp_directory_path() /
          ("ausbau-test-" + prefix + "-" + std::to_string(::getpid()) + "-s" + std::to_string(counter++));
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

ScopedTempDir::~ScopedTempDir() {
  if (KeepTestDirs()) return;
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

OutsideOut::OutsideOut(const std::filesystem::path& around, const std::filesystem::path& out)
    : around_(std::filesystem::absolute(around).lexically_normal()),
      out_(std::filesystem::absolute(out).lexically_normal()) {
  before_ = Snapshot();
}

std::map<std::string, std::string> OutsideOut::Snapshot() const {
  namespace fs = std::filesystem;
  std::map<std::string, std::string> entries;
  std::error_code error;
  // The default options do not follow links to folders: a link is listed
  // as itself (its target's name), never entered.
  fs::recursive_directory_iterator it(around_, error), end;
  for (; !error && it != end; it.increment(error)) {
    const fs::path path = it->path().lexically_normal();
    const std::string relative = path.lexically_relative(around_).generic_string();
    const std::string out_relative = out_.lexically_relative(around_).generic_string();
    if (relative == out_relative || relative.rfind(out_relative + "/", 0) == 0) {
      if (relative == out_relative && it->is_directory() && !it->is_symlink()) it.disable_recursion_pending();
      continue;
    }
    struct stat info;
    if (::lstat(path.c_str(), &info) != 0) continue;
    std::string what;
    if (S_ISLNK(info.st_mode)) {
      std::error_code link_error;
      what = "link -> " + fs::read_symlink(path, link_error).string();
    } else if (S_ISDIR(info.st_mode)) {
      what = "folder";
    } else {
      what = (S_ISREG(info.st_mode) ? "file " : "other ") + std::to_string(info.st_size) + " bytes";
    }
    // A folder's time changes with what is made or removed in it (listed
    // anyway); a file's with its content.
    if (!S_ISDIR(info.st_mode)) {
      what += ", modified " + std::to_string(info.st_mtim.tv_sec) + "." + std::to_string(info.st_mtim.tv_nsec);
    }
    entries[relative] = what;
  }
  return entries;
}

std::string OutsideOut::Changes() const {
  const std::map<std::string, std::string> after = Snapshot();
  std::string changes;
  for (const auto& [name, what] : before_) {
    const auto now = after.find(name);
    if (now == after.end()) {
      changes += "removed: " + name + " (" + what + ")\n";
    } else if (now->second != what) {
      changes += "changed: " + name + " (" + what + " -> " + now->second + ")\n";
    }
  }
  for (const auto& [name, what] : after) {
    if (before_.count(name) == 0) changes += "created: " + name + " (" + what + ")\n";
  }
  return changes;
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

std::string ShellQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

CommandOutcome RunInDir(const std::filesystem::path& dir, const std::string& command, int timeout_s) {
  return RunShellCommand("cd " + ShellQuote(dir.string()) + " && PATH=" + ShellQuote(BinDir().string()) +
                         ":\"$PATH\" timeout -s KILL " + std::to_string(timeout_s) + " bash -c " + ShellQuote(command) +
                         " 2>&1");
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
