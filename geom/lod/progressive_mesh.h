#pragma once
/// \file
/// Progressive meshes: a coarse base mesh plus the sequence of vertex splits that refines it
/// back to the original, so any vertex count between the two is one call away; geomorphs
/// for popping-free transitions; a versioned streaming format (geom/lod/FORMAT.md) whose
/// prefix is already a usable mesh.
///
/// Ref: Hoppe, "Progressive Meshes", SIGGRAPH 1996; Hoppe, "Efficient Implementation of
/// Progressive Meshes", Computers & Graphics 1998.

#include <geom/core/surface_mesh.h>
#include <geom/lod/simplify.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace geom {

/// One vertex split, the inverse of one edge collapse. Split i adds vertex
/// base_vertices + i and its one or two faces at the end of the face list.
struct VertexSplit {
  std::uint32_t vertex = 0;        ///< the vertex that splits (exists before the split)
  Point vertex_position;           ///< its position after the split
  Point new_position;              ///< position of the new vertex
  Point coarse_position;           ///< its position before the split
  /// Corners (3 × face + slot) that switch from `vertex` to the new vertex:
  /// corners()[corner_begin .. corner_end).
  std::uint32_t corner_begin = 0, corner_end = 0;
  /// The split adds 1 (boundary edge) or 2 faces.
  std::uint8_t n_faces = 0;
};

/// Vertex positions of a fine level and of their ancestors at a coarse level, over the fine
/// level's faces: at(0) looks exactly like the coarse level, at(1) is the fine level.
struct Geomorph {
  std::vector<Point> coarse, fine;
  std::vector<std::array<std::uint32_t, 3>> faces;
  /// (1 − t)·coarse + t·fine per vertex; t is clamped to [0, 1].
  std::vector<Point> at(double t) const;
};

struct ProgressiveOptions {
  /// Simplification settings for the collapse sequence; target_faces / ratio set the base
  /// mesh (default: as coarse as the guarantees allow).
  SimplifyOptions simplify{.ratio = 0.0};
};

class ProgressiveMesh {
 public:
  ProgressiveMesh() = default;

  /// Record the collapse sequence of simplify(mesh, options.simplify) as vertex splits. The
  /// result is at full resolution. Polygons are fan-triangulated; isolated vertices are
  /// dropped.
  /// Throws: InvalidArgument as simplify() does, and for refit_iterations above 0
  /// (-1, automatic, means none here).
  /// Complexity: O(F log F).
  static ProgressiveMesh build(const SurfaceMesh& mesh, const ProgressiveOptions& options = {});

  std::size_t base_vertices() const { return base_vertices_; }
  std::size_t base_faces() const { return base_faces_; }
  std::size_t max_vertices() const { return base_vertices_ + splits_.size(); }
  std::size_t max_faces() const { return face_prefix_.empty() ? base_faces_ : face_prefix_.back(); }
  std::size_t n_vertices() const { return n_vertices_; }
  std::size_t n_faces() const { return n_faces_; }
  /// Face count of the level with the given vertex count.
  /// Pre: base_vertices() ≤ vertices ≤ max_vertices().
  std::size_t faces_at(std::size_t vertices) const;
  /// The largest vertex count whose level has at most `faces` faces (base_vertices() when
  /// even the base has more).
  std::size_t vertices_for_faces(std::size_t faces) const;

  /// Apply vertex splits until n_vertices() == vertices (clamped to max_vertices()).
  /// Complexity: O(size of the change).
  void refine_to(std::size_t vertices);
  /// Apply edge collapses until n_vertices() == vertices (clamped to base_vertices()).
  /// Complexity: O(size of the change).
  void coarsen_to(std::size_t vertices);
  /// refine_to or coarsen_to, whichever applies.
  void set_level(std::size_t vertices);

  /// The current level: positions [0, n_vertices()) and faces [0, n_faces()).
  std::span<const Point> positions() const { return {positions_.data(), n_vertices_}; }
  std::span<const std::array<std::uint32_t, 3>> faces() const { return {faces_.data(), n_faces_}; }
  /// The current level as a SurfaceMesh (vertex i, face t in this order).
  /// Throws: TopologyError when the faces are not a manifold mesh (possible only for a
  /// decoded stream that was crafted so).
  SurfaceMesh mesh() const;

  /// Geomorph between the levels with `coarse` and `fine` vertex counts (coarse ≤ fine).
  /// The progressive mesh is left at level `fine`.
  /// Throws: InvalidArgument when coarse > fine or either is out of range.
  /// Complexity: O(size of the change between the current level and both levels).
  Geomorph geomorph(std::size_t coarse, std::size_t fine);

  /// The permutation back to the input: vertex i at full resolution is input vertex
  /// vertex_origin()[i]; face t is input triangle face_origin()[t] (input faces in order,
  /// each polygon fan-triangulated from its first corner, corners in the same order; from
  /// the first corner none of whose diagonals is already a mesh edge, if the first has one).
  const std::vector<Vertex>& vertex_origin() const { return vertex_origin_; }
  const std::vector<std::uint32_t>& face_origin() const { return face_origin_; }

  const std::vector<VertexSplit>& splits() const { return splits_; }
  const std::vector<std::uint32_t>& corners() const { return corners_; }

  /// Serialise as described in geom/lod/FORMAT.md (base mesh first, then the splits in
  /// order). The permutation to the input is not stored.
  std::vector<std::byte> encode() const;
  /// Read a stream written by encode(). With allow_partial, a stream cut inside the split
  /// records yields the levels up to the last complete split (what a viewer streaming the
  /// file shows); the base mesh must be complete. The result is at its finest level.
  /// Throws: DecodeError with the byte offset for a bad magic or version, a truncated
  /// stream (base mesh always; splits unless allow_partial), an index out of range, a split
  /// inconsistent with the mesh so far, or a count larger than the bytes that remain.
  static ProgressiveMesh decode(std::span<const std::byte> data, bool allow_partial = false);

 private:
  void split(std::size_t i);
  void collapse(std::size_t i);

  std::size_t base_vertices_ = 0, base_faces_ = 0;
  std::size_t n_vertices_ = 0, n_faces_ = 0;
  std::vector<Point> positions_;                      // all vertices, current level
  std::vector<std::array<std::uint32_t, 3>> faces_;   // all faces, current corners
  std::vector<VertexSplit> splits_;
  std::vector<std::uint32_t> corners_;
  std::vector<std::size_t> face_prefix_;              // faces after split i
  std::vector<Vertex> vertex_origin_;
  std::vector<std::uint32_t> face_origin_;
};

}  // namespace geom
