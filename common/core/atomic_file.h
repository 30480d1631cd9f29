// Atomic writes of small text files (CSV, OBJ, YAML, JSON): the text goes to
// a temporary file beside the target, which is renamed onto it only when
// complete, so an interrupted run never leaves a half-written file. HDF5
// artifacts do the same through artifact/artifact.h, with the same temporary
// names and the same checks of the target (the helpers below).
#pragma once

#include <filesystem>
#include <string>

namespace ausbau {

// Creates the parent folder if needed; throws std::runtime_error naming the
// file on failure (and leaves no temporary file behind). Refuses (InputError)
// a target that exists and is not a regular file (CheckOutputTarget).
void WriteTextFileAtomically(const std::filesystem::path& file, const std::string& text);

// Throws InputErrorAt(file, ...) when `file` exists and is a directory, a
// symbolic link, a FIFO, a device or a socket: an atomic rename would replace
// it with a plain file (a link's target would stay unchanged, a device node
// would become a file), which is never what the user meant.
void CheckOutputTarget(const std::filesystem::path& file);

// The temporary file an atomic write of `file` uses:
// "<file>.tmp-<pid>-<counter>", unique within and across processes. The pid in
// the name lets a later run tell the files of a dead writer from those of a
// live one (RemoveStaleTemporaries).
std::filesystem::path TemporaryPathFor(const std::filesystem::path& file);

// Removes the temporary files of `file` ("<file>.tmp-<pid>-<n>") left by
// writers that no longer run (killed, or out of disk before they could clean
// up). Files of live processes and any other names are left alone. Errors are
// ignored: this is housekeeping before a write, never a reason to fail it.
void RemoveStaleTemporaries(const std::filesystem::path& file);

}  // namespace ausbau
