// The last block per ray (VerifyOptions::record_last_block) and the block per stock-mesh vertex
// (stock_vertex_blocks), against the closed form: a ball's linear move sweeps a capsule, so the block
// that last shaped a surface point is the last cutting block whose ball-centre segment comes within the
// radius of it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>

#include "helpers.hpp"
#include "moves.hpp"
#include "tiltfield/dexel/stock_blocks.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {
namespace {

constexpr double kRadius = 3.0;

// Two ball slots in a 40 x 30 x 10 box: blocks 2-3 plunge at (8, 15) to the tip at z 8 and run along x
// to x 32; blocks 5-6 plunge at (20, 4) to z 7 and run along y to y 26, across the first slot and deeper.
Program two_slots() {
  return test::Moves()
      .rapid({8, 15, 20})
      .line({.z = 8}, 300)
      .line({.x = 32}, 1000)
      .rapid({.z = 20})
      .rapid({20, 4, 20})
      .line({.z = 7}, 300)
      .line({.y = 26}, 1000)
      .rapid({.z = 20})
      .program();
}

double segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// The closed form at a surface point p: the feed blocks (1-based) whose ball sweeps within `slack` of p.
std::vector<int> blocks_near(const Program& program, const Eigen::Vector3d& p, double slack) {
  std::vector<int> near;
  Joints from = program.start;
  for (size_t i = 0; i < program.blocks.size(); ++i) {
    const Block& b = program.blocks[i];
    const Eigen::Vector3d a(from.x, from.y, from.z + kRadius), e(b.target.x, b.target.y, b.target.z + kRadius);
    if (b.motion != Motion::Rapid && segment_distance(p, a, e) <= kRadius + slack) near.push_back(int(i) + 1);
    from = b.target;
  }
  return near;
}

class StockBlocks : public ::testing::Test {
 protected:
  void SetUp() override {
    scene = test::box_scene({0, 0, 0}, {40, 30, 10}, test::ball_tool(kRadius, 12, kRadius, 30, {{10, 30}}));
    program = two_slots();
    VerifyOptions o;
    o.resolution = 0.2;
    o.record_last_block = true;
    result = verify_program(scene, program, forward_xyz, o);
  }
  Scene scene;
  Program program;
  VerifyResult result;
};

TEST_F(StockBlocks, RaysRecordTheLastBlockThatCutThem) {
  const Lattice& L = result.stock.lattice();
  for (int d = 0; d < 3; ++d) ASSERT_EQ(result.last_block[d].size(), result.stock.grid(d).size());
  // The z ray through (14, 15) is cut by the first slot's run only; the one through (20, 15) last by the
  // second slot's run; the one through (36, 25) by nothing.
  auto z_ray = [&](double x, double y) {
    const int i = int(std::lround((x - L.origin.x()) / L.h)), j = int(std::lround((y - L.origin.y()) / L.h));
    return result.last_block[2][size_t(i) + size_t(L.n[0]) * size_t(j)];
  };
  EXPECT_EQ(z_ray(14, 15), 3u);
  EXPECT_EQ(z_ray(20, 15), 7u);
  EXPECT_EQ(z_ray(20, 6), 7u);
  EXPECT_EQ(z_ray(36, 25), 0u);
  // Recording changes nothing else.
  VerifyOptions plain;
  plain.resolution = 0.2;
  const VerifyResult without = verify_program(scene, program, forward_xyz, plain);
  EXPECT_TRUE(without.last_block[0].empty());
  EXPECT_DOUBLE_EQ(without.report.removed_volume_mm3, result.report.removed_volume_mm3);
}

TEST_F(StockBlocks, VerticesTakeTheBlockThatLastShapedThem) {
  StockMeshOptions mo;
  mo.colour_by_deviation = false;
  const Mesh mesh = reconstruct_stock(result.stock, nullptr, mo);
  const TriDexel initial = make_stock(scene.stock, result.stock.lattice());
  const std::vector<uint32_t> blocks = stock_vertex_blocks(mesh, result.stock, result.last_block, &initial);
  ASSERT_EQ(blocks.size(), mesh.n_vertices());
  const double h = result.stock.lattice().h;
  std::array<size_t, 9> count{};
  size_t agree = 0, compared = 0;
  for (auto v : mesh.vertices()) {
    const Eigen::Vector3d p = to_eigen(mesh.point(v));
    const uint32_t got = blocks[size_t(v.idx())];
    ASSERT_LT(got, count.size());
    ++count[got];
    // Where two blocks' sweeps, or one and a raw face, pass within two spacings of the point (the plunge's
    // ball that the run starts from, the edges where the slots meet each other and the top face) either
    // may have shaped it last: not compared.
    const std::vector<int> near = blocks_near(program, p, 2.0 * h);
    const double to_raw_face = std::min({p.x(), 40.0 - p.x(), p.y(), 30.0 - p.y(), p.z(), 10.0 - p.z()});
    if (near.size() + (to_raw_face <= 2.0 * h ? 1 : 0) > 1) continue;
    ++compared;
    agree += int(got) == (near.empty() ? 0 : near.front());
  }
  EXPECT_GT(count[0], 1000u) << "the raw faces";
  EXPECT_GT(count[3], 100u) << "the first slot's run";
  EXPECT_GT(count[7], 100u) << "the second slot's run";
  EXPECT_EQ(count[1] + count[4] + count[5] + count[8], 0u) << "rapids above the stock cut nothing";
  EXPECT_GT(compared, mesh.n_vertices() / 2);
  EXPECT_EQ(agree, compared);
}

TEST_F(StockBlocks, MismatchedRaysAreRefused) {
  LastBlocks wrong = result.last_block;
  wrong[1].pop_back();
  EXPECT_THROW(stock_vertex_blocks(Mesh(), result.stock, wrong, nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace tf
