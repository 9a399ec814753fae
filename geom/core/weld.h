#pragma once
/// \file
/// Welding: which positions are to be merged into one vertex.

#include <geom/core/soup.h>
#include <geom/core/surface_mesh.h>

#include <cstdint>
#include <span>
#include <vector>

namespace geom {

/// For each position, the index of the vertex it merges into: the lowest index among the
/// positions connected to it by chains of pairs at distance ≤ tolerance (an absolute
/// distance; 0 merges exactly equal coordinates only, with -0 equal to +0). Non-finite
/// positions never merge. result[i] == i for positions that stay.
/// Pre: tolerance ≥ 0.
/// Throws: InvalidArgument when tolerance is negative or not finite.
/// Complexity: O(n log n) plus the close pairs examined (a grid of cell size tolerance).
std::vector<std::uint32_t> weld_map(std::span<const Point> positions, double tolerance);

/// What joining the vertices that `same` maps together (weld_map's result) would lose: the
/// number of vertices whose per-vertex texture coordinate, normal or colour differs from its
/// representative's (a seam stored as split vertices, as PLY and glTF store one).
struct SeamCount {
  std::size_t texcoords = 0, normals = 0, colors = 0;
};
SeamCount count_seams(const PolygonSoup& soup, std::span<const std::uint32_t> same);

/// Before joining: per-vertex texture coordinates and normals that differ within a group of
/// `same` move to the face corners (each corner takes its vertex's value; the per-vertex array
/// is cleared), unless the soup already has per-corner ones. Joining then keeps the seam.
/// Colours have no per-corner form and are left alone. Returns count_seams(soup, same).
/// Pre: same has one entry per position, each a position index.
SeamCount seams_to_corners(PolygonSoup& soup, std::span<const std::uint32_t> same);

}  // namespace geom
