// The driver: mesh → level 0, refine level by level on flat arrays, optional limit, and the
// last level back into a SurfaceMesh with its properties.

#include <geom/subdivision/subdivision.h>

#include <geom/core/errors.h>
#include <geom/core/soup.h>
#include <geom/subdivision/creases.h>
#include <geom/subdivision/face_varying.h>
#include <geom/subdivision/level.h>
#include <geom/subdivision/limit.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <utility>
#include <vector>

namespace geom {
namespace detail::subdiv {

Level build_level0(const SurfaceMesh& mesh, bool sharpen_corners, int face_size) {
  Level l;
  l.nv = static_cast<std::uint32_t>(mesh.vertices_size());
  l.ne = static_cast<std::uint32_t>(mesh.edges_size());
  l.nf = static_cast<std::uint32_t>(mesh.faces_size());
  const std::uint32_t H = 2 * l.ne;
  l.to.resize(H);
  l.next.resize(H);
  l.face.resize(H);
  l.slot.assign(H, kNone);
  l.vh.assign(l.nv, kNone);
  l.fh.resize(l.nf);
  std::vector<std::uint32_t> degree(l.nv, 0), boundary_out(l.nv, 0);
  for (std::uint32_t h = 0; h < H; ++h) {
    const Halfedge hh(h);
    l.to[h] = mesh.to_vertex(hh).idx();
    l.next[h] = mesh.next(hh).idx();
    const Face f = mesh.face(hh);
    l.face[h] = f.is_valid() ? f.idx() : kNone;
  }
  for (std::uint32_t h = 0; h < H; ++h) {
    const std::uint32_t v = l.to[h ^ 1u];
    ++degree[v];
    if (l.vh[v] == kNone) l.vh[v] = h;
    if (l.face[h] == kNone) {
      ++boundary_out[v];
      l.vh[v] = h;
    }
  }
  for (std::uint32_t v = 0; v < l.nv; ++v) {
    if (l.vh[v] == kNone) continue;
    std::uint32_t count = 0, h = l.vh[v];
    do {
      ++count;
      h = l.cw(h);
    } while (h != l.vh[v] && count <= degree[v]);
    if (boundary_out[v] > 1 || count != degree[v])
      throw TopologyError("subdivision: vertex " + std::to_string(v) +
                          " is non-manifold (its faces form more than one fan)");
  }
  std::uint32_t corners = 0;
  l.face_base.resize(l.nf);
  for (std::uint32_t f = 0; f < l.nf; ++f) {
    l.face_base[f] = corners;
    const std::uint32_t h0 = mesh.halfedge(Face(f)).idx();
    l.fh[f] = h0;
    std::uint32_t j = 0, h = h0;
    do {
      l.slot[h] = corners + j++;
      h = l.next[h];
    } while (h != h0 && j <= H);
    if (face_size && j != static_cast<std::uint32_t>(face_size))
      throw InvalidArgument(std::string(face_size == 3 ? "Loop subdivision needs triangles"
                                                       : "Catmull-Clark limit masks need quads") +
                            ": face " + std::to_string(f) + " has " + std::to_string(j) +
                            " corners");
    corners += j;
  }
  l.n_corners = corners;

  l.esharp.assign(l.ne, kSmooth);
  l.vsharp.assign(l.nv, kSmooth);
  auto to_sharpness = [](double s, const char* kind, std::uint32_t i) {
    if (std::isnan(s))
      throw InvalidArgument(std::string("subdivision: ") + kind + " " + std::to_string(i) +
                            " has a NaN sharpness");
    return s >= kInfinite ? kInfinite : (s > 0.0 ? static_cast<float>(s) : kSmooth);
  };
  if (auto es = mesh.get_property<Edge, double>(prop::kEdgeSharpness))
    for (std::uint32_t e = 0; e < l.ne; ++e) l.esharp[e] = to_sharpness(es[Edge(e)], "edge", e);
  if (auto vs = mesh.get_property<Vertex, double>(prop::kVertexSharpness))
    for (std::uint32_t v = 0; v < l.nv; ++v)
      l.vsharp[v] = to_sharpness(vs[Vertex(v)], "vertex", v);
  // OpenSubdiv always refines boundary edges as infinitely sharp creases.
  for (std::uint32_t h = 0; h < H; ++h)
    if (l.face[h] == kNone) l.esharp[h >> 1] = kInfinite;
  if (sharpen_corners)
    for (std::uint32_t v = 0; v < l.nv; ++v)
      if (degree[v] == 2 && boundary_out[v] == 1) l.vsharp[v] = kInfinite;
  bool any = false;
  for (float s : l.esharp) any |= is_sharp(s);
  for (float s : l.vsharp) any |= is_sharp(s);
  if (!any) {
    l.esharp.clear();
    l.vsharp.clear();
  }
  return l;
}

}  // namespace detail::subdiv

namespace {

using detail::subdiv::Context;
using detail::subdiv::kNone;
using detail::subdiv::Level;

/// Call f(std::type_identity<T>) for the property value types that are refined as data.
template <class F>
bool visit_data_type(const std::type_info& t, F&& f) {
  if (t == typeid(double)) return f(std::type_identity<double>{}), true;
  if (t == typeid(float)) return f(std::type_identity<float>{}), true;
  if (t == typeid(Eigen::Vector2d)) return f(std::type_identity<Eigen::Vector2d>{}), true;
  if (t == typeid(Eigen::Vector3d)) return f(std::type_identity<Eigen::Vector3d>{}), true;
  if (t == typeid(Eigen::Vector4d)) return f(std::type_identity<Eigen::Vector4d>{}), true;
  if (t == typeid(Eigen::Vector2f)) return f(std::type_identity<Eigen::Vector2f>{}), true;
  if (t == typeid(Eigen::Vector3f)) return f(std::type_identity<Eigen::Vector3f>{}), true;
  if (t == typeid(Eigen::Vector4f)) return f(std::type_identity<Eigen::Vector4f>{}), true;
  return false;
}

template <class T>
constexpr int width_of() {
  if constexpr (std::is_arithmetic_v<T>)
    return 1;
  else
    return static_cast<int>(T::RowsAtCompileTime);
}

template <class T>
T zero_value() {
  if constexpr (std::is_arithmetic_v<T>)
    return T(0);
  else
    return T::Zero();
}

template <class T>
double component(const T& value, int k) {
  if constexpr (std::is_arithmetic_v<T>)
    return static_cast<double>(value);
  else
    return static_cast<double>(value[k]);
}

template <class T>
void set_component(T& value, int k, double x) {
  if constexpr (std::is_arithmetic_v<T>)
    value = static_cast<T>(x);
  else
    value[k] = static_cast<typename T::Scalar>(x);
}

/// Data properties of one element kind packed into one row-major array of doubles.
struct Channels {
  struct Entry {
    std::string name;
    const std::type_info* type;
    int offset, width;
  };
  std::vector<Entry> entries;
  int width = 0;
  detail::subdiv::Array<double> data;
};

template <class H>
Channels gather_channels(const SurfaceMesh& mesh, std::size_t n, const std::string& skip) {
  Channels ch;
  for (const std::string& name : mesh.property_names<H>()) {
    if (name == skip) continue;
    const std::type_info* t = mesh.props<H>().type_of(name);
    visit_data_type(*t, [&](auto tag) {
      using T = typename decltype(tag)::type;
      ch.entries.push_back({name, t, ch.width, width_of<T>()});
      ch.width += width_of<T>();
    });
  }
  ch.data.assign(n * static_cast<std::size_t>(ch.width), 0.0);
  for (const auto& entry : ch.entries) {
    visit_data_type(*entry.type, [&](auto tag) {
      using T = typename decltype(tag)::type;
      auto prop = mesh.get_property<H, T>(entry.name);
      const auto& values = prop.vector();
      for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < entry.width; ++k)
          ch.data[i * ch.width + entry.offset + k] = component(values[i], k);
    });
  }
  return ch;
}

template <class H>
void scatter_channels(const Channels& ch, SurfaceMesh& mesh, std::size_t n) {
  for (const auto& entry : ch.entries) {
    visit_data_type(*entry.type, [&](auto tag) {
      using T = typename decltype(tag)::type;
      auto prop = mesh.get_or_add_property<H, T>(entry.name, zero_value<T>());
      auto& values = prop.vector();
      for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < entry.width; ++k)
          set_component(values[i], k, ch.data[i * ch.width + entry.offset + k]);
    });
  }
}

void check_size(const Level& l, int levels, bool catmark) {
  double ne = l.ne, nf = l.nf, corners = l.n_corners;
  for (int i = 0; i < levels; ++i) {
    if (catmark) {
      ne = 2 * ne + corners;
      nf = corners;
      corners = 4 * corners;
    } else {
      ne = 2 * ne + 3 * nf;
      nf = 4 * nf;
    }
  }
  if (2 * ne > 2147483647.0)
    throw InvalidArgument("subdivision: " + std::to_string(levels) + " levels would create " +
                          std::to_string(static_cast<long long>(2 * ne)) +
                          " halfedges, more than 2^31");
}

/// The mesh's positions as rows of three doubles (Eigen's Vector3d has no padding).
double* mesh_positions(SurfaceMesh& mesh) {
  static_assert(sizeof(Point) == 3 * sizeof(double));
  auto& points = mesh.positions().vector();
  // An empty mesh has no first point to take the address of.
  return points.empty() ? nullptr : points.front().data();
}

/// A mesh with the level's numbers of vertices, edges and faces and no links yet.
SurfaceMesh skeleton(const Level& counts) {
  SurfaceMesh out;
  out.resize(counts.nv, counts.ne, counts.nf);
  return out;
}

SurfaceMesh to_mesh(const Level& l) {
  SurfaceMesh out = skeleton(l);
  const std::uint32_t H = 2 * l.ne;
  for (std::uint32_t h = 0; h < H; ++h) {
    out.set_vertex(Halfedge(h), Vertex(l.to[h]));
    out.set_next(Halfedge(h), Halfedge(l.next[h]));
    if (l.face[h] != kNone) out.set_face(Halfedge(h), Face(l.face[h]));
  }
  for (std::uint32_t v = 0; v < l.nv; ++v)
    if (l.vh[v] != kNone) out.set_halfedge(Vertex(v), Halfedge(l.vh[v]));
  for (std::uint32_t f = 0; f < l.nf; ++f) out.set_halfedge(Face(f), Halfedge(l.fh[f]));
  return out;
}

}  // namespace

SubdivideResult subdivide(const SurfaceMesh& input, const SubdivideOptions& options) {
  using namespace detail::subdiv;
  if (options.levels < 0 || options.levels > 10)
    throw InvalidArgument("subdivision levels must be in [0, 10], got " +
                          std::to_string(options.levels));
  const bool catmark = options.scheme == SubdivisionScheme::kCatmullClark;
  SubdivideResult result;

  SurfaceMesh working;
  const SurfaceMesh* mesh = &input;
  if (input.has_garbage() || options.crease_angle) {
    working = input;
    if (working.has_garbage()) working.compact();
    if (options.crease_angle)
      result.angle_creased_edges = mark_creases_by_angle(working, *options.crease_angle);
    mesh = &working;
  }

  Context ctx;
  ctx.catmark = catmark;
  ctx.chaikin = options.crease_method == CreaseMethod::kChaikin;
  ctx.parallel = options.parallel;
  const bool sharpen_corners = options.boundary == BoundaryInterpolation::kEdgesAndCorners;
  const bool want_limit_quads = catmark && options.limit && options.levels == 0;
  Level cur = build_level0(*mesh, sharpen_corners, catmark ? (want_limit_quads ? 4 : 0) : 3);
  check_size(cur, options.levels, catmark);

  Channels vdata = gather_channels<Vertex>(*mesh, cur.nv, prop::kVertexSharpness);
  Channels hdata = gather_channels<Halfedge>(*mesh, 2 * static_cast<std::size_t>(cur.ne), "");
  const bool face_props = !mesh->property_names<Face>().empty();
  std::vector<std::uint32_t> face_origin;
  if (face_props) {
    face_origin.resize(cur.nf);
    for (std::uint32_t f = 0; f < cur.nf; ++f) face_origin[f] = f;
  }
  result.per_level.push_back({cur.nv, cur.ne, cur.nf});

  ctx.parent_faces = face_props;
  const bool positions_only = vdata.entries.size() == 1;
  // Smooth face-varying data is refined (and taken to the limit) at the end, through the
  // mesh cut along its seams.
  const bool smooth_fvar = hdata.width > 0 && (options.levels > 0 || options.limit) &&
                           options.face_varying == FaceVaryingInterpolation::kLinearBoundaries;
  Level parent;
  for (int level = 1; level <= options.levels; ++level) {
    ctx.last = level == options.levels;
    Level child;
    if (ctx.last) {
      // The last level goes straight into the result mesh.
      set_child_counts(cur, child, catmark);
      result.mesh = skeleton(child);
      if (catmark)
        refine_topology_catmark(cur, child, result.mesh, ctx);
      else
        refine_topology_loop(cur, child, result.mesh, ctx);
    } else if (catmark) {
      refine_topology_catmark(cur, child, ctx);
    } else {
      refine_topology_loop(cur, child, ctx);
    }
    // With positions only, the last level is interpolated straight into the mesh.
    const bool direct = ctx.last && positions_only && !options.limit;
    detail::subdiv::Array<double> vnext(
        direct ? 0 : static_cast<std::size_t>(child.nv) * vdata.width);
    double* vdst = direct ? mesh_positions(result.mesh) : vnext.data();
    if (catmark)
      interpolate_catmark(cur, child, vdata.data.data(), vdst, vdata.width, ctx);
    else
      interpolate_loop(cur, child, vdata.data.data(), vdst, vdata.width, ctx);
    vdata.data.swap(vnext);
    if (hdata.width > 0 && !smooth_fvar) {
      detail::subdiv::Array<double> hnext(2 * static_cast<std::size_t>(child.ne) * hdata.width, 0.0);
      if (catmark)
        interpolate_fvar_catmark(cur, hdata.data.data(), hnext.data(), hdata.width, ctx);
      else
        interpolate_fvar_loop(cur, hdata.data.data(), hnext.data(), hdata.width, ctx);
      hdata.data.swap(hnext);
    }
    if (face_props) {
      std::vector<std::uint32_t> origin(child.nf);
      for (std::uint32_t f = 0; f < child.nf; ++f)
        origin[f] = face_origin[child.parent_face[f]];
      face_origin.swap(origin);
    }
    // The limit of the last level is computed from its parent's connectivity.
    if (ctx.last && options.limit) parent = std::move(cur);
    cur = std::move(child);
    result.per_level.push_back({cur.nv, cur.ne, cur.nf});
    if (options.progress && !options.progress(static_cast<double>(level) / options.levels))
      throw Error("subdivision cancelled");
  }
  result.levels = options.levels;

  bool vertex_data_in_mesh = options.levels > 0 && positions_only && !options.limit;
  if (options.limit) {
    if (options.levels == 0) result.mesh = to_mesh(cur);
    vertex_data_in_mesh = positions_only;
    detail::subdiv::Array<double> lim(positions_only ? 0 : vdata.data.size());
    double* ldst = positions_only ? mesh_positions(result.mesh) : lim.data();
    if (options.levels > 0)
      limit_children(parent, cur, vdata.data.data(), ldst, vdata.width, ctx);
    else
      limit_points(cur, vdata.data.data(), ldst, vdata.width, nullptr, ctx);
    double sum = 0.0, mx = 0.0;
    const int w = vdata.width;
    int at = 0;
    for (const auto& entry : vdata.entries)
      if (entry.name == SurfaceMesh::kPositions) at = entry.offset;
    for (std::uint32_t v = 0; v < cur.nv; ++v) {
      const double* a = vdata.data.data() + static_cast<std::size_t>(v) * w + at;
      const double* b = ldst + static_cast<std::size_t>(v) * w + at;
      const double d = std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                 (a[2] - b[2]) * (a[2] - b[2]));
      mx = std::max(mx, d);
      sum += d * d;
    }
    result.limit_max_distance = mx;
    result.limit_rms_distance = cur.nv ? std::sqrt(sum / cur.nv) : 0.0;
    vdata.data.swap(lim);
  }

  if (options.levels == 0 && !options.limit) result.mesh = to_mesh(cur);
  if (smooth_fvar) {
    const std::vector<double> rows = detail::subdiv::refine_face_varying_smooth(
        *mesh, hdata.data.data(), hdata.width, options, result.mesh);
    hdata.data.assign(rows.begin(), rows.end());
  }
  if (!vertex_data_in_mesh) scatter_channels<Vertex>(vdata, result.mesh, cur.nv);
  scatter_channels<Halfedge>(hdata, result.mesh, 2 * static_cast<std::size_t>(cur.ne));
  if (face_props) {
    result.mesh.props<Face>() = mesh->props<Face>();
    result.mesh.props<Face>().gather(face_origin);
  }
  const bool had_sharpness = mesh->has_property<Edge>(prop::kEdgeSharpness) ||
                             mesh->has_property<Vertex>(prop::kVertexSharpness);
  if (had_sharpness) {
    auto es = result.mesh.add_property<Edge, double>(prop::kEdgeSharpness, 0.0);
    auto vs = result.mesh.add_property<Vertex, double>(prop::kVertexSharpness, 0.0);
    if (cur.has_sharpness()) {
      for (std::uint32_t e = 0; e < cur.ne; ++e) es[Edge(e)] = cur.esharp[e];
      for (std::uint32_t v = 0; v < cur.nv; ++v) vs[Vertex(v)] = cur.vsharp[v];
    }
  }
  return result;
}

}  // namespace geom
