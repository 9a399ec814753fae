#include <geom/lod/lod_chain.h>
#include <geom/lod/progressive_mesh.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace geom {

namespace {

void check_ratios(const std::vector<double>& ratios) {
  for (double r : ratios)
    if (!(r > 0.0 && r <= 1.0))
      throw InvalidArgument("lod chain: ratios must be in (0, 1], got " + std::to_string(r));
}

void finish(LodLevel& level, const SurfaceMesh& input, const LodChainOptions& options) {
  level.faces = level.mesh.n_faces();
  if (options.measure && !input.is_empty())
    level.error = mesh_distance(input, level.mesh, options.distance);
}

// Positions only: one collapse sequence, each level a prefix of it.
std::vector<LodLevel> from_progressive(const SurfaceMesh& mesh, const LodChainOptions& options) {
  ProgressiveOptions po{.simplify = options.simplify};
  po.simplify.target_faces = 0;
  po.simplify.ratio = *std::min_element(options.ratios.begin(), options.ratios.end());
  ProgressiveMesh pm = ProgressiveMesh::build(mesh, po);
  const double f0 = static_cast<double>(pm.max_faces());
  std::vector<LodLevel> levels;
  for (double r : options.ratios) {
    pm.set_level(pm.vertices_for_faces(static_cast<std::size_t>(std::llround(r * f0))));
    LodLevel level{.mesh = pm.mesh(), .ratio = r};
    finish(level, mesh, options);
    levels.push_back(std::move(level));
  }
  return levels;
}

// With attributes the progressive mesh cannot carry them: each level simplifies the next
// finer one, so the levels still nest and each keeps the input's attributes and seams.
std::vector<LodLevel> from_chained(const SurfaceMesh& mesh, const LodChainOptions& options) {
  std::vector<std::size_t> order(options.ratios.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return options.ratios[a] > options.ratios[b]; });
  std::vector<LodLevel> levels(options.ratios.size());
  const SurfaceMesh* finer = &mesh;
  double f0 = 0;
  for (std::size_t i : order) {
    SimplifyOptions so = options.simplify;
    so.ratio = options.ratios[i];  // the first level: of the input, whose count it reports
    so.target_faces = 0;
    if (finer != &mesh)
      so.target_faces = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(options.ratios[i] * f0)));
    SimplifyResult r = simplify(*finer, so);
    if (finer == &mesh) f0 = static_cast<double>(r.faces_before);
    levels[i] = LodLevel{.mesh = std::move(r.mesh), .ratio = options.ratios[i]};
    finish(levels[i], mesh, options);
    finer = &levels[i].mesh;
  }
  return levels;
}

}  // namespace

std::vector<LodLevel> lod_chain(const SurfaceMesh& mesh, const LodChainOptions& options) {
  check_ratios(options.ratios);
  if (options.ratios.empty()) return {};
  LodChainOptions o = options;
  o.simplify = with_present_attributes(mesh, options.simplify);
  return o.simplify.attributes.any() ? from_chained(mesh, o) : from_progressive(mesh, o);
}

}  // namespace geom
