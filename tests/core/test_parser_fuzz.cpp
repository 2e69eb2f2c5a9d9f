// Mutation fuzzing of every core parser: whatever the bytes, a parser returns a value or throws
// tf::InputError; it never crashes, hangs or throws anything else (run under ASan+UBSan in CI).
#include <gtest/gtest.h>

#include <random>

#include "scene_fixture.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/machine.hpp"
#include "tiltfield/core/oriented_path.hpp"

namespace {

std::string mutate(std::string s, std::mt19937& rng) {
  static const std::string alphabet = "0123456789.,-+eE \n\t/$()[]{}\":naifINFGOTxyz\x01\xff";
  std::uniform_int_distribution<int> op(0, 4);
  const int edits = 1 + static_cast<int>(rng() % 6);
  for (int e = 0; e < edits; ++e) {
    const size_t pos = s.empty() ? 0 : rng() % s.size();
    const char c = alphabet[rng() % alphabet.size()];
    switch (op(rng)) {
      case 0: if (!s.empty()) s[pos] = c; break;
      case 1: s.insert(s.begin() + static_cast<long>(pos), c); break;
      case 2: if (!s.empty()) s.erase(pos, 1 + rng() % 8); break;
      case 3: s = s.substr(0, pos); break;
      default: if (!s.empty()) s.insert(pos, s.substr(rng() % s.size(), 1 + rng() % 16)); break;
    }
  }
  return s;
}

template <class Parse>
void fuzz(const std::string& seed, const std::filesystem::path& file, Parse parse, int rounds) {
  std::mt19937 rng(12345);
  int accepted = 0, refused = 0;
  for (int i = 0; i < rounds; ++i) {
    tf::test::write_text(file, mutate(seed, rng));
    try {
      parse(file);
      ++accepted;
    } catch (const tf::InputError&) {
      ++refused;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "round " << i << ": " << typeid(e).name() << ": " << e.what() << "\n"
                    << tf::test::read_text(file);
      return;
    }
  }
  EXPECT_GT(refused, 0);  // the mutations do reach the error paths
  EXPECT_EQ(accepted + refused, rounds);
}

TEST(ParserFuzz, ToolPathCsv) {
  tf::test::TempDir dir;
  fuzz(tf::test::valid_path_csv(), dir / "p.csv", [](const auto& f) { tf::read_toolpath_csv(f); }, 800);
}

TEST(ParserFuzz, AptCldata) {
  tf::test::TempDir dir;
  tf::Tool tool;
  fuzz("MULTAX/ON\nRAPID\nGOTO/0,0,50,0,0,1\nFEDRAT/MMPM,900\nGOTO/10,0,0,0,0,1\nGOTO/10,5,0,$\n0.6,0,0.8\nFINI\n",
       dir / "p.apt", [&](const auto& f) { tf::read_toolpath_apt(f, tool); }, 800);
}

TEST(ParserFuzz, OrientedCsv) {
  tf::test::TempDir dir;
  fuzz("x,y,z,i,j,k,lead_deg,tilt_deg,clearance_mm,feed\n0,0,0,0,0,1,0,0,1,100\n1,0,0,0,0.6,0.8,3,4,inf,\n",
       dir / "o.csv", [](const auto& f) { tf::read_oriented_csv(f); }, 800);
}

TEST(ParserFuzz, MachineJson) {
  tf::test::TempDir dir;
  fuzz(tf::test::valid_machine_json(), dir / "m.json", [](const auto& f) { tf::read_machine_json(f); }, 800);
}

TEST(ParserFuzz, SceneJson) {
  tf::test::TempDir dir;
  const auto file = tf::test::write_scene(dir, tf::test::valid_scene_json());
  fuzz(tf::test::read_text(file), file, [](const auto& f) { tf::load_scene(f); }, 300);
}

TEST(ParserFuzz, Meshes) {
  tf::test::TempDir dir;
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
  fuzz(obj, dir / "m.obj", [](const auto& f) { tf::load_mesh(f); }, 400);
  const std::string off = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n";
  fuzz(off, dir / "m.off", [](const auto& f) { tf::load_mesh(f); }, 400);
  const std::string stl =
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
  fuzz(stl, dir / "m.stl", [](const auto& f) { tf::load_mesh(f); }, 400);
}

}  // namespace

namespace {
TEST(ParserFuzz, PlyAndBinaryStl) {
  tf::test::TempDir dir;
  tf::Stock box;
  box.kind = tf::Stock::Kind::Box;
  box.box = {{0, 0, 0}, {1, 1, 1}};
  tf::write_mesh(tf::stock_to_mesh(box), dir / "seed.ply");
  tf::write_mesh(tf::stock_to_mesh(box), dir / "seed.stl");
  fuzz(tf::test::read_text(dir / "seed.ply"), dir / "m.ply", [](const auto& f) { tf::load_mesh(f); }, 400);
  fuzz(tf::test::read_text(dir / "seed.stl"), dir / "m.stl", [](const auto& f) { tf::load_mesh(f); }, 400);
}
}  // namespace
