#pragma once
/// \file
/// Mesh simplification by quadric-error edge collapse.
///
/// Ref: Garland, Heckbert, "Surface Simplification Using Quadric Error Metrics", SIGGRAPH
/// 1997 (metric, boundary constraint planes); Hoppe, "New Quadric Metric for Simplifying
/// Meshes with Appearance Attributes", IEEE Visualization 1999; Dey, Edelsbrunner, Guha,
/// Nekhayev, "Topology Preserving Edge Contraction", 1999 (link condition).

#include <geom/core/soup.h>
#include <geom/core/surface_mesh.h>

#include <cstddef>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace geom {

/// Why simplification stopped.
enum class SimplifyStop {
  kTargetReached,    ///< the face target was met
  kMaxError,         ///< every remaining collapse would exceed max_error
  kNoValidCollapse,  ///< every remaining collapse would break a guarantee (topology,
                     ///< orientation, quality, boundary, locks)
  kCancelled,        ///< the progress callback returned false
};
const char* to_string(SimplifyStop stop);

/// One vertex property taking part in attribute-aware simplification.
struct SimplifyAttribute {
  bool enabled = false;
  /// Weight of its squared deviation (attribute units²) against squared distance in a box of
  /// unit diagonal, per unit area. 0: carried and interpolated but not steering collapses.
  double weight = 1.0;
};

/// Which properties take part (Hoppe's attribute quadric) and are carried to the output.
/// Each comes from the corner property ("h:normal", "h:texcoord") when the mesh has one,
/// else from the vertex property ("v:normal", "v:texcoord", "v:color"); the output carries
/// the same properties. Corners of a vertex with different values are an attribute seam.
struct SimplifyAttributes {
  SimplifyAttribute normals, texcoords, colors;
  bool any() const { return normals.enabled || texcoords.enabled || colors.enabled; }
  /// The enabled ones by the names the CLI and Python use: "normals", "uv", "color".
  std::vector<std::string> names() const;
};

struct SimplifyOptions {
  /// Stop at this many triangles (polygons are fan-triangulated first). 0: use ratio.
  std::size_t target_faces = 0;
  /// Target as a fraction of the input's triangle count, used when target_faces == 0.
  double ratio = 0.5;
  /// Skip collapses whose error (RMS distance to the merged planes, model units; with
  /// attributes, their weighted deviation counts as distance) exceeds this; infinity: no bound.
  double max_error = std::numeric_limits<double>::infinity();
  /// Weight of the constraint planes through boundary edges, relative to the faces' planes:
  /// large keeps boundaries where they are. 0: boundaries are not constrained.
  double boundary_weight = 100.0;
  /// Boundary vertices never move and are never removed.
  bool lock_boundary = false;
  /// Vertices that never move and are never removed (a collapse into them is allowed).
  std::vector<Vertex> locked{};
  /// Reject collapses that leave a triangle with quality 4√3·area/Σ edge² below this (1 for
  /// equilateral, 0 for degenerate), unless it was already worse before.
  double min_triangle_quality = 0.02;
  /// Attribute-aware quadrics: the new vertex's position and attribute values minimise the
  /// combined error; seam vertices only slide along their seam (never off it, never merging
  /// its two sides); normals are renormalised, colours clamped to [0, 1].
  /// Not used by ProgressiveMesh.
  SimplifyAttributes attributes{};
  /// Also take part, at weight 1, every attribute the mesh holds that `attributes` leaves
  /// off (present_attributes()), so that the output keeps what the input had unless asked
  /// otherwise. false: exactly the attributes enabled above (none: the output has none).
  bool keep_attributes = true;
  /// Afterwards, refit the output's vertices to the input surface for this many rounds
  /// (refit.h; Hoppe's fit step): RMS 5–25% lower on the benchmark meshes. Boundary and
  /// locked vertices stay, faces do not flip, and moves that would raise a local Hausdorff
  /// estimate are refused. 0: off. -1 (the default): one round where it is cheap, that is
  /// when the input has at least two vertices per output triangle (a closed mesh kept at
  /// about a quarter or less), so that the input's vertices alone are its samples: on a
  /// 1M-triangle input it then costs 0.15–0.25× the collapses' CPU time (on all cores). Off
  /// above that, where it needs surface samples too and costs 1.2× at 50%. With attributes
  /// it moves positions only: their values stay as the collapses set them, and vertices on
  /// an attribute seam move only along their normal, so that they keep their place on the
  /// seam line (on a UV torus at 10% and 1%, RMS 15–20% lower for 2.5% more UV error; the
  /// seam vertices' move takes the Hausdorff error at 1% 13% lower). ProgressiveMesh (and so
  /// lod_chain) takes -1 as 0 and refuses a positive count: its levels must replay the
  /// collapses exactly.
  int refit_iterations = -1;
  /// Called now and then with the fraction done; return false to stop.
  std::function<bool(double)> progress{};
};

struct SimplifyResult {
  SurfaceMesh mesh;
  std::size_t faces_before = 0;  ///< triangles after fan triangulation of the input
  std::size_t faces_after = 0;
  std::size_t collapses = 0;
  /// The largest error of a performed collapse: RMS distance to the planes merged into the
  /// new vertex (model units). Measure the true surface distance with mesh_distance().
  double max_quadric_error = 0;
  SimplifyStop stop = SimplifyStop::kTargetReached;
  /// Refit rounds run on the result (SimplifyOptions::refit_iterations, -1 resolved).
  int refit_rounds = 0;
  /// Input vertex each output vertex came from (its surviving representative).
  std::vector<Vertex> vertex_origin;
  /// The input's properties the output does not carry (missing_properties()): attributes
  /// left out of the options, and those simplify cannot carry (sharpness tags, scalars).
  std::vector<std::string> dropped_properties;
};

/// `options` with the attributes keep_attributes adds enabled (and keep_attributes false).
SimplifyOptions with_present_attributes(const SurfaceMesh& mesh, SimplifyOptions options);

/// The attributes simplify can carry that the mesh holds (normals and texture coordinates
/// per corner or per vertex, vertex colours), enabled with this weight.
/// Throws: InvalidArgument when weight is negative or not finite.
SimplifyAttributes present_attributes(const SurfaceMesh& mesh, double weight = 1.0);

/// Simplify a mesh by collapsing edges in order of quadric error until the target is met.
/// The result keeps the input's topology: it stays manifold (link condition), keeps its
/// boundary loops, genus and components, no face flips against its previous normal, and
/// no two boundaries are merged. Isolated vertices are dropped. From 50k triangles (with
/// attributes too) the collapses run region by region on all cores, in an order close to, but not
/// the same as, the one-core order; the result is the same on any number of cores.
/// Throws: InvalidArgument when ratio is not in [0, 1] or max_error is negative or NaN, an
/// attribute weight is negative or not finite, an enabled attribute is not on the mesh,
/// refit_iterations is below -1, or a polygon (naming the face) has no fan triangulation
/// whose diagonals are not already edges (any would make the mesh non-manifold).
/// Complexity: O(F log F).
SimplifyResult simplify(const SurfaceMesh& mesh, const SimplifyOptions& options = {});

/// Non-manifold input as given. build() splits a non-manifold vertex into copies, one per
/// fan (BuildReport::vertex_origin names each one's input vertex). Lock the copies
/// (SimplifyOptions::locked = split_copies(origin)) so they stay in place, simplify, and
/// join_split_copies() gives the result as a soup on which the surviving copies of one input
/// vertex are one vertex again: the output keeps the input's non-manifold vertices.
/// Complexity: O(V) each.
std::vector<Vertex> split_copies(std::span<const std::uint32_t> vertex_origin);
/// Throws: InvalidArgument when the result names a vertex beyond `vertex_origin`.
PolygonSoup join_split_copies(const SimplifyResult& result,
                              std::span<const std::uint32_t> vertex_origin);

}  // namespace geom
