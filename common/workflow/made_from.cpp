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
  // (role, file) pairs as AddSceneInputs names them.
  std::vector<std::pair<std::string, std::filesystem::path>> files = {{"dynamic", scene.dynamic_file}};
  if (what == MadeFrom::kMeshes) {
    const std::size_t n = scene.static_files.size();
    for (std::size_t i = 0; i < n; ++i) {
      files.emplace_back(n == 1 ? "static" : "static[" + std::to_string(i) + "]", scene.static_files[i]);
    }
  }
  for (const auto& [role, file] : files) {
    const auto it = recorded.find(role);
    if (it == recorded.end()) continue;
    // D picked by name or given units (format /2) is recorded by its
    // selection's hash, not the file's.
    const std::string hash = role == "dynamic" ? DynamicContentHash(scene) : MeshFileHash(scene, file);
    if (it->second != hash) {
      throw InputErrorAt(artifact, "was made from another " + std::string(role == "dynamic" ? "D" : "S") +
                                       " than this scene's " + file.string() +
                                       " (content hash differs: an artifact of "
                                       "another part or scene?)");
    }
  }
}

}  // namespace ausbau
