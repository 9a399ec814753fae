// The collapse engine's attribute hooks (SimplifyOptions::attributes): placement with the
// attribute quadric, the seam rules, and carrying wedges through collapses. Kept apart from
// collapse.cpp so that the engine without attributes pays one untaken branch per hook.

#include <geom/lod/collapse.h>

#include <cmath>
#include <limits>

namespace geom::detail {

void CollapseEngine::init_attributes(const SurfaceMesh& mesh) {
  // The triangles of each face are consecutive, in face order (see the constructor); find
  // the halfedge ending at each of their corners.
  std::vector<std::uint32_t> dense(mesh.vertices_size(), kNone);
  for (std::uint32_t i = 0; i < vertex_of_.size(); ++i) dense[vertex_of_[i].idx()] = i;
  std::vector<Halfedge> corner_halfedge(3 * triangles_.size());
  std::size_t t = 0;
  for (Face f : mesh.faces()) {
    const std::size_t k = mesh.valence(f);
    for (std::size_t i = 0; i + 2 < k; ++i, ++t)
      for (int c = 0; c < 3; ++c)
        for (Halfedge h : mesh.halfedges(f))
          if (dense[mesh.to_vertex(h).idx()] == triangles_[t][c]) {
            corner_halfedge[3 * t + c] = h;
            break;
          }
  }
  attributes_ = std::make_unique<AttributeQuadrics>(mesh, options_.attributes, triangles_, corner_halfedge,
                                                    vertex_of_, normalised_positions());
}

int CollapseEngine::wedge_pairs(std::uint32_t a, std::uint32_t b, AttributeQuadrics::WedgePair* out) const {
  int n = 0;
  for (std::uint32_t i = vd_[a].ref_begin; i < vd_[a].ref_begin + vd_[a].ref_size; ++i) {
    const std::uint32_t t = refs_[i];
    if (!tri_alive_[t] || !has_tri_with(t, b)) continue;
    if (n == 2) return -1;
    const auto& tri = triangles_[t];
    const std::uint32_t ka = tri[0] == a ? 0 : tri[1] == a ? 1 : 2;
    const std::uint32_t kb = tri[0] == b ? 0 : tri[1] == b ? 1 : 2;
    out[n++] = {attributes_->corner_wedge(3 * t + ka), attributes_->corner_wedge(3 * t + kb)};
  }
  return n;
}

CollapseEngine::Placement CollapseEngine::place_with_attributes(std::uint32_t a, std::uint32_t b,
                                                                Quadric q) const {
  using Pair = AttributeQuadrics::WedgePair;
  constexpr double kForbidden = std::numeric_limits<double>::infinity();
  Pair ab[2], ba[2];
  // Away from seams (the common case) each end has one wedge and they simply merge.
  const bool simple = attributes_->wedge_count(a) == 1 && attributes_->wedge_count(b) == 1;
  if (simple) ab[0] = {attributes_->first_wedge(a), attributes_->first_wedge(b)};
  const int n = simple ? 1 : wedge_pairs(a, b, ab);
  if (n <= 0) return {kForbidden, vd_[a].p, 1};
  for (int i = 0; i < n; ++i) ba[i] = {ab[i].to, ab[i].from};
  const bool a_into_b = !vd_[a].locked && (simple || attributes_->keeps_seams(a, ab, n));
  const bool b_into_a = !vd_[b].locked && (simple || attributes_->keeps_seams(b, ba, n));
  if (!a_into_b && !b_into_a) return {kForbidden, vd_[a].p, 1};
  q += attributes_->merged(a, b, ab, n);
  const double ca = b_into_a ? q.evaluate(vd_[a].p) : kForbidden;
  const double cb = a_into_b ? q.evaluate(vd_[b].p) : kForbidden;
  Placement best = cb < ca ? Placement{cb, vd_[b].p, 2} : Placement{ca, vd_[a].p, 1};
  // A seam vertex stays on its seam by landing on its neighbour along it; a locked one
  // stays put. Otherwise the point may move freely, as in place().
  if (!a_into_b || !b_into_a || attributes_->wedge_count(a) > 1 || attributes_->wedge_count(b) > 1) return best;
  const double noise = 1e-12 * (q.a00 + q.a11 + q.a22 + std::abs(q.b0) + std::abs(q.b1) + std::abs(q.b2) +
                                std::abs(q.c));
  if (!(cb < ca - noise)) best = {ca, vd_[a].p, 1};
  const Point mid = 0.5 * (vd_[a].p + vd_[b].p);
  const double cm = q.evaluate(mid);
  if (cm < best.cost - noise) best = {cm, mid, 3};
  const Point opt = q.minimizer(mid);
  if ((opt - mid).squaredNorm() <= 4.0 * (vd_[a].p - vd_[b].p).squaredNorm()) {
    const double co = q.evaluate(opt);
    if (co < best.cost - noise) best = {co, opt, 0};
  }
  return best;
}

bool CollapseEngine::attributes_allow(std::uint32_t u, std::uint32_t v, const Placement& pl) const {
  // try_collapse found one or two shared triangles: single wedges merge whatever the placement.
  if (attributes_->wedge_count(u) == 1 && attributes_->wedge_count(v) == 1) return true;
  AttributeQuadrics::WedgePair pairs[2];
  const int n = wedge_pairs(u, v, pairs);
  if (!attributes_->keeps_seams(u, pairs, n)) return false;
  // A seam vertex never moves off its place on the seam.
  return pl.source == 1 || pl.source == 2;
}

void CollapseEngine::collapse_attributes(std::uint32_t u, std::uint32_t v) {
  AttributeQuadrics::WedgePair pairs[2];
  const int n = wedge_pairs(u, v, pairs);
  attributes_->collapse(u, v, pairs, n);
  // u's corners in the triangles that survive move to the partner wedges at v.
  for (std::uint32_t i = vd_[u].ref_begin; i < vd_[u].ref_begin + vd_[u].ref_size; ++i) {
    const std::uint32_t t = refs_[i];
    if (!tri_alive_[t] || has_tri_with(t, v)) continue;
    for (std::uint32_t k = 0; k < 3; ++k)
      if (triangles_[t][k] == u)
        attributes_->set_corner_wedge(3 * t + k, AttributeQuadrics::partner(attributes_->corner_wedge(3 * t + k), pairs, n));
  }
}

void CollapseEngine::write_attributes(SurfaceMesh& out) const {
  std::vector<std::uint32_t> out_vertex, live;
  out_vertex.reserve(out.n_vertices());
  live.reserve(alive_triangles_);
  for (std::uint32_t v = 0; v < vd_.size(); ++v)
    if (vd_[v].ref_size > 0) out_vertex.push_back(v);
  for (std::uint32_t t = 0; t < triangles_.size(); ++t)
    if (tri_alive_[t]) live.push_back(t);
  attributes_->write(out, out_vertex, live, triangles_, normalised_positions());
}

}  // namespace geom::detail
