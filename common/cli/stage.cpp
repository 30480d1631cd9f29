#include "cli/stage.h"

#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <thread>

#include "core/format.h"
#include "core/hash.h"
#include "core/log.h"

namespace ausbau {

StageDefinition::StageDefinition(const StageSpec& spec)
    : name_(spec.name), up_to_date_(spec.up_to_date), app_(spec.description, name_), scene_hash_(spec.scene) {
  SetLogProgramName(name_);
  app_.add_option("--log-level", log_level_, "error, warn, info or debug (stderr)")->capture_default_str();
  app_.set_version_flag("--version", std::string(AUSBAU_VERSION));
  app_.add_flag("--validate", validate_,
                "check the options and inputs, print the resolved options and the provenance hash, do no work");
  not_in_cache_key_.insert("validate");
  if (scene_hash_ != SceneHash::kNoScene) {
    app_.add_option("--scene", scene_path_, "scene.yaml")->required();
    not_in_cache_key_.insert("scene");  // its content is hashed instead
  }
  // Every stage takes --force: a stage with an artifact computes even when
  // it is up to date; one without has its own meaning or none (it always
  // computes), so that a pipeline may pass it to any stage.
  app_.add_flag("--force", force_, spec.force ? spec.force : "compute even when the output is up to date");
  not_in_cache_key_.insert("force");
  if (spec.output.file) {
    has_output_ = true;
    output_ = spec.output.file;
    output_schema_ = spec.output.schema;
    output_schema_version_ = spec.output.schema_version;
    app_.add_option("-o,--output", output_, "output artifact (HDF5, schema " + output_schema_ + ")")
        ->capture_default_str();
    outputs_.push_back({"--output", &output_, false});
    not_in_cache_key_.insert("output");
  }
}

std::string StageRun::DynamicMeshHash() const {
  for (const auto& [role, hash] : provenance.inputs) {
    if (role == "dynamic") return hash;
  }
  return std::string();
}

CLI::Option* StageDefinition::InputFile(const std::string& flags, std::string* path, const std::string& role,
                                        const std::string& help) {
  CLI::Option* option = app_.add_option(flags, *path, help);
  not_in_cache_key_.insert(option->get_single_name());  // its content is hashed instead
  inputs_.push_back({"--" + option->get_single_name(), path, role, "", 0});
  NameField(path, option);
  return option;
}

CLI::Option* StageDefinition::InputArtifact(const std::string& flags, std::string* path, const std::string& role,
                                            std::string schema, int schema_version, const std::string& help) {
  CLI::Option* option = InputFile(flags, path, role, help);
  inputs_.back().schema = std::move(schema);
  inputs_.back().schema_version = schema_version;
  return option;
}

void StageDefinition::InputPaths(const std::string& flag, std::function<std::vector<std::string>()> files) {
  input_paths_.emplace_back(flag, std::move(files));
}

CLI::Option* StageDefinition::ExtraOutput(const std::string& flags, std::string* path, const std::string& help) {
  CLI::Option* option = Option(flags, path, help, CacheKey::kNo);
  outputs_.push_back({"--" + option->get_single_name(), path, false});
  return option;
}

CLI::Option* StageDefinition::OutputFolder(const std::string& flags, std::string* path, const std::string& help) {
  CLI::Option* option = Option(flags, path, help, CacheKey::kNo);
  outputs_.push_back({"--" + option->get_single_name(), path, true});
  return option;
}

void StageDefinition::CheckOutputs(const std::vector<std::pair<std::string, std::string>>& more_inputs) const {
  std::vector<std::pair<std::string, std::string>> outputs, inputs;  // (flag or what, file)
  for (const OutputSpec& output : outputs_) {
    if (output.path->empty()) continue;  // not written
    // A folder is no file an input could be, but must not be a file either.
    if (output.folder) {
      RefuseFileAsOutputFolder(output.flag, *output.path);
    } else {
      outputs.emplace_back(output.flag, *output.path);
    }
  }
  if (!scene_path_.empty()) inputs.emplace_back("--scene", scene_path_);
  for (const InputFileSpec& input : inputs_) {
    if (!input.path->empty()) inputs.emplace_back(input.flag, *input.path);
  }
  for (const auto& [flag, files] : input_paths_) {
    for (const std::string& file : files()) inputs.emplace_back(flag, file);
  }
  inputs.insert(inputs.end(), more_inputs.begin(), more_inputs.end());
  RefuseOverwritingInputs(outputs, inputs);
}

void StageRun::RefuseOutputsOver(const std::vector<std::pair<std::string, std::string>>& inputs) const {
  stage.CheckOutputs(inputs);
}

void StageDefinition::Query(const std::string& flags, const std::string& help,
                            std::function<int(const StageRun&)> answer) {
  Flag(flags, &query_, help, CacheKey::kNo);
  answer_query_ = std::move(answer);
}

CLI::Option* StageDefinition::Flag(const std::string& flags, bool* value, const std::string& help, CacheKey key) {
  CLI::Option* option = app_.add_flag(flags, *value, help);
  if (key == CacheKey::kNo) not_in_cache_key_.insert(option->get_single_name());
  NameField(value, option);
  return option;
}

// The flag that wrote to the field, where the error is about the options
// themselves; else the flag of the option's name (the library checks copies
// it made, e.g. with "auto" resolved); else the library's name.
std::string StageDefinition::FlagOf(const OptionError& error) const {
  for (const auto& [field, flag] : flag_of_field_) {
    if (field == error.field()) return flag;
  }
  std::string name = error.field_name();
  std::replace(name.begin(), name.end(), '_', '-');
  for (const CLI::Option* option : app_.get_options()) {
    if (option->get_single_name() == name) return "--" + name;
  }
  return error.field_name();
}

void StageDefinition::NameField(const void* field, const CLI::Option* option) {
  flag_of_field_.emplace_back(field, "--" + option->get_single_name());
}

void StageDefinition::Threads(int* threads) {
  threads_ = threads;
  NameField(threads, app_.add_option("--threads", *threads, "OpenMP threads; 0 = all cores, at most 1024")
                         ->capture_default_str()
                         ->check(ThreadCount()));
  not_in_cache_key_.insert("threads");
}

void StageDefinition::Seed(std::uint64_t* seed, const std::string& help) {
  NameField(seed, app_.add_option("--seed", *seed, help)->capture_default_str()->check(NonNegative()));
}

std::string StageDefinition::OptionsText() const {
  return OptionsYaml(app_, std::vector<std::string>(not_in_cache_key_.begin(), not_in_cache_key_.end()));
}

Provenance StageDefinition::MakeProvenance(const Scene& scene) const {
  Provenance provenance{name_, AUSBAU_VERSION, OptionsText(), {}};
  if (scene_hash_ == SceneHash::kWholeScene) {
    AddSceneInputs(scene, &provenance);
  } else if (scene_hash_ == SceneHash::kDynamicMesh) {
    provenance.inputs.emplace_back("dynamic", DynamicContentHash(scene));
  }
  for (const InputFileSpec& input : inputs_) {
    if (input.path->empty() || input.role.empty()) continue;
    std::error_code error;
    if (!std::filesystem::exists(*input.path, error)) throw InputErrorAt(*input.path, "file not found");
    if (!std::filesystem::is_regular_file(*input.path, error)) throw InputErrorAt(*input.path, "not a regular file");
    if (input.schema.empty()) {
      provenance.inputs.emplace_back(input.role, HashFile(*input.path));
    } else {
      const ArtifactReader reader(*input.path, input.schema, input.schema_version);  // checks the schema
      provenance.inputs.emplace_back(input.role, reader.provenance_hash());
    }
  }
  for (const auto& add : add_inputs_) add(&provenance);
  return provenance;
}

int StageDefinition::PrintValidation(const Provenance& provenance) const {
  // (A stage without an artifact has nothing to be up to date: its work
  // always runs, so the last line is only for those with one.)
  // The options hold file names (the scene's, its meshes'): their control
  // characters are shown, not sent to the terminal.
  std::printf("%s: the options and inputs are valid\n", name_.c_str());
  std::printf("options (cache key):\n%s", TerminalSafeLines(provenance.parameters_yaml).c_str());
  std::printf("inputs:\n");
  for (const auto& [role, hash] : provenance.inputs) std::printf("  %s: %s\n", role.c_str(), hash.c_str());
  std::printf("provenance hash: %s\n", provenance.Hash().c_str());
  if (has_output_) {
    const bool current = ExistingProvenanceHash(output_, output_schema_, output_schema_version_) == provenance.Hash();
    std::printf("output %s: %s\n", TerminalSafe(output_).c_str(), current ? "up to date" : "would be computed");
  }
  return kExitOk;
}

int StageDefinition::RunParsed(const StageWork& work) {
  // (--threads 0 keeps the default ParseStageArguments clamped to the cores.)
  if (threads_ && *threads_ > 0) omp_set_num_threads(*threads_);
  // The outputs against the declared inputs before the scene is read, then
  // also against the mesh files scene.yaml names (--csv onto D's mesh had
  // overwritten it), before any work.
  CheckOutputs({});
  for (const auto& check : option_checks_) check();
  if (validate_) {
    // The inputs that are not hashed (MakeProvenance reads the others): there.
    std::vector<std::string> files;
    for (const InputFileSpec& input : inputs_) files.push_back(*input.path);
    for (const auto& [flag, more] : input_paths_) {
      for (const std::string& file : more()) files.push_back(file);
    }
    for (const std::string& file : files) {
      std::error_code error;
      if (!file.empty() && !std::filesystem::exists(file, error)) throw InputErrorAt(file, "file not found");
    }
  }
  const bool has_scene = scene_hash_ != SceneHash::kNoScene;
  const struct Scene scene = has_scene ? LoadScene(scene_path_) : Scene();
  if (has_scene) {
    std::vector<std::pair<std::string, std::string>> meshes;
    for (std::size_t i = 0; i < scene.static_files.size(); ++i) {
      meshes.emplace_back("scene's static[" + std::to_string(i) + "] mesh", scene.static_files[i].string());
    }
    meshes.emplace_back("scene's dynamic mesh", scene.dynamic_file.string());
    CheckOutputs(meshes);
  }
  const Provenance provenance = MakeProvenance(scene);
  const StageRun run{scene, scene_path_, output_, provenance, *this, force_};
  if (validate_) return PrintValidation(provenance);
  if (query_) return answer_query_(run);
  if (has_output_ && !force_ &&
      ExistingProvenanceHash(output_, output_schema_, output_schema_version_) == provenance.Hash() &&
      !(work.stale && work.stale(run))) {
    LogInfo("%s is up to date (same %s); use --force to %s", output_.c_str(), up_to_date_.inputs, up_to_date_.redo);
    return work.reuse ? work.reuse(run) : kExitOk;
  }
  const int code = work.compute(run);
  CheckInputsUnchanged(scene, provenance);
  return code;
}

void StageDefinition::CheckInputsUnchanged(const Scene& scene, const Provenance& used) const {
  // The provenance was hashed after the inputs were read; hashing them again
  // after the work tells whether one changed while the stage ran. Then the
  // output was made from other bytes than its provenance may claim: it is
  // removed, so that no later run trusts it as up to date.
  const Provenance now = MakeProvenance(scene);
  if (now.Hash() == used.Hash()) return;
  std::string changed = "an input";
  for (std::size_t i = 0; i < now.inputs.size() && i < used.inputs.size(); ++i) {
    if (now.inputs[i] == used.inputs[i]) continue;
    const std::string& role = now.inputs[i].first;
    changed = role;
    if (role == "scene") changed = scene.file.string();
    if (role == "dynamic") changed = scene.dynamic_file.string();
    if (role.rfind("static", 0) == 0 && !scene.static_files.empty()) {
      const std::size_t at = role == "static" ? 0 : std::strtoul(role.c_str() + 7, nullptr, 10);
      if (at < scene.static_files.size()) changed = scene.static_files[at].string();
    }
    for (const InputFileSpec& input : inputs_) {
      if (input.role == role) changed = *input.path;
    }
    break;
  }
  std::error_code ignored;
  if (has_output_) std::filesystem::remove(output_, ignored);
  throw InputErrorAt(changed, "changed while " + name_ + " ran; its output " + (has_output_ ? output_ : "") +
                                  " was removed (run it again)");
}

int StageDefinition::Run(int argc, char** argv, const StageWork& work) {
  const int parsed = ParseStageArguments(name_, app_, argc, argv, log_level_);
  if (parsed >= 0) return parsed;
  return RunWithExitCodes(name_, [&] {
    try {
      return RunParsed(work);
    } catch (const OptionError& e) {
      throw InputError(FlagOf(e) + ": " + e.problem());
    }
  });
}

}  // namespace ausbau
