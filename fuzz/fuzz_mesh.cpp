// libFuzzer harness of the mesh loader (LoadMesh, common/scene/mesh_io.cpp).
// The first byte picks the file name's extension, which is how LoadMesh and
// assimp pick the importer: the formats LoadMesh reads in this process
// (OBJ, STL, PLY, OFF; OBJ also as ".OBJ", the extension in capitals), and
// names LoadMesh must refuse quickly (.txt, no extension). The rest is the
// file's content. COLLADA and the other formats are read in a child process
// (core/child_process.h), where libFuzzer sees no coverage and, under
// AddressSanitizer, cannot bound the child's memory (its malloc limit
// reports the child's allocation as this process's); their guard is tested
// by unit tests (Readers.MeshImporterCrashIsAnInputError, ChildProcess.*)
// and the bad-input suite instead.
#include <cstdint>
#include <string>

#include "fuzz_util.h"
#include "scene/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ausbau::fuzz;
  static const char* const kNames[] = {"mesh.obj", "mesh.stl", "mesh.ply", "mesh.off", "mesh.OBJ", "mesh.txt", "mesh"};
  if (size == 0) return 0;
  const std::filesystem::path file = WorkDir() / kNames[data[0] % (sizeof kNames / sizeof kNames[0])];
  WriteBytes(file, data + 1, size - 1);
  ExpectOnlyInputErrors([&] { ausbau::LoadMesh(file); });
  std::filesystem::remove(file);
  return 0;
}
