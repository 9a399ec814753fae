"""Computational geometry (geom/compgeom): Delaunay, Voronoi and convex hulls on numpy arrays,
every geometric decision by exact predicates."""

import numpy as np

from . import _geom
from ._options import make

__all__ = ["delaunay", "voronoi", "convex_hull", "DelaunayOptions"]

DelaunayOptions = _geom.DelaunayOptions


def delaunay(points, segments=None, **options):
    """Delaunay triangulation of an N×2 array of points.

    ``segments`` (optional, M×2 point indices) are forced in as constrained edges (a
    constrained Delaunay triangulation; a segment through an input point is split there).
    Options (DelaunayOptions fields): ``exact`` (default True; False uses plain floating-point
    predicates, to measure what exactness costs).

    Returns a DelaunayResult with ``.triangles`` (T×3 int64, counter-clockwise, indices into
    ``points``), ``.vertex_of`` (the representative of each point: repeated points merge into
    their first copy), ``.vertices``, ``.duplicates``, ``.collinear`` (then ``.chain`` lists the
    points along the line), ``.cocircular``, ``.constrained_edges``, ``.split_segments`` and
    ``.exact_fallback_rate``.

    Raises ValueError (geom.InvalidArgument) for NaN/infinite coordinates (naming the point),
    bad segment indices, or crossing segments (naming both).
    """
    return _geom.delaunay_2d(points, segments, make(DelaunayOptions, options))


def voronoi(points, clip=None, margin=0.1):
    """Voronoi cells of an N×2 array of points, each clipped to ``clip`` (a convex polygon as
    a K×2 array, counter-clockwise, or a box ``(xmin, ymin, xmax, ymax)``); by default the
    bounding box grown by ``margin`` of its size. Returns a VoronoiResult with ``.cells`` (a
    list of K×2 arrays, one per input point; empty for repeated points), ``.clip`` and
    ``.vertex_of``. The cells tile the clip region.
    """
    if clip is not None:
        c = np.asarray(clip, dtype=float)
        if c.shape == (4,):
            x0, y0, x1, y1 = c
            c = np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]])
        clip = c
    return _geom.voronoi_2d(points, clip, float(margin))


def convex_hull(points):
    """Convex hull of an N×2 or N×3 array of points.

    2D: a Hull2Result with ``.vertices`` (counter-clockwise extreme points; points on edges
    and repeated copies excluded) and ``.degenerate``. 3D: a Hull3Result with ``.triangles``
    (outward, counter-clockwise seen from outside), ``.vertices`` (extreme points), and for
    coplanar input ``.planar`` with ``.polygon``; ``.dimension`` is the input's affine
    dimension.
    """
    p = np.asarray(points, dtype=float)
    if p.ndim == 2 and p.shape[1] == 2:
        return _geom.convex_hull_2d(p)
    if p.ndim == 2 and p.shape[1] == 3:
        return _geom.convex_hull_3d(p)
    raise ValueError(f"points: expected an N×2 or N×3 array, got shape {p.shape}")
