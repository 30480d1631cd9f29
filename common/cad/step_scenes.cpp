#include "cad/step_scenes.h"

#include <Standard_Version.hxx>
#include <cctype>
#include <map>
#include <set>
#include <system_error>

#include "core/error.h"
#include "core/hash.h"
#include "core/json_writer.h"
#include "core/log.h"
#include "scene/mesh_io.h"
#include "scene/units.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

std::string Lower(const std::string& text) {
  std::string out;
  for (const char c : text) out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// SafeFolderName, never empty: an OBJ object needs a name.
std::string SafeName(const std::string& name) {
  const std::string safe = SafeFolderName(name);
  return safe.empty() ? "part" : safe;
}

std::string JoinPath(const std::vector<std::string>& path, std::size_t length) {
  std::string out;
  for (std::size_t k = 0; k < length && k < path.size(); ++k) out += (k > 0 ? "/" : "") + path[k];
  return out;
}

// On one line: [a, b, ...].
std::string JsonList(const std::vector<std::string>& raw_values) {
  std::string out = "[";
  for (std::size_t k = 0; k < raw_values.size(); ++k) out += (k > 0 ? ", " : "") + raw_values[k];
  return out + "]";
}

// The rotation and translation, row by row: [[r00, r01, r02, t0], ...].
std::string PlacementJson(const Eigen::Isometry3d& placement) {
  std::vector<std::string> rows;
  for (int r = 0; r < 3; ++r) {
    std::vector<std::string> row;
    for (int c = 0; c < 4; ++c) row.push_back(JsonNumber(placement.matrix()(r, c)));
    rows.push_back(JsonList(row));
  }
  return JsonList(rows);
}

double SurfaceArea(const TriangleMesh& mesh) {
  double area = 0;
  for (const auto& t : mesh.triangles)
    area += 0.5 * (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]).norm();
  return area;
}

std::string PartSourceJson(const StepPart& part) {
  std::vector<std::string> path;
  for (const std::string& node : part.path) path.push_back(JsonString(node));
  JsonWriter out;
  out.String("name", part.name)
      .String("product", part.product)
      .Add("path", JsonList(path))
      .Add("placement", PlacementJson(part.placement))
      .Int("faces", part.faces)
      .Int("faces_without_triangles", part.faces_without_triangles)
      .Int("faces_meshed_coarser", part.faces_meshed_coarser)
      .Number("coarser_chord_error_mm", part.coarser_chord_error_mm)
      .Number("overlapping_surface_mm2", part.overlapping_surface_mm2);
  return out.Text();
}

}  // namespace

std::string StepMeshFileName(const fs::path& step) { return step.stem().string() + ".tessellated.obj"; }

std::vector<std::string> StepPartNames(const StepAssembly& assembly, const std::string& reserved_file) {
  std::set<std::string> used = {Lower("assembly.json"), Lower(reserved_file)};
  std::vector<std::string> names(assembly.parts.size());
  // The parts with triangles first (they become the scenes' parts), so that
  // an empty compound beside a solid (a Pro/ENGINEER product) does not take
  // the solid's number.
  for (const bool with_triangles : {true, false}) {
    for (std::size_t k = 0; k < assembly.parts.size(); ++k) {
      const StepPart& part = assembly.parts[k];
      if (part.mesh.triangles.empty() == with_triangles) continue;
      const std::string base = SafeName(part.name);
      std::string name = base;
      for (int n = 2; !used.insert(Lower(name)).second; ++n) name = base + "-" + std::to_string(n);
      names[k] = name;
    }
  }
  return names;
}

std::vector<int> PickStepParts(const StepAssembly& assembly, const std::vector<std::string>& names,
                               const std::string& pick) {
  std::vector<int> picked;
  for (int k = 0; k < static_cast<int>(assembly.parts.size()); ++k) {
    const StepPart& part = assembly.parts[k];
    bool match = pick == names[k] || pick == part.name || pick == JoinPath(part.path, part.path.size());
    for (std::size_t length = 1; !match && length < part.path.size(); ++length) {
      match = pick == JoinPath(part.path, length) || pick == part.path[length - 1];
    }
    if (match) picked.push_back(k);
  }
  if (picked.empty()) {
    std::string list;
    for (std::size_t k = 0; k < names.size() && k < 40; ++k) list += (k > 0 ? ", " : "") + names[k];
    if (names.size() > 40) list += ", ... (" + std::to_string(names.size() - 40) + " more)";
    throw InputError("--dynamic: '" + pick + "' names no part of the assembly (parts: " + list + ")");
  }
  return picked;
}

StepScenes WriteStepAssemblyScenes(const fs::path& step, const fs::path& output, const StepSceneOptions& options) {
  const std::optional<double> mm_per_unit = MillimetresPerUnit(options.units);
  if (!mm_per_unit) {
    throw InputError("--units: a STEP assembly is tessellated in a length unit: mm, cm, m or inch (got '" +
                     options.units + "')");
  }
  StepAssembly assembly = ReadStepAssembly(step, options.tessellation);
  const std::string mesh_name = StepMeshFileName(step);
  const std::vector<std::string> names = StepPartNames(assembly, mesh_name);
  std::vector<int> picked;
  for (const std::string& pick : options.dynamic) {
    for (const int k : PickStepParts(assembly, names, pick)) picked.push_back(k);
  }

  StepScenes out;
  out.file_units = assembly.file_units;
  out.products = assembly.products;
  out.instances = static_cast<int>(assembly.parts.size());
  // The OBJ holds the instances with triangles, in order; a part of the
  // OBJ is one of those (LoadMeshFile skips an object without triangles).
  const double scale = 1.0 / *mm_per_unit;
  std::vector<ObjPart> obj_parts;
  std::vector<int> obj_index(assembly.parts.size(), -1);
  std::vector<std::string> part_source_json;
  std::vector<std::string> empty;  // the first few instances without triangles, for the message
  int empty_count = 0;
  for (std::size_t k = 0; k < assembly.parts.size(); ++k) {
    StepPart& part = assembly.parts[k];
    out.faces_without_triangles += part.faces_without_triangles;
    if (part.faces_without_triangles > 0) out.without_faces.emplace_back(part.name, part.faces_without_triangles);
    if (part.faces_meshed_coarser > 0)
      out.coarser.push_back({part.name, part.faces_meshed_coarser, part.coarser_chord_error_mm});
    // Said where it is more than a sliver: 1% of the part's surface (s1-c5's
    // HEAD_BACK: 23%; s1-tu's FOOTBACK: 0.002 mm^2 of sliver triangles
    // along a sharp edge).
    if (part.overlapping_surface_mm2 > 0 && part.overlapping_surface_mm2 > 0.01 * SurfaceArea(part.mesh))
      out.overlapping.emplace_back(part.name, part.overlapping_surface_mm2);
    if (part.mesh.triangles.empty()) {
      if (empty.size() < 3) empty.push_back(JoinPath(part.path, part.path.size()));
      ++empty_count;
      continue;
    }
    for (Eigen::Vector3d& v : part.mesh.vertices) v *= scale;
    out.triangles += static_cast<long long>(part.mesh.triangles.size());
    obj_index[k] = static_cast<int>(obj_parts.size());
    obj_parts.push_back({names[k], &part.mesh});
    part_source_json.push_back(PartSourceJson(part));
  }
  if (empty_count > 0) {
    std::string list;
    for (const std::string& path : empty) list += (list.empty() ? "" : ", ") + path;
    LogWarn("%s: %d instance%s without triangles (no surface: an empty compound, a wireframe) left out: %s%s",
            step.string().c_str(), empty_count, empty_count == 1 ? "" : "s", list.c_str(),
            empty_count > static_cast<int>(empty.size()) ? ", ..." : "");
  }
  std::vector<int> only;
  for (const int k : picked) {
    if (obj_index[k] < 0) {
      throw InputError("--dynamic: part '" + names[k] + "' has no triangle after tessellation");
    }
    only.push_back(obj_index[k]);
  }
  std::error_code error;
  fs::create_directories(output, error);
  if (error) throw InputErrorAt(output.string(), "cannot create the folder (" + error.message() + ")");
  out.mesh = output / mesh_name;
  if (fs::equivalent(step, out.mesh, error) && !error) {
    throw InputErrorAt(out.mesh.string(), "is the STEP file itself; choose another -o");
  }
  char deflection[64];
  std::snprintf(deflection, sizeof deflection, "%.17g mm, angular %.17g rad", options.tessellation.deflection_mm,
                options.tessellation.angular_deflection_rad);
  SaveObjParts(obj_parts, out.mesh,
               {"ausbau-assembly: " + step.filename().string() + " tessellated by OpenCASCADE " + OCC_VERSION_COMPLETE,
                std::string("chord error ") + deflection + "; units: " + options.units +
                    "; one object per instance of the product tree (assembly.json: paths, placements)"});

  const std::string hash = HashFile(step);
  JsonWriter source;
  source
      .String("file", fs::absolute(step)
                          .lexically_normal()
                          .lexically_relative(fs::absolute(output).lexically_normal())
                          .generic_string())
      .String("format", "STEP")
      .String("content_hash", hash)
      .String("file_units", assembly.file_units)
      .String("units", options.units)
      .String("tessellated_by", std::string("OpenCASCADE ") + OCC_VERSION_COMPLETE)
      .Number("deflection_mm", options.tessellation.deflection_mm)
      .Number("angular_deflection_rad", options.tessellation.angular_deflection_rad)
      .Int("products", assembly.products)
      .Int("instances", out.instances)
      .Int("triangles", out.triangles)
      .Int("faces_without_triangles", out.faces_without_triangles);

  AssemblyOptions scenes;
  scenes.units = options.units;
  scenes.name = options.name.empty() ? step.stem().string() : options.name;
  scenes.tessellation_deflection_mm = options.tessellation.deflection_mm;
  scenes.only = only;
  scenes.source_json = source.Text();
  scenes.part_source_json = std::move(part_source_json);
  out.parts = WriteAssemblyScenes(out.mesh, output, scenes);
  return out;
}

}  // namespace ausbau
