// Atomic writes of small text files (CSV, OBJ, YAML, JSON): the text goes to
// a temporary file beside the target, which is renamed onto it only when
// complete, so an interrupted run never leaves a half-written file. HDF5
// artifacts do the same through artifact/artifact.h.
#pragma once

#include <filesystem>
#include <string>

namespace ausbau {

// Creates the parent folder if needed; throws std::runtime_error naming the
// file on failure (and leaves no temporary file behind).
void WriteTextFileAtomically(const std::filesystem::path& file, const std::string& text);

}  // namespace ausbau
