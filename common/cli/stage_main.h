// What every stage's main shares: the CLI11 app with the common flags
// (--log-level, --version), the try/catch that maps exceptions to the
// documented exit codes, and the one-line error format
//   ausbau-<stage>: error: <what>: <where>
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <sstream>
#include <string>

#include "artifact/artifact.h"
#include "core/error.h"

namespace ausbau {

struct StageInfo {
  std::string name;         // "ausbau-plan"
  std::string description;  // one line for --help
};

// Builds the app, lets `declare` add the tool's options, parses argv and
// calls `run`, whose return value is the exit code. Never throws. For the
// benchmark tools (bench/: ausbau-bench, -check-path, -path-quality), which
// are no stages: every stage is declared to the runner of cli/stage.h.
int RunStage(const StageInfo& info, int argc, char** argv, const std::function<void(CLI::App&)>& declare,
             const std::function<int()>& run);

// Defines a stage executable's main, as BENCHMARK_MAIN() does for Google
// Benchmark, so that no stage repeats it: the last line of each
// stages/<name>/main.cpp, after its namespaces close, e.g.
//   AUSBAU_STAGE_MAIN(kPlanStage, DeclarePlan, Plan, Reuse, CutShort)
// calls RunStageMain(argc, argv, <the arguments>) (cli/stage.h), the names
// looked up in namespace ausbau.
#define AUSBAU_STAGE_MAIN(...)                    \
  int main(int argc, char** argv) {               \
    using namespace ausbau;                       \
    return RunStageMain(argc, argv, __VA_ARGS__); \
  }

// The two halves of every stage's main, shared by RunStage and the
// declarative runner (cli/stage.h): parse argv (returns the exit code for
// --help, --version or a bad flag, or -1 to go on), and run the work,
// mapping exceptions to the documented exit codes (InputError: 2, one line
// "<name>: error: <what>"; anything else: 1, "internal error").
int ParseStageArguments(const std::string& name, CLI::App& app, int argc, char** argv, const std::string& log_level);
int RunWithExitCodes(const std::string& name, const std::function<int()>& work);

// A number in [low, high], with a message that names the range in plain
// numbers ("must lie in 0 .. 1024, got -1"); for flags whose type would
// otherwise wrap (-1 as an unsigned seed) or overflow (1e308 seconds).
inline CLI::Validator Within(double low, double high) {
  return CLI::Validator(
      [low, high](std::string& text) -> std::string {
        double value = 0;
        if (!CLI::detail::lexical_cast(text, value)) return "not a number: " + text;
        if (value >= low && value <= high) return std::string();
        std::ostringstream message;
        message << "must lie in " << low << " .. " << high << ", got " << text;
        return message.str();
      },
      "NUMBER");
}
// --threads of every stage and benchmark: 0 = all cores, at most this many
// (OpenMP crashed inside libgomp on --threads 100000 and took -1 as huge).
inline constexpr int kMaxThreads = 1024;
inline CLI::Validator ThreadCount() { return Within(0, kMaxThreads); }
// --time-limit: seconds, positive and at most a week (1e308 overflowed the
// planners' deadline into an instant "no path").
inline CLI::Validator TimeLimit() { return Within(1e-3, 7 * 24 * 3600.0); }
// --seed (unsigned: "-1" would wrap to 2^64 - 1) and other counts and
// amounts that cannot be negative.
inline CLI::Validator NonNegative() { return Within(0, 1.8e19); }

// A flag that was renamed (one meaning per flag, README "Flags"): hidden
// from --help; given, it is a usage error that names the new flag.
inline void AddRenamedFlag(CLI::App& app, const std::string& old_name, const std::string& new_name) {
  app.add_option_function<std::string>(old_name,
                                       [old_name, new_name](const std::string&) {
                                         throw CLI::ValidationError(
                                             old_name,
                                             "was renamed " + new_name + " (one meaning per flag: README \"Flags\")");
                                       })
      ->group("");
}

// Bounds every stage shares by flag name (one meaning per flag: README
// "Flags"), applied by ParseStageArguments before parsing, so that no main
// can forget them: a finite value for every FLOAT option (NaN and inf are
// never meant), and the ranges below. Each is named in the flag's --help.
//   --memory-limit   GiB, kMinMemoryLimitGiB .. kMaxMemoryLimitGiB (1e30 had
//                    overflowed to "must be > 0")
//   --*-iterations   at most kMaxIterationFlag (10^9 hung); --max-iterations
//                    (a cap itself, 0 = none) only >= 0; --coarse-iterations
//                    also -1 (automatic)
//   --rigid-tolerance mm, >= 0
inline constexpr double kMinMemoryLimitGiB = 1e-3;  // about 1 MiB
inline constexpr double kMaxMemoryLimitGiB = 1e6;   // about 1 PiB
inline constexpr double kMaxIterationFlag = 1e6;
void BoundSharedFlags(CLI::App& app);

// Refuses (InputError, before any work) an output path that would replace an
// input or another output (the same file, also by another spelling or a
// link), or that exists and is not a regular file (core/atomic_file.h:
// CheckOutputTarget); on (flag or what, file) pairs. The stage runner
// (cli/stage.h, StageDefinition::CheckOutputs) calls it with the outputs
// and inputs each stage declared.
void RefuseOverwritingInputs(const std::vector<std::pair<std::string, std::string>>& outputs,
                             const std::vector<std::pair<std::string, std::string>>& inputs);
// An output folder that exists as something else than a folder.
void RefuseFileAsOutputFolder(const std::string& flag, const std::string& folder);

// The provenance text of a set of options: "key: value" lines in a stable
// order, recorded in artifacts and hashed for caching.
std::string OptionsYaml(const CLI::App& app, const std::vector<std::string>& excluded = {});

struct Scene;

// Adds the scene's inputs to a provenance, in this order: the scene.yaml,
// each static mesh file, the dynamic mesh file (content hashes), so that a
// change to any of them invalidates the stage's cached output. Roles:
// "scene", "static" (one static file) or "static[0]", "static[1]", ...
// (several), "dynamic".
void AddSceneInputs(const Scene& scene, Provenance* provenance);

// DynamicContentHash (the role "dynamic") is in scene/scene.h: CheckMadeFrom
// compares it too.

}  // namespace ausbau
