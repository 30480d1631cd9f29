// The check every file reader makes before it opens an input: the path is a
// regular file of a sane size. A FIFO blocks a reader forever, a device
// (/dev/zero) never ends, a folder cannot be parsed; a size far beyond any
// real input is refused up front instead of being read into memory.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <system_error>

#include "core/error.h"

namespace ausbau {

// Upper bounds on inputs, far above any real one (a 10M-triangle binary STL
// is 500 MB; a scene.yaml a few KB).
inline constexpr std::uint64_t kMaxMeshFileBytes = std::uint64_t{4} << 30;
inline constexpr std::uint64_t kMaxTextInputBytes = std::uint64_t{1} << 30;  // path CSVs
inline constexpr std::uint64_t kMaxSceneFileBytes = std::uint64_t{16} << 20;

// Throws InputError naming the file: missing, a folder, a FIFO, socket or
// device, or larger than `max_bytes`. `what` names the kind of input in the
// message ("mesh", "scene file").
inline void CheckInputFile(const std::filesystem::path& path, std::uint64_t max_bytes, const std::string& what) {
  const std::string name = path.string();
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) throw InputErrorAt(name, "file not found");
  if (std::filesystem::is_directory(status)) throw InputErrorAt(name, "cannot read " + what + " (is a directory)");
  if (!std::filesystem::is_regular_file(status)) {
    throw InputErrorAt(name, "cannot read " + what + " (not a regular file: a FIFO, socket or device)");
  }
  const std::uint64_t bytes = std::filesystem::file_size(path, ec);
  if (ec) throw InputErrorAt(name, "cannot read " + what + " (" + ec.message() + ")");
  if (bytes > max_bytes) {
    throw InputErrorAt(name, "cannot read " + what + " (" + std::to_string(bytes) + " bytes, more than the limit of " +
                                 std::to_string(max_bytes) + ")");
  }
}

}  // namespace ausbau
