#pragma once
/// \file
/// Internal to the glTF reader: the document's bytes — buffers (GLB chunk, data URIs, files
/// beside the document), buffer views (with EXT_meshopt_compression decoded on first use) and
/// accessors (strided, normalized or quantized, sparse) read as doubles. Every count, offset
/// and stride is checked against the bytes that are there before anything is read.
///
/// Ref: Khronos, "glTF 2.0 Specification" §3.6 (buffers, accessors, sparse accessors);
/// "KHR_mesh_quantization"; "EXT_meshopt_compression".

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace geom::gltf_detail {

using nlohmann::json;

/// The vertex attribute geom writes when welding by position would join vertices the mesh
/// keeps apart (a glTF application-specific semantic, VEC2 UNSIGNED_SHORT: low and high 16
/// bits of the id): vertices with one id are one vertex.
constexpr const char* kVertexIdAttribute = "_GEOM_VERTEX";
constexpr int kFloat = 5126, kUnsignedInt = 5125, kUnsignedShort = 5123, kUnsignedByte = 5121,
              kShort = 5122, kByte = 5120;

/// The file's name and its checked member access; every failure is a ParseError naming the
/// element ("accessors[3].count: …").
class Context {
 public:
  explicit Context(std::string name) : name_(std::move(name)) {}
  const std::string& name() const { return name_; }
  [[noreturn]] void fail(const std::string& where, const std::string& what) const;
  /// doc[key] as an array (an empty one when absent).
  const json& array(const json& doc, const char* key) const;
  std::size_t index(const json& obj, const char* key, std::size_t limit, const std::string& where) const;
  int integer(const json& obj, const char* key, int fallback, const std::string& where) const;
  std::size_t size(const json& obj, const char* key, std::size_t fallback, const std::string& where) const;
  std::string text(const json& obj, const char* key, const std::string& where) const;
  bool flag(const json& obj, const char* key, const std::string& where) const;

 private:
  std::string name_;
};

/// "Box%20With%20Spaces.bin" -> "Box With Spaces.bin" (RFC 3986 percent-decoding).
/// Throws: ParseError via ctx for a malformed escape.
std::string percent_decode(const std::string& uri, const Context& ctx, const std::string& where);

class Buffers {
 public:
  /// Loads every buffer of `doc`. `bin` is the GLB BIN chunk (empty for .gltf); external URIs
  /// are resolved against `base_dir`. A buffer that is only EXT_meshopt_compression's fallback
  /// needs no data.
  Buffers(const Context& ctx, const json& doc, std::span<const std::byte> bin,
          const std::filesystem::path& base_dir);

  /// Bytes of buffer view v (decompressed when it is meshopt-compressed) and its stride (0:
  /// tightly packed).
  struct View {
    std::span<const std::byte> bytes;
    std::size_t stride;
  };
  View view(std::size_t v);

  /// Values of accessor a, count × n doubles, normalized integers mapped to [0, 1] or
  /// [−1, 1], sparse substitutions applied. `n` and the allowed component types are checked.
  std::vector<double> accessor(std::size_t a, int n, std::initializer_list<int> types, std::size_t& count);

  /// Indices of accessor a (an unsigned scalar type), each checked to be below `limit`.
  std::vector<std::uint32_t> indices(std::size_t a, std::size_t limit, const std::string& where);

  /// The accessor's declared element count (for Draco-compressed primitives, whose accessors
  /// carry no data).
  std::size_t declared_count(std::size_t a);

 private:
  std::vector<std::byte> load_uri(const std::string& uri, const std::string& where) const;
  std::span<const std::byte> meshopt_view(std::size_t v, const json& ext, const std::string& where);
  void read_elements(std::span<const std::byte> bytes, std::size_t stride, std::size_t offset, int ct,
                     int n, bool normalized, std::size_t count, const std::string& where,
                     std::vector<double>& out) const;
  void apply_sparse(const json& sparse, int ct, int n, bool normalized, std::size_t count,
                    const std::string& where, std::vector<double>& out);

  const Context& ctx_;
  const json& doc_;
  std::filesystem::path base_;
  std::vector<std::vector<std::byte>> owned_;
  std::vector<std::span<const std::byte>> buffers_;  ///< empty span: a meshopt fallback
  std::vector<bool> fallback_;
  std::map<std::size_t, std::vector<std::byte>> decoded_views_;
};

/// A KHR_draco_mesh_compression primitive decoded: `points` vertices, triangles as point
/// indices, and each wanted attribute per point (points × its component count).
struct DracoPrimitive {
  std::size_t points = 0;
  std::vector<std::uint32_t> triangles;
  std::vector<std::string> semantics;           ///< of each attribute, in the order of `wanted`
  std::vector<std::vector<double>> attributes;  ///< in the order of `wanted`
  /// The values of attribute `semantic`, or nullptr when the stream does not hold it.
  const std::vector<double>* find(const std::string& semantic) const {
    for (std::size_t i = 0; i < semantics.size(); ++i)
      if (semantics[i] == semantic) return &attributes[i];
    return nullptr;
  }
};
struct DracoAttribute {
  std::string semantic;  ///< "POSITION", "NORMAL", … (for messages)
  int unique_id;         ///< the Draco attribute id the glTF names
  int components;
};
/// Throws: ParseError via ctx naming `where` when the stream does not decode, is not a
/// triangle mesh, lacks a wanted attribute, or declares more than memory holds.
DracoPrimitive decode_draco(std::span<const std::byte> bytes, const std::vector<DracoAttribute>& wanted,
                            const Context& ctx, const std::string& where);

int components(const std::string& type);
std::size_t component_size(int component_type);

}  // namespace geom::gltf_detail
