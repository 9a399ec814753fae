"""Mesh compression (geom/compress): the .gmc codec — Edgebreaker-style connectivity,
quantised positions with parallelogram prediction and adaptive rANS coding; see
geom/compress/FORMAT.md for the stream."""

from collections import namedtuple

import numpy as np

from . import _geom
from ._options import make

__all__ = ["compress", "decompress", "decompress_arrays", "DecodedArrays", "Permutation",
           "CompressOptions", "CompressStats"]

CompressOptions = _geom.CompressOptions
CompressStats = _geom.CompressStats

Permutation = namedtuple("Permutation", ["vertices", "faces"])
Permutation.__doc__ = """Input index of each decoded vertex (``vertices``) and face (``faces``),
as int64 numpy arrays: decoded vertex i came from input vertex ``vertices[i]``; indices are
dense (live elements counted in index order)."""

DecodedArrays = namedtuple("DecodedArrays", ["positions", "triangles", "normals", "texcoords",
                                             "corner_normals", "corner_texcoords"])
DecodedArrays.__doc__ = "What decompress_arrays() returns (numpy arrays; see there)."


def compress(mesh, bits=11, level=7, preserve_order=False, precision=None,
             normal_bits=10, texcoord_bits=12, attribute_bits=12, chunk_triangles=131072,
             vertex_origin=None, keep_corner_order=True, keep_triangle_corners=False,
             loose_faces=None, return_permutation=False, return_stats=False):
    """Compress ``mesh`` (triangles and polygons, any number of components, boundaries and
    handles) to .gmc bytes.

    Positions are quantised to ``bits`` bits (1–30) across the largest bounding-box extent,
    or, when ``precision`` is given, to a grid with at most that error per coordinate.
    ``level`` (0–9): higher tries more predictors and traversals and never gives a larger
    stream. ``preserve_order`` keeps the vertex order, face order and each face's first
    corner exactly (at a size cost); otherwise the codec reorders for size. Per-vertex
    normals (octahedral, ``normal_bits`` 2–20, angle error < 4.5 / 2**normal_bits radians)
    and texture coordinates (``texcoord_bits`` 1–30 across the UV box) travel when the mesh
    has them (e.g. loaded from a PLY with nx/ny/nz, s/t); 0 drops them. The same bits apply
    to per-corner normals and texture coordinates (an OBJ with UV seams or normal creases),
    which travel with their seams. Other float / vector vertex properties (colours, PLY
    scalars) are quantised per component to ``attribute_bits`` (1–30; 0 drops them) and come
    back under their names. Face and edge properties are not stored:
    ``return_stats=True`` appends the CompressStats, whose ``dropped_properties`` names them.
    Meshes of at least ``2 * chunk_triangles`` triangles (positions only, order not
    preserved, no split vertices or loose faces, no polygons unless
    ``keep_corner_order=False``) are split into spatial chunks that encode and decode on every core, about 2.5 %
    larger than one stream (``stats.chunks`` says how many); 0 keeps one stream, other
    values must be at least 16384. ``vertex_origin`` (one source vertex index per vertex, as
    ``load_with_report(path).report.vertex_origin``) marks the vertices that loading split
    off a non-manifold edge or vertex: the stream records them as one, and
    ``decompress(data, return_representative=True)`` joins them again.
    ``keep_corner_order`` (default True) keeps every polygon's first corner (faces of 4 or
    more corners: a non-planar polygon's fan triangulation, and so its surface, depends on
    it); False gives the smaller stream of before. ``keep_triangle_corners`` keeps
    triangles' first corners too (their surface does not depend on it; off by default).
    ``loose_faces`` (a list of corner lists over the mesh's vertices) stores faces the mesh
    cannot hold — degenerate, zero-area or duplicate ones that loading dropped — and
    ``decompress(data, return_loose_faces=True)`` returns them.

    Returns the bytes, or ``(bytes, Permutation)`` with ``return_permutation=True`` — the
    permutation is the only way to map decoded elements back to the input when the order
    is not preserved — then the CompressStats with ``return_stats=True``. Raises ValueError (geom.InvalidArgument) for bits, precision or level
    out of range, or non-finite positions.
    """
    options = {"bits": bits, "level": level, "preserve_order": preserve_order,
               "normal_bits": normal_bits, "texcoord_bits": texcoord_bits,
               "attribute_bits": attribute_bits, "chunk_triangles": chunk_triangles,
               "keep_corner_order": keep_corner_order,
               "keep_triangle_corners": keep_triangle_corners}
    if loose_faces is not None:
        options["loose_faces"] = [[int(v) for v in f] for f in loose_faces]
    if vertex_origin is not None:
        options["vertex_origin"] = [int(v) for v in np.asarray(vertex_origin).ravel()]
    if precision is not None:
        if not precision > 0:
            raise _geom.InvalidArgument(f"compress: precision must be positive, got {precision}")
        options["precision"] = precision
    result = _geom.compress(mesh, make(CompressOptions, options))
    out = (result.data,)
    if return_permutation:
        out += (Permutation(result.vertex_permutation, result.face_permutation),)
    if return_stats:
        out += (result.stats,)
    return out if len(out) > 1 else out[0]


def decompress(data, return_representative=False, return_loose_faces=False):
    """Decode .gmc bytes written by compress().

    Returns ``(mesh, permutation)``: ``permutation`` is a Permutation (the identity) when the
    stream was written with ``preserve_order=True`` — the mesh then comes back in input order —
    and None otherwise (the encoder's ``return_permutation`` holds the map then). Every
    position is within the stream's quantisation bound (half a grid step) of the input.
    With ``return_representative=True`` a third item: for a stream written with
    ``vertex_origin`` whose vertices share origins, per mesh vertex the lowest mesh vertex
    that is the same source vertex (``representative[mesh.faces]`` are the source's faces;
    the vertices ``v`` with ``representative[v] == v`` its vertices), else None.

    With ``return_loose_faces=True`` a last item: the faces stored beside the mesh
    (``compress(loose_faces=...)``), a list of corner lists over the mesh's vertices.

    Raises geom.DecodeError (a ValueError) naming the byte offset for data that is not a
    .gmc stream, of an unsupported version, truncated or corrupted.
    """
    result = _geom.decompress(bytes(data))
    perm = None
    if result.order_preserved:
        perm = Permutation(result.vertex_permutation, result.face_permutation)
    out = (result.mesh, perm)
    if return_representative:
        rep = result.vertex_representative
        out += (rep if len(rep) else None,)
    if return_loose_faces:
        out += (result.loose_faces,)
    return out


def decompress_arrays(data):
    """Decode .gmc bytes into numpy arrays only, without building a half-edge mesh: the fast
    path for renderers and numpy code (on a 1M-triangle stream 3× faster than decompress(),
    whose mesh linking dominates).

    Returns a DecodedArrays ``(positions, triangles, normals, texcoords, corner_normals,
    corner_texcoords)``: ``positions`` a
    V×3 float32 array, ``triangles`` a T×3 uint32 array of vertex indices (a polygon comes
    back as triangles over its own corners), ``normals`` V×3 float32 and ``texcoords`` V×2
    float32 when the stream has per-vertex ones, else None; ``corner_normals`` T×3×3 and
    ``corner_texcoords`` T×3×2 float32 (``[t, k]`` belongs to corner k of triangle t) when it
    has per-corner ones (UV seams, normal creases), else None. Vertices are in decoding
    order, the same as decompress()'s mesh unless the stream preserved the input order (this
    path ignores the order section); other properties need decompress(). Vertices that
    compression recorded as split from one (a non-manifold source,
    ``compress(vertex_origin=...)``) come back joined, as in the source.

    Raises geom.DecodeError (a ValueError) naming the byte offset, as decompress().
    """
    arrays = list(_geom.decompress_flat(bytes(data)))
    for k, dims in ((4, 3), (5, 2)):  # per corner: T×3×dims, corner k of triangle t at [t, k]
        if arrays[k] is not None:
            arrays[k] = arrays[k].reshape(-1, 3, dims)
    return DecodedArrays(*arrays)
