"""Meshes, building them from arrays, and checking them (geom/core)."""

from . import _geom
from ._options import make

__all__ = [
    "Mesh", "build", "analyze", "validate",
    "BuildOptions", "BuildReport", "BuildResult", "TopologyReport", "ComponentTopology",
    "ValidationReport",
    "Error", "ParseError", "TopologyError", "InvalidArgument", "DecodeError",
]

Mesh = _geom.Mesh
Mesh.__doc__ = """A half-edge polygon mesh (triangles, quads and n-gons mixed).

    Mesh()                          an empty mesh
    Mesh(vertices, faces, **build)  from arrays: ``vertices`` V×3 (float64 or convertible),
                                    ``faces`` an F×k integer array for uniform faces or a list
                                    of index lists for mixed polygons. The mesh is built with
                                    :func:`build`'s options (keyword names as in BuildOptions);
                                    use :func:`build` to also get the report of what changed.

    Attributes: ``vertices`` (V×3 float64 array, a copy), ``faces`` (F×k int64 array when all
    faces have k corners, otherwise a list of lists), ``n_vertices``, ``n_edges``,
    ``n_halfedges``, ``n_faces``, ``is_empty``. Methods: ``analyze()``, ``validate()``,
    ``copy()``, ``is_triangle_mesh()``, ``is_quad_mesh()``.

    Raises ValueError (geom.InvalidArgument) for arrays of the wrong shape, non-finite
    coordinates, faces with fewer than 3 corners or indices outside [0, V).
"""

BuildOptions = _geom.BuildOptions
BuildReport = _geom.BuildReport
BuildResult = _geom.BuildResult
TopologyReport = _geom.TopologyReport
ComponentTopology = _geom.ComponentTopology
ValidationReport = _geom.ValidationReport
Error = _geom.Error
ParseError = _geom.ParseError
TopologyError = _geom.TopologyError
InvalidArgument = _geom.InvalidArgument
DecodeError = _geom.DecodeError


def build(vertices, faces, **options):
    """Build a mesh from arrays, repairing what is wrong, and report every change.

    ``vertices`` and ``faces`` as for :class:`Mesh`. Options (BuildOptions fields):

    - ``policy``: ``"repair"`` (default: keep every face that can be kept) or ``"strict"``
      (raise geom.TopologyError naming the first offending face);
    - ``weld_tolerance``: weld vertices closer than this × the bounding-box diagonal
      (negative, the default: no welding; 0: exact duplicates only);
    - ``orient``: flip faces to agree with their neighbours (default True);
    - ``drop_unreferenced``: drop vertices no face uses (default False).

    Returns a BuildResult with ``.mesh`` and ``.report`` (a BuildReport: welded_vertices,
    dropped_degenerate, flipped_faces, …, messages, and face_origin/vertex_map arrays).
    """
    return _geom.build(vertices, faces, make(BuildOptions, options))


def analyze(mesh, faces=None):
    """``analyze(mesh)``: the topology of a Mesh. ``analyze(vertices, faces)``: the topology of
    the polygons as given (before any repair: non-manifold edges and vertices, one-sided
    surfaces and degenerate faces are counted, not fixed).

    Returns a TopologyReport with vertices, edges, faces, boundary_loops,
    components, euler_characteristic, genus (None unless an orientable manifold), closed,
    manifold, orientable, face_sizes ({corners: count}), bounds ((min, max) or None) and
    per_component. geom uses the surface form χ = V − E + F = 2(C − G) − H."""
    if faces is not None:
        return _geom.analyze_arrays(mesh, faces)
    return _geom.analyze(mesh)


def validate(mesh, max_problems=100):
    """Check the half-edge invariants of ``mesh``. Returns a ValidationReport with ``ok`` and
    ``problems`` (one line per broken invariant, naming the element)."""
    return _geom.validate(mesh, max_problems)
