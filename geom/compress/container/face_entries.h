#pragma once
/// \file
/// The extension entries that give the source's faces back as they were given: each
/// polygon's first corner (kind 4; a non-planar polygon's fan triangulation depends on it)
/// and the faces a half-edge mesh cannot hold (kind 5: degenerate, zero-area, duplicate).
/// FORMAT.md specifies both.

#include <geom/compress/connectivity.h>
#include <geom/compress/container/codec.h>
#include <geom/compress/container/mesh_tables.h>
#include <geom/compress/rans.h>

#include <cstdint>
#include <span>
#include <vector>

namespace geom::codec::detail {

inline constexpr std::uint8_t kEntryRotation = 4;
inline constexpr std::uint8_t kEntryLooseFaces = 5;

/// Each triangle's polygon (triangles joined across diagonals), numbered in order of lowest
/// triangle, as reassemble() numbers them.
std::vector<std::uint32_t> polygon_of_triangles(const CornerTable& table);

/// Per corner of polys.vertex, the number of diagonal edges at it (each counted from both
/// of its triangles): the rotation symbol ranks a polygon's corners by it.
std::vector<std::uint32_t> diagonal_counts(const CornerTable& table, const Polygons& polys);

/// Writes entry 4 for the decoded polygons of at least min_degree corners (3 or 4), whose
/// first corner is rotation[j] steps into the rebuilt cycle; returns false (nothing written)
/// when every such rotation is 0.
bool encode_rotation(ByteWriter& w, const CornerTable& table, const Polygons& polys,
                     std::span<const std::uint32_t> rotation, unsigned min_degree);

/// Entry 4 as read: its fields, decoded against the polygons by decode_rotation().
struct RotationEntry {
  unsigned min_degree = 0;  ///< 0: no entry
  std::span<const std::uint8_t> rans, raw;
  std::uint64_t rans_at = 0, raw_at = 0, at = 0;
};
void read_rotation(ByteReader& r, std::span<const std::uint8_t> stream, std::size_t at,
                   RotationEntry& e);
/// Each polygon's rotation (0 for those the entry skips).
/// Throws: DecodeError for a symbol beyond a polygon's corners or a corrupt section.
std::vector<std::uint32_t> decode_rotation(const RotationEntry& e, const CornerTable& table,
                                           const Polygons& polys, unsigned lanes);

/// Faces kept outside the mesh, corners in decoded vertex numbers; with positions, each
/// face's index in the source's face list (ascending).
struct LooseFaces {
  std::vector<std::vector<std::uint32_t>> faces;
  std::vector<std::uint32_t> positions;  ///< empty unless the order is preserved
};
void encode_loose(ByteWriter& w, const LooseFaces& loose, bool with_positions);
/// Throws: DecodeError for a vertex ≥ n_vertices, positions not ascending or beyond
/// n_faces + count, a count the bytes left cannot hold, or a second entry.
void decode_loose(ByteReader& r, std::size_t at, std::size_t n_vertices, std::size_t n_faces,
                  bool with_positions, LooseFaces& out, bool& seen);

/// options.loose_faces with decoded vertex numbers (vertex_order: decoded → dense input
/// vertex) and, with preserve_order, their places (after the mesh's n_faces when not given).
LooseFaces loose_in_decoded_order(const CompressOptions& options,
                                  std::span<const std::uint32_t> vertex_order, std::size_t n_faces);

/// Throws: InvalidArgument for a loose face's vertex beyond the mesh's, or positions that
/// are not one per loose face, ascending and within the faces, when the order is kept.
void check_loose_faces(const CompressOptions& o, std::size_t n_vertices, std::size_t n_faces);

/// Bound on both entries' bytes (see max_compressed_size).
std::size_t max_face_entries_size(std::size_t n_faces, std::size_t n_loose_faces,
                                  std::size_t n_loose_corners);

}  // namespace geom::codec::detail
