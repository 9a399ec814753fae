#pragma once
/// \file
/// geom's mesh codec (".gmc"): region-growing connectivity coding, quantised positions with
/// (multi-)parallelogram prediction, adaptive rANS entropy coding, an optional exact vertex
/// and face order, and a decoder that is safe on untrusted input. The stream format is
/// specified in geom/compress/FORMAT.md.
///
/// Ref: J. Rossignac, "Edgebreaker", IEEE TVCG 1999; C. Touma, C. Gotsman, "Triangle mesh
/// compression", GI 1998; J. Duda, "Asymmetric numeral systems", 2013; the Draco and
/// meshoptimizer codecs (format discipline: versioned header, bounds-checked decoding).

#include <geom/core/huge_pages.h>
#include <geom/core/surface_mesh.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace geom {

struct CompressOptions {
  /// Bits per position coordinate (1–30) on a grid across the largest bounding-box extent.
  unsigned bits = 11;
  /// When > 0: the largest allowed error per coordinate, overriding `bits` (the grid step is
  /// 2·precision whatever the object's size, so long objects keep their accuracy).
  double precision = 0.0;
  /// 0–9. Each level tries a superset of the previous level's configurations and keeps the
  /// smallest stream, so a higher level never gives a larger stream: 0 delta prediction;
  /// 1–2 + parallelogram; 3–4 + multi-parallelogram; 5 + multi-parallelogram in degree order
  /// (pulled towards the parallelograms' edge centroid when that measures shorter);
  /// 6–8 + a coded choice among each vertex's parallelograms (predictor 5; isolated vertices
  /// also tried anchored at their nearest vertex) and the left-first traversal with the
  /// predictor that was smallest right-first; 9 + the left-first traversal with every predictor,
  /// and predictors 4 and 5 in growth order (6 and 7: coded in the connectivity's order; on
  /// some meshes smaller, e.g. the Stanford bunny's zippered scans).
  int level = 7;
  /// Keep the input's vertex order, face order and each face's first corner exactly (costs
  /// about log2(n) bits per vertex and face for a random order, much less for a coherent one).
  bool preserve_order = false;
  /// Bits per octahedral coordinate of the vertex normals (property "v:normal"), 2–20;
  /// 0 drops them. The angular error is below 4.5 / 2^bits radians (0.25° at 10 bits).
  unsigned normal_bits = 10;
  /// Bits per texture coordinate (property "v:texcoord") on a grid across the larger UV
  /// extent, 1–30; 0 drops them. normal_bits and texcoord_bits also apply to the per-corner
  /// versions ("h:normal", "h:texcoord": normal creases, UV seams), coded with their seams.
  unsigned texcoord_bits = 12;
  /// Bits per component of every other float or Eigen-vector vertex property ("v:color",
  /// "v:sharpness", PLY's extra scalars, …), each component on its own grid across its
  /// range, 1–30; 0 drops them.
  unsigned attribute_bits = 12;
  /// Meshes of at least twice this many triangles (polygons count as their fans) are split
  /// into spatial chunks (the largest power of two at most n_triangles / chunk_triangles, so
  /// that they share 2, 4, 8... cores evenly), coded as independent streams on
  /// one grid, which decode (and encode) in parallel: a version 3 stream, 2.5 % larger than
  /// one stream on the 1M-triangle benchmark mesh (8 chunks). Each doubling of the chunks adds
  /// about 1.2 % there; 2^17 rather than 2^18 triangles a chunk decodes that mesh about 2 %
  /// faster on 2 cores (interleaved runs: median 58.0 -> 56.8 ms; finer parts share the cores
  /// more evenly), leaves work for 8 cores rather than 4, and gives meshes of 262k–524k
  /// triangles two chunks instead of one stream.
  /// Not with preserve_order, vertex attributes, per-corner attributes, split vertices
  /// (vertex_origin), loose faces, or polygons whose first corners are kept
  /// (keep_corner_order, the default; a chunk has no extension block): those meshes are
  /// coded as one stream. 0: never; else at least 16384.
  std::size_t chunk_triangles = 131072;
  /// Empty, or one entry per vertex (dense order): the source vertex each came from, as
  /// BuildReport::vertex_origin gives it. Vertices with equal entries are one vertex of the
  /// source that build() split apart (a non-manifold edge or vertex); the stream records
  /// them as one (FORMAT.md, extension kind 3), DecompressResult::vertex_representative joins
  /// them and `geom decompress` writes the source's vertex again. Such a mesh is coded as one
  /// stream (no chunks).
  std::vector<std::uint32_t> vertex_origin{};
  /// Keep the first corner of every face of 4 or more corners (FORMAT.md, extension kind 4):
  /// a non-planar polygon's fan triangulation, and so its surface, depends on it. false
  /// gives the smaller stream of before, whose polygons start where the decoder meets them.
  /// Its cost per polygon is what `bench_compress --corner-order` prints.
  bool keep_corner_order = true;
  /// Keep triangles' first corners too. Off by default: a triangle's surface does not depend
  /// on it, and it costs far more per triangle than a polygon's (bench_compress --corner-order).
  bool keep_triangle_corners = false;
  /// Faces of the source that the mesh cannot hold (build() dropped them: fewer than 3
  /// distinct corners, zero area, the vertex set of another face), as corner lists of dense
  /// mesh vertices: stored (extension kind 5) and returned in DecompressResult::loose_faces.
  /// compress(const PolygonSoup&) fills it. Such a mesh is coded as one stream (no chunks).
  std::vector<std::vector<std::uint32_t>> loose_faces{};
  /// With preserve_order: each loose face's index in the source's face list (ascending;
  /// the mesh's faces fill the other places in order), so decoding restores the whole list.
  /// Empty: they follow the mesh's faces.
  std::vector<std::uint32_t> loose_face_positions{};
};

/// One attribute of the stream's extension block (per-corner normals and texture
/// coordinates, generic vertex properties).
struct AttributeStats {
  std::string name;        ///< the property, e.g. "h:texcoord", "v:color"
  std::size_t bytes = 0;   ///< its bytes in the stream
  /// Normals: the angle bound in radians; otherwise the largest per-component error (the
  /// component's grid step / 2; each component has its own grid).
  double max_error = 0.0;
};

/// Where the bytes went, for reports and benchmarks.
struct CompressStats {
  std::size_t header_bytes = 0;
  std::size_t connectivity_bytes = 0;
  std::size_t geometry_bytes = 0;
  std::size_t order_bytes = 0;
  std::size_t normal_bytes = 0;    ///< 0 when the mesh has no normals (or normal_bits = 0)
  std::size_t texcoord_bytes = 0;  ///< likewise for texture coordinates
  double texcoord_max_error = 0.0;  ///< per UV coordinate: the UV grid step / 2
  unsigned bits = 0;        ///< grid bits used
  double step = 0.0;        ///< grid step
  double max_error = 0.0;   ///< bound on each coordinate's error: step / 2
  /// 0 delta, 1 parallelogram, 2 multi-parallelogram, 3 multi-parallelogram in degree order
  /// (decoded, no longer written), 4 the same with the centroid blend, 5 predictor 4 over a
  /// coded subset of the parallelograms, 6 and 7 predictors 4 and 5 in growth order (FORMAT.md)
  int predictor = 0;
  int traversal = 0;
  std::size_t chunks = 1;  ///< independent chunks (CompressOptions::chunk_triangles); predictor and traversal are chunk 0's
  std::vector<AttributeStats> attributes;  ///< coded in the extension block
  std::size_t rotation_bytes = 0;    ///< faces' first corners (keep_corner_order)
  std::size_t loose_face_bytes = 0;  ///< faces the mesh cannot hold (loose_faces)
  /// compress(const PolygonSoup&) only: faces of the source kept outside the mesh, faces
  /// not stored at all (an index beyond the vertices), and vertices split off a
  /// non-manifold edge or vertex (joined again on decoding).
  std::size_t loose_faces = 0;
  std::size_t unstorable_faces = 0;
  std::size_t split_copies = 0;
  /// Properties of the input that the stream does not hold (decoding will not restore
  /// them): face, edge and other halfedge properties, vertex properties of a type the
  /// codec does not code, and attributes dropped by a bits option of 0.
  std::vector<std::string> dropped_properties;
};

struct CompressResult {
  std::vector<std::uint8_t> bytes;
  /// Input (dense) index of each vertex of the decoded mesh; the identity when
  /// preserve_order. Dense indices count live elements in index order.
  std::vector<std::uint32_t> vertex_permutation;
  /// Input (dense) index of each face of the decoded mesh; the identity when preserve_order.
  std::vector<std::uint32_t> face_permutation;
  CompressStats stats;
};

/// Compress a mesh (triangles, quads and n-gons; any number of components, boundaries and
/// handles; isolated vertices kept). Vertex normals and texture coordinates, their per-corner
/// versions with seams, and float / Eigen-vector vertex properties are coded when present;
/// what is not coded is named in stats.dropped_properties. A SurfaceMesh is manifold by
/// construction: a non-manifold source reaches the codec split apart by build(), and
/// options.vertex_origin lets the stream record which vertices the split made of one (so
/// that `geom compress` / `geom decompress` restore a non-manifold file's vertices).
/// Pre: finite positions.
/// Throws: InvalidArgument for bits outside 1–30, a precision ≤ 0 or needing more than 30
/// bits, a level outside 0–9, normal_bits outside {0} ∪ [2, 20], texcoord_bits above 30,
/// attribute_bits above 30, non-finite positions, normals, texture coordinates or
/// attribute values (naming the vertex, or the halfedge of a corner), a polygon
/// that cannot be fanned without repeating an existing edge, or a vertex_origin that is not
/// one entry per vertex or whose equal entries name vertices at different positions, a loose
/// face naming a vertex beyond the mesh's, or loose_face_positions (preserve_order) that are
/// not one per loose face, ascending, below the number of faces and loose faces.
/// Complexity: O(V + F) per configuration tried (1 at level 0, up to 14 at level 9).
CompressResult compress(const SurfaceMesh& mesh, const CompressOptions& options = {});

struct DecompressResult {
  SurfaceMesh mesh;
  /// Input index of each decoded vertex / face when the stream records the order
  /// (preserve_order: the mesh comes back in input order and these are the identity);
  /// empty otherwise — the encoder's CompressResult holds the permutation then.
  std::vector<std::uint32_t> vertex_permutation;
  std::vector<std::uint32_t> face_permutation;
  bool order_preserved = false;
  double max_error = 0.0;  ///< the stream's per-coordinate error bound (step / 2)
  double texcoord_max_error = 0.0;  ///< per UV coordinate (0 without texture coordinates)
  std::vector<AttributeStats> attributes;  ///< those of the extension block, restored on the mesh
  /// Empty unless the stream records split vertices (CompressOptions::vertex_origin): then,
  /// per mesh vertex, the lowest-numbered mesh vertex that is the same source vertex (itself
  /// for most). The mesh keeps them apart (it is manifold); join_vertices() on its soup
  /// gives the source's vertices back (in the source's order when the order was preserved,
  /// since build() numbers the split copies after every source vertex).
  std::vector<std::uint32_t> vertex_representative;
  /// Faces the mesh cannot hold (CompressOptions::loose_faces: degenerate, zero-area,
  /// duplicate), corners as mesh vertices; to_soup(DecompressResult) puts them back.
  std::vector<std::vector<std::uint32_t>> loose_faces;
  /// With the order preserved: each loose face's index in the source's face list.
  std::vector<std::uint32_t> loose_face_positions;
};

/// Decode a stream written by compress().
/// Throws: DecodeError naming the byte offset for a wrong magic, an unsupported version,
/// truncated or corrupt data; never reads outside `bytes` and never allocates more than a
/// constant times the stream size plus the decoded mesh.
/// Complexity: O(V + F).
DecompressResult decompress(std::span<const std::uint8_t> bytes);

/// Upper bound on the size of compress()'s output for a mesh with these counts (corners =
/// sum of face valences), number of coded per-vertex attributes (normals, texture
/// coordinates: 0–2), per-corner attributes ("h:normal", "h:texcoord": 0–2) and components
/// of generic vertex attributes (1 per double, 3 per colour, …) and split copies (vertices
/// whose CompressOptions::vertex_origin an earlier vertex shares) and loose faces with their
/// corners (CompressOptions::loose_faces), at any options.
std::size_t max_compressed_size(std::size_t n_vertices, std::size_t n_faces, std::size_t n_corners,
                                std::size_t n_attributes = 0, std::size_t n_corner_attributes = 0,
                                std::size_t n_generic_components = 0,
                                std::size_t n_split_copies = 0, std::size_t n_loose_faces = 0,
                                std::size_t n_loose_corners = 0);

namespace codec {
/// Decoding into flat arrays only (no SurfaceMesh), for benchmarks and tools that feed a GPU:
/// positions (xyz per decoded vertex) and triangle indices (polygon meshes come back fanned);
/// normals (xyz) and texcoords (uv) per decoded vertex when the stream has them, else empty.
/// positions and triangles are vectors whose resize() does not clear (the decoder writes
/// them whole).
struct FlatDecode {
  geom::detail::UninitialisedVector<float> positions;
  geom::detail::UninitialisedVector<std::uint32_t> triangles;
  std::vector<float> normals;
  std::vector<float> texcoords;
  /// Per triangle corner, in the order of `triangles` (xyz / uv for corner 3t + k), when the
  /// stream has per-corner normals / texture coordinates ("h:normal", "h:texcoord": creases,
  /// UV seams), else empty.
  std::vector<float> corner_normals;
  std::vector<float> corner_texcoords;
};
/// Throws: DecodeError as decompress(). Ignores the order section and, of the extension
/// block, the generic attributes, the face rotations (the triangles are the encoder's fans,
/// which start at a polygon's first corner whenever they can) and the loose faces (the block
/// is still checked whole). A non-manifold source's split vertices are joined again (FORMAT.md,
/// extension kind 3): the arrays hold the source's vertices and triangles, which a
/// SurfaceMesh cannot.
FlatDecode decompress_flat(std::span<const std::uint8_t> bytes);

namespace detail {
struct Workspace;
}

/// decompress_flat() for a caller that decodes stream after stream (a viewer streaming
/// meshes or LOD levels): the decoder keeps its working memory between calls and decodes
/// into the caller's FlatDecode, reusing its capacity. Memory the kernel hands out fresh
/// must be cleared page by page; for the 1M-triangle benchmark mesh that is about a tenth of
/// a decode's time when every call allocates anew. The price is the memory held between
/// calls (RSS with and without the decoder, after malloc_trim): 35 bytes per triangle of the
/// largest stream decoded so far when it is chunked (the 1M-triangle benchmark stream, 8
/// chunks), 74 when it is one stream.
class FlatDecoder {
 public:
  FlatDecoder();
  ~FlatDecoder();
  FlatDecoder(FlatDecoder&&) noexcept;
  FlatDecoder& operator=(FlatDecoder&&) noexcept;
  /// As decompress_flat(bytes), into out (whatever it held is replaced). After a DecodeError
  /// out's contents are unspecified and the decoder is ready for the next stream.
  void decode(std::span<const std::uint8_t> bytes, FlatDecode& out);

 private:
  std::unique_ptr<detail::Workspace> ws_;
};
}  // namespace codec

}  // namespace geom
