#include "core/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <stdexcept>

namespace ausbau {

void WriteTextFileAtomically(const std::filesystem::path& file, const std::string& text) {
  static std::atomic<int> counter{0};
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  const std::filesystem::path temporary =
      file.string() + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  std::error_code ignored;
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) {
      std::filesystem::remove(temporary, ignored);
      throw std::runtime_error(file.string() + ": cannot write file");
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, file, error);
  if (error) {
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(file.string() + ": cannot write file (" + error.message() + ")");
  }
}

}  // namespace ausbau
