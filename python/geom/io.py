"""Reading and writing mesh files (geom/io): OBJ, PLY, OFF, STL and Draco (.drc)."""

import os
import warnings
import weakref

from . import _geom
from ._options import make
from .core import BuildOptions

__all__ = ["load", "load_with_report", "loads", "save", "WriteOptions", "LoadResult",
           "FORMATS"]

WriteOptions = _geom.WriteOptions
LoadResult = _geom.LoadResult
FORMATS = ("obj", "ply", "off", "stl", "drc", "gltf", "glb")


# The material files (OBJ mtllib) of each mesh geom.load returned: a mesh keeps its faces'
# material names only, and geom.save names the files again.
_material_libraries = weakref.WeakKeyDictionary()


def _warn(result, name):
    for line in result.warnings:
        warnings.warn(f"{name}: {line}", UserWarning, stacklevel=3)
    return result


def load_with_report(path, format=None, **build_options):
    """Read a mesh file and build a mesh from it.

    ``format`` is one of FORMATS, or None to judge by the file name and content. Keyword
    options are BuildOptions fields (see :func:`geom.build`). Returns a LoadResult with
    ``.mesh``, ``.report`` (what building changed) and ``.warnings`` (what the reader
    skipped, e.g. a glTF's line primitives; each is also issued as a UserWarning).

    Raises OSError (FileNotFoundError, PermissionError, IsADirectoryError) when the file
    cannot be opened, ValueError (geom.ParseError naming the file and line or byte offset)
    when it is malformed.
    """
    result = _geom.load_mesh(os.fspath(path), format, make(BuildOptions, build_options))
    return _warn(result, os.fspath(path))


def load(path, format=None, **build_options):
    """Read a mesh file: :func:`load_with_report` without the report. The file's material
    files (OBJ mtllib) are remembered for :func:`save` of this mesh."""
    result = load_with_report(path, format, **build_options)
    mesh = result.mesh
    if result.material_libraries:
        _material_libraries[mesh] = list(result.material_libraries)
    return mesh


def loads(data, format, name="<bytes>", **build_options):
    """Read a mesh from ``data`` (bytes) in ``format`` (one of FORMATS); ``name`` is used in
    error messages. Returns a LoadResult."""
    result = _geom.load_mesh_bytes(bytes(data), format, make(BuildOptions, build_options), name)
    return _warn(result, name)


def save(mesh, path, binary=True, format=None, **options):
    """Write ``mesh`` to ``path``; the format comes from the extension unless ``format`` is
    given. ``binary`` selects binary or ASCII PLY/STL (OBJ and OFF are always text). Other
    options (WriteOptions fields): ``attributes`` (write normals/colours/texture coordinates,
    default True), ``drc_position_bits`` (Draco quantisation, 0 = lossless), ``drc_level``,
    ``material_libraries`` (OBJ: the material files to name; by default those of the file
    :func:`load` read ``mesh`` from — a mesh keeps its faces' material names, and a mesh made
    from it, e.g. by simplify, needs them passed).

    What the format cannot hold (polygons in STL/Draco/glTF become triangles, attributes it
    has no place for, UV seams where only per-vertex values are stored) is written without it
    and named in a UserWarning, with counts.

    Raises OSError when the folder does not exist or is not writable, ValueError when the
    extension is unknown or the format cannot hold the data.
    """
    if "material_libraries" not in options and mesh in _material_libraries:
        options["material_libraries"] = _material_libraries[mesh]
    opts = make(WriteOptions, dict(options, binary=binary, format=format))
    for line in _geom.save_mesh(mesh, os.fspath(path), opts):
        warnings.warn(f"{os.fspath(path)}: {line}", UserWarning, stacklevel=2)
