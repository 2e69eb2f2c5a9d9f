// `tiltfield check SCENE [--oriented CSV] [--machine JSON] [--mesh FILE]`: loads and validates files
// without doing any job, and prints what it found. Lets a user (or a script) find a bad input before a
// long run; exit 2 with the file and field/line of the first problem.
#include <iostream>

#include "cli.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/machine.hpp"
#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/oriented_path.hpp"
#include "tiltfield/core/scene.hpp"

namespace tf::cli {

namespace {

// What a scene can use the mesh as: a stock or a design must bound a solid with its faces outward (a scene
// refuses the others); a check surface or a fixture may be an open shell.
std::string mesh_summary(const Mesh& m) {
  std::string out = std::to_string(m.n_faces()) + " triangles, ";
  if (!is_closed(m)) return out + "open (a check surface or fixture; not a stock or a closed design)";
  const double v = signed_volume(m);
  if (v > 0.0) return out + "closed, faces outward, volume " + fixed(v, 3) + " mm3";
  return out + "closed but its faces point inward (volume " + fixed(v, 3) +
         " mm3): refused as a stock or design; reverse the faces' order";
}

}  // namespace

void add_check_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("check", "loads and validates a scene (and optionally other input files)");
  static std::string scene, oriented, machine, mesh;
  cmd->add_option("SCENE", scene, "scene JSON");
  cmd->add_option("--oriented", oriented, "an oriented path CSV to validate");
  cmd->add_option("--machine", machine, "a machine JSON to validate");
  cmd->add_option("--mesh", mesh, "a mesh file to validate");
  cmd->callback([] {
    if (scene.empty() && oriented.empty() && machine.empty() && mesh.empty())
      throw InputError("", 0, "SCENE", "nothing to check: give a scene, --oriented, --machine or --mesh");
    if (!scene.empty()) {
      const Scene s = load_scene(scene);
      size_t check_faces = 0;
      for (const auto& c : s.check_surfaces) check_faces += c.n_faces();
      std::cout << "scene " << scene << ": design " << s.design.n_faces() << " triangles, "
                << s.check_surfaces.size() << " check surface(s) with " << check_faces << " triangles, "
                << s.fixtures.size() << " fixture(s), tool " << s.tool.type_name() << " R"
                << fixed(s.tool.radius(), 3) << " gauge " << fixed(s.tool.length, 3) << ", path "
                << s.path.rows.size() << " rows over "
                << fixed(s.path.rows.empty() ? 0.0 : s.path.arc_length().back(), 1) << " mm, machine "
                << (s.machine ? std::string(to_string(s.machine->kinematics)) : std::string("none")) << "\n";
      for (const ToolEntry& e : s.tools)
        std::cout << "  tool T" << e.number << ": " << e.tool.type_name() << " R" << fixed(e.tool.radius(), 3)
                  << " gauge " << fixed(e.tool.length, 3) << "\n";
      for (const auto& [code, w] : s.work_offsets)
        std::cout << "  work offset " << code << ": X" << fixed(w[0], 3) << " Y" << fixed(w[1], 3) << " Z"
                  << fixed(w[2], 3) << " A" << fixed(w[3], 3) << " B" << fixed(w[4], 3) << " C" << fixed(w[5], 3) << "\n";
    }
    if (!oriented.empty()) {
      const OrientedPath o = read_oriented_csv(oriented);
      // Checked against the scene's path as `post` and `replan` read them: row for row.
      if (!scene.empty()) {
        const Scene s = load_scene(scene);
        if (!s.path.rows.empty()) require_rows_of_path(o, s.path, oriented);
      }
      std::cout << "oriented path " << oriented << ": " << o.rows.size() << " rows\n";
    }
    // Each file is read whole before its line is printed: a bad one leaves no half line on stdout.
    if (!machine.empty()) {
      const MachineSpec m = read_machine_json(machine);
      std::cout << "machine " << machine << ": " << to_string(m.kinematics) << "\n";
    }
    if (!mesh.empty()) {
      // Its summary first: the operands of << run in order, and "mesh X: " had been printed before a bad
      // file's error (black-box testing).
      const std::string summary = mesh_summary(load_mesh(mesh));
      std::cout << "mesh " << mesh << ": " << summary << "\n";
    }
  });
}

}  // namespace tf::cli
