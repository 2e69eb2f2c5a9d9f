// LinuxCNC's interpreter as the judge of the reader's motion: runs `rs274 -g` on a program with a tool
// table and a parameter (.var) file and turns its canonical calls into the machine positions LinuxCNC
// commands: the STRAIGHT_TRAVERSE / STRAIGHT_FEED / ARC_FEED end points (program coordinates; RIGID_TAP's
// point and the way back) plus the
// G5x offset, the G92 offset and the tool length offset in force (SET_G5X_OFFSET, SET_G92_OFFSET,
// USE_TOOL_LENGTH_OFFSET), with the DWELL seconds before each move. rs274 run alone (no INI file) takes
// its tool table and parameters in inches; these helpers write them so.
#pragma once
#include <array>
#include <cstdio>
#include <initializer_list>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "rs274.hpp"
#include "test_support.hpp"

namespace tf::test {

struct CanonMove {
  bool feed = false;           // STRAIGHT_FEED or ARC_FEED
  std::array<double, 6> m{};   // machine X Y Z (mm) A B C (deg)
  double dwell_before = 0.0;   // seconds of DWELL since the previous move
  bool spline = false;         // NURBS_FEED (G5, G5.1): rs274 prints no point of it, m is unknown
};

struct Rs274Run {
  int exit_code = -1;
  std::string output;
  std::vector<CanonMove> moves;
};

// Tool table lines for rs274 from (number, gauge length mm).
inline std::string rs274_tool_table(const std::map<int, double>& lengths) {
  std::string s;
  char buf[128];
  for (const auto& [n, l] : lengths) {
    std::snprintf(buf, sizeof buf, "T%d P%d Z%.10f D0.2\n", n, n, l / 25.4);
    s += buf;
  }
  return s;
}

// A .var file giving coordinate systems 1..9 (G54 ...) their X Y Z (mm) and A B C (deg) offsets.
inline std::string rs274_var_file(const std::map<int, std::array<double, 6>>& systems) {
  std::string s;
  char buf[128];
  for (const auto& [index, o] : systems)
    for (int k = 0; k < 6; ++k) {
      std::snprintf(buf, sizeof buf, "%d %.10f\n", 5201 + 20 * index + k, k < 3 ? o[k] / 25.4 : o[k]);
      s += buf;
    }
  return s;
}

inline std::vector<double> canon_numbers(const std::string& args) {
  std::vector<double> v;
  std::string cleaned = args;
  for (char& c : cleaned)
    if (c == ',') c = ' ';
  std::istringstream in(cleaned);
  for (std::string tok; in >> tok;) {
    try {
      v.push_back(std::stod(tok));
    } catch (...) {
      v.push_back(0.0);  // a name (CANON_PLANE_XY ...): a placeholder keeps the positions
    }
  }
  return v;
}

// Runs rs274 on `program` in `dir` with the given tool table and .var text.
inline Rs274Run run_rs274(const TempDir& dir, const std::string& program, const std::string& tools,
                          const std::string& vars) {
  write_text(dir / "judge.ngc", program);
  write_text(dir / "judge.tbl", tools);
  write_text(dir / "judge.var", vars);
  Rs274Run run;
  const CliResult r = run_command("cd '" + dir.path().string() + "' && " +
                                  rs274_command("-t judge.tbl -v judge.var judge.ngc"));
  run.exit_code = r.exit_code;
  run.output = r.out;
  std::array<double, 6> g5x{}, g92{}, pos{};
  double tlo = 0.0, dwell = 0.0;
  bool inch = false;
  std::string plane = "XY";
  const std::regex call(R"(N[.0-9]+\s+([A-Z_0-9]+)\((.*)\))");
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, call)) continue;
    const std::string name = m[1];
    std::vector<double> v = canon_numbers(m[2]);
    if (name == "USE_LENGTH_UNITS") {
      inch = m[2].str().find("INCHES") != std::string::npos;
      continue;
    }
    // Lengths come in the program's units (G20: inches); the moves are kept in mm.
    auto mm = [&](std::initializer_list<size_t> at) {
      for (size_t k : at)
        if (inch && k < v.size()) v[k] *= 25.4;
    };
    if (name == "SET_G5X_OFFSET") mm({1, 2, 3});
    if (name == "SET_G92_OFFSET" || name == "STRAIGHT_TRAVERSE" || name == "STRAIGHT_FEED" || name == "RIGID_TAP") mm({0, 1, 2});
    if (name == "USE_TOOL_LENGTH_OFFSET") mm({0, 1, 2});
    if (name == "ARC_FEED") mm({0, 1, 2, 3, 5});
    if (name == "SET_G5X_OFFSET" && v.size() >= 7) {
      for (int k = 0; k < 6; ++k) g5x[k] = v[k + 1];
    } else if (name == "SET_G92_OFFSET" && v.size() >= 6) {
      for (int k = 0; k < 6; ++k) g92[k] = v[k];
    } else if (name == "USE_TOOL_LENGTH_OFFSET" && v.size() >= 3) {
      tlo = v[2];
    } else if (name == "SELECT_PLANE") {
      plane = m[2].str().find("XZ") != std::string::npos ? "XZ" : m[2].str().find("YZ") != std::string::npos ? "YZ" : "XY";
    } else if (name == "DWELL" && !v.empty()) {
      dwell += v[0];
    } else if ((name == "STRAIGHT_TRAVERSE" || name == "STRAIGHT_FEED") && v.size() >= 6) {
      for (int k = 0; k < 6; ++k) pos[k] = v[k];
      CanonMove mv;
      mv.feed = name == "STRAIGHT_FEED";
      for (int k = 0; k < 6; ++k) mv.m[k] = pos[k] + g5x[k] + g92[k] + (k == 2 ? tlo : 0.0);
      mv.dwell_before = dwell;
      dwell = 0.0;
      run.moves.push_back(mv);
    } else if (name == "NURBS_FEED") {
      CanonMove mv;
      mv.feed = mv.spline = true;
      run.moves.push_back(mv);
    } else if (name == "RIGID_TAP" && v.size() >= 3) {
      // In to the point and back out to where the tap started (the position does not change).
      for (const bool back : {false, true}) {
        CanonMove mv;
        mv.feed = true;
        for (int k = 0; k < 6; ++k) mv.m[k] = (back || k > 2 ? pos[k] : v[k]) + g5x[k] + g92[k] + (k == 2 ? tlo : 0.0);
        mv.dwell_before = back ? 0.0 : dwell;
        run.moves.push_back(mv);
      }
      dwell = 0.0;
    } else if (name == "ARC_FEED" && v.size() >= 9) {
      // first_end, second_end, first_axis, second_axis, rotation, axis_end_point, a, b, c
      if (plane == "XY") { pos[0] = v[0]; pos[1] = v[1]; pos[2] = v[5]; }
      if (plane == "XZ") { pos[2] = v[0]; pos[0] = v[1]; pos[1] = v[5]; }
      if (plane == "YZ") { pos[1] = v[0]; pos[2] = v[1]; pos[0] = v[5]; }
      pos[3] = v[6];
      pos[4] = v[7];
      pos[5] = v[8];
      CanonMove mv;
      mv.feed = true;
      for (int k = 0; k < 6; ++k) mv.m[k] = pos[k] + g5x[k] + g92[k] + (k == 2 ? tlo : 0.0);
      mv.dwell_before = dwell;
      dwell = 0.0;
      run.moves.push_back(mv);
    }
  }
  return run;
}

}  // namespace tf::test
