"""Levels of detail (geom/lod): quadric simplification, progressive meshes with geomorphs and
the streaming .gpm format, and the sampled surface distance that measures their error."""

import warnings

from . import _geom
from ._options import make

__all__ = ["simplify", "compare", "present_attributes", "ProgressiveMesh", "SimplifyOptions",
           "SimplifyResult", "MeshDistance"]

SimplifyOptions = _geom.SimplifyOptions
SimplifyResult = _geom.SimplifyResult
MeshDistance = _geom.MeshDistance

# The CLI's names, accepted beside the C++ field names.
_ALIASES = {"faces": "target_faces", "keep_boundary": "lock_boundary", "refit": "refit_iterations"}


def _attributes(options, mesh):
    """attributes=("normals", "uv", "color") and attribute_weights=W or {name: W} → the
    binding's {name: weight}. attributes=None (the default): every one ``mesh`` holds;
    attributes=() or "none": none."""
    names = options.pop("attributes", None)
    weights = options.pop("attribute_weights", None)
    options["keep_attributes"] = False
    if names is None:
        names = _geom.present_attributes(mesh)
    elif isinstance(names, str):
        names = [] if names == "none" else [names]
    else:
        names = list(names)
    if isinstance(weights, dict):
        unknown = set(weights) - set(names)
        if unknown:
            raise _geom.InvalidArgument(f"simplify: weights for attributes not asked for or not on the mesh: {sorted(unknown)}")
        options["attributes"] = {n: float(weights.get(n, 1.0)) for n in names}
    else:
        options["attributes"] = {n: 1.0 if weights is None else float(weights) for n in names}


def _options(options, base_ratio, mesh):
    options = {_ALIASES.get(k, k): v for k, v in options.items()}
    _attributes(options, mesh)
    if "ratio" in options and options.get("target_faces"):
        raise _geom.InvalidArgument("simplify: give ratio or faces, not both")
    if "ratio" not in options:
        # A face count or an error bound alone decides where to stop, as in the CLI.
        given = options.get("target_faces") or "max_error" in options
        options["ratio"] = 0.0 if given else base_ratio
    return make(SimplifyOptions, options)


def simplify(mesh, **options):
    """Reduce ``mesh`` by quadric-error edge collapses (polygons are fan-triangulated first).

    Stop at ``ratio`` (fraction of the input's triangles, default 0.5), ``faces`` (alias of
    ``target_faces``) or ``max_error`` (model units; alone, it simplifies as far as the bound
    allows). Other options (SimplifyOptions fields): ``keep_boundary`` (alias of
    ``lock_boundary``: boundary vertices never move), ``boundary_weight`` (default 100),
    ``locked`` (vertex indices that never move), ``min_triangle_quality`` (default 0.02),
    ``refit`` (alias of ``refit_iterations``: rounds of refitting the output's vertices to
    the input surface afterwards, for lower error; default -1, automatic: one round when
    keeping about a quarter of the faces or less, where it costs 0.15-0.25x the collapses'
    time, none above that, where it would cost 1.2x; 0 = off).

    The collapses are attribute-aware (Hoppe's quadric) for every attribute the mesh holds:
    its normals, texture coordinates and colours (per vertex, or per corner as OBJ's vt/vn
    load) steer placement and are interpolated into the output, seams kept.
    ``attributes=("normals", "uv", "color")`` names which (``()`` or ``"none"``: none, and the
    output has none); ``attribute_weights`` is one weight for all (default 1.0) or a dict per
    name. What the output does not carry (attributes left out, sharpness tags, scalars) is
    named in ``.dropped_properties`` and in a UserWarning.

    The result stays manifold, keeps boundary loops and genus, and flips no face. Returns a
    SimplifyResult with ``.mesh``, ``.faces_before``, ``.faces_after``, ``.collapses``,
    ``.max_quadric_error`` (model units), ``.refit_rounds`` (refit rounds run), ``.stop``
    (why it stopped) and ``.vertex_origin``
    (the input vertex of each output vertex). Measure the surface error with compare().

    Raises ValueError (geom.InvalidArgument) for a ratio outside [0, 1], both ratio and
    faces, or a negative max_error; TypeError for an unknown option.
    """
    result = _geom.simplify(mesh, _options(options, 0.5, mesh))
    if result.dropped_properties:
        warnings.warn("simplify: not carried to the output: " + ", ".join(result.dropped_properties),
                      UserWarning, stacklevel=2)
    return result


def present_attributes(mesh):
    """The attributes of ``mesh`` that simplify() keeps by default, by the names its
    ``attributes`` option takes: a list of "normals", "uv" and "color"."""
    return _geom.present_attributes(mesh)


def compare(a, b, samples=200000, seed=1):
    """Symmetric Hausdorff and RMS distance between the surfaces of meshes ``a`` and ``b`` by
    dense area-weighted sampling (``samples`` per direction), as ``geom compare`` prints.

    Returns a MeshDistance with ``.hausdorff``, ``.rms``, ``.diagonal``,
    ``.relative_hausdorff``, ``.relative_rms`` and the one-sided ``.a_to_b`` / ``.b_to_a``.
    Raises ValueError when exactly one mesh has no faces.
    """
    return _geom.compare(a, b, samples, seed)


ProgressiveMesh = _geom.ProgressiveMesh
_compiled_init = ProgressiveMesh.__init__


def _progressive_init(self, mesh, **options):
    _compiled_init(self, mesh, _options(options, 0.0, mesh))
    dropped = _geom.missing_properties(mesh, _geom.Mesh())
    if dropped:
        warnings.warn("ProgressiveMesh holds positions only; not kept: " + ", ".join(dropped),
                      UserWarning, stacklevel=2)


# Patched onto the compiled class (not a Python subclass) so that load() and decode(), which
# the C++ side constructs, return the same type.
ProgressiveMesh.__init__ = _progressive_init
ProgressiveMesh.__doc__ = """A base mesh plus the vertex splits that refine it back to ``mesh`` exactly.

    ``ProgressiveMesh(mesh, **options)`` records the collapse sequence of simplify() with the
    same options (default: as coarse as the guarantees allow); it starts at full resolution.
    ``refine_to(n)`` / ``coarsen_to(n)`` / ``set_level(n)`` move to ``n`` vertices;
    ``n_vertices``, ``n_faces``, ``base_vertices``, ``max_vertices``, ``faces_at(n)``,
    ``vertices_for_faces(f)`` describe the levels; ``positions`` (V×3) and ``faces`` (F×3)
    are numpy copies of the current level, ``mesh()`` a geom.Mesh.
    ``geomorph(coarse, fine, t)`` returns (positions, faces) of the fine level's faces with
    positions interpolated towards the coarse level (t=0 looks exactly like ``coarse``, t=1
    is ``fine``). ``vertex_origin`` / ``face_origin`` map the full level back to the input.
    ``save(path)`` / ``ProgressiveMesh.load(path, allow_partial=False)`` and
    ``encode()`` / ``decode(bytes)`` use the streaming .gpm format.

    Raises ValueError (geom.InvalidArgument) for a level outside [base_vertices,
    max_vertices] or on the wrong side of the current one, t outside [0, 1]; geom.DecodeError
    for a truncated or corrupted stream; OSError when a file cannot be opened.
"""
