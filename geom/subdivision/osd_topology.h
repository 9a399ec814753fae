#pragma once
/// \file
/// Internal: OpenSubdiv's view of a face-vertex soup's topology, as Far's factory builds it
/// (Vtr::Level::completeTopologyFromFaceVertices and prepareComponentTagsAndSharpness): the
/// edge instance of every corner, which edges and vertices are non-manifold, and the
/// sharpness it gives them. The as-given subdivision of a soup uses it to tag the split
/// half-edge mesh so that every copy of an element refines as OpenSubdiv refines the one.

#include <geom/core/soup.h>

#include <array>
#include <cstdint>
#include <vector>

namespace geom::detail::subdiv {

struct OsdTopology {
  /// Per corner c: the edge instance from corner c to the next corner of its face.
  std::vector<std::uint32_t> corner_edge;
  /// Per edge: its vertices as first created (OpenSubdiv's edge orientation).
  std::vector<std::array<std::uint32_t, 2>> edge_vertices;
  std::vector<std::uint32_t> edge_faces;  ///< faces per edge (with repeats)
  std::vector<std::uint8_t> edge_nonmanifold;
  std::vector<std::uint8_t> vertex_nonmanifold;
  /// Per corner: its fan, the corners of its vertex joined across two-face manifold edges
  /// (named by one corner of the fan).
  std::vector<std::uint32_t> corner_fan;
  /// Sharpness after OpenSubdiv's tagging (user tags, boundaries and non-manifold edges
  /// infinitely sharp, non-manifold vertices and, when asked, corners sharpened), in
  /// OpenSubdiv's float convention: 10 is infinite.
  std::vector<float> edge_sharpness, vertex_sharpness;

  std::size_t n_edges() const { return edge_vertices.size(); }
  std::size_t nonmanifold_edges() const;
  std::size_t nonmanifold_vertices() const;  ///< used by a face (isolated ones not counted)
  std::size_t degenerate_edges() const;
};

/// OpenSubdiv's topology of `soup` (indices must be in range), its crease and corner tags
/// applied, corners sharpened when `sharpen_corners` (VTX_BOUNDARY_EDGE_AND_CORNER).
OsdTopology osd_topology(const PolygonSoup& soup, bool sharpen_corners);

}  // namespace geom::detail::subdiv
