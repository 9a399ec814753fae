#pragma once
/// \file
/// Internal: smooth face-varying refinement, OpenSubdiv's FVAR_LINEAR_BOUNDARIES. Inside a
/// UV island (corners whose values agree across every edge) face-varying data follows the
/// vertex rules, creases included; along seams and mesh boundaries it is linear, and every
/// vertex on a seam or boundary keeps its values. That is exactly vertex refinement of the
/// mesh cut open along its seams, with the cut's vertices made corners, so that is how it
/// is computed: the cut mesh is refined by the ordinary path and its face corners are read
/// back (child faces and their corners are numbered identically in both meshes). Taking
/// the cut mesh to the limit is OpenSubdiv's LimitFaceVarying for the same reason.

#include <geom/core/surface_mesh.h>
#include <geom/subdivision/subdivision.h>

#include <vector>

namespace geom::detail::subdiv {

/// Rows of width w per halfedge of `refined` (zero on boundary halfedges) for the rows per
/// halfedge of `mesh` (the value at the corner the halfedge ends at), refined with
/// `options` (its levels, scheme, boundary, crease method and limit). Corners of one
/// vertex share a value when their rows are equal (OpenSubdiv shares value indices).
/// Throws: InvalidArgument when asked for the limit at levels = 0.
/// Pre: `mesh` has no garbage, `refined` is `mesh` refined with `options`.
std::vector<double> refine_face_varying_smooth(const SurfaceMesh& mesh, const double* rows,
                                               int w, const SubdivideOptions& options,
                                               const SurfaceMesh& refined);

}  // namespace geom::detail::subdiv
