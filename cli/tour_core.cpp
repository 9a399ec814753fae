// Tour step "core": the topology of the input, the half-edge checks, and a repaired copy.

#include "tour.h"

#include <geom/core/topology.h>
#include <geom/core/validate.h>

namespace geom::cli {

namespace {

std::vector<std::pair<std::string, std::string>> topology_rows(const TopologyReport& t) {
  std::string sizes;
  for (const auto& [corners, count] : t.face_sizes)
    sizes += (sizes.empty() ? "" : ", ") + std::to_string(count) + " × " +
             std::to_string(corners) + "-gon";
  auto yes = [](bool b) { return std::string(b ? "yes" : "no"); };
  return {{"vertices", std::to_string(t.vertices)},
          {"edges", std::to_string(t.edges)},
          {"faces", std::to_string(t.faces)},
          {"face sizes", sizes.empty() ? "-" : sizes},
          {"boundary loops", std::to_string(t.boundary_loops)},
          {"components", std::to_string(t.components)},
          {"Euler characteristic χ", std::to_string(t.euler_characteristic)},
          {"genus", t.genus ? std::to_string(*t.genus) : "n/a (not an orientable manifold)"},
          {"closed", yes(t.closed)},
          {"manifold", yes(t.manifold)},
          {"orientable", yes(t.orientable)}};
}

}  // namespace

void tour_core(TourContext& tour) {
  tour.heading("The input as given");
  const TopologyReport given = analyze(tour.soup);
  tour.text("`geom info " + tour.input + "` — the surface form of Euler's formula, "
            "χ = V − E + F = 2(C − G) − H, with H the boundary loops.");
  tour.table(topology_rows(given));

  tour.preview(tour.stem + ".png", tour.mesh, "the input");

  tour.heading("Building the half-edge mesh");
  if (tour.build_report.changed()) {
    std::string changes;
    for (const auto& m : tour.build_report.messages) changes += "- " + m + "\n";
    tour.text("Building the mesh changed the input:\n\n" + changes);
  } else {
    tour.text("The input built into a half-edge mesh without any change.");
  }
  const ValidationReport structure = validate(tour.mesh);
  tour.text(structure.ok() ? "`validate()`: every half-edge invariant holds."
                           : "`validate()` found problems:\n\n```\n" + structure.to_string() +
                                 "\n```");
  const TopologyReport built = analyze(tour.mesh);

  tour.heading("Repair");
  BuildOptions repair;
  repair.weld_tolerance = 0.0;
  repair.drop_unreferenced = true;
  const BuildResult repaired = build(tour.soup, repair);
  tour.write_mesh(tour.stem + "_repaired.obj", repaired.mesh,
                  "repaired: exact duplicates welded, unused vertices dropped, oriented");
  std::string lines;
  for (const auto& m : repaired.report.messages) lines += "- " + m + "\n";
  tour.text("`geom repair` (weld exact duplicates, drop degenerate faces and unused vertices, "
            "orient, split non-manifold elements) wrote `" + tour.stem + "_repaired.obj`" +
            (lines.empty() ? std::string(": nothing needed repair.") : ":\n\n" + lines));

  tour.record({{"input", to_json(given)},
               {"build", to_json(tour.build_report)},
               {"validate", {{"ok", structure.ok()}, {"problems", structure.problems}}},
               {"built", to_json(built)},
               {"repair", to_json(repaired.report)}});
}

}  // namespace geom::cli
