#pragma once
/// \file
/// Small geometric helpers over a SurfaceMesh that many capabilities need: normals, areas,
/// centroids, bounds, edge lengths, dihedral angles, fan triangulation, and an exact
/// collinearity test that decides zero-area faces without an epsilon.

#include <geom/core/surface_mesh.h>

#include <Eigen/Geometry>

#include <array>
#include <span>
#include <vector>

namespace geom {

/// True when p, q, r lie exactly on one line (coincident points included). Exact: a
/// floating-point filter decides almost every case; the rest is evaluated with error-free
/// expansion arithmetic. Non-finite input returns false (undecidable, not degenerate).
/// Complexity: O(1).
/// Ref: J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust
/// Geometric Predicates", DCG 18(3), 1997.
bool is_collinear(const Point& p, const Point& q, const Point& r);

/// True when the polygon through `points` has zero area in the exact sense: fewer than two
/// distinct positions, or every corner on the line through the first two distinct ones.
/// Complexity: O(n).
bool is_zero_area_polygon(std::span<const Point> points);

/// The unit normal of face f by Newell's method (robust for non-planar and non-convex
/// polygons); the zero vector when the face has zero area.
/// Complexity: O(valence(f)).
/// Ref: M. E. Newell, R. G. Newell, T. L. Sancha, "A Solution to the Hidden Surface
/// Problem", Proc. ACM National Conference, 1972.
Normal face_normal(const SurfaceMesh& mesh, Face f);

/// The area of face f: half the length of the Newell vector (exact for planar polygons).
/// Complexity: O(valence(f)).
double face_area(const SurfaceMesh& mesh, Face f);

/// The average of the corners of face f.
/// Complexity: O(valence(f)).
Point face_centroid(const SurfaceMesh& mesh, Face f);

/// The angle-weighted unit normal at v: each incident face's normal weighted by the
/// corner angle at v. Zero for an isolated vertex or when every incident face is degenerate.
/// Complexity: O(sum of incident face valences).
/// Ref: G. Thürmer, C. A. Wüthrich, "Computing Vertex Normals from Polygonal Facets",
/// Journal of Graphics Tools 3(1), 1998.
Normal vertex_normal(const SurfaceMesh& mesh, Vertex v);

/// The axis-aligned bounding box of the live vertices (empty box for an empty mesh).
/// Complexity: O(V).
Eigen::AlignedBox3d bounds(const SurfaceMesh& mesh);

/// The length of edge e.
double edge_length(const SurfaceMesh& mesh, Edge e);

/// The mean length of the live edges; 0 for a mesh without edges.
/// Complexity: O(E).
double mean_edge_length(const SurfaceMesh& mesh);

/// The signed dihedral angle at edge e in radians: the angle between the two face normals,
/// positive where the surface is convex across e, negative where concave, 0 on a boundary
/// edge or when a face is degenerate. Range [-π, π].
/// Complexity: O(valence of the two faces).
double dihedral_angle(const SurfaceMesh& mesh, Edge e);

/// The total area of the live faces.
/// Complexity: O(F + C) for C corners.
double surface_area(const SurfaceMesh& mesh);

/// A fan triangulation of face f from its first corner: (n − 2) triangles as corner
/// positions within the face (0-based, first corner = 0), in face orientation.
/// Complexity: O(valence(f)).
std::vector<std::array<std::uint32_t, 3>> triangulate_fan(const SurfaceMesh& mesh, Face f);

/// A fan triangulation of face f as mesh vertices, in face orientation.
std::vector<std::array<Vertex, 3>> triangulate_fan_vertices(const SurfaceMesh& mesh, Face f);

}  // namespace geom
