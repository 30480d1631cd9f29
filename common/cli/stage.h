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
// Every stage is declared this way, also those that read no scene or write
// no artifact (SceneHash::kNoScene, no output file: always computed).
//
// A stage's main.cpp then says what the stage is, in one constant:
//   constexpr StageSpec kVoxelizeStage{"ausbau-voxelize", "Voxelizes ...", SceneHash::kWholeScene,
//                                      {"voxels.h5", kVoxelsSchema, kVoxelsSchemaVersion}};
// one function that declares its options into its options struct, one that
// does the work (and, where an up-to-date output still needs something, one
// for that), and a main that hands them to the runner:
//   void DeclareVoxelize(StageDefinition& stage, VoxelizeStageOptions* options) {
//     stage.Option("--voxel-size", &options->voxelize.voxel_size, "voxel edge ...", CacheKey::kYes);
//     stage.Threads(&options->threads);
//   }
//   int Voxelize(const StageRun& run, const VoxelizeStageOptions& options) { ... }
//   int main(int argc, char** argv) {
//     return ausbau::RunStageMain(argc, argv, ausbau::kVoxelizeStage, ausbau::DeclareVoxelize, ausbau::Voxelize);
//   }
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "artifact/artifact.h"
#include "cli/stage_main.h"
#include "core/log.h"
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
  kNoScene,      // the stage reads no scene.yaml (no --scene; StageRun::scene is empty)
};

// What a stage is: its name, its line for --help, the scene it reads and
// the artifact it writes (-o/--output, with the schema the cache check and
// --validate read it by; no output file: the stage writes no artifact,
// only files named by ExtraOutput or into an OutputFolder, and cannot be
// up to date: it always computes).
struct StageSpec {
  const char* name;         // "ausbau-plan"
  const char* description;  // one line for --help
  SceneHash scene;
  struct Artifact {
    const char* file = nullptr;  // the default of -o
    const char* schema = nullptr;
    int schema_version = 0;
  } output;
  // The runner's line for an output that is up to date (its work skipped):
  //   "<output> is up to date (same <inputs>); use --force to <redo>"
  struct UpToDate {
    const char* inputs = "inputs and options";
    const char* redo = "compute again";
  } up_to_date;
  // --force's line for --help where it means more than "compute even when
  // the output is up to date" (StageRun::force; ausbau-scene-gen: replace
  // a scene); null: that line.
  const char* force = nullptr;
};

// What the runner hands to the stage's work: the loaded scene (and the file
// it came from), the output file and the provenance to record in it.
class StageDefinition;

struct StageRun {
  const Scene& scene;
  const std::string& scene_file;
  const std::string& output;
  const Provenance& provenance;
  const StageDefinition& stage;
  bool force;  // --force was given (a stage without an artifact: its own meaning, StageSpec::force)
  // D's mesh content hash as the provenance records it ("" without a scene).
  std::string DynamicMeshHash() const;
  // Refuses (InputError, before the work writes anything) an output of the
  // stage that is one of these inputs (what, file): inputs that only the
  // work finds (ausbau-scene-import: the meshes its .cfg names).
  void RefuseOutputsOver(const std::vector<std::pair<std::string, std::string>>& inputs) const;
};

// What a stage does with a run (StageDefinition::Run); each returns the exit
// code.
struct StageWork {
  // The work: the output is missing, out of date, or --force was given.
  std::function<int(const StageRun&)> compute;
  // The output is up to date: after the runner's line saying so, what such
  // an output still needs (its extra files written again) and its exit code.
  // Empty: nothing more, exit 0.
  std::function<int(const StageRun&)> reuse;
  // Whether an up-to-date output is no answer after all and is computed
  // again (ausbau-plan: a search that its time budget cut short). Empty: never.
  std::function<bool(const StageRun&)> stale;
};

class StageDefinition {
 public:
  explicit StageDefinition(const StageSpec& spec);

  // The files a stage reads and writes are declared as such (not as plain
  // options), so that the runner knows them: before any work it refuses an
  // output that would replace an input (also by another spelling or a link),
  // two outputs that name the same file, and an output that exists and is
  // not a regular file (core/atomic_file.h: CheckOutputTarget). The scene's
  // files (--scene and the meshes it names) are inputs too.
  //
  // A further file the stage writes besides its artifact (--csv, --ply, a
  // profile): never part of the cache key; empty = not written.
  CLI::Option* ExtraOutput(const std::string& flags, std::string* path, const std::string& help);
  // A folder the stage writes into (ausbau-scene-gen -o): never part of the
  // cache key; refused where it names a file.
  CLI::Option* OutputFolder(const std::string& flags, std::string* path, const std::string& help);
  // An input file, hashed by content into the provenance under `role`; an
  // empty role: not hashed, only kept from being overwritten (a file the
  // work reads and records itself: ausbau-verdict --csv-name).
  CLI::Option* InputFile(const std::string& flags, std::string* path, const std::string& role, const std::string& help);
  // Input files that an option declared otherwise names (two in one value:
  // --distfield S.h5,D.h5), for the overwrite check only; `files` runs after
  // parsing. Hash them with AddInputs where they are part of the provenance.
  void InputPaths(const std::string& flag, std::function<std::vector<std::string>()> files);
  // An input artifact: its schema is checked (also by --validate), and its
  // recorded provenance hash goes into this stage's provenance under `role`
  // (so that an identical recomputation upstream does not invalidate this).
  CLI::Option* InputArtifact(const std::string& flags, std::string* path, const std::string& role, std::string schema,
                             int schema_version, const std::string& help);
  // A flag that asks the stage a question about the scene instead of doing
  // its work (ausbau-plan --choose-validity): given, `answer` runs once the
  // scene is loaded, in place of the work and the cache (never in the cache
  // key). One per stage.
  void Query(const std::string& flags, const std::string& help, std::function<int(const StageRun&)> answer);
  // Any other option, marked as part of the cache key or not.
  template <class T>
  CLI::Option* Option(const std::string& flags, T* value, const std::string& help, CacheKey key) {
    CLI::Option* option = app_.add_option(flags, *value, help)->capture_default_str();
    if (key == CacheKey::kNo) not_in_cache_key_.insert(option->get_single_name());
    NameField(value, option);
    return option;
  }
  CLI::Option* Flag(const std::string& flags, bool* value, const std::string& help, CacheKey key);
  // A mode: one of `names` (a wrong one is the usual one-line usage error
  // listing them), stored as the enum `parse` makes of it. The provenance
  // and --help keep its spelling, `name` of the default where not given.
  template <class Enum>
  CLI::Option* Choice(const std::string& flags, Enum* value, const std::vector<std::string>& names,
                      Enum (*parse)(const std::string&), std::string (*name)(Enum), const std::string& help,
                      CacheKey key) {
    CLI::Option* option = app_.add_option_function<std::string>(
                                  flags, [value, parse](const std::string& text) { *value = parse(text); }, help)
                              ->default_str(name(*value))
                              ->check(CLI::IsMember(names));
    if (key == CacheKey::kNo) not_in_cache_key_.insert(option->get_single_name());
    NameField(value, option);
    return option;
  }
  // Inputs that no single option names (e.g. two files in one option),
  // added to the provenance after the declared ones.
  void AddInputs(std::function<void(Provenance*)> add) { add_inputs_.push_back(std::move(add)); }
  // --threads (0 = all cores; applied to OpenMP by the runner).
  void Threads(int* threads);
  // --seed (part of the cache key).
  void Seed(std::uint64_t* seed, const std::string& help = "random seed");
  // A check of options together (flags that exclude each other, flags that
  // apply only to some modes), after parsing and before the scene is read:
  // --validate refuses what the work would. Throws InputError.
  void CheckOptions(std::function<void()> check) { option_checks_.push_back(std::move(check)); }

  // Which flag writes `field`, for options added through app() directly:
  // an OptionError thrown by a Check() about that field then names the flag.
  // (Every declaration above does this itself.)
  void NameField(const void* field, const CLI::Option* option);

  // For what the declarations above do not cover (option groups, excludes).
  CLI::App& app() { return app_; }

  // Parses argv and runs the stage (see StageWork). Never throws.
  int Run(int argc, char** argv, const StageWork& work);

  // The provenance text of the options (for tests and --validate).
  std::string OptionsText() const;

  // The overwrite check above, of the declared outputs against the declared
  // inputs and `more_inputs` (what, file). Throws InputError.
  void CheckOutputs(const std::vector<std::pair<std::string, std::string>>& more_inputs) const;

 private:
  struct InputFileSpec {
    std::string flag;  // "--path"
    std::string* path;
    std::string role;    // empty: not hashed
    std::string schema;  // empty: hashed by content
    int schema_version = 0;
  };
  struct OutputSpec {
    std::string flag;  // "--csv"
    std::string* path;
    bool folder = false;
  };
  int RunParsed(const StageWork& work);
  // --validate: prints the resolved options, the inputs and whether the
  // output is up to date.
  int PrintValidation(const Provenance& provenance) const;
  Provenance MakeProvenance(const Scene& scene) const;
  std::string FlagOf(const OptionError& error) const;
  // After the work: throws InputError (and removes the output) when an input
  // changed while the stage ran.
  void CheckInputsUnchanged(const Scene& scene, const Provenance& used) const;

  std::string name_;
  StageSpec::UpToDate up_to_date_;
  CLI::App app_;
  std::string log_level_ = "info";
  bool validate_ = false;
  bool force_ = false;
  bool query_ = false;  // the Query flag was given
  std::function<int(const StageRun&)> answer_query_;
  int* threads_ = nullptr;
  std::string scene_path_;
  SceneHash scene_hash_ = SceneHash::kWholeScene;
  bool has_output_ = false;  // the stage writes an artifact
  std::string output_;
  std::vector<OutputSpec> outputs_;  // -o (where the stage writes an artifact) first
  std::string output_schema_;
  int output_schema_version_ = 0;
  std::vector<InputFileSpec> inputs_;
  std::vector<std::pair<std::string, std::function<std::vector<std::string>()>>> input_paths_;  // InputPaths
  std::vector<std::function<void(Provenance*)>> add_inputs_;
  std::vector<std::function<void()>> option_checks_;
  std::set<std::string> not_in_cache_key_;
  std::vector<std::pair<const void*, std::string>> flag_of_field_;  // address -> "--flag"
};

// Builds the stage's definition, lets `declare` fill a default-constructed
// `Options`, and runs the StageWork that `work` makes for those options.
template <class Options, class MakeWork>
int RunDeclaredStage(int argc, char** argv, const StageSpec& spec, void (*declare)(StageDefinition&, Options*),
                     const MakeWork& work) {
  Options options;
  StageDefinition stage(spec);
  declare(stage, &options);
  return stage.Run(argc, argv, work(options));
}

// A stage's whole main: its spec, the function that declares its options
// into a default-constructed `Options`, the work, and optionally what an
// up-to-date output still needs and when it is stale (StageWork).
template <class Options>
int RunStageMain(int argc, char** argv, const StageSpec& spec, void (*declare)(StageDefinition&, Options*),
                 int (*compute)(const StageRun&, const Options&),
                 int (*reuse)(const StageRun&, const Options&) = nullptr,
                 bool (*stale)(const StageRun&, const Options&) = nullptr) {
  return RunDeclaredStage(argc, argv, spec, declare, [&](const Options& options) {
    StageWork work;
    work.compute = [&](const StageRun& run) { return compute(run, options); };
    if (reuse) work.reuse = [&](const StageRun& run) { return reuse(run, options); };
    if (stale) work.stale = [&](const StageRun& run) { return stale(run, options); };
    return work;
  });
}

// An artifact with one entry per vertex of D (Artifact::VertexCount()) and
// two views of it that its stage writes on request, also when the artifact
// is up to date: --csv (x,y,z,value per vertex) and --ply (D coloured by the
// value), each empty when not asked for (ausbau-medial-spheres,
// ausbau-pbd-label). The library's writer, reader and views writer.
template <class Artifact>
struct PerVertexArtifact {
  void (*write)(const std::filesystem::path& file, const Artifact& artifact, const Provenance& provenance);
  Artifact (*read)(const std::filesystem::path& file);
  void (*write_views)(const Scene& scene, const Artifact& artifact, const std::string& csv, const std::string& ply);
};

// The main of a stage whose work is to compute such an artifact (its
// `Options` have the members `csv` and `ply`, declared by ExtraOutput):
// computed, it is written, logged ("wrote <output> (<n> vertices of D)")
// and its views written; up to date, it is read back for its views.
template <class Options, class Artifact>
int RunStageMain(int argc, char** argv, const StageSpec& spec, void (*declare)(StageDefinition&, Options*),
                 Artifact (*compute)(const StageRun&, const Options&), const PerVertexArtifact<Artifact>& artifact) {
  return RunDeclaredStage(argc, argv, spec, declare, [&](const Options& options) {
    StageWork work;
    work.compute = [&](const StageRun& run) {
      const Artifact computed = compute(run, options);
      artifact.write(run.output, computed, run.provenance);
      LogInfo("wrote %s (%zu vertices of D)", run.output.c_str(), computed.VertexCount());
      artifact.write_views(run.scene, computed, options.csv, options.ply);
      return static_cast<int>(kExitOk);
    };
    work.reuse = [&](const StageRun& run) {
      artifact.write_views(run.scene, artifact.read(run.output), options.csv, options.ply);
      return static_cast<int>(kExitOk);
    };
    return work;
  });
}

}  // namespace ausbau
