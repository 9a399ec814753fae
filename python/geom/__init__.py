"""geom: polygon mesh processing.

    >>> import geom, numpy as np
    >>> mesh = geom.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), [[0, 1, 2]])
    >>> mesh.analyze().boundary_loops
    1
    >>> geom.save(mesh, "triangle.ply")
    >>> geom.load("triangle.ply").n_faces
    1

Functions take meshes (geom.Mesh) and keyword options named like the C++ options' fields, and
return result objects with the C++ results' field names. Errors: ValueError (or its subclasses
geom.ParseError, geom.TopologyError, geom.InvalidArgument, geom.DecodeError) with the library's
message; OSError when a file cannot be opened. Long work releases the GIL.
"""

import importlib as _importlib

__version__ = "0.1.0"

# One entry per capability: the module python/geom/<capability>.py, whose __all__ names are
# re-exported here.
_SUBMODULES = (
    "core",
    "io",
    "isosurface",
    "render",
    "compgeom",
    "subdivision",
    "lod",
    "compress",
    "batch",
)

__all__ = []
for _name in _SUBMODULES:
    _module = _importlib.import_module("." + _name, __name__)
    globals().update({_n: getattr(_module, _n) for _n in _module.__all__})
    __all__ += list(_module.__all__)
del _name, _module
