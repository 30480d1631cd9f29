// Logging to stderr (stdout is kept for machine-readable output) and a
// progress reporter that draws a bar on a terminal and prints a line every
// 10% otherwise. Library code may log; it never exits.
#pragma once

#include <cstdarg>
#include <cstdint>
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

// Reports progress of one phase of known size. Thread-compatible: call
// Update from one thread.
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
};

}  // namespace ausbau
