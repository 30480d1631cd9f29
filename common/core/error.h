// Error types shared by every stage and the exit codes they map to.
//
// Library code throws; only the stage runner (cli/stage_main.h) turns an
// exception into a one-line message and an exit code. The codes are part of
// the command-line contract and are documented in README.md.
#pragma once

#include <stdexcept>
#include <string>

namespace ausbau {

enum ExitCode : int {
  kExitOk = 0,           // done
  kExitInternal = 1,     // a bug or an environment failure (disk full, ...)
  kExitBadInput = 2,     // bad input or usage: the message names file and problem
  kExitNoPath = 3,       // the planner found no path within its budget
  kExitCancelled = 130,  // interrupted (SIGINT, SIGTERM, SIGHUP; core/cancel.h): nothing written, as a shell's 128+2
};

// Bad input: a missing or malformed file, a wrong option value, an invalid
// scene. The message reads "<what>: <where> (expected X, got Y)".
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A field of an options struct out of its range, thrown by the structs'
// Check(). It names the option as the library knows it, in words with
// underscores ("range_max": the field, or the option's documented name where
// the field is spelled otherwise), and where the field lives. The stage
// runner says it by the flag that wrote to that address, or by the flag of
// that name ("--range-max: must lie in (0, 1]"); a caller without flags (a
// test, a bench, another library) reads "range_max: must lie in (0, 1]". So
// the library never names a flag that its caller may not have.
class OptionError : public InputError {
 public:
  OptionError(const void* field, const std::string& field_name, const std::string& problem)
      : InputError(field_name + ": " + problem), field_(field), field_name_(field_name), problem_(problem) {}
  const void* field() const { return field_; }
  const std::string& field_name() const { return field_name_; }
  const std::string& problem() const { return problem_; }

 private:
  const void* field_;
  std::string field_name_;
  std::string problem_;
};

// Convenience: InputError("<where>: <what>").
inline InputError InputErrorAt(const std::string& where, const std::string& what) {
  return InputError(where + ": " + what);
}

}  // namespace ausbau
