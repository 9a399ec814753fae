#include <geom/lod/collapse.h>
#include <geom/lod/simplify.h>

#include <cmath>

namespace geom {

const char* to_string(SimplifyStop stop) {
  switch (stop) {
    case SimplifyStop::kTargetReached: return "target reached";
    case SimplifyStop::kMaxError: return "every remaining collapse exceeds max_error";
    case SimplifyStop::kNoValidCollapse:
      return "no valid collapse remains (topology, orientation, quality, boundary or locks)";
    case SimplifyStop::kCancelled: return "cancelled";
  }
  return "unknown";
}

SimplifyResult simplify(const SurfaceMesh& mesh, const SimplifyOptions& options) {
  detail::CollapseEngine engine(mesh, options, false);
  SimplifyResult result;
  result.faces_before = engine.n_triangles_initial();
  const std::size_t target =
      options.target_faces > 0
          ? options.target_faces
          : static_cast<std::size_t>(std::llround(options.ratio * static_cast<double>(result.faces_before)));
  result.stop = engine.run(target);
  result.mesh = engine.extract(&result.vertex_origin);
  result.faces_after = engine.n_triangles();
  result.collapses = engine.n_collapses();
  result.max_quadric_error = engine.max_error();
  return result;
}

}  // namespace geom
