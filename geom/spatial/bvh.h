#pragma once
/// \file
/// A bounding-volume hierarchy over triangles: closest-point queries (point-to-mesh
/// distance, the basis of Hausdorff/RMS comparison) and ray queries (first hit, any hit)
/// for renderers and signed-distance evaluation. Polygons are fan-triangulated; each
/// triangle remembers the face it came from.
///
/// Ref: Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies", 2007 (binned
/// SAH build); Ericson, "Real-Time Collision Detection", 2004, §5.1.5 (closest point on a
/// triangle); Möller, Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection", 1997.

#include <geom/core/surface_mesh.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

namespace geom {

using Vector3 = Eigen::Vector3d;

/// The closest surface point to a query.
struct ClosestPoint {
  Point point = Point::Zero();
  std::uint32_t triangle = std::numeric_limits<std::uint32_t>::max();  ///< BVH triangle index
  double distance_squared = std::numeric_limits<double>::infinity();
  /// True when a triangle was found (false only for an empty BVH or when nothing lies
  /// within the query's max distance).
  bool found() const { return triangle != std::numeric_limits<std::uint32_t>::max(); }
};

/// A ray hit: point = origin + t·dir = (1−u−v)·a + u·b + v·c for triangle (a, b, c).
struct RayHit {
  double t = 0;
  std::uint32_t triangle = 0;
  double u = 0, v = 0;  ///< barycentric coordinates of corners b and c
};

/// Closest point to p on triangle (a, b, c), also for degenerate triangles (segments,
/// points). Complexity: O(1). Ref: Ericson 2004, §5.1.5.
Point closest_point_on_triangle(const Point& p, const Point& a, const Point& b, const Point& c);

/// Ray/triangle intersection with t in [tmin, tmax]; both sides of the triangle count.
/// Degenerate triangles are never hit. Complexity: O(1). Ref: Möller, Trumbore 1997.
std::optional<RayHit> intersect_triangle(const Point& origin, const Vector3& dir, double tmin,
                                         double tmax, const Point& a, const Point& b,
                                         const Point& c);

class TriangleBvh {
 public:
  /// An empty BVH: every query finds nothing.
  TriangleBvh() = default;
  /// Build over the mesh's live faces; polygons are fan-triangulated from their first
  /// corner. triangle_face(t) gives the face of BVH triangle t.
  /// Complexity: O(F log F).
  explicit TriangleBvh(const SurfaceMesh& mesh);
  /// Build over triangles indexing positions.
  /// Throws: InvalidArgument when an index is out of range.
  /// Complexity: O(T log T).
  TriangleBvh(std::vector<Point> positions, std::vector<std::array<std::uint32_t, 3>> triangles);

  std::size_t n_triangles() const { return triangles_.size(); }
  bool empty() const { return triangles_.empty(); }
  /// The corners of BVH triangle t (original numbering, not BVH order).
  std::array<Point, 3> triangle(std::uint32_t t) const {
    const auto& i = triangles_[t];
    return {positions_[i[0]], positions_[i[1]], positions_[i[2]]};
  }
  /// Corner indices of triangle t into positions(); for a mesh-built BVH these are vertex
  /// indices (positions() is indexed by Vertex::idx()).
  const std::array<std::uint32_t, 3>& triangle_indices(std::uint32_t t) const { return triangles_[t]; }
  const std::vector<Point>& positions() const { return positions_; }
  /// The mesh face BVH triangle t came from (invalid when built from arrays).
  Face triangle_face(std::uint32_t t) const {
    return t < triangle_faces_.size() ? triangle_faces_[t] : Face();
  }
  /// Bounding box of all triangles (empty box when there are none).
  const Eigen::AlignedBox3d& bounds() const { return bounds_; }

  /// The closest point on the surface to q among points within max_distance (pass a
  /// bound to speed up queries whose answer you only need when it is near).
  /// Complexity: O(log T) typical.
  ClosestPoint closest_point(const Point& q,
                             double max_distance = std::numeric_limits<double>::infinity()) const;
  /// Squared distance from q to the surface (infinity when empty).
  double distance_squared(const Point& q) const { return closest_point(q).distance_squared; }

  /// The nearest hit of the ray origin + t·dir with t in [tmin, tmax] (dir need not be
  /// unit length; t is in units of dir).
  /// Complexity: O(log T) typical.
  std::optional<RayHit> intersect(const Point& origin, const Vector3& dir, double tmin = 0.0,
                                  double tmax = std::numeric_limits<double>::infinity()) const;
  /// Whether any triangle is hit with t in [tmin, tmax] (shadow rays); stops at the first.
  bool any_hit(const Point& origin, const Vector3& dir, double tmin = 0.0,
               double tmax = std::numeric_limits<double>::infinity()) const;

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    // Leaf (count > 0): triangles order_[first .. first + count). Inner (count == 0):
    // children at first and first + 1 (allocated in pairs).
    std::uint32_t first = 0;
    std::uint32_t count = 0;
  };
  void build();

  std::vector<Point> positions_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::vector<Face> triangle_faces_;
  std::vector<std::uint32_t> order_;  ///< triangle indices in leaf order
  std::vector<Node> nodes_;
  Eigen::AlignedBox3d bounds_;
};

}  // namespace geom
