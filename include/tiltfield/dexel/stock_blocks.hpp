// tiltfield dexel: which motion block last cut each place of the machined stock, for colouring the stock
// mesh by block or by tool (the report of `tiltfield verify --html`).
//
// The simulation records per ray only the last block that changed it (VerifyOptions::record_last_block,
// VerifyResult::last_block), not where along the ray. A stock-mesh vertex lies where rays of the three
// grids cross the surface; the block that last moved one of those crossings changed that ray, so each
// such ray's last block is at least the block that last cut its crossing, and it is that block unless the
// ray was cut again later somewhere else along its length. The vertex gets the smallest over the rays
// crossing the surface near it: exact where one of them was last cut there; a later block where every one
// was cut again elsewhere; and where two passes meet (the rays near the vertex shaped by either) possibly
// the earlier pass. An approximation, then, not a bound. A crossing that is still where the raw stock had
// it was not cut at all: block 0 (so a cut wall within 1.5 spacings of an uncut face may read 0).
#pragma once
#include <cstdint>
#include <vector>

#include "tiltfield/core/mesh.hpp"
#include "tiltfield/dexel/tridexel.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {

// In:  `mesh` a stock mesh of `stock` (reconstruct_stock), mm; `last_block` from the same simulation;
//      `initial` the raw stock on the same lattice (make_stock(scene.stock, stock.lattice())), or null.
// Out: per mesh vertex, the 1-based motion block that last cut there (the smallest last block of the rays
//      whose material ends within 1.5 lattice spacings of the vertex, on the four rays of each grid
//      around it); 0 where one of those crossings is the raw stock's own (needs `initial`) or none is
//      found. Throws std::invalid_argument when last_block does not match the stock's grids.
std::vector<uint32_t> stock_vertex_blocks(const Mesh& mesh, const TriDexel& stock, const LastBlocks& last_block,
                                          const TriDexel* initial);

}  // namespace tf
