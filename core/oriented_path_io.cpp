#include <algorithm>
#include <cmath>
#include <iterator>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/oriented_path.hpp"

namespace tf {

Eigen::Vector3d row_tip(const OrientedRow& row, const Tool& tool) {
  const Eigen::Vector3d a = row.axis.normalized();
  return tool.tip_at(row.p, row.n, a);
}

namespace {
// The first row whose point lies more than 0.001 mm from its path row's; the row count when none does.
size_t first_row_off_path(const OrientedPath& oriented, const ToolPath& path) {
  for (size_t i = 0; i < path.rows.size(); ++i)
    if ((oriented.rows[i].p - path.rows[i].p).norm() > 1e-3) return i;
  return path.rows.size();
}
}  // namespace

bool attach_path_normals(OrientedPath& oriented, const ToolPath& path) {
  if (oriented.rows.size() != path.rows.size() || first_row_off_path(oriented, path) < path.rows.size()) return false;
  for (size_t i = 0; i < path.rows.size(); ++i) {
    oriented.rows[i].n = path.rows[i].contact_normal();
    oriented.rows[i].approach = path.rows[i].approach;
  }
  return true;
}

void require_rows_of_path(const OrientedPath& oriented, const ToolPath& path, const std::string& file) {
  if (oriented.rows.size() != path.rows.size())
    throw InputError(file, 0, "", "has " + std::to_string(oriented.rows.size()) + " rows, the scene's path " +
                                      std::to_string(path.rows.size()));
  const size_t i = first_row_off_path(oriented, path);
  if (i < path.rows.size())
    throw InputError(file, oriented.rows[i].source_line, "x",
                     "row " + std::to_string(i + 1) + " is not the scene's path row (" + fixed(path.rows[i].p.x(), 4) +
                         ", " + fixed(path.rows[i].p.y(), 4) + ", " + fixed(path.rows[i].p.z(), 4) +
                         "): an oriented path of another path");
}

namespace fs = std::filesystem;

OrientedPath read_oriented_csv(const fs::path& file) {
  const std::string name = file.string();
  const CsvTable t = read_csv(file);
  const char* cols[] = {"x", "y", "z", "i", "j", "k", "lead_deg", "tilt_deg", "clearance_mm"};
  int c[9];
  for (int i = 0; i < 9; ++i) {
    c[i] = t.column(cols[i]);
    if (c[i] < 0)
      throw InputError(name, 1, cols[i], "missing column (header must be x,y,z,i,j,k,lead_deg,tilt_deg,clearance_mm)");
  }
  const int feed_col = t.column("feed");
  for (const auto& h : t.header)
    if (std::find(std::begin(cols), std::end(cols), h) == std::end(cols) && h != "feed")
      throw InputError(name, 1, h, "unknown column (header must be x,y,z,i,j,k,lead_deg,tilt_deg,clearance_mm[,feed])");
  OrientedPath path;
  path.rows.reserve(t.rows.size());
  for (size_t r = 0; r < t.rows.size(); ++r) {
    const int line = t.lines[r];
    double v[9];
    for (int i = 0; i < 9; ++i) {
      // No check surface within reach is written as "inf" clearance.
      if (i == 8 && t.rows[r][c[i]] == "inf") {
        v[i] = std::numeric_limits<double>::infinity();
        continue;
      }
      v[i] = i < 3 ? parse_coordinate(t.rows[r][c[i]], name, line, cols[i]) : parse_number(t.rows[r][c[i]], name, line, cols[i]);
    }
    OrientedRow row;
    row.source_line = line;
    row.p = {v[0], v[1], v[2]};
    Eigen::Vector3d a(v[3], v[4], v[5]);
    const double n = a.norm();
    if (n < 1e-12) throw InputError(name, line, "i,j,k", "zero tool axis");
    if (std::abs(n - 1.0) > 1e-3) throw InputError(name, line, "i,j,k", "tool axis is not a unit vector (length " + fixed(n, 6) + ")");
    // An axis written to 9 decimals is unit within 1e-9: kept as written, so a row re-planning leaves alone
    // is copied to the digit (normalised, its last decimal had moved on rows outside every window).
    row.axis = std::abs(n - 1.0) <= 1e-8 ? a : Eigen::Vector3d(a / n);
    row.lead_deg = v[6];
    row.tilt_deg = v[7];
    row.clearance_mm = v[8];
    if (feed_col >= 0 && !t.rows[r][feed_col].empty()) {
      row.feed = parse_number(t.rows[r][feed_col], name, line, "feed");
      if (row.feed <= 0) throw InputError(name, line, "feed", "must be positive (mm/min)");
    }
    path.rows.push_back(row);
  }
  if (path.rows.empty()) throw InputError(name, 0, "", "oriented path has no rows");
  return path;
}

void write_oriented_csv(const OrientedPath& path, const fs::path& file) {
  bool with_feed = false;
  for (const auto& r : path.rows) with_feed |= std::isfinite(r.feed);
  write_file_atomic(file, [&](std::ostream& out) {
    out << "x,y,z,i,j,k,lead_deg,tilt_deg,clearance_mm" << (with_feed ? ",feed" : "") << "\n";
    for (const auto& r : path.rows) {
      out << fixed(r.p.x(), 9) << ',' << fixed(r.p.y(), 9) << ',' << fixed(r.p.z(), 9) << ',' << fixed(r.axis.x(), 9)
          << ',' << fixed(r.axis.y(), 9) << ',' << fixed(r.axis.z(), 9) << ',' << fixed(r.lead_deg, 6) << ','
          << fixed(r.tilt_deg, 6) << ',' << (std::isfinite(r.clearance_mm) ? fixed(r.clearance_mm, 6) : "inf");
      if (with_feed) out << ',' << (std::isfinite(r.feed) ? fixed(r.feed, 3) : "");
      out << '\n';
    }
  });
}

}  // namespace tf
