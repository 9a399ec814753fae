#include <geom/io/gltf.h>

#include <geom/core/errors.h>

#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <tuple>

namespace geom {
namespace {

using nlohmann::json;

constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;
constexpr std::uint32_t kChunkBin = 0x004E4942;
constexpr int kFloat = 5126, kUnsignedInt = 5125, kUnsignedShort = 5123, kUnsignedByte = 5121,
              kShort = 5122, kByte = 5120;

std::uint32_t le32(std::span<const std::byte> d, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | std::to_integer<std::uint32_t>(d[at + i]);
  return v;
}

class Reader {
 public:
  Reader(std::string name, std::filesystem::path base) : name_(std::move(name)), base_(std::move(base)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw ParseError(name_, ParseError::Unit::kNone, 0, where + ": " + what);
  }

  GltfDocument read(std::span<const std::byte> data) {
    std::span<const std::byte> json_bytes = data;
    if (data.size() >= 4 && le32(data, 0) == kGlbMagic) json_bytes = split_glb(data);
    try {
      doc_ = json::parse(reinterpret_cast<const char*>(json_bytes.data()),
                         reinterpret_cast<const char*>(json_bytes.data()) + json_bytes.size());
    } catch (const json::parse_error& e) {
      throw ParseError(name_, ParseError::Unit::kByte, e.byte, std::string("invalid glTF JSON: ") + e.what());
    } catch (const json::exception& e) {  // a number beyond a double's range ("1e999")
      throw ParseError(name_, ParseError::Unit::kNone, 0, std::string("invalid glTF JSON: ") + e.what());
    }
    if (!doc_.is_object()) fail("document", "expected a JSON object");
    check_version();
    load_buffers();
    GltfDocument out;
    for (std::size_t m = 0; m < array("meshes").size(); ++m) {
      out.meshes.push_back(read_mesh(m));
      out.mesh_names.push_back(text(array("meshes")[m], "name", "meshes[" + std::to_string(m) + "]"));
    }
    read_nodes(out);
    return out;
  }

 private:
  std::span<const std::byte> split_glb(std::span<const std::byte> d) {
    if (d.size() < 20) throw ParseError(name_, ParseError::Unit::kByte, d.size(), "GLB shorter than its header");
    if (le32(d, 4) != 2) throw ParseError(name_, ParseError::Unit::kByte, 4, "GLB version " + std::to_string(le32(d, 4)) + " (expected 2)");
    if (le32(d, 8) > d.size()) throw ParseError(name_, ParseError::Unit::kByte, 8, "GLB length exceeds the file");
    std::span<const std::byte> json_chunk;
    std::size_t at = 12;
    for (int chunk = 0; at + 8 <= le32(d, 8); ++chunk) {
      std::uint32_t len = le32(d, at), type = le32(d, at + 4);
      if (at + 8 + std::uint64_t(len) > le32(d, 8))
        throw ParseError(name_, ParseError::Unit::kByte, at, "GLB chunk runs past the end");
      auto body = d.subspan(at + 8, len);
      if (chunk == 0 && type != kChunkJson) throw ParseError(name_, ParseError::Unit::kByte, at, "first GLB chunk is not JSON");
      if (chunk == 0) json_chunk = body;
      if (chunk == 1 && type == kChunkBin) bin_ = body;
      at += 8 + len;
    }
    if (json_chunk.empty()) throw ParseError(name_, ParseError::Unit::kByte, 12, "GLB has no JSON chunk");
    return json_chunk;
  }

  void check_version() {
    if (!doc_.contains("asset") || !doc_["asset"].is_object()) fail("asset", "missing");
    std::string v = text(doc_["asset"], "version", "asset");
    if (v.rfind("2.", 0) != 0) fail("asset.version", "'" + v + "' is not glTF 2.x");
    for (const auto& ext : doc_.value("extensionsRequired", json::array()))
      if (ext != "MSFT_lod") fail("extensionsRequired", "extension " + ext.dump() + " is not supported");
  }

  const json& array(const char* key) const {
    static const json empty = json::array();
    if (!doc_.contains(key)) return empty;
    if (!doc_[key].is_array()) fail(key, "expected an array");
    return doc_[key];
  }

  std::size_t index(const json& obj, const char* key, std::size_t limit, const std::string& where) const {
    if (!obj.contains(key) || !obj[key].is_number_unsigned()) fail(where + "." + key, "missing or not an index");
    std::size_t i = obj[key].get<std::size_t>();
    if (i >= limit) fail(where + "." + key, std::to_string(i) + " is out of range (" + std::to_string(limit) + ")");
    return i;
  }

  // Typed members: json::value() converts whatever is there (a string where a number belongs
  // threw nlohmann's type_error, and 1e300 as an int was undefined behaviour).
  int integer(const json& obj, const char* key, int fallback, const std::string& where) const {
    if (!obj.contains(key)) return fallback;
    const json& v = obj[key];
    const bool fits = v.is_number_unsigned() ? v.get<std::uint64_t>() <= 0x7fffffffu
                                             : v.is_number_integer() && v.get<std::int64_t>() >= -0x7fffffff &&
                                                   v.get<std::int64_t>() <= 0x7fffffff;
    if (!fits) fail(where + "." + key, v.dump() + " is not an integer");
    return static_cast<int>(v.get<std::int64_t>());
  }
  std::string text(const json& obj, const char* key, const std::string& where) const {
    if (!obj.contains(key)) return "";
    if (!obj[key].is_string()) fail(where + "." + key, "expected a string");
    return obj[key].get<std::string>();
  }
  bool flag(const json& obj, const char* key, const std::string& where) const {
    if (!obj.contains(key)) return false;
    if (!obj[key].is_boolean()) fail(where + "." + key, "expected true or false");
    return obj[key].get<bool>();
  }

  std::size_t size(const json& obj, const char* key, std::size_t fallback, const std::string& where) const {
    if (!obj.contains(key)) return fallback;
    if (!obj[key].is_number_unsigned()) fail(where + "." + key, "expected a non-negative integer");
    return obj[key].get<std::size_t>();
  }

  static int base64_value(char c) {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+' || c == '-') return 62;
    if (c == '/' || c == '_') return 63;
    return -1;
  }

  std::vector<std::byte> decode_base64(const std::string& s, const std::string& where) const {
    std::vector<std::byte> out;
    out.reserve(s.size() / 4 * 3);
    std::uint32_t acc = 0;
    int bits = 0;
    for (char c : s) {
      if (c == '=') break;
      int v = base64_value(c);
      if (v < 0) fail(where, "invalid base64 character");
      acc = (acc << 6) | static_cast<std::uint32_t>(v);
      bits += 6;
      if (bits >= 8) {
        bits -= 8;
        out.push_back(static_cast<std::byte>((acc >> bits) & 0xFF));
      }
    }
    return out;
  }

  void load_buffers() {
    const json& buffers = array("buffers");
    for (std::size_t b = 0; b < buffers.size(); ++b) {
      const std::string where = "buffers[" + std::to_string(b) + "]";
      const json& buf = buffers[b];
      std::size_t length = size(buf, "byteLength", 0, where);
      std::span<const std::byte> bytes;
      if (!buf.contains("uri")) {
        if (b != 0 || bin_.empty()) fail(where, "has no uri and there is no GLB binary chunk");
        bytes = bin_;
      } else {
        std::string uri = buf["uri"].get<std::string>();
        if (uri.rfind("data:", 0) == 0) {
          auto comma = uri.find(";base64,");
          if (comma == std::string::npos) fail(where + ".uri", "only base64 data URIs are supported");
          owned_.push_back(decode_base64(uri.substr(comma + 8), where + ".uri"));
        } else {
          if (base_.empty()) fail(where + ".uri", "external buffer '" + uri + "' but no folder to find it in");
          std::ifstream in(base_ / uri, std::ios::binary);
          if (!in) fail(where + ".uri", "cannot open external buffer '" + (base_ / uri).string() + "'");
          std::vector<char> raw{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
          std::vector<std::byte> v(raw.size());
          std::memcpy(v.data(), raw.data(), raw.size());
          owned_.push_back(std::move(v));
        }
        bytes = owned_.back();
      }
      if (bytes.size() < length)
        fail(where, "byteLength " + std::to_string(length) + " but only " + std::to_string(bytes.size()) + " bytes are there");
      buffers_.push_back(bytes.first(length));
    }
  }

  struct View {
    std::span<const std::byte> bytes;
    std::size_t stride;
  };

  View buffer_view(std::size_t v) const {
    const std::string where = "bufferViews[" + std::to_string(v) + "]";
    const json& view = array("bufferViews")[v];
    std::size_t b = index(view, "buffer", buffers_.size(), where);
    std::size_t offset = size(view, "byteOffset", 0, where), length = size(view, "byteLength", 0, where);
    if (offset > buffers_[b].size() || length > buffers_[b].size() - offset)
      fail(where, "range [" + std::to_string(offset) + ", +" + std::to_string(length) + ") exceeds buffer " + std::to_string(b));
    std::size_t stride = size(view, "byteStride", 0, where);
    if (stride && (stride < 4 || stride > 252 || stride % 4)) fail(where + ".byteStride", std::to_string(stride) + " is not a multiple of 4 in [4, 252]");
    return {buffers_[b].subspan(offset, length), stride};
  }

  static int components(const std::string& type) {
    if (type == "SCALAR") return 1;
    if (type == "VEC2") return 2;
    if (type == "VEC3") return 3;
    if (type == "VEC4") return 4;
    return 0;
  }
  static std::size_t component_size(int ct) {
    switch (ct) {
      case kFloat: case kUnsignedInt: return 4;
      case kUnsignedShort: case kShort: return 2;
      case kUnsignedByte: case kByte: return 1;
      default: return 0;
    }
  }

  /// Values of accessor a as doubles, count × n; `n` and allowed component types checked.
  std::vector<double> accessor(std::size_t a, int want_n, std::initializer_list<int> types, std::size_t& count) const {
    const std::string where = "accessors[" + std::to_string(a) + "]";
    const json& acc = array("accessors")[a];
    if (acc.contains("sparse")) fail(where, "sparse accessors are not supported");
    int ct = integer(acc, "componentType", 0, where);
    bool type_ok = false;
    for (int t : types) type_ok |= t == ct;
    if (!type_ok) fail(where + ".componentType", std::to_string(ct) + " is not allowed here");
    const std::string type = text(acc, "type", where);
    int n = components(type);
    if (n != want_n) fail(where + ".type", "'" + type + "' (expected " + std::to_string(want_n) + " components)");
    count = size(acc, "count", 0, where);
    const std::size_t elem = component_size(ct) * n;
    std::vector<double> out;
    if (!acc.contains("bufferView")) {  // all zeros, per the specification
      out.assign(count * n, 0.0);
      return out;
    }
    View view = buffer_view(index(acc, "bufferView", array("bufferViews").size(), where));
    std::size_t offset = size(acc, "byteOffset", 0, where);
    std::size_t stride = view.stride ? view.stride : elem;
    if (stride < elem) fail(where, "byteStride " + std::to_string(stride) + " is smaller than the element size " + std::to_string(elem));
    const std::size_t room = view.bytes.size();
    if (count > 0 && (offset > room || elem > room - offset || (count - 1) > (room - offset - elem) / stride))
      fail(where, std::to_string(count) + " elements do not fit in their buffer view");
    const bool normalized = flag(acc, "normalized", where);
    out.resize(count * n);
    for (std::size_t i = 0; i < count; ++i)
      for (int c = 0; c < n; ++c) {
        const std::byte* p = view.bytes.data() + offset + i * stride + c * component_size(ct);
        double v = 0;
        switch (ct) {
          case kFloat: { float f; std::memcpy(&f, p, 4); v = f; break; }
          case kUnsignedInt: { std::uint32_t u; std::memcpy(&u, p, 4); v = u; break; }
          case kUnsignedShort: { std::uint16_t u; std::memcpy(&u, p, 2); v = normalized ? u / 65535.0 : u; break; }
          case kShort: { std::int16_t s; std::memcpy(&s, p, 2); v = normalized ? std::max(s / 32767.0, -1.0) : s; break; }
          case kUnsignedByte: { v = std::to_integer<std::uint8_t>(*p); if (normalized) v /= 255.0; break; }
          case kByte: { v = static_cast<std::int8_t>(std::to_integer<std::uint8_t>(*p)); if (normalized) v = std::max(v / 127.0, -1.0); break; }
        }
        if (!std::isfinite(v)) fail(where, "element " + std::to_string(i) + " is not finite");
        out[i * n + c] = v;
      }
    return out;
  }

  void add_primitive(PolygonSoup& soup, const json& prim, const std::string& where, bool& normals, bool& uvs) const {
    int mode = integer(prim, "mode", 4, where);
    if (mode < 4 || mode > 6) fail(where + ".mode", std::to_string(mode) + " (points/lines) is not a surface; geom reads triangles, strips and fans");
    if (prim.contains("extensions") && prim["extensions"].contains("KHR_draco_mesh_compression"))
      fail(where, "Draco-compressed primitives are not supported (decompress with draco_decoder first)");
    if (!prim.contains("attributes") || !prim["attributes"].contains("POSITION")) fail(where, "has no POSITION attribute");
    const json& at = prim["attributes"];
    const std::size_t n_acc = array("accessors").size();
    std::size_t nv = 0;
    auto pos = accessor(index(at, "POSITION", n_acc, where + ".attributes"), 3, {kFloat}, nv);
    const auto base = static_cast<std::uint32_t>(soup.positions.size());
    if (soup.positions.size() + nv > 0xFFFFFFF0u) fail(where, "too many vertices");
    for (std::size_t i = 0; i < nv; ++i) soup.positions.emplace_back(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
    if (normals && at.contains("NORMAL")) {
      std::size_t k = 0;
      auto nrm = accessor(index(at, "NORMAL", n_acc, where + ".attributes"), 3, {kFloat}, k);
      if (k != nv) fail(where + ".attributes.NORMAL", "count differs from POSITION's");
      for (std::size_t i = 0; i < nv; ++i) soup.vertex_normals.emplace_back(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
    } else {
      normals = false;
    }
    if (uvs && at.contains("TEXCOORD_0")) {
      std::size_t k = 0;
      auto uv = accessor(index(at, "TEXCOORD_0", n_acc, where + ".attributes"), 2, {kFloat, kUnsignedByte, kUnsignedShort}, k);
      if (k != nv) fail(where + ".attributes.TEXCOORD_0", "count differs from POSITION's");
      for (std::size_t i = 0; i < nv; ++i) soup.vertex_texcoords.emplace_back(uv[2 * i], uv[2 * i + 1]);
    } else {
      uvs = false;
    }
    std::vector<std::uint32_t> idx;
    if (prim.contains("indices")) {
      std::size_t k = 0;
      auto raw = accessor(index(prim, "indices", n_acc, where), 1, {kUnsignedByte, kUnsignedShort, kUnsignedInt}, k);
      idx.reserve(k);
      for (std::size_t i = 0; i < k; ++i) {
        if (raw[i] >= static_cast<double>(nv)) fail(where + ".indices", "index " + std::to_string(static_cast<std::uint64_t>(raw[i])) + " at " + std::to_string(i) + " is not below the vertex count " + std::to_string(nv));
        idx.push_back(static_cast<std::uint32_t>(raw[i]));
      }
    } else {
      for (std::size_t i = 0; i < nv; ++i) idx.push_back(static_cast<std::uint32_t>(i));
    }
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

  PolygonSoup read_mesh(std::size_t m) const {
    const std::string where = "meshes[" + std::to_string(m) + "]";
    const json& mesh = array("meshes")[m];
    if (!mesh.contains("primitives") || !mesh["primitives"].is_array()) fail(where, "has no primitives");
    PolygonSoup soup;
    bool normals = true, uvs = true;
    const json& prims = mesh["primitives"];
    for (std::size_t p = 0; p < prims.size(); ++p)
      add_primitive(soup, prims[p], where + ".primitives[" + std::to_string(p) + "]", normals, uvs);
    // An attribute only some primitives have cannot describe the whole mesh: drop it.
    if (!normals) soup.vertex_normals.clear();
    if (!uvs) soup.vertex_texcoords.clear();
    return soup;
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
      node.name = text(n, "name", where);
      node.matrix = node_matrix(n, where);
      if (n.contains("mesh")) node.mesh = static_cast<int>(index(n, "mesh", out.meshes.size(), where));
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
      std::size_t s = doc_.contains("scene") ? index(doc_, "scene", scenes.size(), "document") : 0;
      for (const auto& r : scenes[s].value("nodes", json::array())) {
        if (!r.is_number_unsigned() || r.get<std::size_t>() >= nodes.size()) fail("scenes[" + std::to_string(s) + "].nodes", "refers to a missing node");
        out.roots.push_back(r.get<int>());
      }
    } else {
      for (std::size_t i = 0; i < nodes.size(); ++i)
        if (!is_child[i]) out.roots.push_back(static_cast<int>(i));
    }
  }

  std::string name_;
  std::filesystem::path base_;
  json doc_;
  std::span<const std::byte> bin_;
  std::vector<std::vector<std::byte>> owned_;
  std::vector<std::span<const std::byte>> buffers_;
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
