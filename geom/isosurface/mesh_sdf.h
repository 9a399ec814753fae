#pragma once
/// \file
/// Signed distance to a closed triangle mesh, as a point query and sampled on a grid (the
/// implicit input that turns a mesh into a voxelised level set: contour it at level 0 to
/// remesh, at level L > 0 for an offset surface, L < 0 for an inset).
///
/// Sign: from the angle-weighted pseudo-normal at the closest point (face normal inside a
/// triangle, sum of the two face normals on an edge, angle-weighted sum on a vertex); for a
/// closed, consistently oriented, self-intersection-free mesh (q − p)·n > 0 exactly when q
/// is outside, with no ray casting and no parity ambiguity. Negative inside, positive
/// outside, as the built-in implicits. An inside-out mesh (normals pointing in) gives the
/// negated field. The closest feature (face, edge, corner) is found by the closest point's
/// distance to the edges and corners, not by its barycentric coordinates, which on a sliver
/// misread an edge point as interior. Where the pseudo-normal is not trustworthy — the
/// closest triangle has a corner on a fold (an edge whose two faces lie back to back,
/// within ~11° of a full fold, as in the hole-fill fans of shared bunny_closed.off that
/// overlap themselves), or the offset is nearly perpendicular to it — the sign comes from
/// the generalized winding number, O(F) per such query; within a grid, a query whose
/// surface-free ball overlaps that of a recent query reuses its sign instead. Limitation:
/// where a mesh passes through itself with no fold edge nearby (two sheets crossing), the
/// pseudo-normal is still used and the sign near the crossing can be wrong.
///
/// Only the work the surface needs: the grid is cut into 8³-sample blocks and one exact
/// query at each block centre bounds the distance of all its samples (the distance is
/// 1-Lipschitz). Blocks farther than the exact band get the correct sign and the lower bound
/// d(centre) − |p − centre| (never nearer than the band) without further queries; a block
/// near the surface is split into 4³ ones that are tested the same way, and only those near
/// the surface are evaluated sample by sample. Samples within `band` of the
/// surface are exact, so every grid edge that crosses the level, and the central
/// differences used for vertex normals, see exact values.
///
/// Ref: Bærentzen, Aanæs, "Signed distance computation using the angle weighted
/// pseudonormal", IEEE TVCG 2005; Jacobson, Kavan, Sorkine-Hornung, "Robust inside-outside
/// segmentation using generalized winding numbers", SIGGRAPH 2013; Van Oosterom, Strackee,
/// "The solid angle of a plane triangle", IEEE Trans. Biomed. Eng. 1983.

#include <geom/core/surface_mesh.h>
#include <geom/isosurface/grid.h>
#include <geom/spatial/bvh.h>

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <limits>
#include <vector>

namespace geom {

/// Exact signed distance to a closed mesh (polygons fan-triangulated).
class MeshSignedDistance {
 public:
  /// Throws: InvalidArgument when the mesh has no faces or is open (the message counts the
  /// boundary edges and names one by its vertices): an open surface has no inside.
  /// Complexity: O(F log F).
  explicit MeshSignedDistance(const SurfaceMesh& mesh);

  /// Signed distance from p (negative inside). Complexity: O(log F) typical; O(F) when the
  /// closest feature touches a fold (see the file comment).
  double operator()(const Eigen::Vector3d& p) const;
  /// The nearest surface point and the sign of p relative to it (+1 outside or on the
  /// surface, −1 inside). Searches only within max_distance (returns sign 0 when nothing
  /// is that near).
  struct Query {
    ClosestPoint closest;
    int sign = 0;
  };
  /// Balls free of surface and the sign of their points, from the last few queries; a
  /// later query that would need the winding number reuses the sign of one its own empty
  /// ball overlaps. Pass one per thread to a run of nearby queries (a grid does).
  struct SignMemo {
    static constexpr int kSize = 8;
    std::array<Eigen::Vector3d, kSize> centre;
    std::array<double, kSize> radius{};
    std::array<int, kSize> sign{};  ///< 0: empty slot
    int next = 0;                   ///< slot to overwrite
  };
  Query query(const Eigen::Vector3d& p,
              double max_distance = std::numeric_limits<double>::infinity(),
              SignMemo* memo = nullptr) const;

  /// Generalized winding number of the surface around p (1 inside, 0 outside a closed,
  /// outward-oriented mesh; overlapping layers count with their orientation).
  /// Complexity: O(F).
  double winding_number(const Eigen::Vector3d& p) const;

  const TriangleBvh& bvh() const { return bvh_; }

 private:
  Eigen::Vector3d pseudo_normal(std::uint32_t triangle, const Point& on_triangle) const;
  void mark_folds();

  TriangleBvh bvh_;
  std::vector<Eigen::Vector3d> face_normals_;                 ///< per BVH triangle
  std::vector<std::array<Eigen::Vector3d, 3>> edge_normals_;  ///< edge k joins corners k, k+1
  std::vector<Eigen::Vector3d> vertex_normals_;               ///< per position
  std::vector<char> near_fold_;  ///< per BVH triangle: a corner ends a folded edge
};

struct MeshSdfOptions {
  /// Samples along the longest axis of the box; the spacing is the same on all axes.
  std::size_t resolution = 128;
  /// The level the grid will be contoured at: the box grows by max(level, 0) so an offset
  /// surface stays inside it, and the exact band covers it.
  double level = 0.0;
  /// Exact within |level| + band_cells·spacing of the surface (≥ 2 keeps the crossings and
  /// the normals' central differences exact).
  double band_cells = 3.0;
  /// Evaluate every sample exactly (for tests and for users who need the whole field).
  bool exact_everywhere = false;
  bool use_double = false;  ///< float64 samples instead of float32
};

struct MeshSdfStats {
  std::size_t samples = 0;
  std::size_t exact_samples = 0;  ///< samples given by their own closest-point query
  std::size_t blocks = 0;
  std::size_t near_blocks = 0;  ///< 8³ blocks near enough to be split into 4³ ones
};

struct MeshSdf {
  ScalarGrid grid;
  MeshSdfStats stats;
};

/// Sample the signed distance to a closed mesh on a grid around it: the mesh's bounding box
/// plus a margin of max(level, 0) + 3 cells on every side, with cubic cells, `resolution`
/// samples along the longest axis.
/// Throws: InvalidArgument as MeshSignedDistance, when resolution < 8 or > 4096, or when
/// level or band_cells is not finite (band_cells must be ≥ 1).
/// Complexity: O(B log F) for B blocks plus O(S log F) for the S samples of near blocks;
/// parallel over blocks.
MeshSdf signed_distance_grid(const SurfaceMesh& mesh, const MeshSdfOptions& options = {});
/// As above with a prepared distance (reuse it for several grids).
MeshSdf signed_distance_grid(const MeshSignedDistance& distance, const MeshSdfOptions& options = {});

}  // namespace geom
