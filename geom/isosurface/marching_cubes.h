#pragma once
/// \file
/// Marching cubes that produces a crack-free, edge- and vertex-manifold, consistently
/// oriented triangle mesh, closed whenever the level set does not reach the grid boundary.
///
/// Rules, stated once:
/// - Ties: a sample is "above" when value ≥ level, "below" otherwise (NaN is rejected; ±inf
///   are ordinary far values). A vertex sits on each grid edge with one above and one below
///   end, at the linear crossing clamped to [1/1024, 1 − 1/1024] of the edge, so no two
///   vertices coincide and no triangle has zero area even when samples equal the level
///   (integer volumes with an integer level).
/// - Faces: on a cube face with four crossings the asymptotic decider joins the two above
///   corners when a·c ≥ b·d (a, c the above diagonal, b, d the below one, values minus
///   level), i.e. when the bilinear saddle is not below the level. Both cubes sharing the
///   face compute the same products of the same samples, so they always agree.
/// - Interior: each cube's face segments form loops triangulated as fans; two loops become
///   a tube when the trilinear interpolant joins their corners through the cube's interior
///   (the tunnels of MC33 cases 4.1.2, 6.1.2, 7.4.2, 10.1.2, 12.1.2, 13.5.2; see
///   mc_tables.h), so within a cube the surface has the trilinear interpolant's topology
///   (Euler characteristic and components agree with the finely sampled interpolant on
///   6000 random cubes of the tunnel cases; tests/isosurface/test_mc33.cpp runs 300). At most
///   one tube per cube is made. Only the cube's interior changes, so the result stays
///   crack-free and manifold.
/// - Orientation: triangles wind counter-clockwise seen from the side the normal points to;
///   `normals_toward` chooses increasing (default: outward for a signed distance field,
///   negative inside) or decreasing values (outward for a density).
///
/// Ref: Lorensen, Cline, "Marching cubes", SIGGRAPH 1987. Nielson, Hamann, "The asymptotic
/// decider", IEEE Visualization 1991. Lewiner et al., "Efficient implementation of marching
/// cubes' cases with topological guarantees", JGT 2003 (the topology goal).

#include <geom/core/from_triangles.h>  // mesh_from_triangles, to link the output
#include <geom/core/surface_mesh.h>
#include <geom/isosurface/grid.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace geom {

enum class NormalDirection {
  kIncreasing,  ///< triangles face larger values (outward for f < level inside)
  kDecreasing,  ///< triangles face smaller values (outward for f > level inside)
};

struct MarchingCubesOptions {
  double level = 0.0;
  NormalDirection normals_toward = NormalDirection::kIncreasing;
  /// Also compute unit vertex normals from the field's central-difference gradient
  /// (property prop::kVertexNormal "v:normal" on the mesh; `normals` in the arrays).
  bool compute_normals = false;
  /// Split the work over z-slabs with TBB; false runs on the calling thread only.
  bool parallel = true;
};

/// What the extraction did (no timings: the benchmark measures those).
struct MarchingCubesStats {
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  std::size_t edge_vertices = 0;      ///< vertices on grid edges (one per crossed edge)
  std::size_t centroid_vertices = 0;  ///< extra vertices inside ambiguous cubes
  std::size_t active_cells = 0;       ///< cells with both above and below corners
  std::size_t ambiguous_faces = 0;    ///< face decisions taken (counted once per cube side)
  std::size_t tunnels = 0;            ///< cubes given an interior tube (MC33 tunnel cases)
  std::size_t cells = 0;              ///< (nx-1)(ny-1)(nz-1)
  /// True when the surface has no boundary (all samples on the grid's outer faces are on
  /// the same side of the level).
  bool closed = true;
};

/// The surface as plain arrays: what skimage and OpenVDB return, and what the mesh is
/// built from.
struct IsoSurface {
  std::vector<Point> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<Normal> normals;  ///< empty unless compute_normals
  MarchingCubesStats stats;
};

struct MarchingCubesResult {
  SurfaceMesh mesh;
  MarchingCubesStats stats;
};

/// Extract the level set of a grid as arrays.
/// Pre: grid.check() passes (it is called).
/// Throws: InvalidArgument when the grid is malformed (see GridView::check) or a sample is
/// NaN (the message names the first one's x, y, z); the level must be finite.
/// Complexity: one streaming pass over the samples (1 bit per sample kept for two layers at
/// a time), then O(1) per active cell found 64 at a time by bit tests; memory O(surface +
/// nx·ny per thread).
IsoSurface marching_cubes_arrays(const GridView& grid, const MarchingCubesOptions& options = {});

/// Extract the level set as a SurfaceMesh (closed and manifold when `stats.closed`).
/// Throws: as marching_cubes_arrays.
/// Complexity: marching_cubes_arrays plus O(V + F) to link the halfedges.
MarchingCubesResult marching_cubes(const GridView& grid, const MarchingCubesOptions& options = {});

}  // namespace geom
