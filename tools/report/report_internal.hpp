// tiltfield report: the pieces report.cpp assembles into the page (not part of the public interface).
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "report.hpp"

namespace tf::reporting {

// The SVG plots in page order: orientation and clearance along the path, then the per-block plots
// (rotary axes, MRR, engaged area, engagement angles). Plots without data say so instead of drawing.
std::vector<std::string> build_plots(const ReportInputs& in);

// "holder – stock": a collision's component and what it met, as the tables and markers name them.
std::string collision_kind(const Collision& c);

// Cumulative arc length (mm) of the oriented rows' cutter locations.
std::vector<double> arc_length(const OrientedPath& path);

// The 3-D view's data (meshes, tool axes, path, collision sites, tool profile) as the viewer script
// reads it; see tools/report/src/viewer.js for the consumer.
nlohmann::json build_scene_json(const ReportInputs& in, const ReportOptions& options);

// The page's style sheet (report_style.cpp).
std::string_view report_css();

// The bundled viewer script (three.js + tools/report/src/*.js), generated at build time; empty when the
// build had no npm (TILTFIELD_REPORT_VIEWER=OFF).
std::string_view viewer_script();

}  // namespace tf::reporting
