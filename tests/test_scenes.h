// Helpers for tests: fresh temporary folders and generated scenes.
#pragma once

#include <filesystem>
#include <string>

namespace ausbau::testing {

// A new empty folder under the system's temporary directory, unique per call.
std::filesystem::path MakeTempDir(const std::string& prefix);

// Generates `family` (see fixtures/generators.h) into a fresh folder and
// returns the scene.yaml path.
std::filesystem::path MakeGeneratedScene(const std::string& family, std::uint64_t seed = 1);

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
// Runs `ausbau-<stage> <arguments>` from BinDir(), with `environment`
// ("NAME=value ...", may be empty) in front.
CommandOutcome RunStageCommand(const std::string& stage, const std::string& arguments,
                               const std::string& environment = "");
// A whole file as a string (empty when it cannot be read).
std::string ReadTextFile(const std::filesystem::path& path);

// ../shared/benchmarks/ompl/<name>.yaml next to the repository, or empty.
std::filesystem::path OmplScene(const std::string& name);

}  // namespace ausbau::testing
