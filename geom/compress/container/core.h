#pragma once
// The part of the stream reader that decompress() and decompress_flat() share: one version 1
// or 2 stream decoded up to its corner table and grid points (codec.cpp). The chunked reader
// (chunks.cpp) runs it once per chunk and merges the results into one Core.

#include <geom/compress/connectivity.h>
#include <geom/compress/predict.h>
#include <geom/compress/quantise.h>
#include <geom/compress/scratch.h>

#include <tbb/enumerable_thread_specific.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace geom::codec::detail {

struct Header {
  std::uint8_t flags = 0;
  Predictor predictor = Predictor::kDelta;
  Blend blend;  // with kMultiParallelogramBlend
  bool anchored = false;  // predictor 5's and 7's isolated vertex byte
  unsigned log2_deadline = 0;  // predictors 6 and 7
  Quantiser quantiser;
  unsigned normal_bits = 0;
  Quantiser uv_quantiser;
  std::uint64_t n_faces = 0, n_triangles = 0, n_vertices = 0, n_isolated = 0;
};

/// Everything up to the decoded positions.
struct Core {
  Header h;
  CornerTable table;
  std::vector<QPoint> q, normals, uvs;
  std::span<const std::uint8_t> order_rans, order_raw;
  std::uint64_t order_offset = 0, connectivity_offset = 0;
  std::size_t extension_at = 0;  // the extension block runs from here to the end
  /// The table's corners without an opposite (ascending), when asked for and the position
  /// pass found them on its way (degree-order predictors), for the chunk merge's boundary.
  std::vector<std::uint32_t> open_corners;
  bool open_corners_known = false;
};

/// Decode a version 1 or 2 stream up to its positions and vertex attributes; with
/// open_corners, list them in the Core where that costs no pass of its own.
/// Throws: DecodeError naming the byte offset (in `bytes`).
Core decode_core(std::span<const std::uint8_t> bytes, bool open_corners = false);
/// decode_core() into `core`, whose arrays (and the scratch block) keep their capacity from
/// an earlier decode: a decoder used stream after stream then writes pages it has already
/// touched instead of fresh ones the kernel must clear. Whatever core held is replaced.
void decode_core_into(std::span<const std::uint8_t> bytes, Core& core, Scratch& scratch,
                      bool open_corners = false);

/// A decoder's memory kept between streams (FlatDecoder): per chunk its Core, per thread
/// a scratch block (a chunk's is dead once its positions are decoded, so the next chunk
/// a thread decodes writes the same pages: half the fresh memory of a block per chunk).
struct Workspace {
  std::vector<Core> cores;
  tbb::enumerable_thread_specific<Scratch> scratch;
  /// Per thread, the opposite table of the chunk it decoded last, for the flat decode: its
  /// output needs no opposites (the seams are never zipped), so once a chunk's boundary is
  /// ranked its table's opposites are dead and the thread's next chunk writes them into the
  /// same pages: one array of fresh pages per thread instead of one per chunk.
  tbb::enumerable_thread_specific<std::vector<std::uint32_t>> spare_opposite;
  /// A single decode (decompress_flat): the scratch blocks are freed as soon as the chunks
  /// are decoded, so that the output arrays get their pages from the allocator rather than
  /// fresh ones (held to the end, they made a one-shot decode of the 1M-triangle stream 8%
  /// slower).
  bool one_shot = false;
};

}  // namespace geom::codec::detail
