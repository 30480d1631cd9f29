#include "core/child_process.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <stdexcept>

#include "core/cancel.h"
#include "core/error.h"

namespace ausbau {
namespace {

// The first byte of what the child writes: how `work` ended.
constexpr char kReturned = 'R';
constexpr char kInputError = 'I';
constexpr char kOtherError = 'E';
constexpr char kOutOfMemory = 'M';

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

// The data segment and private writable mappings this process has now
// (VmData), in bytes; 0 when /proc does not say.
std::size_t DataBytesNow() {
  std::FILE* status = std::fopen("/proc/self/status", "r");
  if (status == nullptr) return 0;
  char line[256];
  unsigned long long kib = 0;
  while (std::fgets(line, sizeof line, status) != nullptr) {
    if (std::sscanf(line, "VmData: %llu kB", &kib) == 1) break;
  }
  std::fclose(status);
  return static_cast<std::size_t>(kib) * 1024;
}

bool WriteAll(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

[[noreturn]] void RunChild(int fd, const std::function<std::string()>& work, std::size_t memory_allowance) {
  // A crash must kill the child with its signal, for the parent to see:
  // not run a handler inherited from this process (a sanitizer's or a
  // fuzzer's would report it as this process's crash), nor dump a core.
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP, SIGSYS}) std::signal(sig, SIG_DFL);
  const rlimit no_core = {0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);
  if (memory_allowance > 0 && !kSanitized) {
    const std::size_t now = DataBytesNow();
    if (now > 0) {
      const rlimit data = {now + memory_allowance, now + memory_allowance};
      ::setrlimit(RLIMIT_DATA, &data);
    }
  }
  std::string out;
  try {
    out = kReturned + work();
  } catch (const std::bad_alloc&) {
    out = std::string(1, kOutOfMemory);
  } catch (const InputError& e) {
    out = kInputError + std::string(e.what());
  } catch (const std::exception& e) {
    out = kOtherError + std::string(e.what());
  } catch (...) {
    out = kOtherError + std::string("unknown exception");
  }
  ::_exit(WriteAll(fd, out.data(), out.size()) ? 0 : 1);
}

}  // namespace

bool ChildMemoryIsBounded() { return !kSanitized; }

std::string RunInChildProcess(const std::function<std::string()>& work, const std::string& what,
                              const std::string& code, std::size_t memory_allowance) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error(what + ": cannot create a pipe: " + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int error = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::runtime_error(what + ": cannot start a child process: " + std::strerror(error));
  }
  if (pid == 0) {
    ::close(fds[0]);
    RunChild(fds[1], work, memory_allowance);
  }
  ::close(fds[1]);
  std::string bytes;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    bytes.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  // Interrupted (Ctrl-C reaches the child too, which stops with an error):
  // the run is cancelled, not failed (core/cancel.h).
  ThrowIfCancelled();
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const char* name = sigabbrev_np(sig);
    throw InputErrorAt(what, code + " crashed (signal " + std::to_string(sig) +
                                 (name != nullptr ? std::string(", SIG") + name : std::string()) +
                                 "): the file is malformed");
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || bytes.empty()) {
    throw std::runtime_error(what + ": the child process reading it ended without a result");
  }
  const char ending = bytes[0];
  bytes.erase(0, 1);
  if (ending == kReturned) return bytes;
  if (ending == kInputError) throw InputError(bytes);
  if (ending == kOutOfMemory) {
    throw InputErrorAt(what, code + " needs more than the " + std::to_string(memory_allowance >> 20) +
                                 " MiB of memory this input may take: the file is malformed or too large");
  }
  throw std::runtime_error(bytes);
}

}  // namespace ausbau
