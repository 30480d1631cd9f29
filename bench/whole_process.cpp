#include "whole_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

#include "core/error.h"
#include "core/format.h"
#include "planning/path_io.h"

extern char** environ;

namespace ausbau::bench {

namespace fs = std::filesystem;

fs::path OwnBinDir() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  return error ? fs::path(".") : self.parent_path();
}

WholeProcessRun RunAusbauPlan(const fs::path& ausbau_plan, const fs::path& scene, std::uint64_t seed,
                              double time_limit_s, const fs::path& artifact, const fs::path& csv, const fs::path& log,
                              double kill_after_s) {
  WholeProcessRun run;
  std::vector<std::string> args = {
      ausbau_plan.string(),       "--scene", scene.string(),    "--seed", std::to_string(seed), "--time-limit",
      Fmt("%.17g", time_limit_s), "-o",      artifact.string(), "--csv",  csv.string(),         "--force"};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);

  std::error_code ignored;
  fs::remove(artifact, ignored);  // a stale artifact must not pass for this run's
  fs::remove(csv, ignored);
  using Clock = std::chrono::steady_clock;
  const auto begin = Clock::now();
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    throw InputError(ausbau_plan.string() + ": cannot run: " + std::strerror(spawned) + " (build it, or give --bin)");
  }
  int status = 0;
  bool killed = false;
  while (true) {
    const pid_t done = waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) {
      run.failure = std::string("waitpid: ") + std::strerror(errno);
      break;
    }
    const double elapsed = std::chrono::duration<double>(Clock::now() - begin).count();
    if (!killed && elapsed > kill_after_s) {
      kill(pid, SIGKILL);
      killed = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  run.time_s = std::chrono::duration<double>(Clock::now() - begin).count();
  if (killed) {
    run.failure = Fmt("killed after %.0f s (a hang)", kill_after_s);
    return run;
  }
  if (!run.failure.empty()) return run;
  if (WIFSIGNALED(status)) {
    run.failure = Fmt("died of signal %d", WTERMSIG(status));
    return run;
  }
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  // Exit 3 (no path) still writes the artifact, with the search's counts.
  const bool artifact_expected = run.exit_code == 0 || run.exit_code == kExitNoPath;
  if (!artifact_expected) {
    run.failure = Fmt("exit %d (see %s)", run.exit_code, log.string().c_str());
    return run;
  }
  try {
    const PathArtifact path = ReadPathArtifact(artifact);
    run.stats = path.stats;
    if (run.exit_code != 0) {
      run.failure = Fmt("exit %d: no path (see %s)", run.exit_code, log.string().c_str());
    } else if (!path.success) {
      run.failure = "exit 0 but the artifact says unsolved";
    } else {
      run.path = path.waypoints;
      run.solved = true;
    }
  } catch (const std::exception& e) {
    run.failure = Fmt("exit %d; artifact not readable: %s", run.exit_code, e.what());
  }
  return run;
}

}  // namespace ausbau::bench
