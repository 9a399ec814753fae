#pragma once
/// \file
/// Topological analysis: counts, components, boundary loops, Euler characteristic, genus.
///
/// geom uses the surface form of Euler's formula. For a surface mesh with C components,
/// H boundary loops and genus G: χ = V − E + F = 2(C − G) − H. The textbook form
/// V − E + F − H = 2(C − G) is the Euler–Poincaré formula for solids, where H counts holes
/// inside faces (rings); our faces have no inner loops, and boundary loops *lower* χ.
/// Check: one triangle has V=3, E=3, F=1, so χ = 1, H = 1, C = 1 and G = (2 − 1 − 1)/2 = 0.
/// (With the solid form one would get G = (2 − 1 + 1)/2 = 1 for a triangle: wrong.)
///
/// Isolated (unreferenced) vertices are not components and are left out of χ, so the
/// identity above holds for every manifold, consistently oriented input. Per component
/// G = (2 − χ − H) / 2; it is reported only where that formula applies (an orientable
/// manifold component), never guessed for a non-manifold or non-orientable one.

#include <geom/core/soup.h>
#include <geom/core/surface_mesh.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstddef>
#include <map>
#include <optional>
#include <vector>

namespace geom {

struct ComponentTopology {
  std::size_t vertices = 0, edges = 0, faces = 0, boundary_loops = 0;
  long euler_characteristic = 0;
  bool orientable = true;
  bool manifold = true;
  /// Orientable genus; empty when the component is not an orientable manifold.
  std::optional<long> genus;
};

struct TopologyReport {
  std::size_t vertices = 0, edges = 0, faces = 0;
  std::size_t isolated_vertices = 0;
  std::size_t boundary_edges = 0, boundary_loops = 0;
  std::size_t components = 0;  ///< connected components with at least one face
  /// χ = (V − isolated) − E + F.
  long euler_characteristic = 0;
  /// Sum of component genera (0 when there is no face); empty when any component is
  /// non-manifold or non-orientable.
  std::optional<long> genus;
  bool closed = false, manifold = false, orientable = false;
  /// Every edge with two faces is traversed by them in opposite directions. A SurfaceMesh
  /// always is; a soup may be orientable without being consistently oriented.
  bool consistently_oriented = false;
  /// Soup only: faces naming a vertex that does not exist; left out of every other count.
  std::size_t out_of_range_faces = 0;
  std::size_t nonmanifold_vertices = 0;  ///< vertices with more than one fan
  std::size_t nonmanifold_edges = 0;     ///< always 0 in a SurfaceMesh; kept for soups
  std::size_t degenerate_faces = 0;      ///< faces with zero area (exact test)
  std::map<std::size_t, std::size_t> face_sizes;  ///< corners → face count
  Eigen::AlignedBox3d bounds;
  std::vector<ComponentTopology> per_component;
};

/// Analyze the mesh's topology.
/// Complexity: O(V + E + F).
TopologyReport analyze(const SurfaceMesh& mesh);

/// Analyze a soup as given, before any repair: V counts vertex records, E the distinct
/// undirected edges, F the faces whose indices are in range. Components are faces joined
/// through shared vertices. An edge is manifold with at most two faces, a vertex when its
/// faces form a single fan across such edges. Boundary loops count the cycles of the
/// boundary-edge graph (the same as
/// the loops where the soup is manifold; loops touching at a non-manifold vertex count once). Degenerate
/// faces (a repeated index, or zero area by an exact test) are counted and still included.
/// Complexity: O(V + C log d) for C corners and maximum valence d.
TopologyReport analyze(const PolygonSoup& soup);

}  // namespace geom
