// Subdividing a soup as given. OpenSubdiv refines non-manifold edges and vertices, repeated
// corners, fins and zero-area faces as they are; the half-edge core cannot hold them. So a
// vertex that a face repeats gets a vertex per fan, build() splits the rest, every copy is
// tagged with the sharpness OpenSubdiv gives the element it copies, and one subdivide()
// call refines all levels. OpenSubdiv's numbering of every level is followed face corner by
// face corner (faces are the same on both sides), and the copies are joined again at the
// end, in OpenSubdiv's vertex order.

#include <geom/subdivision/subdivision.h>

#include <geom/core/build.h>
#include <geom/core/errors.h>
#include <geom/subdivision/creases.h>
#include <geom/subdivision/osd_topology.h>

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <string>
#include <utility>

namespace geom {
namespace {

using detail::subdiv::kInfinite;
using detail::subdiv::OsdTopology;
constexpr std::uint32_t kUnset = 0xffffffffu;

/// The soup with no face visiting a vertex twice: a vertex that some face repeats gets a
/// vertex per fan (OpenSubdiv's fans, so that its manifold edges stay joined), and a corner
/// still repeating its face's vertex one of its own.
PolygonSoup split_repeated_corners(const PolygonSoup& in, const OsdTopology& topo,
                                   std::vector<std::uint32_t>& original) {
  PolygonSoup s = in;
  original.resize(in.positions.size());
  std::iota(original.begin(), original.end(), 0u);
  auto copy_vertex = [&](std::uint32_t v) {
    s.positions.push_back(in.positions[v]);
    if (!s.vertex_normals.empty()) s.vertex_normals.push_back(in.vertex_normals[v]);
    if (!s.vertex_colors.empty()) s.vertex_colors.push_back(in.vertex_colors[v]);
    if (!s.vertex_texcoords.empty()) s.vertex_texcoords.push_back(in.vertex_texcoords[v]);
    for (NamedScalars& n : s.vertex_scalars) n.values.push_back(n.values[v]);
    original.push_back(v);
    return static_cast<std::uint32_t>(s.positions.size() - 1);
  };
  auto repeats = [&](std::uint32_t b, std::uint32_t c) {
    return std::find(s.face_indices.begin() + b, s.face_indices.begin() + c,
                     s.face_indices[c]) != s.face_indices.begin() + c;
  };
  std::vector<std::uint8_t> repeated(in.positions.size(), 0);
  for (std::size_t f = 0; f < s.n_faces(); ++f)
    for (std::uint32_t c = s.face_offsets[f] + 1; c < s.face_offsets[f + 1]; ++c)
      if (repeats(s.face_offsets[f], c)) repeated[s.face_indices[c]] = 1;
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> fan_vertex;
  std::vector<std::uint8_t> first_fan_taken(in.positions.size(), 0);
  for (std::uint32_t c = 0; c < s.face_indices.size(); ++c) {
    const std::uint32_t v = in.face_indices[c];
    if (!repeated[v]) continue;
    auto [it, fresh] = fan_vertex.try_emplace({v, topo.corner_fan[c]}, v);
    if (fresh && first_fan_taken[v]) it->second = copy_vertex(v);
    first_fan_taken[v] = 1;
    s.face_indices[c] = it->second;
  }
  for (std::size_t f = 0; f < s.n_faces(); ++f)
    for (std::uint32_t c = s.face_offsets[f] + 1; c < s.face_offsets[f + 1]; ++c)
      if (repeats(s.face_offsets[f], c)) s.face_indices[c] = copy_vertex(original[s.face_indices[c]]);
  return s;
}

/// One level in OpenSubdiv's numbering, face corner by face corner (faces and their corner
/// order are the same in the split mesh and in OpenSubdiv): the vertex at each corner, the
/// edge from it to the next corner, and each edge's first vertex. Read through the faces,
/// a mesh element shared by copies that OpenSubdiv keeps apart is told apart.
struct Corners {
  std::vector<std::uint32_t> offsets, vertex, edge;
  std::vector<std::uint32_t> edge_v0;  ///< per OpenSubdiv edge
  std::uint32_t n_vertices = 0;
  std::size_t n_edges() const { return edge_v0.size(); }
};

Corners corners_level0(const PolygonSoup& soup, const OsdTopology& topo) {
  Corners c;
  c.offsets = soup.face_offsets;
  if (c.offsets.empty()) c.offsets.push_back(0);
  c.vertex = soup.face_indices;
  c.edge = topo.corner_edge;
  c.edge_v0.reserve(topo.n_edges());
  for (const auto& ends : topo.edge_vertices) c.edge_v0.push_back(ends[0]);
  c.n_vertices = static_cast<std::uint32_t>(soup.positions.size());
  return c;
}

/// Face f's mesh vertices (corner j) and edges (from corner j to j + 1).
void face_elements(const SurfaceMesh& m, Face f, std::vector<std::uint32_t>& vertices,
                   std::vector<std::uint32_t>& edges) {
  vertices.clear();
  edges.clear();
  for (Halfedge h : m.halfedges(f)) {  // h ends at corner j
    vertices.push_back(m.to_vertex(h).idx());
    edges.push_back(m.edge(m.next(h)).idx());
  }
}

/// The corners of the next level, by OpenSubdiv's (and geom's) child numbering alone:
/// vertices face-points (Catmull-Clark), edge-points, vertex-points; edges one per parent
/// corner (face-point or middle-triangle side), then two per parent edge from its
/// edge-point, the first at the edge's first vertex; faces the children of each parent face
/// in corner order, child j holding the vertex-point of corner j (Catmull-Clark children of
/// a non-quad, and Loop's middle triangle, start otherwise: see catmull_clark.cpp, loop.cpp).
Corners corners_child(const Corners& p, bool catmark) {
  const auto nf = static_cast<std::uint32_t>(p.offsets.size() - 1);
  const auto ne = static_cast<std::uint32_t>(p.n_edges());
  const std::uint32_t fp = catmark ? nf : 0, C = p.offsets.back();
  auto ep = [&](std::uint32_t E) { return fp + E; };
  auto vp = [&](std::uint32_t V) { return fp + ne + V; };
  Corners c;
  c.n_vertices = fp + ne + p.n_vertices;
  c.edge_v0.assign(C + 2 * std::size_t{ne}, kUnset);
  const std::size_t child_corners = catmark ? 4 * std::size_t{C} : 12 * std::size_t{nf};
  c.vertex.resize(child_corners);
  c.edge.resize(child_corners);
  c.offsets.resize(child_corners / (catmark ? 4 : 3) + 1);
  for (std::size_t f = 0; f < c.offsets.size(); ++f)
    c.offsets[f] = static_cast<std::uint32_t>(f * (catmark ? 4 : 3));
  auto put = [&](std::size_t at, std::uint32_t v, std::uint32_t e, std::uint32_t v0) {
    c.vertex[at] = v;
    c.edge[at] = e;
    c.edge_v0[e] = v0;
  };
  for (std::uint32_t g = 0; g < nf; ++g) {
    const std::uint32_t base = p.offsets[g], n = p.offsets[g + 1] - base;
    auto E = [&](std::uint32_t j) { return p.edge[base + j % n]; };
    // The end of OpenSubdiv's edge at the face's corner j (a degenerate edge starts at the
    // corner that made it).
    auto start_half = [&](std::uint32_t j) {
      const std::uint32_t v = p.vertex[base + j % n], w = p.vertex[base + (j + 1) % n];
      return v == w || v == p.edge_v0[E(j)] ? 0u : 1u;
    };
    auto half = [&](std::uint32_t j, bool at_start) {
      return C + 2 * E(j) + (at_start ? start_half(j) : 1 - start_half(j));
    };
    for (std::uint32_t m = 0; m < (catmark ? n : 3); ++m) {
      const std::uint32_t pm = (m + n - 1) % n;  // the corner before m
      const std::uint32_t V = vp(p.vertex[base + m]);
      if (catmark) {
        // Around the child of corner m: VP(v_m), EP(e_m), FP, EP(e_m-1); a quad's child is
        // rotated so that VP(v_m) is its corner m.
        const std::size_t at = 4 * std::size_t{base + m};
        const std::uint32_t r = n == 4 ? m : 0;
        const std::uint32_t ring_v[4] = {V, ep(E(m)), g, ep(E(pm))};
        const std::uint32_t ring_e[4] = {half(m, true), base + m, base + pm, half(pm, false)};
        const std::uint32_t ring_v0[4] = {ep(E(m)), g, g, ep(E(pm))};
        for (std::uint32_t i = 0; i < 4; ++i) {
          const std::uint32_t k = (4 - r + i) & 3u;
          put(at + i, ring_v[k], ring_e[k], ring_v0[k]);
        }
      } else {
        // Corner triangle m: VP(v_m), EP(e_m), EP(e_m-1), rotated so VP(v_m) is corner m.
        const std::size_t at = 12 * std::size_t{g} + 3 * m;
        const std::uint32_t ring_v[3] = {V, ep(E(m)), ep(E(pm))};
        const std::uint32_t ring_e[3] = {half(m, true), base + m, half(pm, false)};
        const std::uint32_t ring_v0[3] = {ep(E(m)), ep(E(m)), ep(E(pm))};
        for (std::uint32_t i = 0; i < 3; ++i) {
          const std::uint32_t k = (3 - m + i) % 3;
          put(at + i, ring_v[k], ring_e[k], ring_v0[k]);
        }
      }
    }
    if (!catmark)  // the middle triangle: EP(e_1), EP(e_2), EP(e_0)
      for (std::uint32_t i = 0; i < 3; ++i)
        put(12 * std::size_t{g} + 9 + i, ep(E(i + 1)), base + (i + 2) % 3, ep(E(i + 2)));
  }
  return c;
}

/// Whether the split mesh is OpenSubdiv's level 0 element for element, orientations
/// included: then every level is, and the copies need no joining.
bool is_identity(const SurfaceMesh& mesh, const Corners& c) {
  if (mesh.vertices_size() != c.n_vertices || mesh.edges_size() != c.n_edges()) return false;
  std::vector<std::uint32_t> pv, pe;
  for (Face f : mesh.faces()) {
    face_elements(mesh, f, pv, pe);
    const std::uint32_t base = c.offsets[f.idx()];
    for (std::uint32_t j = 0; j < pv.size(); ++j)
      if (pv[j] != c.vertex[base + j] || pe[j] != c.edge[base + j] ||
          mesh.from_vertex(Halfedge(2 * pe[j])).idx() != c.edge_v0[pe[j]])
        return false;
  }
  return true;
}

/// OpenSubdiv's vertex and edge of each mesh vertex and edge of level 0, through the faces
/// (isolated vertices through the build's vertex origins).
struct Level0Map {
  std::vector<std::uint32_t> vertex, edge;
};

Level0Map map_level0(const SurfaceMesh& mesh, const BuildReport& report,
                     const std::vector<std::uint32_t>& original, const Corners& c) {
  Level0Map m;
  m.vertex.resize(mesh.vertices_size());
  for (Vertex v : mesh.vertices()) m.vertex[v.idx()] = original[report.vertex_origin[v.idx()]];
  m.edge.assign(mesh.edges_size(), kUnset);
  std::vector<std::uint32_t> pv, pe;
  for (Face f : mesh.faces()) {
    face_elements(mesh, f, pv, pe);
    for (std::uint32_t j = 0; j < pe.size(); ++j) {
      std::uint32_t& e = m.edge[pe[j]];
      if (e == kUnset) e = c.edge[c.offsets[f.idx()] + j];
    }
  }
  return m;
}

/// Every copy gets the sharpness OpenSubdiv gives its original (boundaries are geom's own).
void tag_sharpness(SurfaceMesh& mesh, const Level0Map& map, const OsdTopology& topo) {
  auto sharp = [](float s) { return s > 0.0f; };
  const bool edges = std::any_of(topo.edge_sharpness.begin(), topo.edge_sharpness.end(), sharp);
  const bool vertices =
      std::any_of(topo.vertex_sharpness.begin(), topo.vertex_sharpness.end(), sharp);
  mesh.remove_property<Edge>(prop::kEdgeSharpness);
  mesh.remove_property<Vertex>(prop::kVertexSharpness);
  if (edges) {
    auto es = mesh.add_property<Edge, double>(prop::kEdgeSharpness, 0.0);
    for (Edge e : mesh.edges())
      if (!mesh.is_boundary(e)) es[e] = topo.edge_sharpness[map.edge[e.idx()]];
  }
  if (vertices) {
    auto vs = mesh.add_property<Vertex, double>(prop::kVertexSharpness, 0.0);
    for (Vertex v : mesh.vertices()) vs[v] = topo.vertex_sharpness[map.vertex[v.idx()]];
  }
}

/// Edges OpenSubdiv refines smooth that the split left open (a boundary here).
std::size_t opened_edges(const SurfaceMesh& mesh, const Level0Map& map, const OsdTopology& topo) {
  std::size_t n = 0;
  for (Edge e : mesh.edges())
    if (mesh.is_boundary(e) && topo.edge_sharpness[map.edge[e.idx()]] < kInfinite) ++n;
  return n;
}

/// The final mesh as a soup on OpenSubdiv's vertices, in its order. Vertices no face uses
/// stay as they were in `input` (`isolated`: final number, input vertex).
PolygonSoup join_copies(const SurfaceMesh& mesh, const Corners& c, bool keep_tags,
                        const std::vector<std::pair<std::uint32_t, std::uint32_t>>& isolated,
                        const PolygonSoup& input) {
  PolygonSoup s = to_soup(mesh);
  if (!keep_tags) {
    s.creases.clear();
    s.corners.clear();
  }
  // Each OpenSubdiv vertex takes its values from one mesh copy; isolated ones their own.
  std::vector<std::uint32_t> from(c.n_vertices, kUnset), id_of(s.positions.size(), kUnset);
  for (std::size_t k = 0; k < c.vertex.size(); ++k) {
    const std::uint32_t x = s.face_indices[k];
    if (from[c.vertex[k]] == kUnset) from[c.vertex[k]] = x;
    if (id_of[x] == kUnset) id_of[x] = c.vertex[k];
    s.face_indices[k] = c.vertex[k];
  }
  auto gather = [&](auto& values, const auto& given) {
    if (values.empty()) return;
    auto old = std::move(values);
    values.assign(c.n_vertices, old.front());
    for (std::uint32_t id = 0; id < c.n_vertices; ++id)
      if (from[id] != kUnset) values[id] = old[from[id]];
    if (given.size() == input.positions.size())
      for (const auto& [id, v] : isolated) values[id] = given[v];
  };
  gather(s.positions, input.positions);
  gather(s.vertex_normals, input.vertex_normals);
  gather(s.vertex_colors, input.vertex_colors);
  gather(s.vertex_texcoords, input.vertex_texcoords);
  for (std::size_t k = 0; k < s.vertex_scalars.size(); ++k)
    gather(s.vertex_scalars[k].values, k < input.vertex_scalars.size()
                                           ? input.vertex_scalars[k].values
                                           : std::vector<double>{});
  std::erase_if(s.creases, [&](const EdgeSharpness& e) { return id_of[e.a] == kUnset || id_of[e.b] == kUnset; });
  for (EdgeSharpness& e : s.creases) e = {id_of[e.a], id_of[e.b], e.sharpness};
  std::erase_if(s.corners, [&](const VertexSharpness& v) { return id_of[v.v] == kUnset; });
  for (VertexSharpness& v : s.corners) v.v = id_of[v.v];
  return s;
}

/// What the soup holds beside its mesh: material files and the boundary tag.
void keep_file_data(const PolygonSoup& input, PolygonSoup& out) {
  out.material_libraries = input.material_libraries;
  out.boundary_interpolation = input.boundary_interpolation;
}

void check_indices(const PolygonSoup& soup) {
  const std::size_t n = soup.positions.size();
  for (std::size_t f = 0; f < soup.n_faces(); ++f)
    for (std::uint32_t v : soup.face(f))
      if (v >= n)
        throw InvalidArgument("subdivision: face " + std::to_string(f) + " has index " +
                              std::to_string(v) + " with " + std::to_string(n) + " vertices");
  for (std::size_t f = 0; f < soup.n_faces(); ++f)
    if (soup.face(f).size() < 3)
      throw InvalidArgument("subdivision: face " + std::to_string(f) + " has " +
                            std::to_string(soup.face(f).size()) + " corners (3 or more needed)");
}

}  // namespace

SoupSubdivideResult subdivide(const PolygonSoup& input, const SubdivideOptions& options) {
  check_soup(input);
  check_indices(input);
  if (options.levels < 0 || options.levels > 10)
    throw InvalidArgument("subdivision levels must be in [0, 10], got " +
                          std::to_string(options.levels));
  const bool catmark = options.scheme == SubdivisionScheme::kCatmullClark;
  const OsdTopology topo = detail::subdiv::osd_topology(
      input, options.boundary == BoundaryInterpolation::kEdgesAndCorners);
  std::vector<std::uint32_t> original;
  const PolygonSoup split = split_repeated_corners(input, topo, original);
  BuildOptions bo;
  bo.orient = false;
  bo.keep_degenerate = true;
  BuildResult built = build(split, bo);
  Corners c = corners_level0(input, topo);
  const Level0Map map = map_level0(built.mesh, built.report, original, c);

  SoupSubdivideResult result;
  result.nonmanifold_edges = topo.nonmanifold_edges();
  result.nonmanifold_vertices = topo.nonmanifold_vertices();
  result.degenerate_edges = topo.degenerate_edges();
  result.split_vertices = built.mesh.n_vertices() - input.positions.size();
  result.opened_edges = opened_edges(built.mesh, map, topo);
  tag_sharpness(built.mesh, map, topo);

  SubdivideOptions tagged = options;
  tagged.boundary = BoundaryInterpolation::kEdges;  // corners are tagged already
  const bool identity = is_identity(built.mesh, c);
  SubdivideResult r = subdivide(built.mesh, tagged);
  result.levels = r.levels;
  result.angle_creased_edges = r.angle_creased_edges;
  result.limit_max_distance = r.limit_max_distance;
  result.limit_rms_distance = r.limit_rms_distance;
  const bool keep_tags = !input.creases.empty() || !input.corners.empty();
  if (identity) {
    result.per_level = std::move(r.per_level);
    result.soup = to_soup(r.mesh);
    if (!keep_tags) result.soup.creases.clear(), result.soup.corners.clear();
  } else {
    // Vertices no face uses stay put, renumbered as vertex-points level by level.
    std::vector<std::uint8_t> used(input.positions.size(), 0);
    for (std::uint32_t v : input.face_indices) used[v] = 1;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> isolated;
    for (std::uint32_t v = 0; v < used.size(); ++v)
      if (!used[v]) isolated.emplace_back(v, v);
    auto counts = [](const Corners& k) {
      return LevelCounts{k.n_vertices, k.n_edges(), k.offsets.size() - 1};
    };
    result.per_level.push_back(counts(c));
    for (int level = 1; level <= options.levels; ++level) {
      const std::size_t faces = catmark ? c.offsets.size() - 1 : 0;
      for (auto& iso : isolated) iso.first += static_cast<std::uint32_t>(faces + c.n_edges());
      c = corners_child(c, catmark);
      result.per_level.push_back(counts(c));
    }
    result.soup = join_copies(r.mesh, c, keep_tags, isolated, input);
  }
  keep_file_data(input, result.soup);
  return result;
}

}  // namespace geom
