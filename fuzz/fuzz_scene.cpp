// libFuzzer harness of the scene reader (LoadScene, common/scene/scene.cpp):
// the input is scene.yaml, in a folder that also holds two small valid
// meshes (s.obj, d.obj) for the scene to name.
#include <cstdint>
#include <string>

#include "fuzz_util.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ausbau::fuzz;
  static const std::filesystem::path dir = [] {
    const std::string tetra = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    for (const char* name : {"s.obj", "d.obj"}) {
      WriteBytes(WorkDir() / name, reinterpret_cast<const std::uint8_t*>(tetra.data()), tetra.size());
    }
    return WorkDir();
  }();
  const std::filesystem::path file = dir / "scene.yaml";
  WriteBytes(file, data, size);
  ExpectOnlyInputErrors([&] { ausbau::LoadScene(file); });
  return 0;
}
