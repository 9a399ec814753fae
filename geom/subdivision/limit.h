#pragma once
/// \file
/// Internal: limit masks applied to the vertices of a refinement level — OpenSubdiv's
/// PrimvarRefiner::Limit. Smooth and dart vertices use the scheme's eigen-analysis masks
/// (Catmull-Clark: v·(1 − n(e+f)) with f = 1/(n(n+5)), e = 4f on the ring's edge ends and
/// opposite face corners; Loop: 1/(n + 3/(8γ)) on the edge ends), crease vertices the cubic
/// B-spline limit (1/6, 2/3, 1/6) along the crease, corners stay.
///
/// The last level of subdivide() is taken to the limit from its parent's connectivity
/// (limit_children): each child vertex's ring is known from the parent element that made
/// it, so the pass reads and writes in array order instead of walking rings scattered over
/// the level, which is most of its speed.
///
/// Ref: J. Stam, "Exact evaluation of Catmull-Clark subdivision surfaces at arbitrary
/// parameter values", SIGGRAPH 1998; M. Halstead, M. Kass, T. DeRose, "Efficient, fair
/// interpolation using Catmull-Clark surfaces", SIGGRAPH 1993; C. Loop, 1987 (limit and
/// tangent masks); OpenSubdiv Sdc::Scheme limit masks.

#include <geom/subdivision/level.h>

namespace geom::detail::subdiv {

/// Limit positions of the vertices of `l` for data of width w (row-major), and unit limit
/// normals (3 per vertex) from the first three columns when `normals` is non-null: the
/// cross product of OpenSubdiv's limit tangent masks for the vertex's rule (smooth, crease
/// across the faces after its leading sharp edge, corner along its first face), oriented as
/// the faces are. Catmull-Clark masks take the corner two steps after the vertex in each
/// face as its opposite.
void limit_points(const Level& l, const double* src, double* dst, int w, double* normals,
                  const Context& ctx);

/// Limit positions of the vertices of `c`, the refinement of `p`, for data of width w laid
/// out as c's vertices: computed from p's connectivity and c's sharpness, child by child in
/// the order refinement made them (no normals).
void limit_children(const Level& p, const Level& c, const double* src, double* dst, int w,
                    const Context& ctx);

}  // namespace geom::detail::subdiv
