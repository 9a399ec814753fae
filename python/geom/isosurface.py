"""Iso-surfaces (geom/isosurface): watertight marching cubes on numpy volumes and functions."""

import numpy as np

from . import _geom
from ._options import make

__all__ = ["marching_cubes", "isosurface", "signed_distance_grid", "mesh_isosurface",
           "MarchingCubesOptions", "MarchingCubesStats",
           "IsoSurface"]

MarchingCubesOptions = _geom.MarchingCubesOptions
MarchingCubesStats = _geom.MarchingCubesStats
IsoSurface = _geom.IsoSurface


def marching_cubes(volume, level=0.0, spacing=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0),
                   **options):
    """Extract the surface where ``volume`` equals ``level``.

    ``volume[i, j, k]`` is the sample at ``origin + (i, j, k) * spacing`` (scikit-image's
    convention). C- or Fortran-contiguous float32/float64 arrays are used without a copy;
    other arrays are converted to float64 once. A sample equal to ``level`` counts as above
    it, so integer volumes give closed surfaces.

    Options (MarchingCubesOptions fields): ``normals_toward`` ('increasing', the default, or
    'decreasing': the side the triangles face), ``compute_normals`` (vertex normals from the
    field gradient, default False), ``parallel`` (default True).

    Returns an IsoSurface with ``.vertices`` (V×3 float64), ``.faces`` (F×3 int64),
    ``.normals`` (V×3, or None unless asked), ``.stats`` (counts; ``.stats.closed``) and
    ``.to_mesh()`` (a geom.Mesh). The surface is manifold and consistently oriented, and closed
    when the level set does not reach the volume's border.

    Raises ValueError (geom.InvalidArgument) for a non-3-D volume, a NaN sample (the message
    names its grid index, x being the axis that varies fastest in memory), a non-positive
    spacing or a non-finite level.
    """
    opts = make(MarchingCubesOptions, options)
    opts.level = float(level)
    return _geom.marching_cubes(volume, tuple(float(s) for s in spacing),
                                tuple(float(o) for o in origin), opts)


def isosurface(function, bounds, resolution, level=0.0, **options):
    """Sample a vectorised ``function(x, y, z)`` (numpy arrays in, an array of the same shape
    out) on a grid over ``bounds = ((xmin, ymin, zmin), (xmax, ymax, zmax))`` with
    ``resolution`` samples per axis (an int or three ints), then run :func:`marching_cubes`.
    Returns an IsoSurface in world coordinates.
    """
    lo = np.asarray(bounds[0], dtype=float)
    hi = np.asarray(bounds[1], dtype=float)
    n = np.broadcast_to(np.asarray(resolution, dtype=int), (3,))
    if np.any(n < 2):
        raise ValueError(f"resolution must be at least 2 per axis, got {tuple(n)}")
    if lo.shape != (3,) or hi.shape != (3,) or np.any(~(hi > lo)):
        raise ValueError(f"bounds must be (min, max) corners with max > min, got {bounds}")
    axes = [np.linspace(lo[k], hi[k], n[k]) for k in range(3)]
    x, y, z = np.meshgrid(*axes, indexing="ij")
    values = np.asarray(function(x, y, z), dtype=float)
    if values.shape != x.shape:
        raise ValueError(f"function returned shape {values.shape}, expected {x.shape}")
    spacing = (hi - lo) / (n - 1)
    return marching_cubes(values, level, spacing, lo, **options)


def signed_distance_grid(mesh, resolution=128, level=0.0, exact_everywhere=False):
    """Sample the signed distance to the closed ``mesh`` (a geom.Mesh; negative inside) on a
    grid around it: its bounding box plus max(level, 0) + 3 cells per side, cubic cells,
    ``resolution`` samples along the longest axis.

    Samples within |level| + 3 cells of the surface are exact; farther ones have the right
    sign and a lower bound of the distance (one query per 8³ block), unless
    ``exact_everywhere``. Returns ``(volume, spacing, origin, stats)`` with ``volume[i, j, k]``
    at ``origin + (i, j, k) * spacing`` (float32), ready for :func:`marching_cubes`.

    Raises ValueError when the mesh is open or empty (an open surface has no inside; the
    message names a boundary edge) or the resolution is outside [8, 4096].
    """
    return _geom.signed_distance_grid(mesh, int(resolution), float(level), bool(exact_everywhere))


def mesh_isosurface(mesh, resolution=128, level=0.0, **options):
    """The ``level`` iso-surface of the signed distance to the closed ``mesh``: a voxel
    remesh at level 0, an offset surface for level > 0, an inset for level < 0. Same options
    and result as :func:`marching_cubes`.
    """
    volume, spacing, origin, _ = signed_distance_grid(mesh, resolution, level)
    return marching_cubes(volume, level, spacing, origin, **options)
