#include "core/hash.h"

#include <xxhash.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <vector>

#include "core/error.h"

namespace ausbau {

Hasher::Hasher() : state_(XXH3_createState()) { XXH3_128bits_reset(static_cast<XXH3_state_t*>(state_)); }

Hasher::~Hasher() { XXH3_freeState(static_cast<XXH3_state_t*>(state_)); }

Hasher& Hasher::Add(const void* data, std::size_t size) {
  XXH3_128bits_update(static_cast<XXH3_state_t*>(state_), data, size);
  return *this;
}

Hasher& Hasher::Add(std::string_view text) {
  const std::uint64_t size = text.size();
  Add(&size, sizeof size);
  return Add(text.data(), text.size());
}

Hasher& Hasher::AddFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputErrorAt(path.string(), "cannot open file for hashing");
  std::vector<char> buffer(1 << 16);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    Add(buffer.data(), static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw InputErrorAt(path.string(), "read error while hashing");
  return *this;
}

std::string Hasher::HexDigest() const {
  const XXH128_hash_t h = XXH3_128bits_digest(static_cast<XXH3_state_t*>(state_));
  char text[33];
  std::snprintf(text, sizeof text, "%016llx%016llx", static_cast<unsigned long long>(h.high64),
                static_cast<unsigned long long>(h.low64));
  return text;
}

std::string HashString(std::string_view text) { return Hasher().Add(text).HexDigest(); }

std::string HashFile(const std::filesystem::path& path) { return Hasher().AddFile(path).HexDigest(); }

}  // namespace ausbau
