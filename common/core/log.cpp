#include "core/log.h"

#include <unistd.h>

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <memory>

#include "core/error.h"
#include "core/format.h"

namespace ausbau {
namespace {

LogLevel g_level = LogLevel::kInfo;
std::string g_program = "ausbau";
// A progress bar is drawn on the terminal's last line (no newline yet): a
// log line first clears it, and the bar is drawn again at its next update.
bool g_bar_drawn = false;

// 1234567 -> "1,234,567".
std::string Thousands(std::int64_t n) {
  std::string digits = std::to_string(n < 0 ? -n : n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return n < 0 ? "-" + out : out;
}

void Emit(LogLevel level, const char* tag, const char* format, va_list args) {
  if (level > g_level) return;
  if (g_bar_drawn) {
    std::fputs("\r\033[K", stderr);
    g_bar_drawn = false;
  }
  // The message may hold names from files (parts, meshes, file names):
  // their control characters are shown, not sent to the terminal.
  va_list copy;
  va_copy(copy, args);
  const int length = std::vsnprintf(nullptr, 0, format, copy);
  va_end(copy);
  std::string message(length > 0 ? static_cast<std::size_t>(length) + 1 : 1, '\0');
  if (length > 0) std::vsnprintf(message.data(), message.size(), format, args);
  message.resize(length > 0 ? static_cast<std::size_t>(length) : 0);
  std::fprintf(stderr, "%s: %s%s\n", g_program.c_str(), tag, TerminalSafe(message).c_str());
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

Progress::Progress(std::string phase, std::int64_t total, Left left, double quiet_s)
    : phase_(std::move(phase)),
      total_(total > 0 ? total : 1),
      left_(left),
      tty_(isatty(STDERR_FILENO) != 0),
      quiet_s_(quiet_s >= 0 ? quiet_s
               : tty_       ? 0.5
                            : 2.0) {}

Progress::~Progress() { Finish(); }

void Progress::Update(std::int64_t done, const std::string& detail) {
  if (g_level < LogLevel::kInfo || finished_) return;
  const int percent = static_cast<int>(100 * std::clamp<std::int64_t>(done, 0, total_) / total_);
  // A terminal redraws on each percent and, for the detail (work done), at
  // most 4 times a second; a log gets one line per 10%.
  const auto now = std::chrono::steady_clock::now();
  if (now - start_ < std::chrono::duration<double>(quiet_s_)) return;
  if (tty_) {
    const bool detail_due = !detail.empty() && now - last_draw_ >= std::chrono::milliseconds(250);
    if (percent == last_percent_ && !detail_due && g_bar_drawn) return;
  } else if (percent / 10 == last_decile_) {
    return;
  }
  last_draw_ = now;
  // Elapsed seconds, and the time left (once there is an estimate).
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  char timing[96];
  if (done > 0 && done < total_ && left_ == Left::kAtRate) {
    std::snprintf(timing, sizeof timing, "%.1f s, about %.0f s left", elapsed,
                  elapsed * static_cast<double>(total_ - done) / static_cast<double>(done));
  } else if (done < total_ && left_ == Left::kAtMostBudget) {
    std::snprintf(timing, sizeof timing, "%.1f s, at most %.0f s left", elapsed,
                  std::max(0.0, static_cast<double>(total_ - std::max<std::int64_t>(done, 0)) / 1000.0));
  } else {
    std::snprintf(timing, sizeof timing, "%.1f s", elapsed);
  }
  const std::string tail = detail.empty() ? "" : ", " + detail;
  if (tty_) {
    last_percent_ = percent;
    const int width = 30, filled = width * percent / 100;
    // \033[K clears what a longer previous line left.
    std::fprintf(stderr, "\r%s: %s [%.*s%*s] %3d%% %s%s\033[K", g_program.c_str(), phase_.c_str(), filled,
                 "##############################", width - filled, "", percent, timing, tail.c_str());
    std::fflush(stderr);
    g_bar_drawn = true;
  } else {
    last_decile_ = percent / 10;
    std::fprintf(stderr, "%s: %s %d%% (%s%s)\n", g_program.c_str(), phase_.c_str(), last_decile_ * 10, timing,
                 tail.c_str());
  }
}

void Progress::Finish() {
  if (finished_) return;
  finished_ = true;
  // Only this bar's own line (a quiet one drew nothing).
  if (tty_ && last_percent_ >= 0 && g_bar_drawn) {
    if (g_level >= LogLevel::kInfo) std::fputc('\n', stderr);
    g_bar_drawn = false;
  }
}

ProgressCallback ShowProgress(const std::string& phase) {
  struct State {
    std::unique_ptr<Progress> bar;
    std::int64_t total = -1;
  };
  auto state = std::make_shared<State>();
  return [state, phase](std::int64_t done, std::int64_t total) {
    if (total != state->total || !state->bar) {
      state->bar = std::make_unique<Progress>(phase, total);
      state->total = total;
    }
    state->bar->Update(done);
    if (done >= total) state->bar.reset();  // finished: the next report starts a new bar
  };
}

ProgressCallback ShowSearchProgress(const std::string& phase, double seconds, const std::string& unit) {
  const auto total_ms = static_cast<std::int64_t>(std::min(1e12, std::max(1.0, 1000 * seconds)));
  auto bar = std::make_shared<Progress>(phase, total_ms, Progress::Left::kAtMostBudget);
  const auto begin = std::chrono::steady_clock::now();
  return [bar, begin, unit](std::int64_t done, std::int64_t total) {
    const auto elapsed_ms =
        std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - begin).count();
    std::string detail = Thousands(done) + " " + unit;
    if (total > 0) detail += " of " + Thousands(total);
    bar->Update(elapsed_ms, detail);
  };
}

}  // namespace ausbau
