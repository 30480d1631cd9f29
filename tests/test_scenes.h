// Helpers for tests: fresh temporary folders, running the stages, reading
// files back. No layer of common/ (the library ausbau_test_support links
// none), so that a test of core/ stays a test of core/ only; a generated
// scene is in generated_scene.h (links the fixtures).
#pragma once

#include <filesystem>
#include <map>
#include <string>

namespace ausbau::testing {

// A new empty folder under the system's temporary directory, unique per call
// (removed, with what it holds, when the test process ends).
std::filesystem::path MakeTempDir(const std::string& prefix);

// A temporary folder of one test, removed (with what it holds) when the
// object goes out of scope, also when an ASSERT returns early.
// AUSBAU_KEEP_TEST_DIRS=1 keeps it, for a look after a failure.
class ScopedTempDir {
 public:
  explicit ScopedTempDir(const std::string& prefix);
  ~ScopedTempDir();
  ScopedTempDir(const ScopedTempDir&) = delete;
  ScopedTempDir& operator=(const ScopedTempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

// "Nothing outside OUT changed": a snapshot of the folder `around` (all of
// it, recursively, without following links), taken before a stage or a
// pipeline runs and compared after. Per entry: its type, size and
// modification time, and for a symbolic link its target. `out` (the run's
// own folder, inside `around`) and what it holds are left out: the run may
// write there and only there.
class OutsideOut {
 public:
  OutsideOut(const std::filesystem::path& around, const std::filesystem::path& out);
  // What changed outside `out` since the constructor: one line per entry
  // created, removed or changed; empty when nothing did.
  std::string Changes() const;

 private:
  std::map<std::string, std::string> Snapshot() const;
  std::filesystem::path around_, out_;
  std::map<std::string, std::string> before_;
};

// The repository root (AUSBAU_SOURCE_DIR, set by CTest) and the stage
// executables' folder (AUSBAU_BIN_DIR).
std::filesystem::path SourceDir();
std::filesystem::path BinDir();
// The exit code and the output (stdout and stderr together) of a command.
struct CommandOutcome {
  int exit_code = -1;
  std::string output;
};
// Runs a shell command line; its stdout (and what it redirects there) and
// exit status (-1 when it did not exit normally).
CommandOutcome RunShellCommand(const std::string& command);
// A word for bash, whatever it holds ('...', with ' written '\'').
std::string ShellQuote(const std::string& text);
// Runs `command` with bash in `dir`, the stages first on PATH, stdout and
// stderr together; killed after `timeout_s` (exit 137: a hang fails the
// test, not the suite).
CommandOutcome RunInDir(const std::filesystem::path& dir, const std::string& command, int timeout_s);
// Runs `ausbau-<stage> <arguments>` from BinDir(), with `environment`
// ("NAME=value ...", may be empty) in front.
CommandOutcome RunStageCommand(const std::string& stage, const std::string& arguments,
                               const std::string& environment = "");
// A whole file as a string (empty when it cannot be read).
std::string ReadTextFile(const std::filesystem::path& path);

// ../shared/benchmarks/ompl/<name>.yaml next to the repository, or empty.
std::filesystem::path OmplScene(const std::string& name);

}  // namespace ausbau::testing
