#include "generated_scene.h"

#include "fixtures/generators.h"
#include "test_scenes.h"

namespace ausbau::testing {

std::filesystem::path MakeGeneratedScene(const std::string& family, std::uint64_t seed) {
  return GenerateScene(family, seed, MakeTempDir(family));
}

}  // namespace ausbau::testing
