#include <geom/core/errors.h>
#include <geom/core/soup.h>
#include <geom/lod/attribute_quadric.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace geom::detail {

namespace {

struct Names {
  const char* option;   // as SimplifyAttributes calls it
  const char* vertex;   // per-vertex property
  const char* corner;   // per-corner property, or null
  int dims;
};

constexpr Names kNames[] = {{"normals", prop::kVertexNormal, prop::kCornerNormal, 3},
                            {"texcoords", prop::kVertexTexCoord, prop::kCornerTexCoord, 2},
                            {"colors", prop::kVertexColor, nullptr, 3}};

// Reads a 2- or 3-vector property as doubles; null when absent.
template <class H>
struct Reader {
  Property<H, const Eigen::Vector3d> v3;
  Property<H, const Eigen::Vector2d> v2;
  Reader(const SurfaceMesh& mesh, const char* name, int dims) {
    if (!name) return;
    if (dims == 3) v3 = mesh.get_property<H, Eigen::Vector3d>(name);
    else v2 = mesh.get_property<H, Eigen::Vector2d>(name);
  }
  explicit operator bool() const { return v3 || v2; }
  double get(H h, int k) const { return v3 ? v3[h][k] : v2[h][k]; }
};

template <class T>
void put(SurfaceMesh& out, const std::string& name, bool halfedges, int dims,
         const std::vector<double>& values, int stride, int offset) {
  auto fill = [&](auto p) {
    for (std::size_t i = 0; i < p.vector().size(); ++i)
      for (int k = 0; k < dims; ++k) p.vector()[i][k] = values[i * stride + offset + k];
  };
  if (halfedges) fill(out.add_property<Halfedge, T>(name));
  else fill(out.add_property<Vertex, T>(name));
}

}  // namespace

AttributeQuadrics::AttributeQuadrics(const SurfaceMesh& mesh, const SimplifyAttributes& options,
                                     const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                     const std::vector<Halfedge>& corner_halfedge,
                                     const std::vector<Vertex>& vertex_of, const std::vector<Point>& pos) {
  add_field(mesh, Kind::kNormal, options.normals);
  add_field(mesh, Kind::kTexCoord, options.texcoords);
  add_field(mesh, Kind::kColor, options.colors);

  const std::size_t n = vertex_of.size(), nc = corner_halfedge.size();
  std::vector<double> vertex_values(n * vertex_.m), corner_values(nc * corner_.m);
  for (const Field& f : fields_) {
    const Names& nm = kNames[static_cast<int>(f.kind)];
    if (f.corner) {
      const Reader<Halfedge> r(mesh, nm.corner, f.dims);
      for (std::size_t c = 0; c < nc; ++c)
        for (int k = 0; k < f.dims; ++k) corner_values[c * corner_.m + f.offset + k] = r.get(corner_halfedge[c], k);
    } else {
      const Reader<Vertex> r(mesh, nm.vertex, f.dims);
      for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < f.dims; ++k) vertex_values[i * vertex_.m + f.offset + k] = r.get(vertex_of[i], k);
    }
  }
  // Reject non-finite input here: one NaN would poison every quadric it is added to.
  for (std::size_t i = 0; i < vertex_values.size(); ++i)
    if (!std::isfinite(vertex_values[i]))
      throw InvalidArgument("simplify: vertex " + std::to_string(vertex_of[i / vertex_.m].idx()) +
                            " has a non-finite attribute value");
  for (std::size_t i = 0; i < corner_values.size(); ++i)
    if (!std::isfinite(corner_values[i]))
      throw InvalidArgument("simplify: halfedge " + std::to_string(corner_halfedge[i / corner_.m].idx()) +
                            " has a non-finite corner attribute value");

  auto range = [](Channel& ch, const std::vector<double>& values) {
    ch.lo.assign(ch.m, std::numeric_limits<double>::infinity());
    ch.hi.assign(ch.m, -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < values.size(); ++i) {
      const std::size_t j = i % ch.m;
      ch.lo[j] = std::min(ch.lo[j], values[i]), ch.hi[j] = std::max(ch.hi[j], values[i]);
    }
  };
  range(vertex_, vertex_values);
  range(corner_, corner_values);
  vertex_.value = vertex_values;
  vertex_.data.assign(n * vertex_.stride(), 0.0);
  build_wedges(triangles, corner_values, n);
  accumulate(triangles, pos, vertex_values, corner_values);
}

void AttributeQuadrics::add_field(const SurfaceMesh& mesh, Kind kind, const SimplifyAttribute& a) {
  if (!a.enabled) return;
  const Names& nm = kNames[static_cast<int>(kind)];
  if (!(a.weight >= 0) || !std::isfinite(a.weight))
    throw InvalidArgument(std::string("simplify: the weight of ") + nm.option + " must be finite and >= 0, got " +
                          std::to_string(a.weight));
  Field f{kind, false, bool(Reader<Vertex>(mesh, nm.vertex, nm.dims)),
          bool(Reader<Halfedge>(mesh, nm.corner, nm.dims)), 0, nm.dims, a.weight};
  if (!f.vertex_prop && !f.corner_prop)
    throw InvalidArgument(std::string("simplify: attribute ") + nm.option + " asked for but the mesh has no \"" +
                          nm.vertex + "\"" + (nm.corner ? std::string(" or \"") + nm.corner + "\"" : "") +
                          " property");
  // A per-vertex property cannot have seams, so it wins when both exist (readers fill it
  // only when each vertex's corners agree).
  f.corner = !f.vertex_prop;
  Channel& ch = f.corner ? corner_ : vertex_;
  f.offset = ch.m;
  ch.m += f.dims;
  ch.weight.insert(ch.weight.end(), f.dims, a.weight);
  fields_.push_back(f);
}

void AttributeQuadrics::build_wedges(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                     const std::vector<double>& corner_values, std::size_t n) {
  // Corners grouped by vertex (counting sort), then split by value: O(corners × wedges of
  // the vertex), which is small except at poles.
  const std::size_t nc = 3 * triangles.size();
  std::vector<std::uint32_t> first(n + 1, 0), order(nc);
  for (const auto& t : triangles)
    for (std::uint32_t v : t) ++first[v + 1];
  for (std::size_t v = 0; v < n; ++v) first[v + 1] += first[v];
  std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
  for (std::uint32_t c = 0; c < nc; ++c) order[fill[triangles[c / 3][c % 3]]++] = c;

  const int m = corner_.m;
  auto same = [&](std::uint32_t c, std::uint32_t d) {
    for (int k = 0; k < m; ++k)
      if (corner_values[c * m + k] != corner_values[d * m + k]) return false;
    return true;
  };
  corner_wedge_.assign(nc, 0);
  wedge_begin_.assign(n, 0);
  wedge_count_.assign(n, 0);
  std::vector<std::uint32_t> representative;  // a corner of each wedge
  for (std::size_t v = 0; v < n; ++v) {
    wedge_begin_[v] = static_cast<std::uint32_t>(representative.size());
    for (std::uint32_t i = first[v]; i < first[v + 1]; ++i) {
      const std::uint32_t c = order[i];
      std::uint32_t w = wedge_begin_[v];
      while (w < representative.size() && !same(representative[w], c)) ++w;
      if (w == representative.size()) representative.push_back(c);
      corner_wedge_[c] = w;
    }
    wedge_count_[v] = static_cast<std::uint32_t>(representative.size()) - wedge_begin_[v];
  }
  if (m == 0) return;
  corner_.data.assign(representative.size() * corner_.stride(), 0.0);
  corner_.value.resize(representative.size() * m);
  for (std::size_t w = 0; w < representative.size(); ++w)
    std::copy_n(corner_values.begin() + representative[w] * m, m, corner_.value.begin() + w * m);
}

void AttributeQuadrics::accumulate(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                   const std::vector<Point>& pos, const std::vector<double>& vertex_values,
                                   const std::vector<double>& corner_values) {
  // Per component j: the affine s(x) = g·x + d interpolating the corners, with g in the
  // triangle's plane; the block gains area·w·(g·x + d − s)² expanded as in the header.
  auto add_face = [](Channel& ch, double* blk, double area, const Eigen::Vector3d* g, const double* d) {
    for (int j = 0; j < ch.m; ++j) {
      const double w = area * ch.weight[j];
      const Eigen::Vector3d& gj = g[j];
      blk[0] += w * gj.x() * gj.x(), blk[1] += w * gj.x() * gj.y(), blk[2] += w * gj.x() * gj.z();
      blk[3] += w * gj.y() * gj.y(), blk[4] += w * gj.y() * gj.z(), blk[5] += w * gj.z() * gj.z();
      blk[6] += w * d[j] * gj.x(), blk[7] += w * d[j] * gj.y(), blk[8] += w * d[j] * gj.z();
      blk[9] += w * d[j] * d[j];
      for (int k = 0; k < 3; ++k) blk[11 + 3 * j + k] += area * gj[k];
      blk[11 + 3 * ch.m + j] += area * d[j];
    }
    blk[10] += area;
  };
  std::array<Eigen::Vector3d, 16> g;
  std::array<double, 16> d;
  auto gradients = [&](const Channel& ch, const double* s0, const double* s1, const double* s2,
                       const Point& p0, const Eigen::Vector3d& u1, const Eigen::Vector3d& u2) {
    for (int j = 0; j < ch.m; ++j) {
      g[j] = (s1[j] - s0[j]) * u1 + (s2[j] - s0[j]) * u2;
      d[j] = s0[j] - g[j].dot(p0);
    }
  };
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& tri = triangles[t];
    const Point &p0 = pos[tri[0]], &p1 = pos[tri[1]], &p2 = pos[tri[2]];
    const Eigen::Vector3d e1 = p1 - p0, e2 = p2 - p0, nrm = e1.cross(e2);
    const double nn = nrm.squaredNorm();
    // Degenerate triangles have no plane to interpolate over, and no area to weigh by.
    if (!(nn > 0) || !std::isfinite(nn)) continue;
    const double area = 0.5 * std::sqrt(nn);
    // g·e1 = s1 − s0, g·e2 = s2 − s0, g·n = 0.
    const Eigen::Vector3d u1 = e2.cross(nrm) / nn, u2 = nrm.cross(e1) / nn;
    if (vertex_.m > 0) {
      const int m = vertex_.m;
      gradients(vertex_, &vertex_values[tri[0] * m], &vertex_values[tri[1] * m], &vertex_values[tri[2] * m], p0,
                u1, u2);
      for (std::uint32_t v : tri) add_face(vertex_, vertex_.block(v), area, g.data(), d.data());
    }
    if (corner_.m > 0) {
      const std::size_t m = corner_.m, c = 3 * t;
      gradients(corner_, &corner_values[c * m], &corner_values[(c + 1) * m], &corner_values[(c + 2) * m], p0, u1,
                u2);
      for (std::size_t k = 0; k < 3; ++k) add_face(corner_, corner_.block(corner_wedge_[c + k]), area, g.data(), d.data());
    }
  }
}

Quadric AttributeQuadrics::reduce(const Channel& ch, const double* b) const {
  // min over s of Σ_j w_j (xᵀP_j x + 2p_j·x + r_j − 2 s (B_j·x + e_j) + W s²) is at
  // s = (B_j·x + e_j) / W, leaving w_j (P_j − B_j B_jᵀ/W, p_j − e_j B_j/W, r_j − e_j²/W).
  Quadric q;
  const double wsum = b[10];
  if (!(wsum > 0)) return q;
  q.a00 = b[0], q.a01 = b[1], q.a02 = b[2], q.a11 = b[3], q.a12 = b[4], q.a22 = b[5];
  q.b0 = b[6], q.b1 = b[7], q.b2 = b[8], q.c = b[9];
  for (int j = 0; j < ch.m; ++j) {
    const double f = ch.weight[j] / wsum;
    if (f == 0) continue;
    const double* bj = b + 11 + 3 * j;
    const double e = b[11 + 3 * ch.m + j];
    q.a00 -= f * bj[0] * bj[0], q.a01 -= f * bj[0] * bj[1], q.a02 -= f * bj[0] * bj[2];
    q.a11 -= f * bj[1] * bj[1], q.a12 -= f * bj[1] * bj[2], q.a22 -= f * bj[2] * bj[2];
    q.b0 -= f * e * bj[0], q.b1 -= f * e * bj[1], q.b2 -= f * e * bj[2];
    q.c -= f * e * e;
  }
  return q;
}

bool AttributeQuadrics::keeps_seams(std::uint32_t u, const WedgePair* pairs, int n) const {
  if (n <= 0) return false;
  int distinct = 0;
  for (int i = 0; i < n; ++i) {
    bool seen = false;
    for (int j = 0; j < i; ++j) {
      // One wedge splitting in two, or two merging into one, would smear a seam.
      if ((pairs[i].from == pairs[j].from) != (pairs[i].to == pairs[j].to)) return false;
      seen |= pairs[i].from == pairs[j].from;
    }
    distinct += !seen;
  }
  // A wedge of u that no collapsing triangle carries has no partner: u is a seam corner,
  // or the seam does not run along this edge.
  return static_cast<std::uint32_t>(distinct) == wedge_count_[u];
}

std::uint32_t AttributeQuadrics::partner(std::uint32_t w, const WedgePair* pairs, int n) {
  for (int i = 0; i < n; ++i)
    if (pairs[i].from == w) return pairs[i].to;
  return w;
}

Quadric AttributeQuadrics::merged(std::uint32_t a, std::uint32_t b, const WedgePair* pairs, int n) const {
  Quadric q;
  std::array<double, 11 + 4 * 16> sum;
  auto add_blocks = [&](const Channel& ch, const double* x, const double* y) {
    for (int k = 0; k < ch.stride(); ++k) sum[k] = x[k] + (y ? y[k] : 0.0);
  };
  if (vertex_.m > 0) {
    add_blocks(vertex_, vertex_.block(a), vertex_.block(b));
    q += reduce(vertex_, sum.data());
  }
  if (corner_.m > 0) {
    // Pairs are a partial bijection between a's and b's wedges (keeps_seams held in one
    // direction), so each wedge of b is merged with at most one wedge of a.
    for (std::uint32_t w = wedge_begin_[b]; w < wedge_begin_[b] + wedge_count_[b]; ++w) {
      const double* other = nullptr;
      for (int i = 0; i < n && !other; ++i)
        if (pairs[i].to == w) other = corner_.block(pairs[i].from);
      add_blocks(corner_, corner_.block(w), other);
      q += reduce(corner_, sum.data());
    }
    for (std::uint32_t w = wedge_begin_[a]; w < wedge_begin_[a] + wedge_count_[a]; ++w)
      if (partner(w, pairs, n) == w) q += reduce(corner_, corner_.block(w));
  }
  return q;
}

void AttributeQuadrics::collapse(std::uint32_t u, std::uint32_t v, const WedgePair* pairs, int n) {
  if (vertex_.m > 0) {
    const double* from = vertex_.block(u);
    double* to = vertex_.block(v);
    for (int k = 0; k < vertex_.stride(); ++k) to[k] += from[k];
  }
  if (corner_.m > 0)
    for (int i = 0; i < n; ++i) {
      bool seen = false;
      for (int j = 0; j < i; ++j) seen |= pairs[j].from == pairs[i].from;
      if (seen) continue;
      const double* from = corner_.block(pairs[i].from);
      double* to = corner_.block(pairs[i].to);
      for (int k = 0; k < corner_.stride(); ++k) to[k] += from[k];
    }
}

void AttributeQuadrics::solve(bool corner, std::size_t i, const Point& x, double* s) const {
  const Channel& ch = corner ? corner_ : vertex_;
  const double* b = ch.block(i);
  const double* fallback = ch.value.data() + i * ch.m;
  for (int j = 0; j < ch.m; ++j) {
    const double* bj = b + 11 + 3 * j;
    s[j] = (bj[0] * x.x() + bj[1] * x.y() + bj[2] * x.z() + b[11 + 3 * ch.m + j]) / b[10];
    // No area (all triangles degenerate): keep the input value.
    if (!(b[10] > 0) || !std::isfinite(s[j])) s[j] = fallback[j];
  }
  for (const Field& f : fields_) {
    if (f.corner != corner) continue;
    double* v = s + f.offset;
    if (f.kind == Kind::kNormal) {
      const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      // Opposite normals can average to nothing; the input value is the only sane answer.
      if (len > 1e-12 && std::isfinite(len)) {
        for (int k = 0; k < 3; ++k) v[k] /= len;
      } else {
        std::copy_n(fallback + f.offset, 3, v);
      }
    } else {
      for (int k = 0; k < f.dims; ++k) {
        const double lo = f.kind == Kind::kColor ? 0.0 : ch.lo[f.offset + k];
        const double hi = f.kind == Kind::kColor ? 1.0 : ch.hi[f.offset + k];
        v[k] = std::max(lo, std::min(hi, v[k]));
      }
    }
  }
}

void AttributeQuadrics::write(SurfaceMesh& out, const std::vector<std::uint32_t>& out_vertex,
                              const std::vector<std::uint32_t>& live,
                              const std::vector<std::array<std::uint32_t, 3>>& triangles,
                              const std::vector<Point>& pos) const {
  // Values per output vertex (vertex channel) and per output halfedge (corner channel, and
  // vertex fields the input also had per corner).
  const int mv = vertex_.m, mc = corner_.m;
  std::vector<double> vval(out_vertex.size() * mv), hval(out.halfedges_size() * (mv + mc));
  for (std::size_t i = 0; i < out_vertex.size() && mv > 0; ++i)
    solve(false, out_vertex[i], pos[out_vertex[i]], &vval[i * mv]);
  std::size_t f = 0;
  for (Face face : out.faces()) {
    const auto& tri = triangles[live[f++]];
    for (Halfedge h : out.halfedges(face)) {
      const std::uint32_t ov = out.to_vertex(h).idx(), dv = out_vertex[ov];
      double* dst = &hval[h.idx() * (mv + mc)];
      std::copy_n(vval.begin() + ov * mv, mv, dst);
      if (mc == 0) continue;
      const int k = tri[0] == dv ? 0 : tri[1] == dv ? 1 : 2;
      solve(true, corner_wedge_[3 * live[f - 1] + k], pos[dv], dst + mv);
    }
  }
  for (const Field& fl : fields_) {
    const Names& nm = kNames[static_cast<int>(fl.kind)];
    auto emit = [&](bool halfedges, const char* name, const std::vector<double>& values, int stride, int offset) {
      if (fl.dims == 3) put<Eigen::Vector3d>(out, name, halfedges, 3, values, stride, offset);
      else put<Eigen::Vector2d>(out, name, halfedges, 2, values, stride, offset);
    };
    if (!fl.corner) emit(false, nm.vertex, vval, mv, fl.offset);
    if (fl.corner_prop) emit(true, nm.corner, hval, mv + mc, fl.corner ? mv + fl.offset : fl.offset);
  }
}

}  // namespace geom::detail

namespace geom {

std::vector<std::string> SimplifyAttributes::names() const {
  std::vector<std::string> out;
  if (normals.enabled) out.push_back("normals");
  if (texcoords.enabled) out.push_back("uv");
  if (colors.enabled) out.push_back("color");
  return out;
}

SimplifyAttributes present_attributes(const SurfaceMesh& mesh, double weight) {
  if (!(weight >= 0) || !std::isfinite(weight))
    throw InvalidArgument("simplify: an attribute weight must be finite and >= 0, got " + std::to_string(weight));
  SimplifyAttributes out;
  SimplifyAttribute* slots[] = {&out.normals, &out.texcoords, &out.colors};
  for (int k = 0; k < 3; ++k) {
    const detail::Names& nm = detail::kNames[k];
    if (detail::Reader<Vertex>(mesh, nm.vertex, nm.dims) || detail::Reader<Halfedge>(mesh, nm.corner, nm.dims))
      *slots[k] = {.enabled = true, .weight = weight};
  }
  return out;
}

}  // namespace geom
