// Logging to stderr (stdout is kept for machine-readable output) and a
// progress reporter that draws a bar on a terminal and prints a line every
// 10% otherwise. Library code may log; it never exits.
#pragma once

#include <cstdarg>
#include <chrono>
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
// it into a Progress below.
using ProgressCallback = std::function<void(std::int64_t done, std::int64_t total)>;

// Reports progress of one phase of known size: on a terminal a bar with the
// elapsed time and an estimate of the time left, in a log a line every 10%
// with the same figures. Thread-compatible: call Update from one thread.
class Progress {
 public:
  Progress(std::string phase, std::int64_t total);
  ~Progress();
  void Update(std::int64_t done);
  void Finish();

 private:
  std::string phase_;
  std::int64_t total_;
  int last_decile_ = -1;
  int last_percent_ = -1;
  bool tty_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace ausbau
