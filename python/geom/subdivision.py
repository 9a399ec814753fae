"""Subdivision surfaces (geom/subdivision): Catmull-Clark and Loop with OpenSubdiv's rules."""

import warnings

from . import _geom
from ._options import make

__all__ = ["subdivide", "limit_positions", "SubdivideOptions", "SubdivideResult",
           "SoupSubdivideResult", "LimitOptions", "LimitResult"]

SubdivideOptions = _geom.SubdivideOptions
SubdivideResult = _geom.SubdivideResult
SoupSubdivideResult = _geom.SoupSubdivideResult
LimitOptions = _geom.LimitOptions
LimitResult = _geom.LimitResult


def subdivide(mesh, faces=None, creases=None, corners=None, **options):
    """Refine ``mesh`` uniformly; the numbers are OpenSubdiv's, vertex for vertex.

    ``subdivide(vertices, faces, ...)`` (a V×3 array and an F×k array or a list of index
    lists) refines the faces as given, as OpenSubdiv does: non-manifold edges and vertices,
    faces that disagree on orientation, repeated corners, duplicate and zero-area faces are
    refined, none dropped or repaired (non-manifold elements are infinitely sharp). It
    returns a SoupSubdivideResult with ``.vertices`` (in OpenSubdiv's order: face-points,
    edge-points, vertex-points), ``.faces``, ``.per_level``, and what the input held:
    ``.nonmanifold_edges``, ``.nonmanifold_vertices``, ``.degenerate_edges`` (vertex to
    itself), ``.split_vertices`` (copies made for the half-edge core and joined again),
    ``.opened_edges`` (smooth edges the split had to open; the result differs from
    OpenSubdiv's next to them, and a UserWarning says so).

    Options (SubdivideOptions fields): ``scheme`` ('catmull-clark', the default, or 'loop',
    which needs triangles), ``levels`` (default 1, 0 to 10), ``boundary`` ('edges', the
    default, 'corners' to keep one-face corners in place, or 'none'), ``crease_method``
    ('uniform' or 'chaikin'), ``face_varying`` (texture coordinates and other corner data:
    'linear', the default, or 'smooth' inside each UV island and linear along seams, as
    OpenSubdiv's FVAR_LINEAR_BOUNDARIES), ``limit`` (push the final vertices onto the limit
    surface),
    ``crease_angle`` (degrees: sharper dihedral angles become infinitely sharp creases),
    ``parallel`` (default True).

    ``creases``: an N×3 array of (vertex a, vertex b, sharpness) rows, one per edge;
    ``corners``: an N×2 array of (vertex, sharpness). Sharpness 0 is smooth, 10 or more
    infinitely sharp, values between decay by one per level. Vertices are numbered as in
    ``mesh.vertices``. Creases already on the mesh (read from OBJ ``t crease`` tags) are kept.

    Returns a SubdivideResult with ``.mesh``, ``.levels``, ``.per_level`` (counts),
    ``.angle_creased_edges`` and, with ``limit``, ``.limit_max_distance`` /
    ``.limit_rms_distance`` (how far the vertices moved onto the limit surface).

    Raises ValueError (geom.TopologyError) for a non-manifold vertex, (geom.InvalidArgument)
    for Loop on non-triangles, bad options, or a crease row that names no edge.
    """
    if faces is not None:
        result = _geom.subdivide_soup(mesh, faces, make(SubdivideOptions, options), creases,
                                      corners)
        if result.opened_edges:
            warnings.warn(f"subdivide: {result.opened_edges} smooth edges had to be opened to "
                          "split non-manifold input; next to them the result differs from "
                          "OpenSubdiv's", UserWarning, stacklevel=2)
        return result
    return _geom.subdivide(mesh, make(SubdivideOptions, options), creases, corners)


def limit_positions(mesh, **options):
    """Limit positions (and with ``normals=True`` unit normals) of the vertices of ``mesh``
    taken as a control mesh. Options: ``scheme`` ('catmull-clark' needs quads, 'loop'
    triangles — subdivide once first otherwise), ``boundary``, ``normals``.

    Returns a LimitResult with ``.positions`` (V×3), ``.normals`` (V×3 or None),
    ``.max_distance`` and ``.rms_distance`` (how far the vertices are from their limits).
    """
    return _geom.limit_positions(mesh, make(LimitOptions, options))
