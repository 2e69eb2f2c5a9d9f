// tiltfield grind: cross-section simulation of tool grinding (docs/grinding.md).
#include <cmath>
#include <iostream>

#include "cli.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/grind/sections.hpp"

namespace tf::cli {

void add_grind_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("grind", "cross-section simulation of tool grinding");
  struct Args {
    std::string scene, out, svg;
    grind::SectionOptions sections;
  };
  static Args args;  // CLI11 binds to storage that outlives the parse; one command line per process
  cmd->add_option("GRIND", args.scene, "grinding scene JSON")->required();
  cmd->add_option("-o,--output", args.out, "tool mesh (PLY; .stl/.obj/.off also accepted)")->required()->check(output_file());
  cmd->add_option("--sections", args.svg, "also write the sections as an SVG")->check(output_file());
  cmd->add_option("--spacing", args.sections.spacing, "section spacing, mm")->capture_default_str();
  cmd->add_option("--step", args.sections.step, "largest relative motion per increment, mm")->capture_default_str();
  cmd->callback([] {
    if (!(args.sections.spacing >= 0.001) || !std::isfinite(args.sections.spacing))
      throw InputError("", 0, "--spacing", "must be a number of at least 0.001 mm");
    if (!(args.sections.step >= 0.001) || !std::isfinite(args.sections.step))
      throw InputError("", 0, "--step", "must be a number of at least 0.001 mm");
    const grind::GrindScene scene = grind::load_grind_scene(args.scene);
    check_outputs_apart({{"-o", args.out}, {"--sections", args.svg}}, {args.scene, scene.program});
    // Longer than the blank, the sections are its two ends and nothing between (black-box testing: a tip cut
    // came out at half its volume, without a word).
    if (args.sections.spacing >= scene.blank.length * (1.0 - 1e-9))
      throw InputError("", 0, "--spacing", "is as long as the blank (" + fixed(scene.blank.length, 3) +
                                               " mm) or longer: the sections would be its two ends only");
    if (scene.blank.length / args.sections.spacing > 1e6)
      throw InputError("", 0, "--spacing", "more than a million sections: use a larger spacing");
    const double need = grind::minimum_section_bytes(scene, args.sections), have = available_memory_bytes();
    if (have > 0 && need > have)
      throw InputError("", 0, "--spacing", "the sections need at least " + fixed(need / 1e9, 1) + " GB, this machine has " +
                                               fixed(have / 1e9, 1) + " GB available: use a larger spacing");
    const Progress progress = terminal_progress();
    const grind::SectionStack stack = grind::simulate_sections(scene, args.sections, progress);
    grind::TilingStats stats;
    const Mesh mesh = grind::tile_sections(stack, {}, &stats);
    if (mesh.n_faces() == 0) throw JobError("the program grinds the whole blank away: no tool left");
    if (!is_closed(mesh)) throw JobError("the rebuilt tool surface is not closed (please report this scene)");
    if (!args.svg.empty()) grind::write_sections_svg(stack, args.svg);
    write_mesh(mesh, args.out);
    if (!global_options().quiet) {
      std::cerr << "grind: " << stack.sections.size() << " sections, " << mesh.n_faces() << " triangles, volume "
                << fixed(signed_volume(mesh), 3) << " mm3, " << stats.branching_groups << " branching groups, "
                << stats.fallback_slabs << " stair-stepped slabs\n";
      // Both had passed without a word: the mesh the plain blank, or two tools (black-box testing).
      if (stack.sections_ground == 0)
        std::cerr << "warning: the wheel takes no material from any section: the tool is the blank\n";
      if (const size_t pieces = connected_pieces(mesh); pieces > 1)
        std::cerr << "warning: the tool comes out in " << pieces << " separate pieces (the program grinds through the blank)\n";
    }
  });
}

}  // namespace tf::cli
