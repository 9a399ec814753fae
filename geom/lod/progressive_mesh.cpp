#include <geom/core/from_triangles.h>
#include <geom/lod/collapse.h>
#include <geom/lod/progressive_mesh.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace geom {

using detail::kNone;

std::vector<Point> Geomorph::at(double t) const {
  t = std::clamp(t, 0.0, 1.0);
  std::vector<Point> out(fine.size());
  // Exact endpoints: t = 0 and t = 1 reproduce the two levels bit for bit.
  if (t == 0.0) return coarse;
  if (t == 1.0) return fine;
  for (std::size_t i = 0; i < fine.size(); ++i) out[i] = (1.0 - t) * coarse[i] + t * fine[i];
  return out;
}

ProgressiveMesh ProgressiveMesh::build(const SurfaceMesh& mesh, const ProgressiveOptions& options) {
  // A refit moves every level's vertices at once; vertex splits replay single collapses, so
  // refining could no longer reproduce the input exactly.
  if (options.simplify.refit_iterations > 0)
    throw InvalidArgument("progressive mesh: refit_iterations must be 0 or -1 (a refit is a "
                          "property of one level, not of a collapse sequence)");
  detail::CollapseEngine engine(mesh, options.simplify, true);
  const std::size_t f0 = engine.n_triangles_initial();
  const SimplifyOptions& so = options.simplify;
  const std::size_t target =
      so.target_faces > 0 ? so.target_faces
                          : static_cast<std::size_t>(std::llround(so.ratio * static_cast<double>(f0)));
  engine.run(target);

  const auto& records = engine.records();
  const std::size_t n = engine.vertex_of().size();
  const std::size_t k = records.size();
  ProgressiveMesh pm;

  std::vector<std::uint32_t> pm_vertex(n, kNone);
  std::uint32_t next = 0;
  for (std::uint32_t v = 0; v < n; ++v)
    if (engine.vertex_alive(v)) pm_vertex[v] = next++;
  pm.base_vertices_ = next;
  for (std::size_t i = 0; i < k; ++i) pm_vertex[records[k - 1 - i].u] = next++;

  const auto& tris = engine.original_triangles();
  std::vector<std::uint32_t> pm_face(tris.size(), kNone);
  next = 0;
  for (std::uint32_t t = 0; t < tris.size(); ++t)
    if (engine.triangle_alive(t)) pm_face[t] = next++;
  pm.base_faces_ = next;
  for (std::size_t i = 0; i < k; ++i)
    for (std::uint32_t t : records[k - 1 - i].dead)
      if (t != kNone) pm_face[t] = next++;

  pm.positions_.resize(n);
  pm.vertex_origin_.resize(n);
  for (std::uint32_t v = 0; v < n; ++v) {
    pm.positions_[pm_vertex[v]] = engine.original_positions()[v];
    pm.vertex_origin_[pm_vertex[v]] = engine.vertex_of()[v];
  }
  pm.faces_.resize(tris.size());
  pm.face_origin_.resize(tris.size());
  for (std::uint32_t t = 0; t < tris.size(); ++t) {
    const auto& c = tris[t];
    pm.faces_[pm_face[t]] = {pm_vertex[c[0]], pm_vertex[c[1]], pm_vertex[c[2]]};
    pm.face_origin_[pm_face[t]] = t;
  }

  pm.splits_.resize(k);
  pm.face_prefix_.resize(k);
  std::size_t faces = pm.base_faces_;
  for (std::size_t i = 0; i < k; ++i) {
    const detail::CollapseRecord& r = records[k - 1 - i];
    VertexSplit& s = pm.splits_[i];
    s.vertex = pm_vertex[r.v];
    s.vertex_position = r.pos_v_before;
    s.new_position = r.pos_u;
    s.coarse_position = r.pos_v_after;
    s.corner_begin = static_cast<std::uint32_t>(pm.corners_.size());
    for (std::uint32_t j = r.changed_begin; j < r.changed_end; ++j) {
      const std::uint32_t c = engine.changed()[j];
      pm.corners_.push_back(3 * pm_face[c / 3] + c % 3);
    }
    s.corner_end = static_cast<std::uint32_t>(pm.corners_.size());
    s.n_faces = static_cast<std::uint8_t>(r.dead[1] == kNone ? 1 : 2);
    faces += s.n_faces;
    pm.face_prefix_[i] = faces;
  }
  pm.n_vertices_ = n;
  pm.n_faces_ = tris.size();
  return pm;
}

std::size_t ProgressiveMesh::faces_at(std::size_t vertices) const {
  if (vertices < base_vertices_ || vertices > max_vertices())
    throw InvalidArgument("progressive mesh: vertex count " + std::to_string(vertices) +
                          " outside [" + std::to_string(base_vertices_) + ", " +
                          std::to_string(max_vertices()) + "]");
  return vertices == base_vertices_ ? base_faces_ : face_prefix_[vertices - base_vertices_ - 1];
}

std::size_t ProgressiveMesh::vertices_for_faces(std::size_t faces) const {
  // face_prefix_ is increasing: count the splits whose level stays within `faces`.
  if (faces < base_faces_) return base_vertices_;
  const auto it = std::upper_bound(face_prefix_.begin(), face_prefix_.end(), faces);
  return base_vertices_ + static_cast<std::size_t>(it - face_prefix_.begin());
}

void ProgressiveMesh::split(std::size_t i) {
  const VertexSplit& s = splits_[i];
  const auto added = static_cast<std::uint32_t>(base_vertices_ + i);
  for (std::uint32_t j = s.corner_begin; j < s.corner_end; ++j)
    faces_[corners_[j] / 3][corners_[j] % 3] = added;
  positions_[s.vertex] = s.vertex_position;
  positions_[added] = s.new_position;
  n_faces_ += s.n_faces;
  ++n_vertices_;
}

void ProgressiveMesh::collapse(std::size_t i) {
  const VertexSplit& s = splits_[i];
  for (std::uint32_t j = s.corner_begin; j < s.corner_end; ++j)
    faces_[corners_[j] / 3][corners_[j] % 3] = s.vertex;
  positions_[s.vertex] = s.coarse_position;
  n_faces_ -= s.n_faces;
  --n_vertices_;
}

void ProgressiveMesh::refine_to(std::size_t vertices) {
  vertices = std::min(vertices, max_vertices());
  while (n_vertices_ < vertices) split(n_vertices_ - base_vertices_);
}

void ProgressiveMesh::coarsen_to(std::size_t vertices) {
  vertices = std::max(vertices, base_vertices_);
  while (n_vertices_ > vertices) collapse(n_vertices_ - base_vertices_ - 1);
}

void ProgressiveMesh::set_level(std::size_t vertices) {
  if (vertices >= n_vertices_) refine_to(vertices);
  else coarsen_to(vertices);
}

SurfaceMesh ProgressiveMesh::mesh() const { return mesh_from_triangles(positions(), faces()); }

Geomorph ProgressiveMesh::geomorph(std::size_t coarse, std::size_t fine) {
  if (coarse > fine || coarse < base_vertices_ || fine > max_vertices())
    throw InvalidArgument("geomorph: need base ≤ coarse ≤ fine ≤ max vertices, got coarse " +
                          std::to_string(coarse) + ", fine " + std::to_string(fine) + " (base " +
                          std::to_string(base_vertices_) + ", max " +
                          std::to_string(max_vertices()) + ")");
  set_level(fine);
  Geomorph g;
  g.fine.assign(positions_.begin(), positions_.begin() + static_cast<std::ptrdiff_t>(fine));
  g.faces.assign(faces_.begin(), faces_.begin() + static_cast<std::ptrdiff_t>(n_faces_));
  // Each vertex added after the coarse level descends from the vertex it split off; the
  // splitting vertex always has a smaller index, so one increasing pass resolves chains.
  std::vector<std::uint32_t> ancestor(fine);
  for (std::size_t v = 0; v < fine; ++v)
    ancestor[v] = v < coarse ? static_cast<std::uint32_t>(v)
                             : ancestor[splits_[v - base_vertices_].vertex];
  coarsen_to(coarse);
  g.coarse.resize(fine);
  for (std::size_t v = 0; v < fine; ++v) g.coarse[v] = positions_[ancestor[v]];
  refine_to(fine);
  return g;
}

}  // namespace geom
