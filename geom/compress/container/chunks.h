#pragma once
// Chunked streams (version 3): a large mesh split into spatial chunks, each coded as an
// independent version 1 stream on one shared grid, so that decoders (and the encoder) work
// on the chunks in parallel; a merge map says which chunk boundary vertices are the same
// vertex. FORMAT.md specifies the layout.

#include <geom/compress/container/codec.h>
#include <geom/compress/container/core.h>
#include <geom/compress/container/mesh_tables.h>

#include <cstdint>
#include <optional>
#include <span>

namespace geom::codec::detail {

inline constexpr std::uint8_t kVersionChunked = 3;
/// The smallest chunk_triangles a caller may ask for (smaller chunks cost more in seams
/// than a thread saves).
inline constexpr std::size_t kMinChunkTriangles = 16384;
inline constexpr std::uint64_t kMaxChunks = 4096;

/// compress() on a given grid (the chunks share the whole mesh's), without chunking.
CompressResult compress_on_grid(const SurfaceMesh& mesh, const CompressOptions& options,
                                const FlatMesh& flat, const Quantiser& grid);

/// The chunked stream of `mesh` when options and mesh call for one (options.chunk_triangles,
/// no preserve_order, no coded or dropped vertex attributes, no per-corner attributes),
/// else nothing. Also nothing when a chunk's faces do not form a SurfaceMesh on their own.
std::optional<CompressResult> compress_chunked(const SurfaceMesh& mesh,
                                               const CompressOptions& options,
                                               const FlatMesh& flat, const Quantiser& grid);

/// Whether bytes claim to be a chunked stream (magic and version 3).
bool is_chunked(std::span<const std::uint8_t> bytes);

/// Decode every chunk (in parallel) and merge them: one Core as if the mesh had been coded
/// as one stream (vertices: chunk 0's, then each later chunk's unmerged ones, in order;
/// faces in chunk order; isolated vertices last).
/// Throws: DecodeError naming the byte offset in `bytes`.
Core decode_chunked(std::span<const std::uint8_t> bytes);

/// FlatDecoder::decode() of a chunked stream: the same vertices and triangles as
/// decode_chunked gives, without merging the chunks' tables (flat output needs no
/// opposites), into out; the chunks' memory is ws's, kept for the next stream.
/// Throws: DecodeError naming the byte offset in `bytes`.
void decode_chunked_flat(std::span<const std::uint8_t> bytes, Workspace& ws, FlatDecode& out);

}  // namespace geom::codec::detail
