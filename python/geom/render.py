"""Pictures (geom/render): a preview renderer that does only what the scene asks for."""

import os

from . import _geom

__all__ = ["render", "RenderStats"]

RenderStats = _geom.RenderStats


def render(mesh_or_scene, size=None, wireframe=False, shadows=False, samples=None, flat=False,
           raytrace=False, ground=False, return_stats=False):
    """Render a geom.Mesh, or a JSON scene file (a path; see geom/render/SCENE.md), to an
    H×W×3 uint8 numpy array.

    ``size`` is (width, height) (default 800×600, or the scene's). The image is rasterised
    unless something needs rays: ``shadows=True`` (the key light casts shadows onto a ground
    plane) or a scene with shadowed lights or mirror materials; ``raytrace=True`` forces rays.
    ``wireframe`` overlays polygon edges; ``flat`` uses face normals (no vertex normals are
    computed); ``samples`` per pixel (rounded to a square, default 4).

    With ``return_stats=True`` returns (image, RenderStats): the path taken, whether a BVH was
    built, ray counts and seconds per stage.

    Raises ValueError (geom.ParseError) for a malformed scene, naming the key; OSError when a
    file cannot be opened.
    """
    args = (None if size is None else (int(size[0]), int(size[1])), bool(wireframe),
            bool(shadows), None if samples is None else int(samples), bool(flat),
            bool(raytrace), bool(ground))
    if isinstance(mesh_or_scene, (str, os.PathLike)):
        image, stats = _geom.render_scene(os.fspath(mesh_or_scene), *args)
    else:
        image, stats = _geom.render_mesh(mesh_or_scene, *args)
    return (image, stats) if return_stats else image
