"""geom.load / geom.save / geom.loads: round trips in every format and every error path."""

import os

import numpy as np
import pytest

import geom
from conftest import SAMPLE, TETRAHEDRON_OBJ

QUAD_V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0.5]], float) * 0.1
QUAD_F = [[0, 1, 2, 3], [1, 4, 2]]


def test_load_sample():
    m = geom.load(SAMPLE)
    assert (m.n_vertices, m.n_faces) == (1536, 1632)


def test_load_pathlike_and_str():
    assert geom.load(str(SAMPLE)).n_faces == geom.load(SAMPLE).n_faces


def test_load_with_report():
    r = geom.load_with_report(SAMPLE)
    assert r.mesh.n_faces == 1632 and not r.report.changed()


@pytest.mark.parametrize("name,options", [
    ("m.obj", {}), ("m.ply", {}), ("m_ascii.ply", {"binary": False}), ("m.off", {}),
    ("m.drc", {})])
def test_round_trip_polygons(tmp_path, name, options):
    mesh = geom.Mesh(QUAD_V, QUAD_F)
    path = tmp_path / name
    geom.save(mesh, path, **options)
    back = geom.load(path)
    assert back.n_vertices == 5
    if not name.endswith(".drc"):  # Draco stores triangles
        assert back.faces == QUAD_F
        np.testing.assert_array_equal(back.vertices, QUAD_V)  # lossless, bit for bit
    else:
        assert back.n_faces == 3
        np.testing.assert_allclose(np.sort(back.vertices, axis=0), np.sort(QUAD_V, axis=0),
                                   rtol=1e-6)


@pytest.mark.parametrize("binary", [True, False])
def test_round_trip_stl_triangulates(tmp_path, binary):
    path = tmp_path / "m.stl"
    geom.save(geom.Mesh(QUAD_V, QUAD_F), path, binary=binary)
    back = geom.load(path)
    assert back.n_faces == 3 and back.n_vertices == 5
    assert back.is_triangle_mesh()


def test_save_format_keyword(tmp_path):
    path = tmp_path / "mesh.bin"
    geom.save(geom.load(SAMPLE), path, format="ply")
    assert path.read_bytes().startswith(b"ply")
    assert geom.load(path, format="ply").n_faces == 1632


def test_loads_bytes():
    r = geom.loads(TETRAHEDRON_OBJ.encode(), "obj")
    assert r.mesh.n_faces == 4
    assert r.mesh.analyze().euler_characteristic == 2


def test_load_build_options(tmp_path):
    path = tmp_path / "dup.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 4 6 5\n")
    assert geom.load(path).n_vertices == 6
    assert geom.load(path, weld_tolerance=0.0).n_vertices == 4


# ---- errors ------------------------------------------------------------------------------------

def test_load_missing_file_is_oserror(tmp_path):
    missing = tmp_path / "missing.obj"
    with pytest.raises(FileNotFoundError) as info:
        geom.load(missing)
    assert isinstance(info.value, OSError)
    assert info.value.filename == str(missing)


def test_load_directory_is_oserror(tmp_path):
    with pytest.raises(IsADirectoryError):
        geom.load(tmp_path)


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads every file")
def test_load_unreadable_is_oserror(tmp_path):
    path = tmp_path / "secret.obj"
    path.write_text(TETRAHEDRON_OBJ)
    path.chmod(0)
    with pytest.raises(PermissionError):
        geom.load(path)


def test_malformed_file_is_parse_error(tmp_path):
    path = tmp_path / "broken.obj"
    path.write_text("v 0 0 0\nv 1 0 zero\nf 1 2 3\n")
    with pytest.raises(geom.ParseError) as info:
        geom.load(path)
    assert isinstance(info.value, ValueError)
    assert "broken.obj" in str(info.value)


def test_truncated_binary_is_parse_error(tmp_path):
    path = tmp_path / "t.ply"
    geom.save(geom.load(SAMPLE), path)
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(ValueError, match="t.ply"):
        geom.load(path)


def test_loads_garbage():
    with pytest.raises(ValueError):
        geom.loads(b"ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
                   b"end_header\n", "ply")


def test_unknown_extension(tmp_path):
    with pytest.raises(ValueError, match="xyz"):
        geom.save(geom.load(SAMPLE), tmp_path / "m.xyz")
    path = tmp_path / "m.xyz"
    path.write_text(TETRAHEDRON_OBJ)
    assert geom.load(path).n_faces == 4  # judged by content
    path.write_text("hello, world\n")
    with pytest.raises(ValueError, match="m.xyz"):
        geom.load(path)


def test_unknown_format_name(tmp_path):
    with pytest.raises(ValueError, match="format"):
        geom.save(geom.load(SAMPLE), tmp_path / "m.obj", format="3ds")
    with pytest.raises(ValueError, match="format"):
        geom.loads(b"", "3ds")


def test_save_into_missing_folder_is_oserror(tmp_path):
    with pytest.raises(FileNotFoundError):
        geom.save(geom.load(SAMPLE), tmp_path / "no" / "dir" / "m.obj")


def test_save_onto_directory_is_oserror(tmp_path):
    with pytest.raises(IsADirectoryError):
        geom.save(geom.load(SAMPLE), tmp_path)


def test_unknown_write_option(tmp_path):
    with pytest.raises(TypeError, match="unknown option 'compression'"):
        geom.save(geom.load(SAMPLE), tmp_path / "m.drc", compression=3)


def test_gltf_opens_in_an_independent_reader(tmp_path):
    """A .gltf geom writes is read back here with json + base64 + numpy alone."""
    import base64
    import json

    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    geom.save(geom.Mesh(v, [[0, 1, 2, 3]]), str(tmp_path / "quad.gltf"))
    doc = json.loads((tmp_path / "quad.gltf").read_text())
    assert doc["asset"]["version"] == "2.0"
    uri = doc["buffers"][0]["uri"]
    blob = base64.b64decode(uri.split(",", 1)[1])
    prim = doc["meshes"][0]["primitives"][0]

    def accessor(i, dtype, width):
        acc = doc["accessors"][i]
        view = doc["bufferViews"][acc["bufferView"]]
        start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
        data = np.frombuffer(blob, dtype=dtype, count=acc["count"] * width, offset=start)
        return data.reshape(acc["count"], width)

    pos = accessor(prim["attributes"]["POSITION"], np.float32, 3)
    idx = accessor(prim["indices"], np.uint32, 1).ravel()
    assert np.array_equal(pos, v.astype(np.float32))
    assert len(idx) == 6  # the quad became two triangles
    assert sorted(set(idx.tolist())) == [0, 1, 2, 3]
    back = geom.load(str(tmp_path / "quad.gltf"))
    assert back.n_faces == 2 and back.n_vertices == 4
    geom.save(back, str(tmp_path / "quad.glb"))
    assert (tmp_path / "quad.glb").read_bytes()[:4] == b"glTF"
    assert geom.load(str(tmp_path / "quad.glb")).n_faces == 2
