#include <geom/lod/lod_chain.h>
#include <geom/lod/progressive_mesh.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace geom {

std::vector<LodLevel> lod_chain(const SurfaceMesh& mesh, const LodChainOptions& options) {
  double smallest = 1.0;
  for (double r : options.ratios) {
    if (!(r > 0.0 && r <= 1.0))
      throw InvalidArgument("lod chain: ratios must be in (0, 1], got " + std::to_string(r));
    smallest = std::min(smallest, r);
  }
  ProgressiveOptions po{.simplify = options.simplify};
  po.simplify.target_faces = 0;
  po.simplify.ratio = smallest;
  ProgressiveMesh pm = ProgressiveMesh::build(mesh, po);
  const double f0 = static_cast<double>(pm.max_faces());
  std::vector<LodLevel> levels;
  levels.reserve(options.ratios.size());
  for (double r : options.ratios) {
    const auto target = static_cast<std::size_t>(std::llround(r * f0));
    pm.set_level(pm.vertices_for_faces(target));
    LodLevel level;
    level.ratio = r;
    level.mesh = pm.mesh();
    level.faces = pm.n_faces();
    if (options.measure && !mesh.is_empty())
      level.error = mesh_distance(mesh, level.mesh, options.distance);
    levels.push_back(std::move(level));
  }
  return levels;
}

}  // namespace geom
