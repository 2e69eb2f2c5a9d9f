// tiltfield grind: cross-section simulation of tool grinding and surface tiling between sections.
//
// In: a grinding scene (blank, wheel, program of labelled operations; grind.hpp). Out: the sections of the
// ground tool, the tool's surface mesh tiled between them, and an SVG of the sections. Units: mm, deg.
//
// The blank is cut into planar sections z = const. Each operation sweeps the wheel; in every section the
// wheel's plane sections at consecutive increments are hulled and subtracted from the section (Clipper).
// The surface is rebuilt by tiling consecutive sections (docs/grinding.md).
#pragma once
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "tiltfield/grind/grind.hpp"
#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/progress.hpp"

namespace tf::grind {

struct SectionOptions {
  double spacing = 0.05;            // mm between sections (the last gap is shrunk to end exactly at l)
  double step = 0.25;               // mm, largest relative displacement of the blank within one increment
  double chord_tolerance = 0.002;   // mm, polygonisation of the blank circle and the wheel's rings
  double clean_tolerance = 0.0005;  // mm, vertices closer than this to the line of their neighbours are dropped
  int generators = 180;             // wheel generator lines sampled when a section plane crosses the wheel steeply
};

// A closed contour of a section: outer boundaries counter-clockwise, holes clockwise (material on the left).
// labels[i] is the operation that made edge points[i] -> points[i+1]: 0 for the blank's surface, k for
// operation k-1 of the scene.
struct Contour {
  std::vector<Eigen::Vector2d> points;  // mm, in the section plane (blank x, y)
  std::vector<int> labels;
  bool hole = false;
};

struct Section {
  double z = 0.0;  // mm
  std::vector<Contour> contours;
};

struct SectionStack {
  Blank blank;
  std::vector<Section> sections;        // z increasing, first at 0, last at l
  std::vector<std::string> op_labels;  // op_labels[k] names label k ("blank" for 0)
  int sections_ground = 0;              // sections the wheel took material from
};

// Runs the scene's operations on the sections. `progress` gets the fraction of operations done.
SectionStack simulate_sections(const GrindScene& scene, const SectionOptions& options = {},
                               const Progress& progress = {});

// In: the scene and the options. Out: a lower bound of the memory (bytes) simulate_sections and
// tile_sections need: every section holds at least the blank's circle, about 400 bytes a point with its
// share of the tiled mesh (measured: 46 KB a section of a 111-point circle). A grind of a million sections
// had been accepted and failed with std::bad_alloc.
double minimum_section_bytes(const GrindScene& scene, const SectionOptions& options);

// Area (mm^2) enclosed by a section (holes subtracted).
double section_area(const Section& section);

struct TilingOptions {
  // Each slab between two sections is checked for self-intersection; a slab whose tiles intersect is rebuilt
  // as a stair step (vertical walls to the mid-plane, exact caps there). Off only for benchmarking.
  bool check_slabs = true;
};

struct TilingStats {
  int slabs = 0;
  int tiled_pairs = 0;       // contour pairs tiled by correspondence
  int label_matched = 0;     // of which tiled run by run (same operation labels)
  int branching_groups = 0;  // contour groups that split, merge, appear or vanish: stair-stepped
  int fallback_slabs = 0;    // slabs re-built as stair steps after a self-intersection
};

// Rebuilds the tool surface from the sections: tiles between consecutive contours, branching handled by
// stair steps at the slab's mid-plane, end caps at z = 0 and z = l. Out: closed, outward-oriented mesh (mm).
Mesh tile_sections(const SectionStack& stack, const TilingOptions& options = {}, TilingStats* stats = nullptr);

// Writes an SVG with small multiples of up to `panels` sections evenly chosen along z, edges coloured by
// the operation that made them. Atomic.
void write_sections_svg(const SectionStack& stack, const std::filesystem::path& file, int panels = 24);

}  // namespace tf::grind
