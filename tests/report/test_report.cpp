// The report layer's readers and wording (common/report): the JSON reader
// behind the headline, the headline itself, profile.csv read by column names,
// and the part names kept from a mesh file's nodes.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "core/error.h"
#include "report/json_read.h"
#include "report/report_headline.h"
#include "report/report_parts.h"
#include "report/report_profile.h"
#include "report/report_util.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"
#include "test_scenes.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;
using namespace report_internal;

void WriteText(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
}

TEST(ReportJson, ParsesNestedValuesAndEscapes) {
  JsonValue v;
  std::string error;
  ASSERT_TRUE(
      ParseJson(R"({"a": {"b": [1, 2.5e1, -3]}, "s": "x\"\u00e9\ud83d\ude00", "t": true, "n": null})", &v, &error))
      << error;
  ASSERT_NE(v.At("a.b"), nullptr);
  ASSERT_EQ(v.At("a.b")->items.size(), 3u);
  EXPECT_EQ(v.At("a.b")->items[1].number, 25.0);
  EXPECT_EQ(v.At("a.b")->items[2].number, -3.0);
  EXPECT_EQ(v.Find("s")->string, "x\"\xc3\xa9\xf0\x9f\x98\x80");
  EXPECT_TRUE(v.Find("t")->boolean);
  EXPECT_EQ(v.Find("n")->type, JsonValue::Type::kNull);
  EXPECT_EQ(v.At("a.c"), nullptr);
  EXPECT_EQ(v.At("s.x"), nullptr);
}

TEST(ReportJson, RefusesMalformedText) {
  JsonValue v;
  std::string error;
  for (const char* bad : {"{", "[1,]", "{\"a\" 1}", "tru", "\"abc", "1 2", "{\"a\": 01x}", ""}) {
    EXPECT_FALSE(ParseJson(bad, &v, &error)) << bad;
    EXPECT_NE(error.find("at byte"), std::string::npos) << bad << ": " << error;
  }
  std::string deep(100, '[');
  EXPECT_FALSE(ParseJson(deep, &v, &error));
}

JsonValue Parse(const std::string& text) {
  JsonValue v;
  std::string error;
  EXPECT_TRUE(ParseJson(text, &v, &error)) << error;
  return v;
}

TEST(ReportHeadline, RemovableSaysHowFarTheRigidPartGoes) {
  const JsonValue v = Parse(R"({"removable": true, "path": {"waypoints": 12},
    "length": {"translation": 31.5, "rotation": 0.25},
    "exact_check": {"valid": true, "rigid_tolerance": 0.05, "max_rigid_penetration": 0.024,
                    "max_fastener_penetration": 1.45}})");
  const Headline h = MakeHeadline(&v, "", nullptr, "mm");
  EXPECT_EQ(h.verdict, "REMOVABLE");
  EXPECT_EQ(h.css, "ok");
  EXPECT_EQ(h.sentence,
            "D comes out of S along a path of 12 waypoints, 31.5 mm of travel and 0.25 rad (14.3\u00b0) of rotation; "
            "its rigid part penetrates S at most 0.024 mm of the 0.05 mm allowed, while its clips bend through up to "
            "1.45 mm.");
}

// What a headline must never say: a number without its unit where a unit
// belongs, "inf", "nan", or a lone dash for a missing value.
void ExpectPlainWords(const std::string& sentence) {
  for (const char* bad : {"inf", "nan", " \u2013", "\u2013 ", "null"}) {
    EXPECT_EQ(sentence.find(bad), std::string::npos) << "'" << bad << "' in: " << sentence;
  }
  // "after 195:" (a length without its unit); "waypoint 9:" names a waypoint.
  const std::string unnamed = std::regex_replace(sentence, std::regex(R"(waypoint \d+:)"), "");
  EXPECT_FALSE(std::regex_search(unnamed, std::regex(R"(\d:)"))) << "a number before a colon: " << sentence;
}

TEST(ReportHeadline, SaysMissingValuesInWords) {
  // No depth, no tolerance, no rotation: said, not printed as "–".
  const JsonValue v = Parse(R"({"removable": true, "length": {"translation": 12, "rotation": null},
    "exact_check": {"valid": true, "max_rigid_penetration": null},
    "max_labeled_mliv": {"measure": "labeled-mliv", "value": null}})");
  const Headline h = MakeHeadline(&v, "", nullptr, "mm");
  EXPECT_EQ(h.sentence,
            "D comes out of S along a path of 12 mm of travel; how deep its rigid part goes into S was not measured; "
            "the largest clip intersection (labeled-mliv) was not measured.");
  ExpectPlainWords(h.sentence);
  // No contact at all, volumes with their cubed unit and the waypoint said as one.
  const JsonValue clear = Parse(R"({"removable": true, "tau": 7.5,
    "exact_check": {"rigid_tolerance": 0.05, "max_rigid_penetration": 0},
    "max_labeled_mliv": {"measure": "labeled-mliv", "value": 3.25, "waypoint": 195}})");
  EXPECT_EQ(MakeHeadline(&clear, "", nullptr, "mm").sentence,
            "D comes out of S along a path; its rigid part stays clear of S (no contact, of the 0.05 mm allowed); "
            "the largest clip intersection (labeled-mliv) is 3.25 mm\u00b3 at waypoint 195 against tau 7.5 mm\u00b3.");
  // A scene without units says "scene units".
  const JsonValue unitless = Parse(R"({"removable": true, "length": {"translation": 2, "rotation": 3.14159265}})");
  EXPECT_EQ(MakeHeadline(&unitless, "", nullptr, "unitless").sentence,
            "D comes out of S along a path of 2 scene units of travel and 3.14 rad (180\u00b0) of rotation.");
}

TEST(ReportHeadline, VerdictTextsGetUnitsAndWaypoints) {
  // what_blocks' summary and the exact check's reason as ausbau-verdict
  // writes them (planning/exact_check.cpp), with unnamed shells.
  EXPECT_EQ(PlainVerdictText("6 of 6 straight pulls along D's principal axes are blocked; the farthest, towards "
                             "[0.003, 1.000, 0.003], after 195: rigid shell 0 (non-convex, 476 triangles, centre "
                             "[10.0576, -7, 65], size 15 x 40 x 15) of D against shell 2 of S, inf deep",
                             "mm"),
            "6 of 6 straight pulls along D's principal axes are blocked; the farthest, towards [0.003, 1.000, 0.003], "
            "after 195 mm of free travel: rigid shell 0 (non-convex, 476 triangles, centre [10.0576, -7, 65] mm, size "
            "15 x 40 x 15 mm) of D against shell 2 of S, intersecting (depth not measured)");
  EXPECT_EQ(PlainVerdictText(
                "a rigid part of D penetrates S 0.0731 deep (tolerance 0.05) on segment 8: D clip_3, S rail", "cm"),
            "a rigid part of D penetrates S 0.0731 cm deep (tolerance 0.05 cm) between waypoint 8 and waypoint 9: D "
            "clip_3, S rail");
  EXPECT_EQ(PlainVerdictText("depth nan, then -inf", ""), "depth not measured, then not measured");
  // The whole headline of a blocked part.
  const JsonValue v = Parse(R"({"removable": false, "planner": {"seconds": 62.05},
    "what_blocks": {"summary": "1 of 6 straight pulls are blocked; the farthest, after 8.916: rigid shell 0 (convex, 12 triangles, centre [1, 2, 3], size 1 x 2 x 3) of D against shell 4 (open, 2 triangles, centre [0, 0, 0], size 1 x 1 x 0) of S, 0.05 deep"}})");
  const ShellNamer names = [](int shell, bool robot) {
    return std::string(robot ? "bolt.obj \u203a shank_" : "frame.obj \u203a plate_") + std::to_string(shell);
  };
  const Headline h = MakeHeadline(&v, "", nullptr, "mm", names);
  EXPECT_EQ(
      h.sentence,
      "no path out of S was found in 62.05 s of planning; 1 of 6 straight pulls are blocked; the farthest, after "
      "8.916 mm of free travel: rigid bolt.obj \u203a shank_0 of D against frame.obj \u203a plate_4 of S, 0.05 mm "
      "deep.");
  ExpectPlainWords(h.sentence);
}

TEST(ReportHeadline, NoVerdictStillSaysThePathsSize) {
  PathEntry shown;
  shown.key = "smoothed";
  shown.artifact.success = true;
  shown.artifact.waypoints.resize(25);
  shown.length_translation = 128.25;
  shown.length_rotation = 0.0687;
  const Headline h = MakeHeadline(nullptr, "no verdict.json", &shown, "mm");
  EXPECT_EQ(h.verdict, "NO VERDICT");
  EXPECT_EQ(h.sentence,
            "no verdict.json; the smoothed path of 25 waypoints, 128.2 mm of travel and 0.0687 rad (3.94\u00b0) of "
            "rotation reaches its goal (not checked by ausbau-verdict).");
  ExpectPlainWords(h.sentence);
}

TEST(ReportUnits, LengthsVolumesAndAngles) {
  EXPECT_EQ(LengthText(0.5, "mm"), "0.5 mm");
  EXPECT_EQ(LengthText(0.5, ""), "0.5 scene units");
  EXPECT_EQ(LengthText(0.5, "None"), "0.5 scene units");
  EXPECT_EQ(VolumeText(7.18, "cm"), "7.18 cm\u00b3");
  EXPECT_EQ(VolumeText(7.18, "unitless"), "7.18 cubic scene units");
  EXPECT_EQ(AngleText(0.221), "0.221 rad (12.7\u00b0)");
  EXPECT_EQ(AngleText(0), "0 rad (0\u00b0)");
}

TEST(ReportHeadline, NotRemovableSaysWhatBlocks) {
  const JsonValue v = Parse(R"({"removable": false, "planner": {"seconds": 60},
    "exact_check": null, "what_blocks": {"summary": "rigid shell 0 already penetrates S at the installed pose"}})");
  const Headline h = MakeHeadline(&v, "", nullptr, "mm");
  EXPECT_EQ(h.verdict, "NOT REMOVABLE");
  EXPECT_EQ(h.sentence,
            "no path out of S was found in 60 s of planning; rigid shell 0 already penetrates S at the installed "
            "pose.");
  const JsonValue failed = Parse(R"({"removable": false, "exact_check": {"valid": false, "reason": "ends inside S"}})");
  EXPECT_EQ(MakeHeadline(&failed, "", nullptr, "").sentence, "the path found fails the exact check: ends inside S.");
}

TEST(ReportHeadline, NamesTheVerdictsShells) {
  const ShellNamer names = [](int shell, bool robot) {
    return std::string(robot ? "panel.obj \u203a clip_" : "frame.obj \u203a rail_") + std::to_string(shell);
  };
  EXPECT_EQ(NameShells("rigid shell 11 (convex, 12 triangles, centre [2500.21, -691.886, 2118.78], size 35.9 x 31.4 x "
                       "10.5) of D against shell 7 (convex, 12 triangles, centre [1, 2, 3], size 1 x 2 x 3) of S, 0.5 "
                       "deep",
                       names),
            "rigid panel.obj \u203a clip_11 of D against frame.obj \u203a rail_7 of S, 0.5 deep");
  const JsonValue v = Parse(R"json({"removable": true, "exact_check": {"rigid_tolerance": 0.05,
    "max_rigid_penetration": 0.02, "rigid_part": "shell 3 (convex, 12 triangles, centre [0, 0, 0], size 1 x 1 x 1)",
    "static_part": "shell 4 (open, 2 triangles, centre [0, 0, 0], size 1 x 1 x 0)"}})json");
  EXPECT_EQ(MakeHeadline(&v, "", nullptr, "mm", names).sentence,
            "D comes out of S along a path; its rigid part penetrates S at most 0.02 mm of the 0.05 mm allowed, "
            "deepest where panel.obj \u203a clip_3 meets frame.obj \u203a rail_4.");
  ExpectPlainWords(MakeHeadline(&v, "", nullptr, "mm", names).sentence);
}

TEST(ReportHeadline, NoVerdictSaysSo) {
  const Headline h = MakeHeadline(nullptr, "no verdict.json", nullptr, "mm");
  EXPECT_EQ(h.verdict, "NO VERDICT");
  EXPECT_EQ(h.sentence, "no verdict.json; no path is shown.");
  const JsonValue odd = Parse(R"({"status": "maybe"})");
  EXPECT_EQ(MakeHeadline(&odd, "", nullptr, "").verdict, "NO VERDICT");
  const JsonValue status = Parse(R"({"status": "not-removable"})");
  EXPECT_EQ(MakeHeadline(&status, "", nullptr, "").verdict, "NOT REMOVABLE");
}

TEST(ReportProfile, FindsColumnsByNamePrefixAndSkipsComments) {
  const fs::path dir = testing::MakeTempDir("report-profile");
  WriteText(dir / "old.csv",
            "segment,fraction,s,volume,part,deformability,clearance\n0,0.000000,0,,,,0\n0,1.000000,0.5,,,,0.25\n");
  const Profile old = ReadProfileCsv(dir / "old.csv");
  ASSERT_EQ(old.rows.size(), 2u);
  EXPECT_FALSE(old.has_volume);
  EXPECT_EQ(old.rows[1].clearance, 0.25);
  EXPECT_TRUE(std::isnan(old.rows[1].volume));

  WriteText(dir / "new.csv",
            "# ausbau-smooth profile, units mm\nsegment,fraction,s,tx,ty,tz,qw,qx,qy,qz,volume_mm3,clearance_mm\n"
            "0,0,0,1,2,3,1,0,0,0,4.5,0\n\n1,0.5,1,1,2,3,1,0,0,0,0,0.75\r\n");
  const Profile now = ReadProfileCsv(dir / "new.csv");
  ASSERT_EQ(now.rows.size(), 2u);
  EXPECT_TRUE(now.has_volume);
  EXPECT_EQ(now.volume_column, "volume_mm3");
  EXPECT_EQ(now.rows[0].volume, 4.5);
  EXPECT_EQ(now.rows[1].segment, 1);
  EXPECT_EQ(now.rows[1].fraction, 0.5);
  EXPECT_EQ(now.rows[1].clearance, 0.75);

  WriteText(dir / "bad.csv", "segment,fraction\n0,x\n");
  EXPECT_THROW(ReadProfileCsv(dir / "bad.csv"), InputError);
  WriteText(dir / "nocols.csv", "a,b\n0,1\n");
  EXPECT_THROW(ReadProfileCsv(dir / "nocols.csv"), InputError);
  fs::remove_all(dir);
}

// Two named objects in one OBJ file, one in another: the parts keep the
// names and cover the triangles in order; the names reach the report's parts.
TEST(ReportParts, NamesComeFromTheMeshFilesNodes) {
  const fs::path dir = testing::MakeTempDir("report-parts");
  const std::string quad_a = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
  WriteText(dir / "static.obj", "o bracket_left\n" + quad_a + "f 1 2 3\nf 1 3 4\no bracket_right\n" +
                                    "v 5 0 0\nv 6 0 0\nv 6 1 0\nf 5 6 7\n");
  WriteText(dir / "dynamic.obj", "o pin\nv 0 0 2\nv 1 0 2\nv 0 1 2\nf 1 2 3\n");
  const MeshFile file = LoadMeshFile(dir / "static.obj");
  ASSERT_EQ(file.Merged().triangles.size(), 3u);
  ASSERT_EQ(file.parts.size(), 2u);
  EXPECT_EQ(file.Part(0).name.substr(0, 12), "bracket_left");
  EXPECT_EQ(file.Part(0).mesh.triangles.size(), 2u);
  EXPECT_EQ(file.Part(1).name.substr(0, 13), "bracket_right");
  EXPECT_EQ(file.Part(1).mesh.triangles.size(), 1u);

  WriteText(dir / "scene.yaml", "format: ausbau-scene/1\nname: parts\nstatic: [static.obj]\ndynamic: dynamic.obj\n");
  const Scene scene = LoadScene(dir / "scene.yaml");
  const PartNamer namer(scene, nullptr);
  EXPECT_EQ(namer.Triangle(0, false).rfind("static.obj \u203a bracket_left", 0), 0u) << namer.Triangle(0, false);
  EXPECT_EQ(namer.Triangle(2, false).rfind("static.obj \u203a bracket_right", 0), 0u) << namer.Triangle(2, false);
  EXPECT_EQ(namer.Triangle(0, true).rfind("dynamic.obj \u203a pin", 0), 0u) << namer.Triangle(0, true);
  EXPECT_EQ(namer.Triangle(-1, true), "\u2013");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ausbau
