// Bulk construction of a SurfaceMesh from an indexed triangle list.
//
// Adding triangles one by one (SurfaceMesh::add_triangle) searches the vertex rings for every
// edge; an algorithm that already holds its whole output as an index buffer (simplification,
// decoders, readers) can instead pair the two halfedges of every edge by index in linear time
// and link the arrays directly. The result is the mesh add_triangle would build from the same
// triangles in the same order: same vertex and face numbering, same edge numbering (edges in
// order of first use, halfedge 2e pointing the way its first face walks it), same face corner
// order and same boundary loops; only the outgoing halfedge of an interior vertex may differ.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include <geom/core/surface_mesh.h>

namespace geom {

/// A mesh with one vertex per position (isolated ones kept) and one face per triangle, whose
/// corners are indices into `positions`, counter-clockwise seen from outside.
/// When the triangles are not a clean oriented manifold (an index out of range, a repeated
/// corner, an edge used twice in one direction or by three faces, a vertex whose faces form
/// more than one fan), this falls back to add_triangle in input order, so the result, or the
/// TopologyError add_face throws, is exactly what that path gives.
/// Complexity: O(V + F) on clean input.
SurfaceMesh mesh_from_triangles(std::span<const Point> positions,
                                std::span<const std::array<std::uint32_t, 3>> triangles);

}  // namespace geom
