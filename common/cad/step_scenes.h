// One scene per part of a STEP assembly (ausbau-assembly --assembly x.step):
// the assembly tessellated once into an OBJ with one object per leaf
// instance, then WriteAssemblyScenes over that OBJ, with the product tree,
// the placements, the file's units and the tessellation recorded in
// assembly.json and the deflection in every scene.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "cad/step_assembly.h"
#include "scene/assembly.h"

namespace ausbau {

// The tessellated assembly's file name: "<stem>.tessellated.obj".
std::string StepMeshFileName(const std::filesystem::path& step);

// The parts' names in the written OBJ (what `part:` picks): each instance's
// name made safe ([A-Za-z0-9._-], others '_'; "part" when empty), unique
// ignoring case by "-2", "-3", ... in tree order, and never the name of a
// file the output folder holds (assembly.json, the OBJ).
std::vector<std::string> StepPartNames(const StepAssembly& assembly, const std::string& reserved_file);

// The parts (indices) that `pick` names: a part's written name or its
// name in the file, its path in the product tree ("car/door/bracket"), a
// node of that path by name or path (every part below it). Throws
// InputError("--dynamic: 'x' names no part of the assembly (parts: ...)").
std::vector<int> PickStepParts(const StepAssembly& assembly, const std::vector<std::string>& names,
                               const std::string& pick);

struct StepSceneOptions {
  StepTessellation tessellation;
  std::string units = "mm";          // the unit of the written OBJ and the scenes (a length)
  std::string name;                  // the scenes' name prefix; empty: the STEP file's stem
  std::vector<std::string> dynamic;  // picks (PickStepParts) of the parts to write a scene for; empty: every part
};

struct StepScenes {
  std::filesystem::path mesh;       // the tessellated assembly: <output>/<stem>.tessellated.obj
  std::vector<AssemblyPart> parts;  // the scenes written
  std::string file_units;           // StepAssembly::file_units
  int products = 0, instances = 0;
  long long triangles = 0;
  int faces_without_triangles = 0;
  // The instances with faces left out (StepPart::faces_without_triangles):
  // name and count.
  std::vector<std::pair<std::string, int>> without_faces;
  // The instances with faces tessellated with a coarser interior
  // (StepPart::faces_meshed_coarser): name, count, and the largest chord
  // error bound of those faces (mm).
  struct Coarser {
    std::string name;
    int faces = 0;
    double chord_error_mm = 0;
  };
  std::vector<Coarser> coarser;
  // Instances whose faces lie on one another over more than 1% of their
  // surface (StepPart::overlapping_surface_mm2): the name, and that area
  // in mm^2.
  std::vector<std::pair<std::string, double>> overlapping;
};

// Reads and tessellates the STEP file (ReadStepAssembly), writes the OBJ
// and the scenes. Throws InputError for a bad file, option or pick.
StepScenes WriteStepAssemblyScenes(const std::filesystem::path& step, const std::filesystem::path& output,
                                   const StepSceneOptions& options);

}  // namespace ausbau
