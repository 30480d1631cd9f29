// Content hashing for provenance: XXH3-128 over bytes, files and strings,
// printed as 32 lower-case hex digits. Not cryptographic: the hash detects
// changed inputs, it does not defend against an adversary.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace ausbau {

class Hasher {
 public:
  Hasher();
  ~Hasher();
  Hasher(const Hasher&) = delete;
  Hasher& operator=(const Hasher&) = delete;

  Hasher& Add(const void* data, std::size_t size);
  // Adds the length first, so that ("ab","c") and ("a","bc") differ.
  Hasher& Add(std::string_view text);
  // Adds the file's bytes; throws InputError when it cannot be read.
  Hasher& AddFile(const std::filesystem::path& path);
  std::string HexDigest() const;

 private:
  void* state_;
};

std::string HashString(std::string_view text);
std::string HashFile(const std::filesystem::path& path);

}  // namespace ausbau
