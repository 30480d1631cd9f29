// Helpers shared by the libFuzzer harnesses (see docs/fuzzing.md).
//
// A harness writes its input to a file and calls one of our readers. The
// documented outcome of bad input is an InputError (core/error.h), which the
// harness swallows; anything else (a crash, a sanitizer report, any other
// exception escaping, a leak, a hang, an allocation over libFuzzer's
// -malloc_limit_mb) is a finding.
#pragma once

#include <sanitizer/allocator_interface.h>
#include <sanitizer/asan_interface.h>
#include <sys/mman.h>
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

// Large blocks on huge pages, mapped at once.
//
// Under ASan every block over 128 KB is a fresh mmap, unmapped again when it
// is freed. On this project's machines (a virtual machine) each first touch
// of a 4 KB page is an expensive fault, and even a memset over already
// mapped 4 KB pages is slow (TLB misses). assimp 5.2's OBJ importer
// allocates, zeroes and fills a 16 MB line buffer per file (IOStreamBuffer,
// fixed size inside libassimp): about 100 ms of CPU per OBJ input under ASan.
// A malloc hook (called by ASan after it has set up the block, its redzones
// and shadow) asks for transparent huge pages on every block of 1 MB or
// more and on its shadow, and maps the block in one call
// (MADV_POPULATE_WRITE) instead of 4096 faults. It changes only how the
// pages are mapped, not what ASan checks. FUZZ_PREFAULT=0 turns it off (to
// compare); bits: 1 populate, 2 huge pages, 4 huge pages for the shadow.
namespace detail {
inline int PrefaultMode() {
  static const int mode = [] {
    const char* env = std::getenv("FUZZ_PREFAULT");
    return env != nullptr && env[0] != '\0' ? std::atoi(env) : 7;
  }();
  return mode;
}
inline void Advise(std::uintptr_t begin, std::uintptr_t end, int advice) {
  constexpr std::uintptr_t kPage = 4096;
  begin = (begin + kPage - 1) & ~(kPage - 1);
  end &= ~(kPage - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, advice);
}
inline void OnMalloc(const volatile void* ptr, std::size_t size) {
  if (size < (std::size_t{1} << 20)) return;
  const int mode = PrefaultMode();
  const auto begin = reinterpret_cast<std::uintptr_t>(ptr);
  if (mode & 4) {
    std::size_t scale = 0, offset = 0;
    __asan_get_shadow_mapping(&scale, &offset);
    Advise((begin >> scale) + offset, ((begin + size) >> scale) + offset, MADV_HUGEPAGE);
  }
  if (mode & 2) Advise(begin, begin + size, MADV_HUGEPAGE);
  // Mapped at once only up to 64 MB: a block of gigabytes (an allocation
  // over libFuzzer's -malloc_limit_mb, which its own hook reports after this
  // one) must not become resident here.
  if ((mode & 1) && size <= (std::size_t{64} << 20)) Advise(begin, begin + size, MADV_POPULATE_WRITE);
}
inline void OnFree(const volatile void*) {}
inline const int kHooksInstalled = __sanitizer_install_malloc_and_free_hooks(OnMalloc, OnFree);
}  // namespace detail

// Runs `read`; an InputError is the normal outcome of bad input.
template <typename Read>
void ExpectOnlyInputErrors(Read&& read) {
  try {
    read();
  } catch (const InputError&) {
  }
}

}  // namespace ausbau::fuzz
