#pragma once
/// \file
/// The stream's extension block (flag EXTENSION, FORMAT.md): per-corner normals and
/// texture coordinates with their seams ("h:normal", "h:texcoord"), and generic vertex
/// properties (float and Eigen-vector types, by name). It follows every other section and is
/// coded on the decoded table, so it composes with whatever the core stream holds.

#include <geom/compress/container/codec.h>
#include <geom/compress/container/face_entries.h>
#include <geom/compress/container/mesh_tables.h>
#include <geom/compress/predict.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace geom::codec::detail {

struct ExtensionEncoding {
  std::vector<std::uint8_t> bytes;  ///< empty: nothing to code, no extension block
  std::vector<AttributeStats> attributes;
  std::vector<std::string> dropped;  ///< input properties the stream will not hold
  std::size_t rotation_bytes = 0, loose_face_bytes = 0;
};

/// The decoded polygons and each one's first corner (its place in the rebuilt cycle), for
/// the rotation entry; rotation empty: none is written (the order section holds them).
struct FaceCorners {
  const Polygons* polys = nullptr;
  std::span<const std::uint32_t> rotation;
  unsigned min_degree = 4;
};

/// Code the mesh's per-corner and generic vertex attributes for the chosen table.
/// `corner_origin`: decoded corner → corner of flat.table; `vertex_order`: decoded vertex →
/// dense input vertex; vertex_normals / vertex_uvs: the core stream codes "v:normal" /
/// "v:texcoord" (a per-corner attribute equal to them everywhere is then sent as a reference).
/// Throws: InvalidArgument for attribute_bits above 30 or a non-finite value (naming the
/// property and the vertex or halfedge).
ExtensionEncoding encode_extension(const SurfaceMesh& mesh, const CompressOptions& options,
                                   const FlatMesh& flat, const CornerTable& decoded,
                                   std::span<const std::uint32_t> corner_origin,
                                   std::span<const std::uint32_t> vertex_order, bool vertex_normals,
                                   bool vertex_uvs, const FaceCorners& corners = {});

struct DecodedCornerAttribute {
  bool normal = false;       ///< "h:normal", else "h:texcoord"
  bool from_vertex = false;  ///< equal to the vertex attribute of the same kind
  unsigned bits = 0;
  double origin[2] = {0, 0}, step = 1;               ///< texture coordinate grid
  std::vector<std::array<std::uint32_t, 2>> values;  ///< per decoded corner
  std::size_t bytes = 0;
};

struct DecodedGeneric {
  std::string name;
  std::uint8_t type = 0;
  unsigned dims = 1;
  std::vector<double> values;  ///< dims per decoded vertex
  double max_error = 0;
  std::size_t bytes = 0;
};

struct ExtensionDecoding {
  std::vector<DecodedCornerAttribute> corners;
  std::vector<DecodedGeneric> generic;
  /// Split vertices: (copy, representative) in decoded numbering, copies ascending, each
  /// representative below its copy and not itself a copy.
  std::vector<std::array<std::uint32_t, 2>> split;
  RotationEntry rotation;  ///< decoded against the polygons by decode_rotation()
  LooseFaces loose;
  std::uint64_t offset = 0;  ///< of the block, for errors found when applying it
};

/// Decode the block (the rest of the stream from `begin`) for the decoded table; q: the
/// decoded grid points (a split vertex must sit on its representative's).
/// Throws: DecodeError naming the byte offset on any inconsistency, truncation or
/// trailing bytes.
ExtensionDecoding decode_extension(std::span<const std::uint8_t> stream, std::size_t begin,
                                   const CornerTable& table, std::span<const QPoint> q,
                                   bool vertex_normals, bool vertex_uvs, unsigned rans_lanes,
                                   std::size_t n_faces = 0, bool order_preserved = false);

/// Put the decoded attributes on the rebuilt mesh: decoded vertex i is mesh vertex
/// vertex_slot[i], decoded polygon j (in order of lowest triangle) is mesh face face_slot[j].
/// representative receives DecompressResult::vertex_representative (empty without splits).
/// Throws: DecodeError when a generic name is already taken on the mesh.
void apply_extension(const ExtensionDecoding& ext, SurfaceMesh& mesh, const CornerTable& table,
                     std::span<const std::uint32_t> vertex_slot,
                     std::span<const std::uint32_t> face_slot, std::vector<AttributeStats>& stats,
                     std::vector<std::uint32_t>& representative);

/// Whether two vertices share an origin (CompressOptions::vertex_origin).
/// Throws: InvalidArgument when two that do have different positions (naming both).
bool has_split_vertices(std::span<const std::uint32_t> vertex_origin,
                        std::span<const Point> positions);

/// Bound on the block's size (see max_compressed_size).
std::size_t max_extension_size(std::size_t n_vertices, std::size_t n_triangle_corners,
                               std::size_t n_corner_attributes, std::size_t n_generic_components,
                               std::size_t n_split_copies, std::size_t n_faces = 0,
                               std::size_t n_loose_faces = 0, std::size_t n_loose_corners = 0);

}  // namespace geom::codec::detail
