#include <geom/io/gltf.h>
#include <geom/io/gltf_buffers.h>

#include <geom/core/errors.h>
#include <geom/core/weld.h>

#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <unordered_map>

namespace geom {
namespace {

using nlohmann::json;
using namespace gltf_detail;

constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;
constexpr std::uint32_t kChunkBin = 0x004E4942;

std::uint32_t le32(std::span<const std::byte> d, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | std::to_integer<std::uint32_t>(d[at + i]);
  return v;
}

// Extensions that change only materials, textures, lights or cameras: a reader of geometry
// may ignore them even when required, and says that it did.
bool only_appearance(const std::string& ext) {
  static const char* const kKnown[] = {"KHR_texture_transform", "KHR_texture_basisu", "EXT_texture_webp",
                                       "EXT_texture_avif", "KHR_lights_punctual", "KHR_materials_variants",
                                       "EXT_lights_image_based", "KHR_xmp_json_ld"};
  if (ext.rfind("KHR_materials_", 0) == 0) return true;
  return std::find(std::begin(kKnown), std::end(kKnown), ext) != std::end(kKnown);
}

bool reads_geometry_of(const std::string& ext) {
  return ext == "MSFT_lod" || ext == "KHR_draco_mesh_compression" || ext == "KHR_mesh_quantization" ||
         ext == "EXT_meshopt_compression";
}

class Reader {
 public:
  Reader(std::string name, std::filesystem::path base) : ctx_(std::move(name)), base_(std::move(base)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const { ctx_.fail(where, what); }

  GltfDocument read(std::span<const std::byte> data) {
    std::span<const std::byte> json_bytes = data;
    if (data.size() >= 4 && le32(data, 0) == kGlbMagic) json_bytes = split_glb(data);
    try {
      doc_ = json::parse(reinterpret_cast<const char*>(json_bytes.data()),
                         reinterpret_cast<const char*>(json_bytes.data()) + json_bytes.size());
    } catch (const json::parse_error& e) {
      throw ParseError(ctx_.name(), ParseError::Unit::kByte, e.byte, std::string("invalid glTF JSON: ") + e.what());
    } catch (const json::exception& e) {  // a number beyond a double's range ("1e999")
      throw ParseError(ctx_.name(), ParseError::Unit::kNone, 0, std::string("invalid glTF JSON: ") + e.what());
    }
    if (!doc_.is_object()) fail("document", "expected a JSON object");
    check_version();
    buffers_.emplace(ctx_, doc_, bin_, base_);
    GltfDocument out;
    for (std::size_t m = 0; m < array("meshes").size(); ++m) {
      out.meshes.push_back(read_mesh(m, out.warnings));
      out.mesh_names.push_back(ctx_.text(array("meshes")[m], "name", "meshes[" + std::to_string(m) + "]"));
    }
    read_nodes(out);
    if (!ignored_.empty()) out.warnings.insert(out.warnings.begin(), ignored_);
    return out;
  }

 private:
  std::span<const std::byte> split_glb(std::span<const std::byte> d) {
    const std::string& name = ctx_.name();
    if (d.size() < 20) throw ParseError(name, ParseError::Unit::kByte, d.size(), "GLB shorter than its header");
    if (le32(d, 4) != 2) throw ParseError(name, ParseError::Unit::kByte, 4, "GLB version " + std::to_string(le32(d, 4)) + " (expected 2)");
    if (le32(d, 8) > d.size()) throw ParseError(name, ParseError::Unit::kByte, 8, "GLB length exceeds the file");
    std::span<const std::byte> json_chunk;
    std::size_t at = 12;
    for (int chunk = 0; at + 8 <= le32(d, 8); ++chunk) {
      std::uint32_t len = le32(d, at), type = le32(d, at + 4);
      if (at + 8 + std::uint64_t(len) > le32(d, 8))
        throw ParseError(name, ParseError::Unit::kByte, at, "GLB chunk runs past the end");
      auto body = d.subspan(at + 8, len);
      if (chunk == 0 && type != kChunkJson) throw ParseError(name, ParseError::Unit::kByte, at, "first GLB chunk is not JSON");
      if (chunk == 0) json_chunk = body;
      if (chunk == 1 && type == kChunkBin) bin_ = body;
      at += 8 + len;
    }
    if (json_chunk.empty()) throw ParseError(name, ParseError::Unit::kByte, 12, "GLB has no JSON chunk");
    return json_chunk;
  }

  void check_version() {
    if (!doc_.contains("asset") || !doc_["asset"].is_object()) fail("asset", "missing");
    std::string v = ctx_.text(doc_["asset"], "version", "asset");
    if (v.rfind("2.", 0) != 0) fail("asset.version", "'" + v + "' is not glTF 2.x");
    std::string ignored;
    for (const auto& ext : array("extensionsRequired")) {
      if (!ext.is_string()) fail("extensionsRequired", "expected strings");
      const std::string e = ext.get<std::string>();
      if (reads_geometry_of(e)) continue;
      if (!only_appearance(e)) fail("extensionsRequired", "extension '" + e + "' is not supported");
      ignored += (ignored.empty() ? "" : ", ") + e;
    }
    if (!ignored.empty()) ignored_ = "required extensions that change only appearance were ignored: " + ignored;
  }

  const json& array(const char* key) const { return ctx_.array(doc_, key); }

  /// One vertex attribute of a primitive: from its accessor, or from the Draco stream.
  std::vector<double> attribute(const json& at, const char* key, int n, std::size_t nv, const std::string& where,
                                const DracoPrimitive* draco) {
    if (draco)
      if (const std::vector<double>* values = draco->find(key)) return *values;
    std::size_t k = 0;
    // Quantized attributes (KHR_mesh_quantization) may use any of these types.
    auto values = buffers_->accessor(ctx_.index(at, key, array("accessors").size(), where), n,
                                     {kFloat, kByte, kUnsignedByte, kShort, kUnsignedShort}, k);
    if (k != nv) fail(where + "." + key, "count " + std::to_string(k) + " differs from POSITION's " + std::to_string(nv));
    return values;
  }

  /// COLOR_0 as RGB (VEC3 or VEC4, alpha set aside), or empty.
  std::vector<double> colors(const json& at, std::size_t nv, const std::string& where, const DracoPrimitive* draco) {
    const std::size_t a = ctx_.index(at, "COLOR_0", array("accessors").size(), where);
    const int n = components(ctx_.text(array("accessors")[a], "type", "accessors[" + std::to_string(a) + "]"));
    if (n != 3 && n != 4) fail(where + ".COLOR_0", "expected VEC3 or VEC4");
    std::vector<double> rgba = attribute(at, "COLOR_0", n, nv, where, draco);
    if (n == 3) return rgba;
    std::vector<double> rgb(nv * 3);
    for (std::size_t i = 0; i < nv; ++i) std::copy_n(rgba.begin() + 4 * i, 3, rgb.begin() + 3 * i);
    return rgb;
  }

  std::optional<DracoPrimitive> draco_of(const json& prim, const json& at, const std::string& where) {
    if (!prim.contains("extensions") || !prim["extensions"].is_object() ||
        !prim["extensions"].contains("KHR_draco_mesh_compression"))
      return std::nullopt;
    const json& ext = prim["extensions"]["KHR_draco_mesh_compression"];
    const std::string w = where + ".extensions.KHR_draco_mesh_compression";
    if (!ext.is_object() || !ext.contains("attributes") || !ext["attributes"].is_object()) fail(w, "has no attributes");
    std::vector<DracoAttribute> wanted;
    for (const char* key : {"POSITION", "NORMAL", "TEXCOORD_0", "COLOR_0"}) {
      if (!ext["attributes"].contains(key) || !at.contains(key)) continue;
      int n = std::string(key) == "TEXCOORD_0" ? 2 : 3;
      if (std::string(key) == "COLOR_0") {
        const std::size_t a = ctx_.index(at, key, array("accessors").size(), where + ".attributes");
        n = components(ctx_.text(array("accessors")[a], "type", "accessors[" + std::to_string(a) + "]"));
      }
      wanted.push_back({key, ctx_.integer(ext["attributes"], key, -1, w + ".attributes"), n});
    }
    const auto view = buffers_->view(ctx_.index(ext, "bufferView", array("bufferViews").size(), w));
    return decode_draco(view.bytes, wanted, ctx_, where);
  }

  struct MeshAttributes {
    bool normals = true, uvs = true, colors = true, ids = true;
  };

  void add_primitive(PolygonSoup& soup, const json& prim, const std::string& where, MeshAttributes& has) {
    if (!prim.is_object()) fail(where, "expected an object");
    const int mode = ctx_.integer(prim, "mode", 4, where);
    if (mode < 0 || mode > 6) fail(where + ".mode", std::to_string(mode) + " is not a glTF primitive mode");
    if (!prim.contains("attributes") || !prim["attributes"].is_object() || !prim["attributes"].contains("POSITION"))
      fail(where, "has no POSITION attribute");
    const json& at = prim["attributes"];
    std::optional<DracoPrimitive> draco = draco_of(prim, at, where);
    const std::size_t n_acc = array("accessors").size();
    const std::size_t nv = draco ? draco->points
                                 : buffers_->declared_count(ctx_.index(at, "POSITION", n_acc, where + ".attributes"));
    if (draco && !draco->find("POSITION"))
      fail(where, "Draco-compressed primitive does not compress POSITION");
    if (soup.positions.size() + nv > 0xFFFFFFF0u) fail(where, "too many vertices");
    const auto base = static_cast<std::uint32_t>(soup.positions.size());
    const DracoPrimitive* d = draco ? &*draco : nullptr;
    const auto pos = attribute(at, "POSITION", 3, nv, where + ".attributes", d);
    for (std::size_t i = 0; i < nv; ++i) soup.positions.emplace_back(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
    has.normals = has.normals && at.contains("NORMAL");
    if (has.normals) {
      const auto v = attribute(at, "NORMAL", 3, nv, where + ".attributes", d);
      for (std::size_t i = 0; i < nv; ++i) soup.vertex_normals.emplace_back(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    }
    has.uvs = has.uvs && at.contains("TEXCOORD_0");
    if (has.uvs) {
      const auto v = attribute(at, "TEXCOORD_0", 2, nv, where + ".attributes", d);
      for (std::size_t i = 0; i < nv; ++i) soup.vertex_texcoords.emplace_back(v[2 * i], v[2 * i + 1]);
    }
    has.ids = has.ids && at.contains(kVertexIdAttribute) && !draco;
    if (has.ids) {
      std::size_t k = 0;
      const auto v = buffers_->accessor(ctx_.index(at, kVertexIdAttribute, n_acc, where + ".attributes"), 2,
                                        {kUnsignedShort}, k);
      if (k != nv) fail(where + ".attributes." + kVertexIdAttribute, "count differs from POSITION's");
      for (std::size_t i = 0; i < nv; ++i)
        ids_.push_back(static_cast<std::uint32_t>(v[2 * i]) | static_cast<std::uint32_t>(v[2 * i + 1]) << 16);
    }
    has.colors = has.colors && at.contains("COLOR_0");
    if (has.colors) {
      const auto v = colors(at, nv, where + ".attributes", d);
      for (std::size_t i = 0; i < nv; ++i) soup.vertex_colors.emplace_back(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    }
    std::vector<std::uint32_t> idx;
    if (draco) {
      idx = std::move(draco->triangles);
    } else if (prim.contains("indices")) {
      idx = buffers_->indices(ctx_.index(prim, "indices", n_acc, where), nv, where + ".indices");
    } else {
      idx.resize(nv);
      for (std::size_t i = 0; i < nv; ++i) idx[i] = static_cast<std::uint32_t>(i);
    }
    const std::size_t faces_before = soup.n_faces();
    add_triangles(soup, mode, base, idx);
    name_material(soup, prim, faces_before, where);
  }

  // The primitive's material names its faces (glTF groups faces by material).
  void name_material(PolygonSoup& soup, const json& prim, std::size_t first_face, const std::string& where) {
    FaceNames& names = soup.face_materials;
    names.of_face.resize(first_face, FaceNames::kUnnamed);
    std::uint32_t id = FaceNames::kUnnamed;
    if (prim.contains("material")) {
      const json& materials = array("materials");
      const std::size_t m = ctx_.index(prim, "material", materials.size(), where);
      std::string name = materials[m].is_object() ? ctx_.text(materials[m], "name", "materials[" + std::to_string(m) + "]") : "";
      if (name.empty()) name = "material" + std::to_string(m);
      const auto it = std::find(names.names.begin(), names.names.end(), name);
      id = static_cast<std::uint32_t>(it - names.names.begin());
      if (it == names.names.end()) names.names.push_back(name);
    }
    names.of_face.resize(soup.n_faces(), id);
    if (names.names.empty()) names.of_face.clear();  // no primitive so far names a material
  }

  static void add_triangles(PolygonSoup& soup, int mode, std::uint32_t base, const std::vector<std::uint32_t>& idx) {
    auto tri = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) { soup.add_face({base + a, base + b, base + c}); };
    if (mode == 4) {
      for (std::size_t i = 0; i + 2 < idx.size(); i += 3) tri(idx[i], idx[i + 1], idx[i + 2]);
    } else if (mode == 5) {  // strips alternate their winding
      for (std::size_t i = 0; i + 2 < idx.size(); ++i)
        i % 2 ? tri(idx[i + 1], idx[i], idx[i + 2]) : tri(idx[i], idx[i + 1], idx[i + 2]);
    } else {
      for (std::size_t i = 1; i + 1 < idx.size(); ++i) tri(idx[0], idx[i], idx[i + 1]);
    }
  }

  PolygonSoup read_mesh(std::size_t m, std::vector<std::string>& warnings) {
    const std::string where = "meshes[" + std::to_string(m) + "]";
    const json& mesh = array("meshes")[m];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
      fail(where, "has no primitives");
    PolygonSoup soup;
    MeshAttributes has;
    std::size_t surfaces = 0, skipped = 0;
    const json& prims = mesh["primitives"];
    for (std::size_t p = 0; p < prims.size(); ++p) {
      const std::string w = where + ".primitives[" + std::to_string(p) + "]";
      if (prims[p].is_object() && ctx_.integer(prims[p], "mode", 4, w) < 4) {
        ++skipped;  // points and lines are not a surface
        continue;
      }
      add_primitive(soup, prims[p], w, has);
      ++surfaces;
    }
    if (skipped)
      warnings.push_back(where + ": " + std::to_string(skipped) + " point or line primitive" + (skipped == 1 ? " was" : "s were") +
                         " skipped (geom reads surfaces)");
    // An attribute only some primitives have cannot describe the whole mesh.
    auto drop = [&](bool keep, auto& values, const char* what) {
      if (keep || values.empty()) return;
      values.clear();
      warnings.push_back(where + ": " + what + " not kept (only some of its " + std::to_string(surfaces) +
                         " primitives have them)");
    };
    drop(has.normals, soup.vertex_normals, "NORMAL");
    drop(has.uvs, soup.vertex_texcoords, "TEXCOORD_0");
    drop(has.colors, soup.vertex_colors, "COLOR_0");
    weld(soup, has.ids);
    return soup;
  }

  // glTF splits a vertex wherever its normal or texture coordinate differs (a seam). The
  // mesh is read as one: vertices at the same position with the same colour (or, in files
  // geom wrote, with the same _GEOM_VERTEX) are one vertex, whose differing normals and
  // texture coordinates move to the face corners.
  void weld(PolygonSoup& soup, bool by_id) {
    const std::size_t n = soup.positions.size();
    std::vector<std::uint32_t> same(n);
    if (by_id && ids_.size() == n) {
      std::unordered_map<std::uint32_t, std::uint32_t> first;
      for (std::uint32_t v = 0; v < n; ++v) same[v] = first.try_emplace(ids_[v], v).first->second;
    } else {
      std::map<std::array<double, 6>, std::uint32_t> first;
      const bool colors = soup.vertex_colors.size() == n;
      for (std::uint32_t v = 0; v < n; ++v) {
        const Point& p = soup.positions[v];
        const Color c = colors ? soup.vertex_colors[v] : Color::Zero();
        // + 0.0 makes -0 and +0 one key.
        same[v] = first.try_emplace({p.x() + 0.0, p.y() + 0.0, p.z() + 0.0, c.x(), c.y(), c.z()}, v).first->second;
      }
    }
    ids_.clear();
    seams_to_corners(soup, same);
    join_vertices(soup, same);
  }

  Eigen::Matrix4d node_matrix(const json& n, const std::string& where) const {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    auto numbers = [&](const char* key, std::size_t k) {
      const json& a = n[key];
      if (!a.is_array() || a.size() != k) fail(where + "." + key, "expected " + std::to_string(k) + " numbers");
      std::vector<double> v;
      for (const auto& x : a) {
        if (!x.is_number()) fail(where + "." + key, "expected numbers");
        v.push_back(x.get<double>());
      }
      return v;
    };
    if (n.contains("matrix")) {
      auto v = numbers("matrix", 16);
      for (int i = 0; i < 16; ++i) m(i % 4, i / 4) = v[i];  // column-major
      return m;
    }
    Eigen::Affine3d t = Eigen::Affine3d::Identity();
    if (n.contains("translation")) { auto v = numbers("translation", 3); t.translate(Eigen::Vector3d(v[0], v[1], v[2])); }
    if (n.contains("rotation")) { auto v = numbers("rotation", 4); t.rotate(Eigen::Quaterniond(v[3], v[0], v[1], v[2]).normalized()); }
    if (n.contains("scale")) { auto v = numbers("scale", 3); t.scale(Eigen::Vector3d(v[0], v[1], v[2])); }
    return t.matrix();
  }

  void read_nodes(GltfDocument& out) const {
    const json& nodes = array("nodes");
    std::vector<std::uint8_t> is_child(nodes.size(), 0);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const std::string where = "nodes[" + std::to_string(i) + "]";
      const json& n = nodes[i];
      GltfNode node;
      node.name = ctx_.text(n, "name", where);
      node.matrix = node_matrix(n, where);
      if (n.contains("mesh")) node.mesh = static_cast<int>(ctx_.index(n, "mesh", out.meshes.size(), where));
      for (const auto& c : n.value("children", json::array())) {
        if (!c.is_number_unsigned() || c.get<std::size_t>() >= nodes.size()) fail(where + ".children", "refers to a missing node");
        node.children.push_back(c.get<int>());
        is_child[c.get<std::size_t>()] = 1;
      }
      if (n.contains("extensions") && n["extensions"].contains("MSFT_lod"))
        for (const auto& id : n["extensions"]["MSFT_lod"].value("ids", json::array())) {
          if (!id.is_number_unsigned() || id.get<std::size_t>() >= nodes.size()) fail(where + ".extensions.MSFT_lod.ids", "refers to a missing node");
          node.lods.push_back(id.get<int>());
        }
      out.nodes.push_back(node);
    }
    const json& scenes = array("scenes");
    if (!scenes.empty()) {
      std::size_t s = doc_.contains("scene") ? ctx_.index(doc_, "scene", scenes.size(), "document") : 0;
      for (const auto& r : scenes[s].value("nodes", json::array())) {
        if (!r.is_number_unsigned() || r.get<std::size_t>() >= nodes.size()) fail("scenes[" + std::to_string(s) + "].nodes", "refers to a missing node");
        out.roots.push_back(r.get<int>());
      }
    } else {
      for (std::size_t i = 0; i < nodes.size(); ++i)
        if (!is_child[i]) out.roots.push_back(static_cast<int>(i));
    }
  }

  Context ctx_;
  std::filesystem::path base_;
  json doc_;
  std::span<const std::byte> bin_;
  std::optional<Buffers> buffers_;
  std::string ignored_;
  std::vector<std::uint32_t> ids_;  ///< _GEOM_VERTEX of the mesh being read
};

}  // namespace

GltfDocument read_gltf(std::span<const std::byte> data, const std::string& name, const std::filesystem::path& base_dir) {
  try {
    return Reader(name, base_dir).read(data);
  } catch (const nlohmann::json::exception& e) {
    // A member of a type the checks above do not look at (they name the element when they
    // do): still the file's fault, so a ParseError.
    throw ParseError(name, ParseError::Unit::kNone, 0, std::string("invalid glTF: ") + e.what());
  }
}

}  // namespace geom
