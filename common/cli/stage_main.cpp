#include "cli/stage_main.h"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <thread>

#include "core/atomic_file.h"
#include "core/cancel.h"
#include "core/format.h"
#include "core/hash.h"
#include "core/log.h"
#include "core/suggest.h"
#include "scene/scene.h"

namespace ausbau {

namespace {

// A value that CLI11 would convert to a non-finite double ("nan", "inf",
// "1e999"); anything else is left to the option's own conversion.
CLI::Validator FiniteNumber() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0;
        if (!CLI::detail::lexical_cast(text, value) || std::isfinite(value)) return std::string();
        return "must be a finite number, got " + text;
      },
      "FINITE");
}

// Two spellings of one file: the same inode where both exist, else the same
// absolute, normalized path.
bool SameFile(const std::string& a, const std::string& b) {
  std::error_code error;
  if (std::filesystem::exists(a, error) && std::filesystem::exists(b, error)) {
    return std::filesystem::equivalent(a, b, error) && !error;
  }
  const auto normal_a = std::filesystem::weakly_canonical(std::filesystem::absolute(a), error);
  const auto normal_b = std::filesystem::weakly_canonical(std::filesystem::absolute(b), error);
  return !error && normal_a == normal_b;
}

// An unknown flag is named before anything else: CLI11 checks required
// options first, so "ausbau-verdict --bogus" had answered "--scene is
// required". Values that merely start with "-" (numbers) are not flags.
void RefuseUnknownFlags(const CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--") break;
    const bool long_flag = arg.size() > 2 && arg.compare(0, 2, "--") == 0;
    const bool short_flag = arg.size() == 2 && arg[0] == '-' && std::isalpha(static_cast<unsigned char>(arg[1]));
    if (!long_flag && !short_flag) continue;
    const std::string name = arg.substr(0, arg.find('='));
    if (app.get_option_no_throw(name) != nullptr) continue;
    std::vector<std::string> known;
    for (const CLI::Option* option : app.get_options()) {
      for (const std::string& long_name : option->get_lnames()) known.push_back("--" + long_name);
    }
    const std::string closest = long_flag ? ClosestName(name, known) : "";
    throw InputError(name + ": unknown flag (" + (closest.empty() ? "" : "did you mean " + closest + "? ") +
                     "see --help)");
  }
}

}  // namespace

void BoundSharedFlags(CLI::App& app) {
  for (CLI::Option* option : app.get_options()) {
    const std::string name = option->get_single_name();
    if (option->get_type_name().rfind("FLOAT", 0) == 0) option->check(FiniteNumber());
    if (name == "memory-limit") {
      option->check(Within(kMinMemoryLimitGiB, kMaxMemoryLimitGiB));
      option->description(option->get_description() + " (at most 1 PiB)");
    } else if (name == "rigid-tolerance") {
      option->check(Within(0, 1e6));  // mm; a negative one had judged every path invalid
    } else if (name == "max-iterations") {
      // A cap itself (0 = none; --time-limit bounds the run): not negative.
      option->check(Within(0, 1e15));
    } else if (name == "coarse-iterations") {
      // -1: automatic (workflow/plan_scene.cpp, ResolvedPlanner).
      option->check(Within(-1, kMaxIterationFlag));
      option->description(option->get_description() + " (at most 10^6)");
    } else if (name.size() > 11 && name.compare(name.size() - 11, 11, "-iterations") == 0) {
      option->check(Within(0, kMaxIterationFlag));
      option->description(option->get_description() + " (at most 10^6)");
    }
  }
}

void RefuseFileAsOutputFolder(const std::string& flag, const std::string& folder) {
  std::error_code error;
  if (!folder.empty() && std::filesystem::exists(folder, error) && !std::filesystem::is_directory(folder, error)) {
    throw InputErrorAt(folder, flag + ": not a folder (" + flag + " names the output folder; this is a file)");
  }
}

void RefuseOverwritingInputs(const std::vector<std::pair<std::string, std::string>>& outputs,
                             const std::vector<std::pair<std::string, std::string>>& inputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const auto& [flag, file] = outputs[i];
    CheckOutputTarget(file);
    for (const auto& [input_flag, input_file] : inputs) {
      if (SameFile(file, input_file)) {
        throw InputErrorAt(file,
                           flag + " is the same file as the input " + input_flag + "; refusing to overwrite an input");
      }
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (SameFile(file, outputs[j].second)) {
        throw InputErrorAt(file, flag + " and " + outputs[j].first + " name the same file");
      }
    }
  }
}

// The first SIGINT, SIGTERM or SIGHUP raises the cancel flag (core/cancel.h):
// the work stops at its next safe point, writes nothing and exits 130. A
// second one, while that is under way, ends the process at once (the
// default action): temporary files are then left, and the next write of the
// same output removes them (RemoveStaleTemporaries).
extern "C" void OnInterrupt(int signal_number) {
  RequestCancel();
  static const char kLine[] = "\ncancelling at the next safe point (again to stop at once)\n";
  const ssize_t ignored = write(STDERR_FILENO, kLine, sizeof kLine - 1);
  (void)ignored;
  (void)signal_number;
}

void CancelOnInterrupt() {
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction action = {};
    action.sa_handler = OnInterrupt;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND;  // the second signal takes the default action
    sigaction(signal_number, &action, nullptr);
  }
}

namespace {

// OpenMP's default team size, from OMP_NUM_THREADS, clamped to the cores
// (and kMaxThreads) before any parallel region: OMP_NUM_THREADS=100000
// with the default --threads 0 made libgomp crash voxelize and
// medial-spheres (SIGSEGV creating the threads). Fewer than the cores (a
// cluster job's share) stay as they are.
void ClampOpenMpThreads() {
  const int cores = std::min(kMaxThreads, static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  if (omp_get_max_threads() > cores) {
    LogWarn("OpenMP's default of %d threads (OMP_NUM_THREADS) is more than the %d cores: using %d",
            omp_get_max_threads(), cores, cores);
    omp_set_num_threads(cores);
  }
}

}  // namespace

int ParseStageArguments(const std::string& name, CLI::App& app, int argc, char** argv, const std::string& log_level) {
  // Past a file size limit (ulimit -f) a write fails with EFBIG instead of
  // killing the process, so that the writer can remove its temporary file
  // and say which output could not be written.
  std::signal(SIGXFSZ, SIG_IGN);
  CancelOnInterrupt();
  try {
    BoundSharedFlags(app);
    RefuseUnknownFlags(app, argc, argv);
    app.parse(argc, argv);
    SetLogLevel(ParseLogLevel(log_level));
    ClampOpenMpThreads();
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: error: %s (see --help)\n", name.c_str(), TerminalSafe(e.what()).c_str());
    return kExitBadInput;
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s: error: %s\n", name.c_str(), TerminalSafe(e.what()).c_str());
    return kExitBadInput;
  }
  return -1;
}

int RunWithExitCodes(const std::string& name, const std::function<int()>& work) {
  try {
    return work();
  } catch (const Cancelled&) {
    std::fprintf(stderr, "%s: cancelled; no output written (what was there before is unchanged)\n", name.c_str());
    return kExitCancelled;
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s: error: %s\n", name.c_str(), TerminalSafe(e.what()).c_str());
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    // Readers bound their sizes by what the file holds and the stages their
    // grids by --memory-limit; what is left is a machine too small for the
    // inputs: an environment failure (exit 1), said so.
    std::fprintf(stderr,
                 "%s: error: out of memory: the inputs need more memory than this machine has (see the stage's "
                 "--memory-limit or a coarser resolution)\n",
                 name.c_str());
    return kExitInternal;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: internal error: %s\n", name.c_str(), TerminalSafe(e.what()).c_str());
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
  for (const SceneInput& input : SceneInputFiles(scene)) {
    provenance->inputs.emplace_back(input.role, SceneInputHash(scene, input));
  }
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
