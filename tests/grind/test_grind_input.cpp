// Grinding scene and program input: bad input is refused with file and field or line (exit 2, no output).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "test_support.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/grind/grind.hpp"
#include "tiltfield/grind/sections.hpp"
#include "tiltfield/core/mesh.hpp"

namespace tf::grind {
namespace {

using nlohmann::json;

json valid_scene() {
  return json::parse(R"({"units": "mm", "blank": {"radius": 3, "length": 6},
    "wheel": {"radius": 20, "thickness": 3, "edge_radius": 0.5},
    "start": {"y": 60}, "program": "prog.ngc"})");
}

const char* kProgram = "; test\nOP fluting slot\nG0 X0 Y40 Z30\nG1 Y21.5 F100\nG1 Z0\nG0 Y40\n";

struct Case {
  std::string name;
  std::function<void(json&, std::string&)> mutate;
  std::string expect;  // substring of the error line
};

std::vector<Case> cases() {
  return {
      {"missing blank radius", [](json& j, std::string&) { j["blank"].erase("radius"); }, "field 'blank.radius': missing"},
      {"negative blank radius", [](json& j, std::string&) { j["blank"]["radius"] = -2; }, "blank.radius"},
      {"blank too thin", [](json& j, std::string&) { j["blank"]["radius"] = 1e-7; }, "blank.radius': must be at least"},
      {"negative wheel radius", [](json& j, std::string&) { j["wheel"]["radius"] = -20; }, "wheel.radius"},
      {"negative edge radius", [](json& j, std::string&) { j["wheel"]["edge_radius"] = -1; }, "wheel.edge_radius"},
      {"string length", [](json& j, std::string&) { j["blank"]["length"] = "six"; }, "blank.length"},
      {"unknown key", [](json& j, std::string&) { j["wheel"]["colour"] = 1; }, "wheel.colour"},
      {"missing wheel", [](json& j, std::string&) { j.erase("wheel"); }, "field 'wheel'"},
      {"missing program file", [](json& j, std::string&) { j["program"] = "nope.ngc"; }, "nope.ngc"},
      {"unknown axis word", [](json&, std::string& p) { p += "G1 Q5\n"; }, "prog.ngc:7: field 'Q5'"},
      {"garbage number", [](json&, std::string& p) { p += "G1 X1.2.3\n"; }, "prog.ngc:7: field 'X'"},
      {"unknown G code", [](json&, std::string& p) { p += "G2 X1\n"; }, "prog.ngc:7: field 'G2'"},
      {"unknown operation", [](json&, std::string& p) { p += "OP drilling\nG1 X1\n"; }, "prog.ngc:7: field 'OP'"},
      {"motion before OP", [](json&, std::string& p) { p = "G1 X1\n" + p; }, "prog.ngc:1"},
      {"empty program name", [](json& j, std::string&) { j["program"] = ""; }, "field 'program': is empty"},
      {"exponent notation", [](json&, std::string& p) { p += "G0 Y1e7\n"; }, "prog.ngc:7: field 'Y1e7': exponent"},
      {"exponent after a point", [](json&, std::string& p) { p += "G0 X1.e3\n"; }, "prog.ngc:7: field 'X1.e3': exponent"},
      {"linear axis out of range", [](json&, std::string& p) { p += "G0 Y9000000\n"; },
       "prog.ngc:7: field 'Y9000000': puts Y at 9000000.000 mm, beyond +-100000 mm"},
      {"incremental axis out of range", [](json&, std::string& p) { p += "G91\nG0 U60000\nU60000\n"; },
       "prog.ngc:9: field 'U60000': puts U at 120000.000 mm"},
      {"rotary axis out of range", [](json&, std::string& p) { p += "G0 A720000\n"; }, "field 'A720000': puts A at"},
      {"start out of range", [](json& j, std::string&) { j["start"]["x"] = -2e5; }, "field 'start.x': puts X at"},
      {"axis word twice", [](json&, std::string& p) { p += "G1 Y44 Y50\n"; }, "prog.ngc:7: field 'Y50': a second Y word"},
      {"motion G code twice", [](json&, std::string& p) { p += "G0 G1 X1\n"; }, "prog.ngc:7: field 'G1': a second motion"},
      {"feed twice", [](json&, std::string& p) { p += "G1 X1 F10 F20\n"; }, "prog.ngc:7: field 'F20'"},
      {"blank radius beyond travel", [](json& j, std::string&) { j["blank"]["radius"] = 1e308; }, "field 'blank.radius': is 1e+308"},
      {"blank length beyond travel", [](json& j, std::string&) { j["blank"]["length"] = 1e9; }, "field 'blank.length'"},
      {"wheel beyond travel", [](json& j, std::string&) { j["wheel"]["radius"] = 1e7; }, "field 'wheel.radius'"},
      {"control byte in the program", [](json&, std::string& p) { p += std::string("G1 X1", 5) + '\0' + "Y2\n"; }, "prog.ngc:7: field '0x00': binary data"},
      {"program is a directory", [](json& j, std::string&) { j["program"] = "."; }, "is a directory"},
      {"concave profile",
       [](json& j, std::string&) {
         j["wheel"].erase("edge_radius");
         j["wheel"]["profile"] = json::parse("[[-1.5, 20], [0, 18], [1.5, 20]]");
       },
       "wheel.profile[1]': profile must be convex (rho concave in t): this point lies 2 mm inside"},
      {"concave beyond the rounding",  // 2 um inside the line through its neighbours
       [](json& j, std::string&) {
         j["wheel"].erase("edge_radius");
         j["wheel"]["profile"] = json::parse("[[-1.5, 20], [0, 19.998], [1.5, 20]]");
       },
       "wheel.profile[1]"},
  };
}

// Writes the case's scene and program into dir.
void write_case(const Case& c, const test::TempDir& dir) {
  json j = valid_scene();
  std::string prog = kProgram;
  c.mutate(j, prog);
  test::write_text(dir / "grind.json", j.dump());
  test::write_text(dir / "prog.ngc", prog);
}

TEST(GrindInput, LoaderNamesFileAndField) {
  for (const Case& c : cases()) {
    test::TempDir dir;
    write_case(c, dir);
    try {
      load_grind_scene(dir / "grind.json");
      ADD_FAILURE() << c.name << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.expect), std::string::npos) << c.name << ": " << e.what();
    }
  }
}

// A profile written to 4 decimals may come up to 0.05 um inside the line through its neighbours: taken as
// on it, not refused (black-box testing: a rounded arc had been refused as not convex).
TEST(GrindInput, AProfileRoundedToFourDecimalsIsAccepted) {
  test::TempDir dir;
  write_case({"rounded", [](json& j, std::string&) {
                j["wheel"].erase("edge_radius");
                j["wheel"]["profile"] = json::parse("[[-1.5, 20], [0, 19.99995], [1.5, 20]]");
              }, ""},
             dir);
  EXPECT_NO_THROW(load_grind_scene(dir / "grind.json"));
}

TEST(GrindInput, CliExitsTwoWithOneLineAndNoOutput) {
  for (const Case& c : cases()) {
    test::TempDir dir;
    write_case(c, dir);
    const auto r = test::run_tiltfield("grind grind.json -o tool.ply --sections s.svg", dir.path());
    EXPECT_EQ(r.exit_code, 2) << c.name << ": " << r.out;
    EXPECT_EQ(test::count_lines(r.out), 1) << c.name << ": " << r.out;
    EXPECT_NE(r.out.find(c.expect), std::string::npos) << c.name << ": " << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir / "tool.ply")) << c.name;
    EXPECT_FALSE(std::filesystem::exists(dir / "s.svg")) << c.name;
  }
}

// A key given twice (the parser kept the last one), a NUL byte after the object (accepted), an infinite
// --spacing (two sections) and a directory given as the scene (exit 1 before).
TEST(GrindInput, DuplicateKeysAndADirectoryAreBadInput) {
  test::TempDir dir;
  test::write_text(dir / "prog.ngc", kProgram);
  test::write_text(dir / "grind.json", R"({"blank": {"radius": 3, "length": 6, "radius": 4},
    "wheel": {"radius": 20, "thickness": 3}, "program": "prog.ngc"})");
  auto r = test::run_tiltfield("grind grind.json -o tool.ply", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.out.find("field 'blank.radius': appears twice"), std::string::npos) << r.out;
  // A NUL byte after the object ended the parser's input: the rest was never read.
  test::write_text(dir / "nul.json", std::string(R"({"blank": {"radius": 3, "length": 6}, "wheel": {"radius": 20, "thickness": 3},
    "program": "prog.ngc"})") + std::string(1, '\0') + "garbage");
  r = test::run_tiltfield("grind nul.json -o tool.ply", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.out.find("nul.json:2: binary data"), std::string::npos) << r.out;
  r = test::run_tiltfield("grind grind.json -o tool.ply --spacing inf", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.out;
  // A spacing longer than the blank: its two ends only (black-box testing: half a tip cut's volume).
  test::write_text(dir / "ok.json", R"({"blank": {"radius": 3, "length": 6}, "wheel": {"radius": 20, "thickness": 3},
    "program": "prog.ngc"})");
  for (const char* spacing : {"7", "6"}) {
    r = test::run_tiltfield(std::string("grind ok.json -o tool.ply --spacing ") + spacing, dir.path());
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.out.find("'--spacing': is as long as the blank (6 mm) or longer"), std::string::npos) << r.out;
    EXPECT_EQ(test::count_lines(r.out), 1) << r.out;
  }
  std::filesystem::create_directory(dir / "scene.json");
  r = test::run_tiltfield("grind scene.json -o tool.ply", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_EQ(test::count_lines(r.out), 1) << r.out;
  EXPECT_NE(r.out.find("is a directory"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "tool.ply"));
}

TEST(GrindInput, CliWritesAClosedPlyAndTheSectionsSvg) {
  test::TempDir dir;
  test::write_text(dir / "grind.json", valid_scene().dump());
  test::write_text(dir / "prog.ngc", kProgram);
  const auto r = test::run_tiltfield("grind grind.json -o tool.ply --sections s.svg --spacing 0.2", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const Mesh mesh = load_mesh(dir / "tool.ply");
  EXPECT_TRUE(is_closed(mesh));
  // A 3 mm slot 1.5 mm deep through a radius-3 blank leaves less than the blank.
  EXPECT_LT(signed_volume(mesh), M_PI * 9 * 6);
  EXPECT_GT(signed_volume(mesh), 0.4 * M_PI * 9 * 6);
  const std::string svg = test::read_text(dir / "s.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("fluting: slot"), std::string::npos);
}

TEST(GrindInput, EndFacedAwayAtTheTipLeavesAClosedTool) {
  // An end-face pass that takes the blank's whole last section (0.01 mm off the tip): the end section is
  // empty, and capping it crashed (found in review).
  test::TempDir dir;
  json scene = json::parse(R"({"blank": {"radius": 5, "length": 30}, "wheel": {"radius": 40, "thickness": 4},
    "start": {"y": 100}, "program": "face.ngc"})");
  test::write_text(dir / "grind.json", scene.dump());
  test::write_text(dir / "face.ngc", "OP end_face face\nG0 W90\nG0 X31.99 Y60 Z0\nG1 Y-60 F100\nG0 Y-100\n");
  const auto r = test::run_tiltfield("grind grind.json -o tool.ply", dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const Mesh mesh = load_mesh(dir / "tool.ply");
  EXPECT_TRUE(is_closed(mesh));
  // At most a section's spacing shorter than the blank less 0.01 mm (the sections stand for their slabs).
  EXPECT_LT(signed_volume(mesh), M_PI * 25 * 29.99);
  EXPECT_GT(signed_volume(mesh), M_PI * 25 * 29.8);
}

// A long move in the air (90 m out and back between the passes) leaves the same tool, and its hundreds of
// thousands of increments, all out of the wheel's reach, are not kept.
TEST(GrindInput, AMoveFarFromTheBlankChangesNothing) {
  test::TempDir dir;
  test::write_text(dir / "grind.json", valid_scene().dump());
  test::write_text(dir / "prog.ngc", kProgram);
  const GrindScene plain = load_grind_scene(dir / "grind.json");
  test::write_text(dir / "prog.ngc", "; test\nOP fluting slot\nG0 X0 Y40 Z30\nG1 Y21.5 F100\nG0 Y90000\nG0 Y21.5\n"
                                     "G1 Z0\nG0 Y40\n");
  const GrindScene detour = load_grind_scene(dir / "grind.json");
  SectionOptions o;
  o.spacing = 0.2;
  const double v0 = signed_volume(tile_sections(simulate_sections(plain, o)));
  const double v1 = signed_volume(tile_sections(simulate_sections(detour, o)));
  EXPECT_NEAR(v1, v0, 1e-9 * v0);
}

// A move that would need more increments than the simulation takes is refused, naming its line, not
// ground with coarser steps than --step asks.
TEST(GrindInput, AMoveNeedingTooManyIncrementsIsRefused) {
  test::TempDir dir;
  test::write_text(dir / "grind.json", valid_scene().dump());
  test::write_text(dir / "prog.ngc", std::string(kProgram) + "G0 Y20000\n");
  const auto r = test::run_tiltfield("grind grind.json -o tool.ply --step 0.001", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_EQ(test::count_lines(r.out), 1) << r.out;
  EXPECT_NE(r.out.find("prog.ngc:7: this move needs more than 10000000 increments of --step 0.001 mm"), std::string::npos)
      << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "tool.ply"));
}

// A grind the machine has not the memory for is refused before the work, naming --spacing: a million
// sections of a large blank had been accepted and ended in std::bad_alloc (black-box testing). The
// estimate is a lower bound of 400 bytes a point of the blank's circle a section (1.4 TB here).
TEST(GrindInput, SectionsBeyondTheMachinesMemoryAreRefused) {
  test::TempDir dir;
  test::write_text(dir / "grind.json", R"({"blank": {"radius": 5000, "length": 1000}, "wheel": {"radius": 40,
    "thickness": 4}, "start": {"y": 6000}, "program": ["OP fluting f", "G0 Y5030", "G1 A360"]})");
  const auto r = test::run_tiltfield("grind grind.json -o tool.ply --spacing 0.001", dir.path());
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_EQ(test::count_lines(r.out), 1) << r.out;
  EXPECT_NE(r.out.find("'--spacing': the sections need at least"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "tool.ply"));
  SectionOptions o;
  o.spacing = 0.001;
  EXPECT_GT(minimum_section_bytes(load_grind_scene(dir / "grind.json"), o), 1e12);
}

// A wheel that never reaches the blank, and a pass that grinds the blank in two, are said (both had passed
// without a word, black-box testing); the end mill gets neither warning.
TEST(GrindInput, NoMaterialTakenAndSeveralPiecesAreWarned) {
  test::TempDir dir;
  const std::string head = R"({"blank": {"radius": 5, "length": 30}, "wheel": {"radius": 40, "thickness": 4},
    "start": {"y": 80}, "program": )";
  test::write_text(dir / "air.json", head + R"(["OP fluting f", "G0 Y60", "G1 A360", "G1 Z50"]})");
  test::write_text(dir / "two.json", head + R"(["OP notching cut", "G0 W90 X15 Y40 Z0", "G1 Y-40", "G0 Y80"]})");
  const std::string grind = "cd '" + dir.path().string() + "' && '" + TILTFIELD_EXE + "' grind ";  // not quiet
  auto r = test::run_command(grind + "air.json -o air.ply --spacing 0.5");
  EXPECT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("warning: the wheel takes no material from any section"), std::string::npos) << r.out;
  r = test::run_command(grind + "two.json -o two.ply --spacing 0.5");
  EXPECT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("warning: the tool comes out in 2 separate pieces"), std::string::npos) << r.out;
  EXPECT_EQ(connected_pieces(load_mesh(dir / "two.ply")), 2u);
  EXPECT_EQ(r.out.find("no material"), std::string::npos) << r.out;
}

TEST(GrindInput, ProgramModesAndComments) {
  const auto ops = parse_grind_program(
      "OP gashing g (comment) \nN10 G91 G1 X1 Y2 ; rest\nX1\nG90 G0 A30 W-5\nOP notching\nU2\n", "p", Axes{});
  ASSERT_EQ(ops.size(), 2u);
  EXPECT_EQ(ops[0].label, "g");
  ASSERT_EQ(ops[0].moves.size(), 3u);
  EXPECT_DOUBLE_EQ(ops[0].moves[1].target.x, 2.0);  // incremental
  EXPECT_DOUBLE_EQ(ops[0].moves[1].target.y, 2.0);
  EXPECT_TRUE(ops[0].moves[2].rapid);
  EXPECT_DOUBLE_EQ(ops[0].moves[2].target.a, 30.0);
  EXPECT_DOUBLE_EQ(ops[0].moves[2].target.w, -5.0);
  EXPECT_EQ(ops[1].label, "notching");
  EXPECT_DOUBLE_EQ(ops[1].moves[0].target.u, 2.0);
  EXPECT_DOUBLE_EQ(ops[1].moves[0].target.x, 2.0);  // modal position carried over
}

TEST(GrindInput, KinematicsOfTheAxes) {
  // W swivels the spindle axis from x toward z; A turns the blank, so the wheel turns the other way in B.
  Axes ax;
  ax.w = 90;
  EXPECT_NEAR((wheel_pose(ax).axis - Eigen::Vector3d(0, 0, 1)).norm(), 0, 1e-12);
  ax = {};
  ax.y = 10;
  ax.a = 90;
  EXPECT_NEAR((wheel_pose(ax).centre - Eigen::Vector3d(10, 0, 0)).norm(), 0, 1e-12);
  ax = {};
  ax.u = 4;
  EXPECT_NEAR((wheel_pose(ax).centre - Eigen::Vector3d(0, 0, -4)).norm(), 0, 1e-12);
  // Increments bound the relative motion: a 90 deg turn of a radius-5 blank at step 0.1 mm.
  EXPECT_EQ(increments(Axes{}, Axes{0, 0, 0, 0, 90, 0}, Blank{5, 10}, 0.1), static_cast<int>(std::ceil(5 * M_PI / 2 / 0.1)));
}

}  // namespace
}  // namespace tf::grind
