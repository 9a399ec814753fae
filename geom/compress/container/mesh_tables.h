#pragma once
/// \file
/// The bridge between SurfaceMesh and the codec's flat corner tables: fan triangulation of
/// polygons (with the diagonals flagged) on the way in, polygon reassembly on the way out.

#include <geom/compress/connectivity.h>
#include <geom/core/surface_mesh.h>

#include <cstdint>
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

}  // namespace geom::codec::detail
