#pragma once
/// \file
/// The bridge between SurfaceMesh and the codec's flat corner tables: fan triangulation of
/// polygons (with the diagonals flagged) on the way in, polygon reassembly (or, for
/// triangle meshes, one-pass linking) on the way out.

#include <geom/compress/connectivity.h>
#include <geom/core/surface_mesh.h>

#include <cstdint>
#include <span>
#include <vector>

namespace geom::codec::detail {

/// A SurfaceMesh flattened for coding: live elements renumbered densely in index order.
struct FlatMesh {
  CornerTable table;                       ///< input numbering; diagonal flags set
  std::vector<Point> positions;            ///< per dense vertex
  std::vector<std::uint32_t> triangle_face;  ///< dense face of each triangle
  std::vector<std::uint32_t> face_first_vertex;  ///< dense first corner vertex of each face
  std::size_t n_faces = 0;
  bool polygons = false;                   ///< some face has more than 3 corners
};

/// Flatten and triangulate. Each polygon is fanned from a corner whose diagonals are not
/// edges of the mesh (or diagonals of another polygon), so every directed edge stays unique.
/// Throws: InvalidArgument when no such corner exists for some face.
/// Complexity: O(V + E + F) for triangle meshes; O(k² · valence) per k-gon.
FlatMesh flatten(const SurfaceMesh& mesh);

/// Polygons reassembled from a decoded table: face j has corners
/// vertex[offset[j] .. offset[j+1]) and its first triangle is first_triangle[j].
struct Polygons {
  std::vector<std::uint32_t> offset, vertex, first_triangle;
  std::size_t size() const { return first_triangle.size(); }
};

/// Merge triangles across diagonal edges into polygons, in order of first triangle; each
/// polygon's cycle starts at the first non-diagonal edge of its first triangle.
/// Throws: DecodeError (offset `where`) when diagonal flags do not form simple polygons.
Polygons reassemble(const CornerTable& table, std::uint64_t where);

/// Add the triangles (vertex[3j], vertex[3j + 1], vertex[3j + 2]) as faces j to a mesh that
/// has vertices and no edges or faces, linking every array at once: the mesh add_face would
/// build (same faces and edge numbering, face j's halfedge ending at its first corner)
/// without its per-face searches. twin[i] is the corner of the reverse of corner i's edge
/// (vertex[i] → the next corner's vertex), kNone on a boundary.
/// Throws: DecodeError (offset `where`) for a triangle with a repeated vertex, twins that
/// do not reverse their edges, two edges between the same vertices, or a vertex whose
/// triangles do not form fans around it (an interior vertex touched by another fan): what
/// add_face refuses.
/// Complexity: O(corners).
void link_triangles(SurfaceMesh& mesh, std::span<const std::uint32_t> vertex,
                    std::span<const std::uint32_t> twin, std::uint64_t where);

/// The decoded triangles as the mesh's faces: output face s is triangle face_of_slot[s] of
/// the table starting at its corner rotation[·], vertices through vertex_slot. The table's
/// opposites give every edge's twin, so link_triangles links the mesh in one pass (add_face
/// per face cost more than the whole flat decode).
/// Throws: DecodeError (offset `where`) as link_triangles. Complexity: O(corners).
void link_decoded_triangles(SurfaceMesh& mesh, const CornerTable& table,
                            std::span<const std::uint32_t> face_of_slot,
                            std::span<const std::uint32_t> rotation,
                            std::span<const std::uint32_t> vertex_slot, std::uint64_t where);

}  // namespace geom::codec::detail
