// Logging to stderr (stdout is kept for machine-readable output) and a
// progress reporter that draws a bar on a terminal and prints a line every
// 10% otherwise. Library code may log; it never exits.
#pragma once

#include <chrono>
#include <cstdarg>
#include <cstdint>
#include <functional>
#include <string>

namespace ausbau {

enum class LogLevel { kError = 0, kWarn = 1, kInfo = 2, kDebug = 3 };

void SetLogLevel(LogLevel level);
LogLevel GetLogLevel();
// Parses "error|warn|info|debug"; throws InputError otherwise.
LogLevel ParseLogLevel(const std::string& text);
// The program name printed in front of every line ("ausbau-plan").
void SetLogProgramName(const std::string& name);

void LogError(const char* format, ...) __attribute__((format(printf, 1, 2)));
void LogWarn(const char* format, ...) __attribute__((format(printf, 1, 2)));
void LogInfo(const char* format, ...) __attribute__((format(printf, 1, 2)));
void LogDebug(const char* format, ...) __attribute__((format(printf, 1, 2)));

// How long work reports progress, in every layer: a callback with the work
// done and the total (any unit); empty = silent (the tests). A stage turns
// it into a Progress below (ShowProgress). The same work polls for
// cancellation (core/cancel.h).
using ProgressCallback = std::function<void(std::int64_t done, std::int64_t total)>;

// Reports progress of one phase of known size: on a terminal a bar with the
// elapsed time, the work done and an estimate of the time left, in a log a
// line every 10% with the same figures. Thread-compatible: call Update from
// one thread.
class Progress {
 public:
  // How the time left is estimated: at the rate so far (work of known size),
  // or as the rest of a budget (`done` and `total` are then milliseconds of a
  // time limit, which a search may end sooner: "at most N s left").
  enum class Left { kAtRate, kAtMostBudget };
  // Work shorter than `quiet_s` shows nothing (its result line says
  // enough): by default 0.5 s on a terminal, 2 s in a log.
  Progress(std::string phase, std::int64_t total, Left left = Left::kAtRate, double quiet_s = -1);
  ~Progress();
  // `detail` (the work done in words: "12,345 iterations") follows the times.
  void Update(std::int64_t done, const std::string& detail = "");
  void Finish();

 private:
  std::string phase_;
  std::int64_t total_;
  Left left_;
  int last_decile_ = -1;
  int last_percent_ = -1;
  std::chrono::steady_clock::time_point last_draw_{};
  bool tty_;
  double quiet_s_;  // after tty_: its default depends on it
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// A ProgressCallback that shows `phase` as a Progress: a new one whenever the
// total changes (the next step of the same work), finished when done reaches
// the total. For work that reports from one thread at a time.
ProgressCallback ShowProgress(const std::string& phase);

// A ProgressCallback for a search under a time limit of `seconds` (a
// planner, whose callback gets the iterations so far and their limit): the
// bar shows the share of the limit used and "at most N s left" (the search
// may end sooner), the detail the work done in `unit` ("12,345 iterations").
ProgressCallback ShowSearchProgress(const std::string& phase, double seconds, const std::string& unit);

}  // namespace ausbau
