// glTF output and document helpers: one binary buffer, accessors with the bounds the
// specification requires, MSFT_lod for LOD chains.

#include <geom/io/gltf.h>
#include <geom/io/gltf_buffers.h>

#include <geom/core/errors.h>

#include <nlohmann/json.hpp>

#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cstring>
#include <functional>
#include <map>
#include <numeric>
#include <tuple>

namespace geom {
namespace {

using nlohmann::json;

// glTF stores attributes per vertex; corner attributes (OBJ's vt/vn) split vertices at seams.
struct Expanded {
  std::vector<Point> positions;
  std::vector<Normal> normals;
  std::vector<TexCoord> texcoords;
  std::vector<Color> colors;
  std::vector<std::uint32_t> triangles;
  std::vector<std::uint32_t> source;  ///< per written vertex: the soup's vertex
  std::vector<std::uint32_t> triangle_face;  ///< per triangle: the soup's face
};

Expanded expand(const PolygonSoup& s) {
  Expanded e;
  // Corner values that agree at every vertex are also given per vertex (see soup.h's
  // readers); then the vertices need no split.
  const bool has_vn = s.vertex_normals.size() == s.positions.size() && !s.positions.empty();
  const bool has_vt = s.vertex_texcoords.size() == s.positions.size() && !s.positions.empty();
  const bool corner_uv = !s.corner_texcoords.empty() && !has_vt, corner_n = !s.corner_normals.empty() && !has_vn;
  const bool vn = !corner_n && has_vn, vt = !corner_uv && has_vt;
  const bool vc = s.vertex_colors.size() == s.positions.size() && !s.positions.empty();
  // Without corner attributes the vertices go out as they are, in their order and with
  // those no face uses (glTF allows them), so that a round trip keeps vertex numbers.
  if (!corner_uv && !corner_n) {
    e.positions = s.positions;
    if (vn) e.normals = s.vertex_normals;
    if (vt) e.texcoords = s.vertex_texcoords;
    if (vc) e.colors = s.vertex_colors;
    e.source.resize(s.positions.size());
    std::iota(e.source.begin(), e.source.end(), 0u);
  }
  std::map<std::tuple<std::uint32_t, double, double, double, double, double>, std::uint32_t> seen;
  auto vertex_of = [&](std::size_t corner, std::uint32_t v) -> std::uint32_t {
    if (!corner_uv && !corner_n) return v;
    TexCoord uv = corner_uv ? s.corner_texcoords[corner] : TexCoord::Zero();
    Normal n = corner_n ? s.corner_normals[corner] : Normal::Zero();
    auto key = std::make_tuple(v, uv.x(), uv.y(), n.x(), n.y(), n.z());
    auto [it, fresh] = seen.emplace(key, static_cast<std::uint32_t>(e.positions.size()));
    if (fresh) {
      e.positions.push_back(s.positions[v]);
      e.source.push_back(v);
      if (corner_n || vn) e.normals.push_back(corner_n ? n : s.vertex_normals[v]);
      if (corner_uv || vt) e.texcoords.push_back(corner_uv ? uv : s.vertex_texcoords[v]);
      if (vc) e.colors.push_back(s.vertex_colors[v]);
    }
    return it->second;
  };
  for (std::size_t f = 0; f < s.n_faces(); ++f) {
    auto c = s.face(f);
    const std::size_t first = s.face_offsets[f];
    for (std::size_t k = 1; k + 1 < c.size(); ++k) {
      e.triangles.push_back(vertex_of(first, c[0]));
      e.triangles.push_back(vertex_of(first + k, c[k]));
      e.triangles.push_back(vertex_of(first + k + 1, c[k + 1]));
      e.triangle_face.push_back(static_cast<std::uint32_t>(f));
    }
  }
  // glTF requires unit normals; a zero or non-finite one has no direction to write.
  for (Normal& n : e.normals) {
    if (!n.allFinite() || n.norm() == 0) {
      e.normals.clear();
      break;
    }
    n.normalize();
  }
  return e;
}

class Writer {
 public:
  json gltf = {{"asset", {{"version", "2.0"}, {"generator", "geom 0.1.0"}}}};
  std::string bin;

  int add_view(const void* data, std::size_t bytes, int target) {
    while (bin.size() % 4) bin.push_back('\0');
    json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}, {"target", target}};
    bin.append(static_cast<const char*>(data), bytes);
    gltf["bufferViews"].push_back(view);
    return static_cast<int>(gltf["bufferViews"].size() - 1);
  }

  template <int N, class V>
  int add_float_accessor(const std::vector<V>& values, const char* type, bool bounds) {
    std::vector<float> f;
    f.reserve(values.size() * N);
    for (const V& v : values)
      for (int k = 0; k < N; ++k) f.push_back(static_cast<float>(v[k]));
    json acc = {{"bufferView", add_view(f.data(), f.size() * 4, 34962)}, {"componentType", 5126},
                {"count", values.size()}, {"type", type}};
    if (bounds && !values.empty()) {  // POSITION must carry min and max
      std::vector<float> lo(f.begin(), f.begin() + N), hi = lo;
      for (std::size_t i = 0; i < f.size(); ++i) {
        lo[i % N] = std::min(lo[i % N], f[i]);
        hi[i % N] = std::max(hi[i % N], f[i]);
      }
      acc["min"] = lo;
      acc["max"] = hi;
    }
    gltf["accessors"].push_back(acc);
    return static_cast<int>(gltf["accessors"].size() - 1);
  }

  /// Whether a reader welding the written vertices by position and colour (as geom's does)
/// would join soup vertices that are apart: written coordinates are single precision.
bool welding_would_join(const Expanded& e) {
  std::map<std::array<float, 6>, std::uint32_t> first;
  for (std::size_t i = 0; i < e.positions.size(); ++i) {
    const Point& p = e.positions[i];
    const Color c = e.colors.empty() ? Color::Zero() : e.colors[i];
    const std::array<float, 6> key = {float(p.x()) + 0.0f, float(p.y()) + 0.0f, float(p.z()) + 0.0f,
                                      float(c.x()), float(c.y()), float(c.z())};
    const auto [it, fresh] = first.try_emplace(key, e.source[i]);
    if (!fresh && it->second != e.source[i]) return true;
  }
  return false;
}

/// The mesh's index in the document, or -1 when it has no triangles: glTF has no empty
  /// mesh (a primitive needs a POSITION accessor, and an accessor a count of at least 1).
  int add_mesh(const PolygonSoup& soup, const std::string& name) {
    Expanded e = expand(soup);
    if (e.triangles.empty()) return -1;
    json prim = {{"mode", 4}};
    prim["attributes"]["POSITION"] = add_float_accessor<3>(e.positions, "VEC3", true);
    if (!e.normals.empty()) prim["attributes"]["NORMAL"] = add_float_accessor<3>(e.normals, "VEC3", false);
    if (!e.texcoords.empty()) prim["attributes"]["TEXCOORD_0"] = add_float_accessor<2>(e.texcoords, "VEC2", false);
    if (!e.colors.empty()) {
      for (Color& c : e.colors) c = c.cwiseMax(0.0).cwiseMin(1.0);  // glTF colours are in [0, 1]
      prim["attributes"]["COLOR_0"] = add_float_accessor<3>(e.colors, "VEC3", false);
    }
    if (welding_would_join(e)) {  // attributes cannot be UNSIGNED_INT: two 16-bit halves
      std::vector<std::uint16_t> halves;
      for (std::uint32_t v : e.source) halves.insert(halves.end(), {std::uint16_t(v & 0xFFFF), std::uint16_t(v >> 16)});
      gltf["accessors"].push_back({{"bufferView", add_view(halves.data(), halves.size() * 2, 34962)},
                                   {"componentType", 5123}, {"count", e.source.size()}, {"type", "VEC2"}});
      prim["attributes"][gltf_detail::kVertexIdAttribute] = gltf["accessors"].size() - 1;
    }
    // One primitive per material (sharing the vertex accessors), in order of first use.
    json primitives = json::array();
    for (const auto& [material, triangles] : by_material(e, soup.face_materials)) {
      json p = prim;
      gltf["accessors"].push_back({{"bufferView", add_view(triangles.data(), triangles.size() * 4, 34963)},
                                   {"componentType", 5125}, {"count", triangles.size()}, {"type", "SCALAR"}});
      p["indices"] = gltf["accessors"].size() - 1;
      if (material != FaceNames::kUnnamed) p["material"] = material_index(soup.face_materials.names[material]);
      primitives.push_back(p);
    }
    json mesh = {{"primitives", primitives}};
    if (!name.empty()) mesh["name"] = name;
    gltf["meshes"].push_back(mesh);
    return static_cast<int>(gltf["meshes"].size() - 1);
  }

  /// The triangles of each material (kUnnamed: faces without one), in order of first use.
  static std::vector<std::pair<std::uint32_t, std::vector<std::uint32_t>>> by_material(const Expanded& e,
                                                                                      const FaceNames& names) {
    std::vector<std::pair<std::uint32_t, std::vector<std::uint32_t>>> groups;
    std::map<std::uint32_t, std::size_t> slot;
    for (std::size_t t = 0; t < e.triangle_face.size(); ++t) {
      const std::uint32_t m = names.empty() ? FaceNames::kUnnamed : names.of_face[e.triangle_face[t]];
      const auto [it, fresh] = slot.try_emplace(m, groups.size());
      if (fresh) groups.push_back({m, {}});
      auto& tri = groups[it->second].second;
      tri.insert(tri.end(), e.triangles.begin() + 3 * t, e.triangles.begin() + 3 * t + 3);
    }
    return groups;
  }

  /// The document's material of that name (a default material carrying the name).
  int material_index(const std::string& name) {
    if (!gltf.contains("materials")) gltf["materials"] = json::array();
    json& materials = gltf["materials"];
    for (std::size_t i = 0; i < materials.size(); ++i)
      if (materials[i]["name"] == name) return static_cast<int>(i);
    materials.push_back({{"name", name}});
    return static_cast<int>(materials.size() - 1);
  }

  /// The specification's arrays have at least one element when present.
  void drop_if_empty(const char* key) {
    if (gltf.contains(key) && gltf[key].empty()) gltf.erase(key);
  }
};

void append_le32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

std::string base64(const std::string& in) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < in.size(); i += 3) {
    std::uint32_t v = static_cast<std::uint8_t>(in[i]) << 16;
    if (i + 1 < in.size()) v |= static_cast<std::uint8_t>(in[i + 1]) << 8;
    if (i + 2 < in.size()) v |= static_cast<std::uint8_t>(in[i + 2]);
    out.push_back(kAlphabet[(v >> 18) & 63]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out.push_back(i + 1 < in.size() ? kAlphabet[(v >> 6) & 63] : '=');
    out.push_back(i + 2 < in.size() ? kAlphabet[v & 63] : '=');
  }
  return out;
}

}  // namespace

std::string write_gltf(const GltfDocument& doc, bool binary) {
  Writer w;
  w.gltf["bufferViews"] = json::array();
  w.gltf["accessors"] = json::array();
  w.gltf["meshes"] = json::array();
  std::vector<int> mesh_index(doc.meshes.size());
  for (std::size_t m = 0; m < doc.meshes.size(); ++m)
    mesh_index[m] = w.add_mesh(doc.meshes[m], m < doc.mesh_names.size() ? doc.mesh_names[m] : "");
  bool lod = false;
  json nodes = json::array();
  for (std::size_t i = 0; i < doc.nodes.size(); ++i) {
    const GltfNode& n = doc.nodes[i];
    json node = json::object();
    if (!n.name.empty()) node["name"] = n.name;
    if (n.mesh >= 0) {
      if (n.mesh >= static_cast<int>(doc.meshes.size())) throw InvalidArgument("glTF node " + std::to_string(i) + " refers to missing mesh " + std::to_string(n.mesh));
      if (mesh_index[n.mesh] >= 0) node["mesh"] = mesh_index[n.mesh];
    }
    if (!n.matrix.isIdentity(0)) {
      std::vector<double> m;
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m.push_back(n.matrix(r, c));
      node["matrix"] = m;
    }
    for (int c : n.children)
      if (c < 0 || c >= static_cast<int>(doc.nodes.size())) throw InvalidArgument("glTF node " + std::to_string(i) + " has a missing child");
    if (!n.children.empty()) node["children"] = n.children;
    if (!n.lods.empty()) {
      node["extensions"]["MSFT_lod"]["ids"] = n.lods;
      lod = true;
    }
    nodes.push_back(node);
  }
  w.gltf["nodes"] = nodes;
  w.gltf["scenes"] = json::array({doc.roots.empty() ? json::object() : json{{"nodes", doc.roots}}});
  w.gltf["scene"] = 0;
  if (lod) w.gltf["extensionsUsed"] = json::array({"MSFT_lod"});
  while (w.bin.size() % 4) w.bin.push_back('\0');
  if (!w.bin.empty()) {  // a document without triangles has no buffer (nor a GLB BIN chunk)
    json buffer = {{"byteLength", w.bin.size()}};
    if (!binary) buffer["uri"] = "data:application/octet-stream;base64," + base64(w.bin);
    w.gltf["buffers"] = json::array({buffer});
  }
  for (const char* key : {"bufferViews", "accessors", "meshes", "nodes"}) w.drop_if_empty(key);
  std::string text = w.gltf.dump();
  if (!binary) return text;
  while (text.size() % 4) text.push_back(' ');
  std::string out;
  append_le32(out, 0x46546C67);
  append_le32(out, 2);
  const std::size_t bin_chunk = w.bin.empty() ? 0 : 8 + w.bin.size();
  append_le32(out, static_cast<std::uint32_t>(12 + 8 + text.size() + bin_chunk));
  append_le32(out, static_cast<std::uint32_t>(text.size()));
  append_le32(out, 0x4E4F534A);
  out += text;
  if (bin_chunk == 0) return out;
  append_le32(out, static_cast<std::uint32_t>(w.bin.size()));
  append_le32(out, 0x004E4942);
  out += w.bin;
  return out;
}

namespace {

// Which attributes a flattened scene keeps: those every instanced mesh has, per corner when
// some mesh has them per corner (the joined seams of a glTF mesh), else per vertex.
struct FlatAttributes {
  bool normals = true, uvs = true, colors = true, corner_normals = false, corner_uvs = false;
  bool any_normals = false, any_uvs = false, any_colors = false;  // some mesh has them

  void add(const PolygonSoup& s) {
    const std::size_t nv = s.positions.size(), nc = s.face_indices.size();
    normals &= s.vertex_normals.size() == nv || (nc > 0 && s.corner_normals.size() == nc);
    uvs &= s.vertex_texcoords.size() == nv || (nc > 0 && s.corner_texcoords.size() == nc);
    colors &= s.vertex_colors.size() == nv;
    corner_normals |= !s.corner_normals.empty();
    corner_uvs |= !s.corner_texcoords.empty();
    any_normals |= !s.vertex_normals.empty() || corner_normals;
    any_uvs |= !s.vertex_texcoords.empty() || corner_uvs;
    any_colors |= !s.vertex_colors.empty();
  }
};

template <class T>
const T& at_corner(const std::vector<T>& corner, const std::vector<T>& vertex, const PolygonSoup& s, std::size_t c) {
  return corner.empty() ? vertex[s.face_indices[c]] : corner[c];
}

}  // namespace

namespace {

/// Append `faces` faces named by `from` to `to`, which names `before` faces so far.
void append_names(FaceNames& to, std::size_t before, const FaceNames& from, std::size_t faces) {
  if (from.empty() && to.empty()) return;
  to.of_face.resize(before, FaceNames::kUnnamed);
  for (std::size_t f = 0; f < faces; ++f) {
    std::uint32_t id = FaceNames::kUnnamed;
    if (!from.empty() && from.of_face[f] != FaceNames::kUnnamed) {
      const std::string& name = from.names[from.of_face[f]];
      const auto it = std::find(to.names.begin(), to.names.end(), name);
      id = static_cast<std::uint32_t>(it - to.names.begin());
      if (it == to.names.end()) to.names.push_back(name);
    }
    to.of_face.push_back(id);
  }
}

}  // namespace

PolygonSoup flatten(const GltfDocument& doc) {
  PolygonSoup out;
  out.warnings = doc.warnings;
  FlatAttributes keep;
  std::vector<std::uint8_t> on_path(doc.nodes.size(), 0);
  std::vector<std::pair<const PolygonSoup*, Eigen::Matrix4d>> instances;
  std::function<void(int, const Eigen::Matrix4d&)> visit = [&](int i, const Eigen::Matrix4d& parent) {
    if (i < 0 || i >= static_cast<int>(doc.nodes.size())) throw InvalidArgument("glTF: missing node " + std::to_string(i));
    if (on_path[i]) throw InvalidArgument("glTF: node " + std::to_string(i) + " is its own ancestor");
    const GltfNode& n = doc.nodes[i];
    const Eigen::Matrix4d world = parent * n.matrix;
    if (n.mesh >= 0) {
      instances.emplace_back(&doc.meshes.at(n.mesh), world);
      keep.add(*instances.back().first);
    }
    on_path[i] = 1;
    for (int c : n.children) visit(c, world);
    on_path[i] = 0;
  };
  for (int r : doc.roots) visit(r, Eigen::Matrix4d::Identity());
  for (const auto& [mesh, world] : instances) {
    const PolygonSoup& s = *mesh;
    const Eigen::Matrix3d lin = world.block<3, 3>(0, 0), nrm = lin.inverse().transpose();
    const auto base = static_cast<std::uint32_t>(out.positions.size());
    for (const Point& p : s.positions) out.positions.push_back(lin * p + world.block<3, 1>(0, 3));
    if (keep.normals && !keep.corner_normals)
      for (const Normal& v : s.vertex_normals) out.vertex_normals.push_back((nrm * v).normalized());
    if (keep.uvs && !keep.corner_uvs) out.vertex_texcoords.insert(out.vertex_texcoords.end(), s.vertex_texcoords.begin(), s.vertex_texcoords.end());
    if (keep.colors) out.vertex_colors.insert(out.vertex_colors.end(), s.vertex_colors.begin(), s.vertex_colors.end());
    const bool flip = lin.determinant() < 0;  // a mirror turns the faces inside out
    append_names(out.face_materials, out.n_faces(), s.face_materials, s.n_faces());
    for (std::size_t f = 0; f < s.n_faces(); ++f) {
      std::vector<std::uint32_t> corners(s.face_offsets[f + 1] - s.face_offsets[f]);
      std::iota(corners.begin(), corners.end(), s.face_offsets[f]);
      if (flip) std::reverse(corners.begin(), corners.end());
      std::vector<std::uint32_t> c;
      for (std::uint32_t k : corners) {
        c.push_back(s.face_indices[k] + base);
        if (keep.normals && keep.corner_normals)
          out.corner_normals.push_back((nrm * at_corner(s.corner_normals, s.vertex_normals, s, k)).normalized());
        if (keep.uvs && keep.corner_uvs) out.corner_texcoords.push_back(at_corner(s.corner_texcoords, s.vertex_texcoords, s, k));
      }
      out.add_face(c);
    }
  }
  auto drop = [&](bool kept, bool any, const char* what) {
    if (!kept && any) out.warnings.push_back(std::string(what) + " not kept: only some of the scene's meshes have them");
  };
  drop(keep.normals, keep.any_normals, "normals");
  drop(keep.uvs, keep.any_uvs, "texture coordinates");
  drop(keep.colors, keep.any_colors, "colours");
  return out;
}

GltfDocument gltf_from_soup(PolygonSoup soup, const std::string& name) {
  GltfDocument d;
  d.meshes.push_back(std::move(soup));
  d.mesh_names.push_back(name);
  d.nodes.push_back(GltfNode{name, Eigen::Matrix4d::Identity(), 0, {}, {}});
  d.roots = {0};
  return d;
}

GltfDocument gltf_lod_chain(std::vector<PolygonSoup> levels) {
  GltfDocument d;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    d.meshes.push_back(std::move(levels[i]));
    d.mesh_names.push_back("lod" + std::to_string(i));
    d.nodes.push_back(GltfNode{"lod" + std::to_string(i), Eigen::Matrix4d::Identity(), static_cast<int>(i), {}, {}});
  }
  if (!d.nodes.empty()) {
    for (std::size_t i = 1; i < d.nodes.size(); ++i) d.nodes[0].lods.push_back(static_cast<int>(i));
    d.roots = {0};  // lower levels are reached through MSFT_lod, not shown beside the first
  }
  return d;
}

}  // namespace geom
