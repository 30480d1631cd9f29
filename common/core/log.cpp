#include "core/log.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "core/error.h"

namespace ausbau {
namespace {

LogLevel g_level = LogLevel::kInfo;
std::string g_program = "ausbau";

void Emit(LogLevel level, const char* tag, const char* format, va_list args) {
  if (level > g_level) return;
  std::fprintf(stderr, "%s: %s", g_program.c_str(), tag);
  std::vfprintf(stderr, format, args);
  std::fputc('\n', stderr);
}

}  // namespace

void SetLogLevel(LogLevel level) { g_level = level; }
LogLevel GetLogLevel() { return g_level; }
void SetLogProgramName(const std::string& name) { g_program = name; }

LogLevel ParseLogLevel(const std::string& text) {
  if (text == "error") return LogLevel::kError;
  if (text == "warn") return LogLevel::kWarn;
  if (text == "info") return LogLevel::kInfo;
  if (text == "debug") return LogLevel::kDebug;
  throw InputError("--log-level: unknown level '" + text + "' (expected error, warn, info or debug)");
}

#define AUSBAU_DEFINE_LOG(Name, level, tag) \
  void Name(const char* format, ...) {      \
    va_list args;                           \
    va_start(args, format);                 \
    Emit(level, tag, format, args);         \
    va_end(args);                           \
  }
AUSBAU_DEFINE_LOG(LogError, LogLevel::kError, "error: ")
AUSBAU_DEFINE_LOG(LogWarn, LogLevel::kWarn, "warning: ")
AUSBAU_DEFINE_LOG(LogInfo, LogLevel::kInfo, "")
AUSBAU_DEFINE_LOG(LogDebug, LogLevel::kDebug, "debug: ")
#undef AUSBAU_DEFINE_LOG

Progress::Progress(std::string phase, std::int64_t total)
    : phase_(std::move(phase)), total_(total > 0 ? total : 1), tty_(isatty(STDERR_FILENO) != 0) {}

Progress::~Progress() { Finish(); }

void Progress::Update(std::int64_t done) {
  if (g_level < LogLevel::kInfo || finished_) return;
  const int percent = static_cast<int>(100 * std::clamp<std::int64_t>(done, 0, total_) / total_);
  if (tty_ ? percent == last_percent_ : percent / 10 == last_decile_) return;
  // Elapsed seconds, and the time left at the rate so far (once there is one).
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  char timing[64];
  if (done > 0 && done < total_) {
    std::snprintf(timing, sizeof timing, "%.1f s, about %.0f s left", elapsed,
                  elapsed * static_cast<double>(total_ - done) / static_cast<double>(done));
  } else {
    std::snprintf(timing, sizeof timing, "%.1f s", elapsed);
  }
  if (tty_) {
    last_percent_ = percent;
    const int width = 30, filled = width * percent / 100;
    std::fprintf(stderr, "\r%s: %s [%.*s%*s] %3d%% %s   ", g_program.c_str(), phase_.c_str(), filled,
                 "##############################", width - filled, "", percent, timing);
    std::fflush(stderr);
  } else {
    last_decile_ = percent / 10;
    std::fprintf(stderr, "%s: %s %d%% (%s)\n", g_program.c_str(), phase_.c_str(), last_decile_ * 10, timing);
  }
}

void Progress::Finish() {
  if (finished_) return;
  finished_ = true;
  if (tty_ && last_percent_ >= 0 && g_level >= LogLevel::kInfo) std::fputc('\n', stderr);
}

}  // namespace ausbau
