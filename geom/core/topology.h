#pragma once
/// \file
/// Topological analysis: counts, components, boundary loops, Euler characteristic, genus.
///
/// geom uses the surface form of Euler's formula. For a surface mesh with C components,
/// H boundary loops and genus G: χ = V − E + F = 2(C − G) − H. The textbook form
/// V − E + F − H = 2(C − G) is the Euler–Poincaré formula for solids, where H counts holes
/// inside faces (rings); our faces have no inner loops, and boundary loops *lower* χ.
/// Check: one triangle has V=3, E=3, F=1, so χ = 1, H = 1, C = 1 and G = (2 − 1 − 1)/2 = 0.

#include <geom/core/surface_mesh.h>

#include <Eigen/Core>

#include <cstddef>
#include <map>
#include <optional>
#include <vector>

namespace geom {

struct ComponentTopology {
  std::size_t vertices = 0, edges = 0, faces = 0, boundary_loops = 0;
  long euler_characteristic = 0;
  bool orientable = true;
  /// Orientable genus; empty when the component is not an orientable manifold.
  std::optional<long> genus;
};

struct TopologyReport {
  std::size_t vertices = 0, edges = 0, faces = 0;
  std::size_t isolated_vertices = 0;
  std::size_t boundary_edges = 0, boundary_loops = 0;
  std::size_t components = 0;  ///< connected components with at least one face
  long euler_characteristic = 0;
  /// Sum of component genera; empty when any component is non-manifold or non-orientable.
  std::optional<long> genus;
  bool closed = false, manifold = false, orientable = false;
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

}  // namespace geom
