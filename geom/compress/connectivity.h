#pragma once
/// \file
/// Connectivity coding of manifold triangle meshes (any number of components, boundaries,
/// holes and handles) by a gate-driven region growing in the spirit of Edgebreaker: the
/// decoded region's open boundary is a set of gates; each popped gate either meets the mesh
/// boundary, or grows a triangle whose third vertex is new (C), the next or previous
/// vertex on the open boundary (R / L), or — rarely, at splits and handles — any earlier
/// vertex, coded by its distance in decoding order. Edges whose two sides are both decoded
/// are zipped implicitly, so E/L/R need no extra bits. Polygon meshes travel as fan
/// triangulations with one flag per interior edge marking the diagonals.
///
/// Ref: J. Rossignac, "Edgebreaker: connectivity compression for triangle meshes", IEEE
/// TVCG 5(1), 1999. S. Gumhold, W. Straßer, "Real time compression of triangle mesh
/// connectivity", SIGGRAPH 1998 (the cut-border / gate view).

#include <geom/compress/rans.h>
#include <geom/compress/scratch.h>
#include <geom/core/huge_pages.h>

#include <cstdint>
#include <vector>

namespace geom::codec::detail {

inline constexpr std::uint32_t kNone = 0xffffffffu;

/// A triangle mesh as flat corner arrays; corner c = 3t + j belongs to triangle t and the
/// edge opposite c runs from vertex[next(c)] to vertex[prev(c)].
struct CornerTable {
  std::uint32_t n_vertices = 0;
  /// Per corner. Not cleared when sized: every writer fills what it sizes (the decoders'
  /// tables become flat outputs, moved, not copied).
  geom::detail::UninitialisedVector<std::uint32_t> vertex;
  std::vector<std::uint32_t> opposite;  ///< per corner; kNone across a boundary edge
  /// Per corner, 1 when the edge opposite is a polygon diagonal (empty: all triangles).
  std::vector<std::uint8_t> diagonal;
  /// Per vertex, its corners, as the connectivity coder counted them while growing the
  /// table (n_vertices entries; the encoder always, the decoder when asked); empty when not
  /// known. Whatever renumbers or edits the table clears it. Not cleared when sized, like
  /// vertex.
  geom::detail::UninitialisedVector<std::uint32_t> corners_of;
  std::size_t n_triangles() const { return vertex.size() / 3; }
};

inline std::uint32_t next_corner(std::uint32_t c) { return c % 3 == 2 ? c - 2 : c + 1; }
inline std::uint32_t prev_corner(std::uint32_t c) { return c % 3 == 0 ? c + 2 : c - 1; }

/// Which of the two new gates of a grown triangle is explored first. Both are valid
/// streams; the encoder may try both and keep the smaller.
enum class Traversal : std::uint8_t { kRightFirst = 0, kLeftFirst = 1 };

/// What the encoder learnt about the order the decoder will see.
struct TraversalOrder {
  std::vector<std::uint32_t> vertex_origin;  ///< decoded vertex → input vertex
  std::vector<std::uint32_t> corner_origin;  ///< decoded corner → input corner
};

/// Code `input` (opposites must pair each directed edge with its reverse; diagonal flags
/// present when polygons is true). Fills `decoded` with exactly the table the decoder will
/// rebuild (decoded numbering) and `order` with the map back to the input.
/// Throws: InvalidArgument when the input's opposite table is inconsistent.
/// Complexity: O(T) for T triangles (plus O(valence) per zip lookup).
void encode_connectivity(const CornerTable& input, bool polygons, Traversal traversal,
                         RansEncoder& rans, BitWriter& raw, CornerTable& decoded,
                         TraversalOrder& order);

/// What the caller of decode_connectivity knows or wants beyond the table.
struct GrowHints {
  /// The vertices expected (the stream header's count): any value is safe, a good one saves
  /// the vertex records a reallocation on meshes with boundaries.
  std::size_t vertices = 0;
  /// Fill CornerTable::corners_of (for the degree pass).
  bool count_corners = false;
};

/// Rebuild the corner table of n_triangles triangles from the streams. Its gates (records
/// and stack) live in `scratch` (a block of its own when null), dead on return.
/// Throws: DecodeError (with the byte offset) on truncated or inconsistent data.
/// Complexity: O(T).
void decode_connectivity(std::size_t n_triangles, bool polygons, Traversal traversal,
                         RansDecoder& rans, BitReader& raw, CornerTable& decoded,
                         Scratch* scratch = nullptr, GrowHints hints = {});

/// The scratch bytes decode_connectivity uses for n_triangles.
std::size_t connectivity_scratch_bytes(std::size_t n_triangles);

}  // namespace geom::codec::detail
