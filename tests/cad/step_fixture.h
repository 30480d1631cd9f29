// A STEP assembly written by OpenCASCADE for the tests (test_step_assembly):
// a plate with a bore, a pin in the bore (touching it: the same radius), and
// a sub-assembly of two pins placed twice, with names and placements, in a
// unit of choice. Built here, so the test knows every answer by hand.
#pragma once

#include <filesystem>
#include <string>

namespace ausbau::testing {

struct StepFixtureOptions {
  std::string unit = "MM";           // OpenCASCADE's write.step.unit: MM, INCH, M, CM
  double gap_mm = 0;                 // the pin's radius is the bore's minus this
  std::string plate_name = "plate";  // UTF-8, written as it is (control characters too)
  std::string pin_instance_name;     // the pin's instance in bench (empty: unnamed)
  // Non-empty: each part in a STEP file of its own beside `file`, named
  // with this prefix, which `file` refers to (OpenCASCADE's multi-file mode).
  std::string external_prefix;
};

// Writes the assembly; sizes in mm whatever the unit (the writer converts):
//   plate  box [0,100] x [0,60] x [0,10] with a bore of radius 5 at (30, 30) along z
//   pin    cylinder radius 5 - gap, z from -5 to 25, in the bore
//   pair   a sub-assembly: two cylinders "stud" (radius 3, height 15) 20 mm apart,
//          placed twice ("pair" instances at (60, 15, 10), and at (60, 45, 10)
//          turned 90 degrees about z: its second stud at (60, 65, 10))
// Product tree: bench / {plate, pin, pair:1 / {stud, stud}, pair:2 / {stud, stud}}.
void WriteStepFixture(const std::filesystem::path& file, const StepFixtureOptions& options = {});

}  // namespace ausbau::testing
