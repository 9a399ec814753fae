#include <geom/core/soup.h>

#include <algorithm>
#include <limits>
#include <map>
#include <unordered_map>
#include <string>

namespace geom {

namespace {

bool is_known_name(const std::string& name) {
  return name == SurfaceMesh::kPositions || name == prop::kVertexNormal || name == prop::kVertexColor ||
         name == prop::kVertexTexCoord || name == prop::kVertexSharpness;
}

// The named double properties of one kind ("v:" or "f:"), other than the ones to_soup()
// carries in dedicated fields.
template <class H>
std::vector<std::string> scalar_names(const SurfaceMesh& mesh, const char* prefix) {
  std::vector<std::string> out;
  for (const std::string& name : mesh.property_names<H>()) {
    if (name.rfind(prefix, 0) != 0 || is_known_name(name)) continue;
    if (mesh.template get_property<H, double>(name)) out.push_back(name);
  }
  return out;
}

// The face property `name` (std::string, empty: no name) as FaceNames over `faces`.
void face_names(const SurfaceMesh& mesh, const std::vector<Face>& faces, const char* name, FaceNames& out) {
  const auto p = mesh.get_property<Face, std::string>(name);
  if (!p) return;
  std::unordered_map<std::string, std::uint32_t> index;
  out.of_face.reserve(faces.size());
  for (Face f : faces) {
    if (p[f].empty()) {
      out.of_face.push_back(FaceNames::kUnnamed);
      continue;
    }
    const auto [it, added] = index.try_emplace(p[f], static_cast<std::uint32_t>(out.names.size()));
    if (added) out.names.push_back(p[f]);
    out.of_face.push_back(it->second);
  }
}

}  // namespace

void check_soup(const PolygonSoup& so) {
  if (so.positions.size() >= std::numeric_limits<std::uint32_t>::max())
    throw InvalidArgument("soup: too many vertices for 32-bit indices");
  if (!so.face_offsets.empty()) {
    if (so.face_offsets.front() != 0)
      throw InvalidArgument("soup: face_offsets must start at 0, found " + std::to_string(so.face_offsets.front()));
    for (std::size_t i = 1; i < so.face_offsets.size(); ++i)
      if (so.face_offsets[i] < so.face_offsets[i - 1])
        throw InvalidArgument("soup: face_offsets decrease at entry " + std::to_string(i));
    if (so.face_offsets.back() != so.face_indices.size())
      throw InvalidArgument("soup: face_offsets ends at " + std::to_string(so.face_offsets.back()) +
                            " but there are " + std::to_string(so.face_indices.size()) + " face indices");
  } else if (!so.face_indices.empty()) {
    throw InvalidArgument("soup: face_indices given without face_offsets");
  }
  auto per = [](std::size_t got, std::size_t want, const char* what, const char* per_what) {
    if (got != 0 && got != want)
      throw InvalidArgument(std::string("soup: ") + what + " has " + std::to_string(got) +
                            " entries, expected 0 or one per " + per_what + " (" +
                            std::to_string(want) + ")");
  };
  std::size_t v = so.positions.size(), c = so.face_indices.size(), f = so.n_faces();
  per(so.vertex_normals.size(), v, "vertex_normals", "vertex");
  per(so.vertex_colors.size(), v, "vertex_colors", "vertex");
  per(so.vertex_texcoords.size(), v, "vertex_texcoords", "vertex");
  per(so.corner_texcoords.size(), c, "corner_texcoords", "corner");
  per(so.corner_normals.size(), c, "corner_normals", "corner");
  for (const auto& sc : so.vertex_scalars)
    if (sc.values.size() != v)
      throw InvalidArgument("soup: vertex scalar '" + sc.name + "' has " + std::to_string(sc.values.size()) +
                            " values for " + std::to_string(v) + " vertices");
  for (const auto* names : {&so.face_objects, &so.face_groups, &so.face_materials}) {
    per(names->of_face.size(), f, "face names", "face");
    for (std::uint32_t i : names->of_face)
      if (i != FaceNames::kUnnamed && i >= names->names.size())
        throw InvalidArgument("soup: a face name index " + std::to_string(i) + " is beyond the " +
                              std::to_string(names->names.size()) + " names");
  }
  for (const auto& sc : so.face_scalars)
    if (sc.values.size() != f)
      throw InvalidArgument("soup: face scalar '" + sc.name + "' has " + std::to_string(sc.values.size()) +
                            " values for " + std::to_string(f) + " faces");
}

PolygonSoup to_soup(const SurfaceMesh& mesh) {
  PolygonSoup soup;
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> vid(mesh.vertices_size(), kNone);
  std::vector<Vertex> live;
  live.reserve(mesh.n_vertices());
  for (Vertex v : mesh.vertices()) {
    vid[v.idx()] = static_cast<std::uint32_t>(live.size());
    live.push_back(v);
  }
  soup.positions.reserve(live.size());
  for (Vertex v : live) soup.positions.push_back(mesh.position(v));

  auto vertex_attr = [&](auto tag, const char* name, auto& dst) {
    using T = decltype(tag);
    auto p = mesh.get_property<Vertex, T>(name);
    if (!p) return;
    dst.reserve(live.size());
    for (Vertex v : live) dst.push_back(p[v]);
  };
  vertex_attr(Normal(), prop::kVertexNormal, soup.vertex_normals);
  vertex_attr(Color(), prop::kVertexColor, soup.vertex_colors);
  vertex_attr(TexCoord(), prop::kVertexTexCoord, soup.vertex_texcoords);
  for (const std::string& name : scalar_names<Vertex>(mesh, "v:")) {
    auto p = mesh.get_property<Vertex, double>(name);
    NamedScalars sc{name.substr(2), {}};
    sc.values.reserve(live.size());
    for (Vertex v : live) sc.values.push_back(p[v]);
    soup.vertex_scalars.push_back(std::move(sc));
  }

  auto ctex = mesh.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  auto cnor = mesh.get_property<Halfedge, Normal>(prop::kCornerNormal);
  std::vector<Face> faces;
  faces.reserve(mesh.n_faces());
  soup.face_offsets.reserve(mesh.n_faces() + 1);
  soup.face_offsets.push_back(0);
  soup.face_indices.reserve(mesh.n_halfedges() / 2 + mesh.n_faces());
  for (Face f : mesh.faces()) {
    faces.push_back(f);
    for (Halfedge h : mesh.halfedges(f)) {
      soup.face_indices.push_back(vid[mesh.to_vertex(h).idx()]);
      if (ctex) soup.corner_texcoords.push_back(ctex[h]);
      if (cnor) soup.corner_normals.push_back(cnor[h]);
    }
    soup.face_offsets.push_back(static_cast<std::uint32_t>(soup.face_indices.size()));
  }
  if (faces.empty()) soup.face_offsets.clear();
  for (const std::string& name : scalar_names<Face>(mesh, "f:")) {
    auto p = mesh.get_property<Face, double>(name);
    NamedScalars sc{name.substr(2), {}};
    sc.values.reserve(faces.size());
    for (Face f : faces) sc.values.push_back(p[f]);
    soup.face_scalars.push_back(std::move(sc));
  }

  face_names(mesh, faces, prop::kFaceObject, soup.face_objects);
  face_names(mesh, faces, prop::kFaceGroup, soup.face_groups);
  face_names(mesh, faces, prop::kFaceMaterial, soup.face_materials);
  if (auto sharp = mesh.get_property<Edge, double>(prop::kEdgeSharpness))
    for (Edge e : mesh.edges())
      if (sharp[e] != 0.0)
        soup.creases.push_back({vid[mesh.vertex(e, 0).idx()], vid[mesh.vertex(e, 1).idx()], sharp[e]});
  if (auto sharp = mesh.get_property<Vertex, double>(prop::kVertexSharpness))
    for (Vertex v : live)
      if (sharp[v] != 0.0) soup.corners.push_back({vid[v.idx()], sharp[v]});
  return soup;
}

void join_vertices(PolygonSoup& soup, std::span<const std::uint32_t> same) {
  check_soup(soup);
  const std::size_t n = soup.positions.size();
  if (same.size() != n)
    throw InvalidArgument("join_vertices: " + std::to_string(same.size()) + " entries for " +
                          std::to_string(n) + " vertices");
  // Kept vertices' new numbers; a removed vertex takes its representative's.
  std::vector<std::uint32_t> id(n);
  std::uint32_t kept = 0;
  for (std::size_t v = 0; v < n; ++v) {
    const std::uint32_t r = same[v];
    if (r >= n)
      throw InvalidArgument("join_vertices: vertex " + std::to_string(v) + " joins vertex " +
                            std::to_string(r) + ", beyond the " + std::to_string(n) + " vertices");
    if (same[r] != r)
      throw InvalidArgument("join_vertices: vertex " + std::to_string(v) + " joins vertex " +
                            std::to_string(r) + ", which is not its own representative");
    if (r == v) id[v] = kept++;
  }
  for (std::size_t v = 0; v < n; ++v) id[v] = id[same[v]];
  auto compact = [&](auto& values) {
    if (values.empty()) return;
    std::size_t out = 0;
    for (std::size_t v = 0; v < n; ++v)
      if (same[v] == v) values[out++] = values[v];
    values.resize(out);
  };
  compact(soup.positions);
  compact(soup.vertex_normals);
  compact(soup.vertex_colors);
  compact(soup.vertex_texcoords);
  for (NamedScalars& s : soup.vertex_scalars) compact(s.values);
  auto to = [&](std::uint32_t v) { return v < n ? id[v] : v; };  // bad indices stay bad
  for (std::uint32_t& c : soup.face_indices) c = to(c);
  // A split edge or vertex carried its tag to each copy: one tag again, the sharpest.
  std::map<std::pair<std::uint32_t, std::uint32_t>, double> creases;
  for (const EdgeSharpness& e : soup.creases) {
    const std::uint32_t a = to(e.a), b = to(e.b);
    double& s = creases.try_emplace({std::min(a, b), std::max(a, b)}, e.sharpness).first->second;
    s = std::max(s, e.sharpness);
  }
  soup.creases.clear();
  for (const auto& [ab, s] : creases) soup.creases.push_back({ab.first, ab.second, s});
  std::map<std::uint32_t, double> corners;
  for (const VertexSharpness& c : soup.corners) {
    double& s = corners.try_emplace(to(c.v), c.sharpness).first->second;
    s = std::max(s, c.sharpness);
  }
  soup.corners.clear();
  for (const auto& [v, s] : corners) soup.corners.push_back({v, s});
}

}  // namespace geom
