#include "cli/stage_main.h"

#include <cstdio>
#include <exception>

#include "core/hash.h"
#include "core/log.h"
#include "scene/scene.h"

namespace ausbau {

int ParseStageArguments(const std::string& name, CLI::App& app, int argc, char** argv, const std::string& log_level) {
  try {
    app.parse(argc, argv);
    SetLogLevel(ParseLogLevel(log_level));
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: error: %s (see --help)\n", name.c_str(), e.what());
    return kExitBadInput;
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s: error: %s\n", name.c_str(), e.what());
    return kExitBadInput;
  }
  return -1;
}

int RunWithExitCodes(const std::string& name, const std::function<int()>& work) {
  try {
    return work();
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s: error: %s\n", name.c_str(), e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: internal error: %s\n", name.c_str(), e.what());
    return kExitInternal;
  } catch (...) {
    std::fprintf(stderr, "%s: internal error: unknown exception\n", name.c_str());
    return kExitInternal;
  }
}

int RunStage(const StageInfo& info, int argc, char** argv, const std::function<void(CLI::App&)>& declare,
             const std::function<int()>& run) {
  SetLogProgramName(info.name);
  CLI::App app(info.description, info.name);
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "error, warn, info or debug (stderr)")->capture_default_str();
  app.set_version_flag("--version", std::string(AUSBAU_VERSION));
  // declare() may throw InputError (a bad default): exit 2 like a bad flag.
  const int declared = RunWithExitCodes(info.name, [&] {
    declare(app);
    return -1;
  });
  if (declared >= 0) return declared;
  const int parsed = ParseStageArguments(info.name, app, argc, argv, log_level);
  if (parsed >= 0) return parsed;
  return RunWithExitCodes(info.name, run);
}

void AddSceneInputs(const Scene& scene, Provenance* provenance) {
  provenance->inputs.emplace_back("scene", HashFile(scene.file));
  // Roles must be unique (ArtifactWriter refuses duplicates). One static file
  // keeps the role "static", so caches written before lists of static files
  // stay valid; several are "static[0]", "static[1]", ... (as scene.yaml's
  // errors name them), one role per file so that a change to any of them
  // changes the provenance hash.
  const std::size_t static_count = scene.static_files.size();
  for (std::size_t i = 0; i < static_count; ++i) {
    const std::string role = static_count == 1 ? "static" : "static[" + std::to_string(i) + "]";
    provenance->inputs.emplace_back(role, HashFile(scene.static_files[i]));
  }
  provenance->inputs.emplace_back("dynamic", HashFile(scene.dynamic_file));
}

std::string OptionsYaml(const CLI::App& app, const std::vector<std::string>& excluded) {
  std::string text;
  for (const CLI::Option* option : app.get_options()) {
    const std::string name = option->get_single_name();
    if (name.empty() || name == "help" || name == "version" || name == "log-level") continue;
    if (std::find(excluded.begin(), excluded.end(), name) != excluded.end()) continue;
    std::string value;
    for (const std::string& r : option->results()) value += (value.empty() ? "" : " ") + r;
    if (value.empty()) value = option->get_default_str();
    text += name + ": \"" + value + "\"\n";
  }
  return text;
}

}  // namespace ausbau
