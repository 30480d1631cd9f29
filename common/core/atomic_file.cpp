#include "core/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "core/cancel.h"
#include "core/error.h"

namespace ausbau {

void CheckOutputTarget(const std::filesystem::path& file) {
  struct stat info;
  // lstat: a symbolic link is judged itself, not what it points to.
  if (::lstat(file.c_str(), &info) != 0) return;  // absent: will be created
  const char* what = nullptr;
  if (S_ISREG(info.st_mode)) return;
  if (S_ISDIR(info.st_mode))
    what = "is a directory";
  else if (S_ISLNK(info.st_mode))
    what = "is a symbolic link";
  else if (S_ISFIFO(info.st_mode))
    what = "is a FIFO";
  else if (S_ISCHR(info.st_mode) || S_ISBLK(info.st_mode))
    what = "is a device";
  else
    what = "is not a regular file";
  throw InputErrorAt(file.string(), std::string(what) + "; an output must be a regular file (not replaced)");
}

std::filesystem::path TemporaryPathFor(const std::filesystem::path& file) {
  static std::atomic<long> counter{0};
  return file.string() + ".tmp-" + std::to_string(static_cast<long>(::getpid())) + "-" +
         std::to_string(counter.fetch_add(1));
}

namespace {

// The writer's pid when `name` is "<base>.tmp-<pid>-<n>" (digits only), else 0.
long TemporaryOwner(const std::string& name, const std::string& base) {
  const std::string prefix = base + ".tmp-";
  if (name.compare(0, prefix.size(), prefix) != 0) return 0;
  const std::string rest = name.substr(prefix.size());
  const std::size_t dash = rest.find('-');
  if (dash == 0 || dash == std::string::npos || dash + 1 == rest.size() || dash > 9) return 0;
  for (std::size_t i = 0; i < rest.size(); ++i) {
    if (i != dash && (rest[i] < '0' || rest[i] > '9')) return 0;
  }
  return std::stol(rest.substr(0, dash));
}

}  // namespace

void RemoveStaleTemporaries(const std::filesystem::path& file) {
  const std::filesystem::path folder = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  const std::string base = file.filename().string();
  std::error_code error;
  std::filesystem::directory_iterator it(folder, error), end;
  for (; !error && it != end; it.increment(error)) {
    const long pid = TemporaryOwner(it->path().filename().string(), base);
    if (pid <= 0) continue;
    // kill(pid, 0) fails with ESRCH only when no such process exists; EPERM
    // means it lives under another user: leave its file alone.
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    std::error_code ignored;
    if (it->is_regular_file(ignored)) std::filesystem::remove(it->path(), ignored);
  }
}

void WriteTextFileAtomically(const std::filesystem::path& file, const std::string& text) {
  CheckOutputTarget(file);
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  RemoveStaleTemporaries(file);
  const std::filesystem::path temporary = TemporaryPathFor(file);
  std::error_code ignored;
  // O_EXCL | O_NOFOLLOW: the temporary is a new regular file of ours. A name
  // that already exists (a link planted under it, pointing outside the
  // output folder) is refused instead of written through.
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) {
    throw std::runtime_error(file.string() + ": cannot create temporary file (" + std::strerror(errno) + ")");
  }
  const char* data = text.data();
  std::size_t left = text.size();
  while (left > 0) {
    const ssize_t written = ::write(fd, data, left);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) {
      // errno is that of the failed write (no space left, file too large).
      const std::string reason = std::strerror(written < 0 ? errno : EIO);
      ::close(fd);
      std::filesystem::remove(temporary, ignored);
      throw std::runtime_error(file.string() + ": cannot write file (" + reason + ")");
    }
    data += written;
    left -= static_cast<std::size_t>(written);
  }
  if (::close(fd) != 0) {
    const std::string reason = std::strerror(errno);
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(file.string() + ": cannot write file (" + reason + ")");
  }
  // A cancelled run commits nothing (core/cancel.h).
  if (CancelRequested()) {
    std::filesystem::remove(temporary, ignored);
    throw Cancelled();
  }
  std::error_code error;
  std::filesystem::rename(temporary, file, error);
  if (error) {
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(file.string() + ": cannot write file (" + error.message() + ")");
  }
}

}  // namespace ausbau
