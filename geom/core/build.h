#pragma once
/// \file
/// Building a valid SurfaceMesh from a polygon soup, repairing what real files get wrong and
/// reporting every change. The rest of geom may assume the valid mesh this produces.

#include <geom/core/soup.h>
#include <geom/core/surface_mesh.h>

#include <cstddef>
#include <string>
#include <vector>

namespace geom {

enum class RepairPolicy {
  kRepair,  ///< keep every face that can be kept, report what changed
  kStrict,  ///< throw TopologyError naming the first offending face
};

struct BuildOptions {
  RepairPolicy policy = RepairPolicy::kRepair;
  /// Weld vertices closer than weld_tolerance × bounding-box diagonal. Negative: no
  /// welding. Zero: weld exact duplicates only.
  double weld_tolerance = -1.0;
  /// Flip faces to agree with their neighbours where the surface is orientable.
  bool orient = true;
  /// Drop vertices no face uses.
  bool drop_unreferenced = false;
  /// Keep zero-area faces and faces with the same vertex set as another, as given (they are
  /// dropped otherwise). A kept duplicate that doubles an edge gets vertices of its own.
  bool keep_degenerate = false;
};

/// What build() changed. Each count comes with a few example element indices (input
/// numbering) so a message can name them.
struct BuildReport {
  std::size_t welded_vertices = 0;        ///< vertices merged into another
  std::size_t unreferenced_vertices = 0;  ///< vertices no face uses (kept unless asked)
  std::size_t dropped_out_of_range = 0;   ///< faces with an index ≥ V (dropped)
  std::size_t dropped_degenerate = 0;     ///< faces with < 3 distinct corners or zero area
  std::size_t dropped_duplicate = 0;      ///< faces with the same corner set as another
  std::size_t split_nonmanifold_edges = 0;     ///< edges with 3+ faces, split apart
  std::size_t split_nonmanifold_vertices = 0;  ///< bow-tie vertices split into fans
  std::size_t flipped_faces = 0;          ///< faces reoriented to agree with neighbours
  /// Faces that visited a vertex twice in a row (after welding) and lost the repeat; kept.
  std::size_t collapsed_corners = 0;
  /// Edges whose two faces could not be made to agree (a non-orientable component, or
  /// options.orient off): both sides were left as boundary.
  std::size_t cut_edges = 0;
  /// Faces on a non-manifold edge that would have doubled an edge even after vertex
  /// splitting: they keep their corners but get vertices of their own.
  std::size_t detached_faces = 0;
  std::size_t dropped_unreferenced = 0;   ///< unreferenced vertices removed (option)
  bool orientable = true;                 ///< false when some component is not (Möbius)
  std::vector<std::string> messages;      ///< one line per kind of change, with examples
  /// Input face index of each output face (faces are never reordered, only dropped).
  std::vector<std::uint32_t> face_origin;
  /// Output vertex of each input vertex (invalid when dropped); splits add new vertices
  /// whose origin is in vertex_origin.
  std::vector<Vertex> vertex_map;
  std::vector<std::uint32_t> vertex_origin;

  bool changed() const;
  /// Whether non-manifold edges or vertices were split apart (or faces detached): some
  /// output vertices then share an entry of vertex_origin.
  bool split_apart() const {
    return split_nonmanifold_edges + split_nonmanifold_vertices + detached_faces > 0;
  }
};

struct BuildResult {
  SurfaceMesh mesh;
  BuildReport report;
};

/// Build a mesh from a soup.
///
/// In order: weld (when asked; chains of close vertices merge into the lowest index); drop
/// faces with an index out of range; collapse a vertex repeated in consecutive corners;
/// drop faces left with fewer than 3 distinct corners, visiting a vertex twice, or of zero
/// area (all corners on one line, decided exactly); drop faces with the same vertex set as
/// an earlier face; pair the halfedges of each edge, at most two faces per edge (faces
/// beyond the second stay on their own edge); flip faces to agree with their neighbours,
/// per component keeping the orientation most faces had, and cut edges where a component
/// is not orientable; give every fan of faces around a vertex after the first its own copy
/// of the vertex (attributes copied). Faces keep input order and their first corner:
/// halfedge(f) ends at it, so vertices(f) yields the input corners in order. The returned
/// mesh is valid, manifold and free of doubled edges. Attributes become the properties
/// named in soup.h `prop::`.
///
/// Throws: TopologyError (policy kStrict) naming the first offending face; InvalidArgument
/// when the soup's arrays disagree in length.
/// Complexity: O(V + C·d) for C corners and maximum valence d (bucketing by vertex); linear
/// on clean input, with no per-element allocation. Welding adds O(V log V).
/// Ref: M. Botsch et al., "Polygon Mesh Processing", 2010, ch. 2 (halfedge construction);
/// A. Guéziec, G. Taubin, F. Lazarus, W. Horn, "Cutting and Stitching: Converting Sets of
/// Polygons to Manifold Surfaces", IEEE TVCG 7(2), 2001 (splitting non-manifold input).
BuildResult build(const PolygonSoup& soup, const BuildOptions& options = {});

}  // namespace geom
