// Running a third-party parser where its crash cannot take this process
// with it.
//
// Debian's assimp 5.2 dereferences a null pointer on a malformed COLLADA
// file (fuzz_mesh; fuzz/known-findings/), and its importers for the other
// formats are not hardened either. Our own structure checks guard the
// formats we read most (OBJ, PLY, OFF); a format without one is read in a
// child process, so that a crash there is a clear input error (exit 2),
// not the death of the stage.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace ausbau {

// Runs `work` in a forked child process and returns the bytes it returned.
// An InputError thrown by `work` is rethrown here with its message, any
// other exception as std::runtime_error. When the child dies of a signal
// (a crash inside the parser), throws InputError("<what>: <code> crashed
// (signal N, SIGSEGV): the file is malformed"), where `what` names the
// input and `code` the code that ran. `memory_allowance` > 0 bounds what
// the child may allocate beyond what it inherits (RLIMIT_DATA); past it,
// InputError("<what>: <code> needs more than the N MiB ..."). A sanitizer
// build reserves terabytes of shadow memory and dies on a failed `new`, so
// there the bound is not set. The child writes no core file, and it ends
// with _exit: no atexit handler and no stdio buffer of this process runs
// twice.
std::string RunInChildProcess(const std::function<std::string()>& work, const std::string& what,
                              const std::string& code, std::size_t memory_allowance = 0);

// Whether RunInChildProcess bounds the child's memory in this build.
bool ChildMemoryIsBounded();

}  // namespace ausbau
