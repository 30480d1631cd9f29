#include "workflow/made_from.h"

#include <map>
#include <sstream>

#include "artifact/artifact.h"
#include "core/error.h"
#include "core/hash.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

// The "inputs" attribute as written by ArtifactWriter: one "role: hash" line
// per input (YAML block map of plain scalars; quotes are stripped).
std::map<std::string, std::string> RecordedInputs(const std::string& text) {
  std::map<std::string, std::string> inputs;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const std::size_t colon = line.find(": ");
    if (colon == std::string::npos) continue;
    std::string role = line.substr(0, colon), hash = line.substr(colon + 2);
    for (std::string* s : {&role, &hash}) {
      if (s->size() >= 2 && (s->front() == '"' || s->front() == '\'') && s->back() == s->front()) {
        *s = s->substr(1, s->size() - 2);
      }
    }
    inputs[role] = hash;
  }
  return inputs;
}

}  // namespace

void CheckMadeFrom(const std::string& artifact, const std::string& schema, int schema_version, const Scene& scene,
                   MadeFrom what) {
  std::map<std::string, std::string> recorded;
  {
    const ArtifactReader reader(artifact, schema, schema_version);
    recorded = RecordedInputs(reader.ReadStringAttribute("", "inputs"));
  }
  // Roles and hashes as AddSceneInputs records them (scene/scene.h).
  const SceneInputs which = what == MadeFrom::kMeshes ? SceneInputs::kAll : SceneInputs::kDynamicOnly;
  for (const SceneInput& input : SceneInputFiles(scene, which)) {
    if (input.role == "scene") continue;  // scene.yaml itself: an edit that keeps the meshes is no other scene
    const auto it = recorded.find(input.role);
    if (it == recorded.end()) continue;
    const std::string& role = input.role;
    const std::filesystem::path& file = input.file;
    const std::string hash = SceneInputHash(scene, input);
    if (it->second != hash) {
      throw InputErrorAt(artifact, "was made from another " + std::string(role == "dynamic" ? "D" : "S") +
                                       " than this scene's " + file.string() +
                                       " (content hash differs: an artifact of "
                                       "another part or scene?)");
    }
  }
}

}  // namespace ausbau
