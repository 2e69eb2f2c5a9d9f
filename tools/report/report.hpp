// tiltfield: the HTML report of a job (`tiltfield run` writes it as report.html).
//
// One self-contained file that opens offline: a summary header, SVG plots along the path (lead/tilt,
// clearance) and per block (rotary axes, MRR, engagement), a 3-D view (three.js, bundled at build time
// and embedded in the binary) of the stock coloured by deviation, the check surfaces and the tool axes
// at sampled rows, and the tables of collisions and gouges with block and G-code line.
// docs/report.md describes the page and how the viewer is built.
//
// Units: mm, deg, mm^3, mm^3/min, mm^2, seconds.
#pragma once
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/oriented_path.hpp"
#include "tiltfield/core/program.hpp"
#include "tiltfield/core/report.hpp"
#include "tiltfield/core/scene.hpp"

namespace tf::reporting {

// The posted program's axis values at the end of each motion block.
struct BlockAxes {
  int block = 0;
  int line = 0;
  Joints joints;  // X Y Z mm, A B C deg
  bool rapid = false;
  bool tcp = false;  // X Y Z are the tool tip in the part frame (tf::Block::tcp), not machine axes
  int tool = 0;      // the tool number in the spindle (tf::Block::tool; 0 when the program selects none)
};

struct StageTime {
  std::string name;  // "plan", "post", "verify", "replan", ...
  double seconds = 0.0;
};

// Row range [first, last] (0-based, inclusive) of the oriented path that the re-planner changed.
struct RowWindow {
  int first = 0;
  int last = 0;
};

// The headline numbers. Negative values mean "not known" and are shown as "-".
struct Summary {
  std::string title;        // e.g. the scene name; default: the scene file's stem
  std::string note;         // one free line under the title (e.g. what is missing from this run)
  int collisions_found = -1;  // by the first verification
  int collisions_fixed = -1;  // by the re-planning
  int collisions_new = -1;    // brought by the re-planning (rows the first program's collisions did not touch)
  double min_clearance_mm = -1.0;
  double removed_volume_mm3 = -1.0;
  double max_gouge_mm = -1.0;
  double resolution_mm = -1.0;  // verifier's dexel spacing
  std::vector<StageTime> stages;
};

// Everything the report shows. Pointers are not owned and must outlive the call; the vectors are
// plain copies the caller fills (from memory or from verify.json / blocks.csv).
struct ReportInputs {
  const Scene* scene = nullptr;               // required: check surfaces, design, tool, path, machine
  const OrientedPath* oriented = nullptr;     // the final oriented path (may be null: no path plots)
  const OrientedPath* first_plan = nullptr;   // the plan before re-planning (optional, drawn grey)
  std::vector<RowWindow> replanned;           // windows the re-planner changed (shaded in the plots)
  std::vector<BlockAxes> axes;                // posted program, one entry per motion block
  std::vector<BlockRow> blocks;               // verifier's per-block table
  std::vector<Collision> collisions;          // collisions left in the final program
  std::vector<Gouge> gouges;
  const Mesh* stock = nullptr;                // simulated stock (optional)
  std::vector<double> stock_deviation_mm;     // per stock vertex: + material left, - cut into the design
                                              // (stock_deviation() computes it)
  // Per stock vertex: the 1-based motion block that last cut there, 0 where the raw stock is left
  // (stock_vertex_blocks in tiltfield_dexel computes it). Colours the stock by block, and by tool
  // (BlockAxes::tool) when the blocks that cut use more than one tool.
  std::vector<uint32_t> stock_block;
  std::optional<StockMeshStats> stock_mesh;   // the bound and sizes of the stock mesh (shown as a card)
  Summary summary;
  // The verification report (JSON) the tables' footnotes send the reader to for what they leave out
  // (empty: none was written).
  std::string report_json = "verify.json";
};

struct ReportOptions {
  // Triangle budget over all meshes in the 3-D view; larger meshes are decimated by vertex clustering.
  // 400k triangles keep the impeller (hub + blades + its 1.15M-triangle stock) at 6.5 MB of HTML.
  size_t max_triangles = 400000;
  int axis_samples = 150;          // tool axes drawn in the 3-D view (evenly spaced rows)
  size_t max_table_rows = 500;     // rows per table; the rest are counted, not listed
  bool include_design = true;      // the design mesh as its own layer
};

// Writes report.html (atomically). Throws std::invalid_argument when inputs.scene is null or the stock
// deviation or blocks have the wrong size, std::runtime_error when the file cannot be written.
void write_html_report(const ReportInputs& inputs, const std::filesystem::path& out_html,
                       const ReportOptions& options = {});

// The same page as a string (what write_html_report writes).
std::string render_html_report(const ReportInputs& inputs, const ReportOptions& options = {});

// Signed distance (mm) of every stock vertex to the design surface: + on the side the design's faces
// face (material left), - behind it (over-cut). The sign comes from the nearest triangle's normal, so
// right at the design's sharp edges it can flip for vertices off to the side (colour only).
std::vector<double> stock_deviation(const Mesh& stock, const Mesh& design);

// The motion blocks of a program as the report plots them: block numbers from 1 in program order (as
// the verifier numbers them), the G-code line, the axis values at the block's end.
std::vector<BlockAxes> block_axes(const Program& program);

// The verification's part of the inputs: the program's axes per block, the per-block rows, collisions and
// gouges of `report`, and `stock` (not owned; may be null) with its deviation from `design` when the
// design has faces (the mesh's own, vertex_deviation, when it carries one: it must then be from the same
// design). What `run` and `verify --html` share.
void set_verification(ReportInputs& inputs, const Program& program, const VerifyReport& report, const Mesh* stock,
                      const Mesh& design);

// The report's inputs read back from the files of a `tiltfield run` folder (oriented.csv,
// program.ngc, verify.json, blocks.csv, stock.ply); a missing file leaves its part empty, a bad one
// throws InputError. The stock's deviation is computed against the scene's design.
struct RunFolder {
  OrientedPath oriented;
  Mesh stock;
  ReportInputs inputs;  // points into this object and at `scene`, which must outlive it
};
std::unique_ptr<RunFolder> load_run_folder(const Scene& scene, const std::filesystem::path& dir);

// True when the 3-D viewer script was built into this binary (npm was available at build time).
bool viewer_built_in();

}  // namespace tf::reporting
