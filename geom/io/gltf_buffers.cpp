// glTF buffers, buffer views and accessors: see gltf_buffers.h.

#include <geom/io/gltf_buffers.h>

#include <geom/core/errors.h>

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

namespace geom::gltf_detail {

void Context::fail(const std::string& where, const std::string& what) const {
  throw ParseError(name_, ParseError::Unit::kNone, 0, where + ": " + what);
}

const json& Context::array(const json& doc, const char* key) const {
  static const json empty = json::array();
  if (!doc.contains(key)) return empty;
  if (!doc[key].is_array()) fail(key, "expected an array");
  return doc[key];
}

std::size_t Context::index(const json& obj, const char* key, std::size_t limit, const std::string& where) const {
  if (!obj.contains(key) || !obj[key].is_number_unsigned()) fail(where + "." + key, "missing or not an index");
  std::size_t i = obj[key].get<std::size_t>();
  if (i >= limit) fail(where + "." + key, std::to_string(i) + " is out of range (" + std::to_string(limit) + ")");
  return i;
}

// Typed members: json::value() converts whatever is there (a string where a number belongs
// threw nlohmann's type_error, and 1e300 as an int was undefined behaviour).
int Context::integer(const json& obj, const char* key, int fallback, const std::string& where) const {
  if (!obj.contains(key)) return fallback;
  const json& v = obj[key];
  const bool fits = v.is_number_unsigned() ? v.get<std::uint64_t>() <= 0x7fffffffu
                                           : v.is_number_integer() && v.get<std::int64_t>() >= -0x7fffffff &&
                                                 v.get<std::int64_t>() <= 0x7fffffff;
  if (!fits) fail(where + "." + key, v.dump() + " is not an integer");
  return static_cast<int>(v.get<std::int64_t>());
}

std::size_t Context::size(const json& obj, const char* key, std::size_t fallback, const std::string& where) const {
  if (!obj.contains(key)) return fallback;
  if (!obj[key].is_number_unsigned()) fail(where + "." + key, "expected a non-negative integer");
  return obj[key].get<std::size_t>();
}

std::string Context::text(const json& obj, const char* key, const std::string& where) const {
  if (!obj.contains(key)) return "";
  if (!obj[key].is_string()) fail(where + "." + key, "expected a string");
  return obj[key].get<std::string>();
}

bool Context::flag(const json& obj, const char* key, const std::string& where) const {
  if (!obj.contains(key)) return false;
  if (!obj[key].is_boolean()) fail(where + "." + key, "expected true or false");
  return obj[key].get<bool>();
}

int components(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  return 0;
}

std::size_t component_size(int ct) {
  switch (ct) {
    case kFloat: case kUnsignedInt: return 4;
    case kUnsignedShort: case kShort: return 2;
    case kUnsignedByte: case kByte: return 1;
    default: return 0;
  }
}

std::string percent_decode(const std::string& uri, const Context& ctx, const std::string& where) {
  auto hex = [&](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    ctx.fail(where, "malformed percent escape in '" + uri + "'");
  };
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] != '%') {
      out.push_back(uri[i]);
      continue;
    }
    if (i + 2 >= uri.size()) ctx.fail(where, "malformed percent escape in '" + uri + "'");
    out.push_back(static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2])));
    i += 2;
  }
  return out;
}

namespace {

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+' || c == '-') return 62;
  if (c == '/' || c == '_') return 63;
  return -1;
}

std::vector<std::byte> decode_base64(std::string_view s, const Context& ctx, const std::string& where) {
  std::vector<std::byte> out;
  out.reserve(s.size() / 4 * 3);
  std::uint32_t acc = 0;
  int bits = 0;
  for (char c : s) {
    if (c == '=') break;
    int v = base64_value(c);
    if (v < 0) ctx.fail(where, "invalid base64 character");
    acc = (acc << 6) | static_cast<std::uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<std::byte>((acc >> bits) & 0xFF));
    }
  }
  return out;
}

bool is_meshopt_fallback(const json& buf) {
  return buf.contains("extensions") && buf["extensions"].is_object() &&
         buf["extensions"].contains("EXT_meshopt_compression") &&
         buf["extensions"]["EXT_meshopt_compression"].value("fallback", false) == true;
}

}  // namespace

std::vector<std::byte> Buffers::load_uri(const std::string& uri, const std::string& where) const {
  if (uri.rfind("data:", 0) == 0) {
    auto comma = uri.find(";base64,");
    if (comma == std::string::npos) ctx_.fail(where, "only base64 data URIs are supported");
    return decode_base64(std::string_view(uri).substr(comma + 8), ctx_, where);
  }
  if (base_.empty()) ctx_.fail(where, "external buffer '" + uri + "' but no folder to find it in (read from memory)");
  if (uri.find("://") != std::string::npos) ctx_.fail(where, "'" + uri + "' is not a relative path (geom reads no URLs)");
  const std::filesystem::path file = base_ / std::filesystem::u8path(percent_decode(uri, ctx_, where));
  std::ifstream in(file, std::ios::binary);
  if (!in) ctx_.fail(where, "cannot open external buffer '" + file.string() + "'");
  std::vector<char> raw{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  std::vector<std::byte> v(raw.size());
  if (!raw.empty()) std::memcpy(v.data(), raw.data(), raw.size());
  return v;
}

Buffers::Buffers(const Context& ctx, const json& doc, std::span<const std::byte> bin,
                 const std::filesystem::path& base_dir)
    : ctx_(ctx), doc_(doc), base_(base_dir) {
  const json& buffers = ctx_.array(doc_, "buffers");
  owned_.reserve(buffers.size());
  for (std::size_t b = 0; b < buffers.size(); ++b) {
    const std::string where = "buffers[" + std::to_string(b) + "]";
    const json& buf = buffers[b];
    if (!buf.is_object()) ctx_.fail(where, "expected an object");
    const std::size_t length = ctx_.size(buf, "byteLength", 0, where);
    std::span<const std::byte> bytes;
    if (buf.contains("uri")) {
      owned_.push_back(load_uri(ctx_.text(buf, "uri", where), where + ".uri"));
      bytes = owned_.back();
    } else if (b == 0 && !bin.empty()) {
      bytes = bin;
    } else if (is_meshopt_fallback(buf)) {
      buffers_.emplace_back();
      fallback_.push_back(true);
      continue;
    } else {
      ctx_.fail(where, "has no uri and there is no GLB binary chunk");
    }
    if (bytes.size() < length)
      ctx_.fail(where, "byteLength " + std::to_string(length) + " but only " + std::to_string(bytes.size()) +
                           " bytes are there");
    buffers_.push_back(bytes.first(length));
    fallback_.push_back(false);
  }
}

std::span<const std::byte> Buffers::meshopt_view(std::size_t v, const json& ext, const std::string& where) {
  if (auto it = decoded_views_.find(v); it != decoded_views_.end()) return it->second;
  const std::string w = where + ".extensions.EXT_meshopt_compression";
  const std::size_t b = ctx_.index(ext, "buffer", buffers_.size(), w);
  if (fallback_[b]) ctx_.fail(w + ".buffer", "refers to a fallback buffer with no data");
  const std::size_t offset = ctx_.size(ext, "byteOffset", 0, w), length = ctx_.size(ext, "byteLength", 0, w);
  if (offset > buffers_[b].size() || length > buffers_[b].size() - offset)
    ctx_.fail(w, "compressed range exceeds buffer " + std::to_string(b));
  const std::size_t stride = ctx_.size(ext, "byteStride", 0, w), count = ctx_.size(ext, "count", 0, w);
  const std::string mode = ctx_.text(ext, "mode", w), filter = ctx_.text(ext, "filter", w);
  if (stride == 0 || stride > 256) ctx_.fail(w + ".byteStride", std::to_string(stride) + " is not in [1, 256]");
  // A decoded stream is at most the count times the stride; meshopt's format bounds how many
  // elements a compressed byte can yield, so a huge count in a tiny stream is refused first.
  if (count > (std::size_t{1} << 32) || count * stride > std::max<std::size_t>(length, 64) * 4096)
    ctx_.fail(w + ".count", std::to_string(count) + " elements cannot come from " + std::to_string(length) + " bytes");
  std::vector<std::byte> out(count * stride);
  const auto* src = reinterpret_cast<const unsigned char*>(buffers_[b].data() + offset);
  int rc = -1;
  if (mode == "ATTRIBUTES") {
    if (stride % 4) ctx_.fail(w + ".byteStride", "must be a multiple of 4 for ATTRIBUTES");
    rc = meshopt_decodeVertexBuffer(out.data(), count, stride, src, length);
  } else if (mode == "TRIANGLES" || mode == "INDICES") {
    if (stride != 2 && stride != 4) ctx_.fail(w + ".byteStride", "must be 2 or 4 for indices");
    if (mode == "TRIANGLES" && count % 3) ctx_.fail(w + ".count", "is not a multiple of 3");
    rc = mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out.data(), count, stride, src, length)
                             : meshopt_decodeIndexSequence(out.data(), count, stride, src, length);
  } else {
    ctx_.fail(w + ".mode", "'" + mode + "' is not ATTRIBUTES, TRIANGLES or INDICES");
  }
  if (rc != 0) ctx_.fail(w, "meshopt stream is malformed (decoder returned " + std::to_string(rc) + ")");
  if (filter == "OCTAHEDRAL") {
    if (stride != 4 && stride != 8) ctx_.fail(w + ".filter", "OCTAHEDRAL needs a stride of 4 or 8");
    meshopt_decodeFilterOct(out.data(), count, stride);
  } else if (filter == "QUATERNION") {
    if (stride != 8) ctx_.fail(w + ".filter", "QUATERNION needs a stride of 8");
    meshopt_decodeFilterQuat(out.data(), count, stride);
  } else if (filter == "EXPONENTIAL") {
    if (stride % 4) ctx_.fail(w + ".filter", "EXPONENTIAL needs a stride that is a multiple of 4");
    meshopt_decodeFilterExp(out.data(), count, stride);
  } else if (!filter.empty() && filter != "NONE") {
    ctx_.fail(w + ".filter", "'" + filter + "' is not a known filter");
  }
  return decoded_views_.emplace(v, std::move(out)).first->second;
}

Buffers::View Buffers::view(std::size_t v) {
  const std::string where = "bufferViews[" + std::to_string(v) + "]";
  const json& view = ctx_.array(doc_, "bufferViews")[v];
  if (!view.is_object()) ctx_.fail(where, "expected an object");
  const std::size_t stride = ctx_.size(view, "byteStride", 0, where);
  if (stride && (stride < 4 || stride > 252 || stride % 4))
    ctx_.fail(where + ".byteStride", std::to_string(stride) + " is not a multiple of 4 in [4, 252]");
  const std::size_t length = ctx_.size(view, "byteLength", 0, where);
  if (view.contains("extensions") && view["extensions"].is_object() &&
      view["extensions"].contains("EXT_meshopt_compression")) {
    auto bytes = meshopt_view(v, view["extensions"]["EXT_meshopt_compression"], where);
    if (bytes.size() < length) ctx_.fail(where, "decompressed data is shorter than byteLength");
    return {bytes.first(length), stride};
  }
  const std::size_t b = ctx_.index(view, "buffer", buffers_.size(), where);
  if (fallback_[b]) ctx_.fail(where, "refers to a fallback buffer and is not compressed");
  const std::size_t offset = ctx_.size(view, "byteOffset", 0, where);
  if (offset > buffers_[b].size() || length > buffers_[b].size() - offset)
    ctx_.fail(where, "range [" + std::to_string(offset) + ", +" + std::to_string(length) + ") exceeds buffer " +
                         std::to_string(b));
  return {buffers_[b].subspan(offset, length), stride};
}

void Buffers::read_elements(std::span<const std::byte> bytes, std::size_t stride, std::size_t offset, int ct,
                            int n, bool normalized, std::size_t count, const std::string& where,
                            std::vector<double>& out) const {
  const std::size_t elem = component_size(ct) * n;
  if (stride == 0) stride = elem;
  if (stride < elem)
    ctx_.fail(where, "byteStride " + std::to_string(stride) + " is smaller than the element size " + std::to_string(elem));
  const std::size_t room = bytes.size();
  if (count > 0 && (offset > room || elem > room - offset || (count - 1) > (room - offset - elem) / stride))
    ctx_.fail(where, std::to_string(count) + " elements do not fit in their buffer view");
  out.resize(count * n);
  for (std::size_t i = 0; i < count; ++i)
    for (int c = 0; c < n; ++c) {
      const std::byte* p = bytes.data() + offset + i * stride + c * component_size(ct);
      double v = 0;
      switch (ct) {
        case kFloat: { float f; std::memcpy(&f, p, 4); v = f; break; }
        case kUnsignedInt: { std::uint32_t u; std::memcpy(&u, p, 4); v = u; break; }
        case kUnsignedShort: { std::uint16_t u; std::memcpy(&u, p, 2); v = normalized ? u / 65535.0 : u; break; }
        case kShort: { std::int16_t s; std::memcpy(&s, p, 2); v = normalized ? std::max(s / 32767.0, -1.0) : s; break; }
        case kUnsignedByte: { v = std::to_integer<std::uint8_t>(*p); if (normalized) v /= 255.0; break; }
        case kByte: { v = static_cast<std::int8_t>(std::to_integer<std::uint8_t>(*p)); if (normalized) v = std::max(v / 127.0, -1.0); break; }
      }
      if (!std::isfinite(v)) ctx_.fail(where, "element " + std::to_string(i) + " is not finite");
      out[i * n + c] = v;
    }
}

void Buffers::apply_sparse(const json& sparse, int ct, int n, bool normalized, std::size_t count,
                           const std::string& where, std::vector<double>& out) {
  const std::string w = where + ".sparse";
  if (!sparse.is_object() || !sparse.contains("indices") || !sparse.contains("values"))
    ctx_.fail(w, "needs count, indices and values");
  const std::size_t k = ctx_.size(sparse, "count", 0, w);
  if (k == 0 || k > count) ctx_.fail(w + ".count", std::to_string(k) + " is not in [1, " + std::to_string(count) + "]");
  const json& ji = sparse["indices"];
  const json& jv = sparse["values"];
  const std::size_t n_views = ctx_.array(doc_, "bufferViews").size();
  const int ict = ctx_.integer(ji, "componentType", 0, w + ".indices");
  if (ict != kUnsignedByte && ict != kUnsignedShort && ict != kUnsignedInt)
    ctx_.fail(w + ".indices.componentType", std::to_string(ict) + " is not an unsigned integer type");
  std::vector<double> at, values;
  const View iv = view(ctx_.index(ji, "bufferView", n_views, w + ".indices"));
  read_elements(iv.bytes, 0, ctx_.size(ji, "byteOffset", 0, w + ".indices"), ict, 1, false, k, w + ".indices", at);
  const View vv = view(ctx_.index(jv, "bufferView", n_views, w + ".values"));
  read_elements(vv.bytes, 0, ctx_.size(jv, "byteOffset", 0, w + ".values"), ct, n, normalized, k, w + ".values", values);
  for (std::size_t i = 0; i < k; ++i) {
    if (at[i] >= static_cast<double>(count) || (i > 0 && at[i] <= at[i - 1]))
      ctx_.fail(w + ".indices", "index " + std::to_string(static_cast<std::uint64_t>(at[i])) + " at " + std::to_string(i) +
                                    " is out of range or not increasing");
    std::copy_n(values.begin() + i * n, n, out.begin() + static_cast<std::size_t>(at[i]) * n);
  }
}

std::vector<double> Buffers::accessor(std::size_t a, int want_n, std::initializer_list<int> types, std::size_t& count) {
  const std::string where = "accessors[" + std::to_string(a) + "]";
  const json& acc = ctx_.array(doc_, "accessors")[a];
  if (!acc.is_object()) ctx_.fail(where, "expected an object");
  const int ct = ctx_.integer(acc, "componentType", 0, where);
  if (std::find(types.begin(), types.end(), ct) == types.end())
    ctx_.fail(where + ".componentType", std::to_string(ct) + " is not allowed here");
  const std::string type = ctx_.text(acc, "type", where);
  const int n = components(type);
  if (n != want_n) ctx_.fail(where + ".type", "'" + type + "' (expected " + std::to_string(want_n) + " components)");
  count = ctx_.size(acc, "count", 0, where);
  const bool normalized = ctx_.flag(acc, "normalized", where);
  std::vector<double> out;
  if (acc.contains("bufferView")) {
    const View v = view(ctx_.index(acc, "bufferView", ctx_.array(doc_, "bufferViews").size(), where));
    read_elements(v.bytes, v.stride, ctx_.size(acc, "byteOffset", 0, where), ct, n, normalized, count, where, out);
  } else {
    // All zeros, per the specification: nothing in the file bounds the count, so a limit does.
    if (count > (std::size_t{1} << 26)) ctx_.fail(where + ".count", std::to_string(count) + " zeros without a bufferView");
    out.assign(count * n, 0.0);
  }
  if (acc.contains("sparse")) apply_sparse(acc["sparse"], ct, n, normalized, count, where, out);
  return out;
}

std::vector<std::uint32_t> Buffers::indices(std::size_t a, std::size_t limit, const std::string& where) {
  std::size_t k = 0;
  const auto raw = accessor(a, 1, {kUnsignedByte, kUnsignedShort, kUnsignedInt}, k);
  std::vector<std::uint32_t> idx(k);
  for (std::size_t i = 0; i < k; ++i) {
    if (raw[i] >= static_cast<double>(limit))
      ctx_.fail(where, "index " + std::to_string(static_cast<std::uint64_t>(raw[i])) + " at " + std::to_string(i) +
                           " is not below the vertex count " + std::to_string(limit));
    idx[i] = static_cast<std::uint32_t>(raw[i]);
  }
  return idx;
}

std::size_t Buffers::declared_count(std::size_t a) {
  const std::string where = "accessors[" + std::to_string(a) + "]";
  return ctx_.size(ctx_.array(doc_, "accessors")[a], "count", 0, where);
}

}  // namespace geom::gltf_detail
