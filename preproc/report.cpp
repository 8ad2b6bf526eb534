// The one-screen summary that `talus mesh` prints.
#include <iomanip>
#include <ostream>

#include "preproc/preproc.hpp"

namespace talus::preproc {

void print_report(const MeshReport& report, std::ostream& out) {
  const auto flags = out.flags();
  const auto precision = out.precision();
  out << "mesh " << report.scene << " (" << report.geometry << ")\n";
  out << "  background mesh: " << report.nodes << " nodes, " << report.elements << " triangles";
  if (report.quadrilaterals > 0) {
    out << " (crossed: " << report.quadrilaterals << " quadrilaterals";
    if (report.quadrilaterals_cut_in_two > 0)
      out << ", " << report.quadrilaterals_cut_in_two << " of them not convex and cut in two";
    out << ")";
  }
  out << "\n";
  out << "  boundary: " << report.fixed_nodes << " fixed nodes, " << report.roller_nodes << " roller nodes";
  if (report.friction_nodes > 0) out << ", " << report.friction_nodes << " friction nodes";
  out << "\n";
  std::size_t width = 4;
  for (const auto& body : report.bodies) width = std::max(width, body.name.size());
  for (const auto& body : report.bodies) {
    out << "  body " << std::left << std::setw(static_cast<int>(width)) << body.name << std::right << " "
        << std::setw(9) << body.particles << " particles, volume " << std::setprecision(6) << body.particle_volume
        << " m^2 vs polygon " << body.polygon_area << " m^2 (" << std::showpos << std::scientific
        << std::setprecision(1) << 100 * body.relative_difference << std::noshowpos << " %)\n";
    out.flags(flags);
  }
  for (const auto& load : report.loads)
    out << "  load " << load.name << ": carried by " << load.particles << " particles along " << std::setprecision(6)
        << load.length << " m\n";
  out << "  particles: " << report.particles << "\n";
  if (!report.locking_material.empty())
    out << "  note: Mohr-Coulomb material '" << report.locking_material
        << "' on Delaunay triangles with EVS off: they lock in plastic flow at\n"
           "        constant volume, which stiffens the failure and shortens the runout. For a runout,\n"
           "        set [mesh] pattern = \"crossed\" (docs/slope.md, \"Crossed triangles\").\n";
  out << std::fixed << std::setprecision(3) << "  time: gmsh " << report.gmsh_seconds << " s, seeding "
      << report.seeding_seconds << " s, total " << report.seconds << " s\n";
  out.flags(flags);
  out.precision(precision);
}

}  // namespace talus::preproc
