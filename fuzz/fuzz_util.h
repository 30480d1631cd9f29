// Helpers shared by the libFuzzer harnesses (see README.md, section Fuzzing).
//
// A harness writes its input to a file and calls one of our readers. The
// documented outcome of bad input is an InputError (core/error.h), which the
// harness swallows; anything else (a crash, a sanitizer report, any other
// exception escaping, a leak, a hang, an allocation over libFuzzer's
// -malloc_limit_mb) is a finding.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"

namespace ausbau::fuzz {

// A folder of this process for the harness's files: under $AUSBAU_FUZZ_TMP,
// else /dev/shm (memory, no disk wear at 10^6 runs), else the temp folder.
inline const std::filesystem::path& WorkDir() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path base;
    if (const char* env = std::getenv("AUSBAU_FUZZ_TMP"); env != nullptr && env[0] != '\0') {
      base = env;
    } else if (std::filesystem::is_directory("/dev/shm")) {
      base = "/dev/shm";
    } else {
      base = std::filesystem::temp_directory_path();
    }
    std::filesystem::path d = base / ("ausbau-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

inline void WriteBytes(const std::filesystem::path& path, const std::uint8_t* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (!out) {
    std::fprintf(stderr, "fuzz harness: cannot write %s\n", path.c_str());
    std::abort();  // the harness's own failure, not a finding in the reader
  }
}

// Runs `read`; an InputError is the normal outcome of bad input.
template <typename Read>
void ExpectOnlyInputErrors(Read&& read) {
  try {
    read();
  } catch (const InputError&) {
  }
}

}  // namespace ausbau::fuzz
