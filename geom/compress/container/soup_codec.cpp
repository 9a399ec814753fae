#include <geom/compress/container/soup_codec.h>

#include <geom/core/build.h>

#include <algorithm>
#include <numeric>

namespace geom {

namespace {

enum class FaceFate : std::uint8_t { kBuild, kLoose, kUnstorable };

bool repeats_a_vertex(std::span<const std::uint32_t> f, std::vector<std::uint32_t>& scratch) {
  if (f.size() <= 8) {  // most faces: no allocation
    for (std::size_t i = 0; i < f.size(); ++i)
      for (std::size_t j = i + 1; j < f.size(); ++j)
        if (f[i] == f[j]) return true;
    return false;
  }
  scratch.assign(f.begin(), f.end());
  std::sort(scratch.begin(), scratch.end());
  return std::adjacent_find(scratch.begin(), scratch.end()) != scratch.end();
}

/// Faces with an index beyond the vertices cannot be stored; faces with a repeated index
/// go around build(), which would drop them or lose the repeated corner.
std::vector<FaceFate> sort_faces(const PolygonSoup& soup) {
  std::vector<FaceFate> fate(soup.n_faces(), FaceFate::kBuild);
  std::vector<std::uint32_t> scratch;
  for (std::size_t f = 0; f < fate.size(); ++f) {
    const auto c = soup.face(f);
    if (std::any_of(c.begin(), c.end(), [&](std::uint32_t v) { return v >= soup.positions.size(); }))
      fate[f] = FaceFate::kUnstorable;
    else if (repeats_a_vertex(c, scratch))
      fate[f] = FaceFate::kLoose;
  }
  return fate;
}

/// The soup with only the faces to build (per-corner and per-face values with them).
PolygonSoup faces_to_build(const PolygonSoup& soup, std::span<const FaceFate> fate,
                           std::vector<std::uint32_t>& origin) {
  PolygonSoup out = soup;
  out.face_offsets.clear();
  out.face_indices.clear();
  out.corner_texcoords.clear();
  out.corner_normals.clear();
  for (NamedScalars& s : out.face_scalars) s.values.clear();
  for (FaceNames* names : {&out.face_objects, &out.face_groups, &out.face_materials}) names->of_face.clear();
  for (std::uint32_t f = 0; f < fate.size(); ++f) {
    if (fate[f] != FaceFate::kBuild) continue;
    origin.push_back(f);
    out.add_face(soup.face(f));
    for (std::uint32_t c = soup.face_offsets[f]; c < soup.face_offsets[f + 1]; ++c) {
      if (!soup.corner_texcoords.empty()) out.corner_texcoords.push_back(soup.corner_texcoords[c]);
      if (!soup.corner_normals.empty()) out.corner_normals.push_back(soup.corner_normals[c]);
    }
    for (std::size_t k = 0; k < soup.face_scalars.size(); ++k)
      out.face_scalars[k].values.push_back(soup.face_scalars[k].values[f]);
    for (auto [from, to] : {std::pair{&soup.face_objects, &out.face_objects}, std::pair{&soup.face_groups, &out.face_groups},
                            std::pair{&soup.face_materials, &out.face_materials}})
      if (!from->empty()) to->of_face.push_back(from->of_face[f]);
  }
  return out;
}

}  // namespace

CompressResult compress(const PolygonSoup& soup, const CompressOptions& options) {
  check_soup(soup);
  std::vector<FaceFate> fate = sort_faces(soup);
  const bool all_built = std::all_of(fate.begin(), fate.end(), [](FaceFate x) { return x == FaceFate::kBuild; });
  std::vector<std::uint32_t> origin;  // soup face of each face given to build()
  BuildOptions build_options;
  build_options.orient = false;  // a flip would change the face; a split keeps it
  BuildResult built = all_built ? build(soup, build_options)
                                : build(faces_to_build(soup, fate, origin), build_options);
  if (all_built) origin.resize(soup.n_faces()), std::iota(origin.begin(), origin.end(), 0u);
  // Faces build() dropped (degenerate, zero area, duplicates) travel loose too.
  std::vector<std::uint8_t> in_mesh(soup.n_faces(), 0);
  for (std::uint32_t f : built.report.face_origin) in_mesh[origin[f]] = 1;
  CompressOptions o = options;
  o.loose_faces.clear();
  o.loose_face_positions.clear();
  o.vertex_origin.clear();
  std::size_t stored = 0, unstorable = 0;
  for (std::uint32_t f = 0; f < fate.size(); ++f) {
    if (fate[f] == FaceFate::kUnstorable) {
      ++unstorable;
      continue;
    }
    if (!in_mesh[f]) {
      std::vector<std::uint32_t> corners;
      for (std::uint32_t v : soup.face(f)) corners.push_back(built.report.vertex_map[v].idx());
      o.loose_faces.push_back(std::move(corners));
      o.loose_face_positions.push_back(static_cast<std::uint32_t>(stored));
    }
    ++stored;
  }
  if (built.report.split_apart()) o.vertex_origin = built.report.vertex_origin;
  CompressResult r = compress(built.mesh, o);
  r.stats.loose_faces = o.loose_faces.size();
  r.stats.unstorable_faces = unstorable;
  // A loose face travels as its corners' vertices only.
  const std::string loose = std::to_string(o.loose_faces.size()) + " loose face" +
                            (o.loose_faces.size() == 1 ? "" : "s") + " (they decode as zeros)";
  if (!o.loose_faces.empty() && !soup.corner_texcoords.empty())
    r.stats.dropped_properties.push_back("corner texture coordinates of " + loose);
  if (!o.loose_faces.empty() && !soup.corner_normals.empty())
    r.stats.dropped_properties.push_back("corner normals of " + loose);
  r.stats.split_copies = built.mesh.n_vertices() - soup.positions.size();
  return r;
}

PolygonSoup to_soup(const DecompressResult& decoded) {
  PolygonSoup soup = to_soup(decoded.mesh);
  const auto& loose = decoded.loose_faces;
  if (!loose.empty()) {
    const PolygonSoup mesh_faces = soup;
    soup.face_offsets.clear();
    soup.face_indices.clear();
    soup.corner_texcoords.clear();
    soup.corner_normals.clear();
    const std::size_t n = mesh_faces.n_faces() + loose.size();
    std::size_t next_mesh = 0, next_loose = 0;
    for (std::size_t f = 0; f < n; ++f) {
      // Without positions the loose faces follow the mesh's.
      const bool is_loose = decoded.loose_face_positions.empty()
                                ? f >= mesh_faces.n_faces()
                                : next_loose < loose.size() && decoded.loose_face_positions[next_loose] == f;
      if (is_loose) {
        const auto& c = loose[next_loose++];
        soup.add_face(c);
        if (!mesh_faces.corner_texcoords.empty()) soup.corner_texcoords.resize(soup.face_indices.size(), TexCoord::Zero());
        if (!mesh_faces.corner_normals.empty()) soup.corner_normals.resize(soup.face_indices.size(), Normal::Zero());
        continue;
      }
      soup.add_face(mesh_faces.face(next_mesh));
      for (std::uint32_t c = mesh_faces.face_offsets[next_mesh]; c < mesh_faces.face_offsets[next_mesh + 1]; ++c) {
        if (!mesh_faces.corner_texcoords.empty()) soup.corner_texcoords.push_back(mesh_faces.corner_texcoords[c]);
        if (!mesh_faces.corner_normals.empty()) soup.corner_normals.push_back(mesh_faces.corner_normals[c]);
      }
      ++next_mesh;
    }
    soup.face_scalars.clear();  // the stream holds none
  }
  if (!decoded.vertex_representative.empty()) join_vertices(soup, decoded.vertex_representative);
  return soup;
}

}  // namespace geom
