// The declarative stage runner: a stage says once what it is (name, output
// schema), what it reads (the scene, input files: hashed into the provenance
// automatically) and which options it has, each marked at its declaration as
// part of the cache key or not. The runner owns what every stage shares:
//   -o/--output   the artifact (schema checked for the cache)
//   --force       compute even when the output is up to date
//   --threads     OpenMP threads (0 = all cores); never part of the cache key
//   --seed        where the stage is random; part of the cache key
//   --validate    parse, check the options and input artifacts, print the
//                 resolved options and the provenance hash, do no work
//   --log-level, --version, --help, and the exit codes (core/error.h)
// and the cache short-circuit: when the output's recorded provenance equals
// this run's, the stage's work is skipped (its `reuse` step runs instead).
//
// A stage's main.cpp then starts with what the stage is, in one constant:
//   constexpr StageSpec kVoxelizeStage{"ausbau-voxelize", "Voxelizes ...", SceneHash::kWholeScene,
//                                      {"voxels.h5", kVoxelsSchema, kVoxelsSchemaVersion}};
// and its main declares the options and runs:
//   StageDefinition stage(kVoxelizeStage);
//   stage.Option("--voxel-size", &options.voxel_size, "voxel edge ...", CacheKey::kYes);
//   stage.Threads(&options.threads);
//   return stage.Run(argc, argv, [&](const StageRun& run) { return Voxelize(run, options); });
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "artifact/artifact.h"
#include "cli/stage_main.h"
#include "scene/scene.h"

namespace ausbau {

// Whether an option takes part in the provenance, so that changing it
// recomputes the output (kYes), or only in how the work is done or what
// else is written (kNo: --csv, --threads, file names already hashed).
enum class CacheKey { kYes, kNo };

// What of the scene (--scene, required) the output depends on.
enum class SceneHash {
  kWholeScene,   // scene.yaml, every static mesh file, D's mesh file
  kDynamicMesh,  // only D's mesh file (e.g. the medial spheres)
};

// What a stage is: its name, its line for --help, the scene it reads and
// the artifact it writes (-o/--output, with the schema the cache check and
// --validate read it by; no output file: the stage writes no artifact,
// only files named by ExtraOutput).
struct StageSpec {
  const char* name;         // "ausbau-plan"
  const char* description;  // one line for --help
  SceneHash scene;
  struct Artifact {
    const char* file = nullptr;  // the default of -o
    const char* schema = nullptr;
    int schema_version = 0;
  } output;
};

// What the runner hands to the stage's work: the loaded scene (and the file
// it came from), the output file and the provenance to record in it.
struct StageRun {
  const Scene& scene;
  const std::string& scene_file;
  const std::string& output;
  const Provenance& provenance;
  // D's mesh content hash as the provenance records it ("" without a scene).
  std::string DynamicMeshHash() const;
};

class StageDefinition {
 public:
  explicit StageDefinition(const StageSpec& spec);

  // A further file the stage writes besides its artifact (--csv, --ply, a
  // profile): never part of the cache key; empty = not written.
  CLI::Option* ExtraOutput(const std::string& flags, std::string* path, const std::string& help);
  // An input file, hashed into the provenance under `role` where given.
  CLI::Option* InputFile(const std::string& flags, std::string* path, const std::string& role, const std::string& help);
  // An input artifact: its schema is checked (also by --validate), and its
  // recorded provenance hash goes into this stage's provenance under `role`
  // (so that an identical recomputation upstream does not invalidate this).
  CLI::Option* InputArtifact(const std::string& flags, std::string* path, const std::string& role, std::string schema,
                             int schema_version, const std::string& help);
  // Any other option, marked as part of the cache key or not.
  template <class T>
  CLI::Option* Option(const std::string& flags, T* value, const std::string& help, CacheKey key) {
    CLI::Option* option = app_.add_option(flags, *value, help)->capture_default_str();
    if (key == CacheKey::kNo) not_in_cache_key_.insert(option->get_single_name());
    NameField(value, option);
    return option;
  }
  CLI::Option* Flag(const std::string& flags, bool* value, const std::string& help, CacheKey key);
  // Inputs that no single option names (e.g. two files in one option),
  // added to the provenance after the declared ones.
  void AddInputs(std::function<void(Provenance*)> add) { add_inputs_.push_back(std::move(add)); }
  // --threads (0 = all cores; applied to OpenMP by the runner).
  void Threads(int* threads);
  // --seed (part of the cache key).
  void Seed(std::uint64_t* seed);

  // Which flag writes `field`, for options added through app() directly:
  // an OptionError thrown by a Check() about that field then names the flag.
  // (Every declaration above does this itself.)
  void NameField(const void* field, const CLI::Option* option);

  // For what the declarations above do not cover (option groups, excludes).
  CLI::App& app() { return app_; }

  // Parses argv and runs the stage: `compute` when the output is missing,
  // out of date or --force; otherwise `reuse` (default: a log line). Their
  // return value is the exit code. Never throws.
  int Run(int argc, char** argv, const std::function<int(const StageRun&)>& compute,
          const std::function<int(const StageRun&)>& reuse = {});

  // The provenance text of the options (for tests and --validate).
  std::string OptionsText() const;

 private:
  struct InputFileSpec {
    std::string* path;
    std::string role;
    std::string schema;  // empty: hashed by content
    int schema_version = 0;
  };
  int RunParsed(const std::function<int(const StageRun&)>& compute, const std::function<int(const StageRun&)>& reuse);
  Provenance MakeProvenance(const Scene& scene) const;
  std::string FlagOf(const OptionError& error) const;
  // After the work: throws InputError (and removes the output) when an input
  // changed while the stage ran.
  void CheckInputsUnchanged(const Scene& scene, const Provenance& used) const;

  std::string name_;
  CLI::App app_;
  std::string log_level_ = "info";
  bool validate_ = false;
  bool force_ = false;
  int* threads_ = nullptr;
  std::string scene_path_;
  SceneHash scene_hash_ = SceneHash::kWholeScene;
  bool has_output_ = false;  // the stage writes an artifact
  std::string output_;
  std::vector<std::string*> extra_outputs_;
  std::string output_schema_;
  int output_schema_version_ = 0;
  std::vector<InputFileSpec> inputs_;
  std::vector<std::function<void(Provenance*)>> add_inputs_;
  std::set<std::string> not_in_cache_key_;
  std::vector<std::pair<const void*, std::string>> flag_of_field_;  // address -> "--flag"
};

}  // namespace ausbau
