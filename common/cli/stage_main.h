// What every stage's main shares: the CLI11 app with the common flags
// (--log-level, --version), the try/catch that maps exceptions to the
// documented exit codes, and the one-line error format
//   ausbau-<stage>: error: <what>: <where>
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "artifact/artifact.h"
#include "core/error.h"

namespace ausbau {

struct StageInfo {
  std::string name;         // "ausbau-plan"
  std::string description;  // one line for --help
};

// Builds the app, lets `declare` add the stage's options, parses argv and
// calls `run`, whose return value is the exit code. Never throws.
int RunStage(const StageInfo& info, int argc, char** argv, const std::function<void(CLI::App&)>& declare,
             const std::function<int()>& run);

// --threads of every stage and benchmark: 0 = all cores, at most this many
// (OpenMP crashed inside libgomp on --threads 100000 and took -1 as huge).
inline constexpr int kMaxThreads = 1024;
inline CLI::Validator ThreadCount() { return CLI::Range(0, kMaxThreads); }

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

}  // namespace ausbau
