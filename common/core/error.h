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
  kExitOk = 0,        // done
  kExitInternal = 1,  // a bug or an environment failure (disk full, ...)
  kExitBadInput = 2,  // bad input or usage: the message names file and problem
  kExitNoPath = 3,    // the planner found no path within its budget
};

// Bad input: a missing or malformed file, a wrong option value, an invalid
// scene. The message reads "<what>: <where> (expected X, got Y)".
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Convenience: InputError("<where>: <what>").
inline InputError InputErrorAt(const std::string& where, const std::string& what) {
  return InputError(where + ": " + what);
}

}  // namespace ausbau
