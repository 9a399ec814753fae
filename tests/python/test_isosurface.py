"""geom.marching_cubes / geom.isosurface from Python: axis convention, zero-copy dtypes,
closed output on integer volumes, and the error paths."""

import numpy as np
import pytest

import geom


def edge_counts(faces):
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    keys = directed[:, 0] * (1 << 32) + directed[:, 1]
    rev = directed[:, 1] * (1 << 32) + directed[:, 0]
    unique, counts = np.unique(keys, return_counts=True)
    return int((counts > 1).sum()), int((~np.isin(rev, keys)).sum())


def sphere_volume(n, dtype=np.float32, order="C"):
    ax = np.linspace(-1, 1, n)
    x, y, z = np.meshgrid(ax, ax, ax, indexing="ij")
    v = np.sqrt((x - 0.2) ** 2 + y ** 2 + z ** 2) - 0.6
    return np.asarray(v, dtype=dtype, order=order)


@pytest.mark.parametrize("dtype", [np.float32, np.float64, np.int16])
@pytest.mark.parametrize("order", ["C", "F"])
def test_sphere_is_closed_in_volume_index_coordinates(dtype, order):
    vol = sphere_volume(40, np.float64, order)
    if dtype == np.int16:
        vol = np.asarray(np.round(vol * 1000), dtype=dtype, order=order)
    else:
        vol = np.asarray(vol, dtype=dtype, order=order)
    s = geom.marching_cubes(vol, spacing=(2 / 39,) * 3, origin=(-1, -1, -1))
    repeated, open_edges = edge_counts(s.faces)
    assert repeated == 0 and open_edges == 0
    assert s.stats.closed
    # volume[i, j, k] sits at origin + (i, j, k) * spacing: the centre is at x = +0.2.
    centre = s.vertices.mean(axis=0)
    assert abs(centre[0] - 0.2) < 0.02 and abs(centre[1]) < 0.02 and abs(centre[2]) < 0.02
    r = np.linalg.norm(s.vertices - [0.2, 0, 0], axis=1)
    assert np.abs(r - 0.6).max() < 0.01
    # Outward (increasing values): positive signed volume.
    a, b, c = (s.vertices[s.faces[:, k]] for k in range(3))
    assert np.einsum("ij,ij->i", a, np.cross(b, c)).sum() > 0
    mesh = s.to_mesh()
    assert mesh.n_faces == len(s.faces)


def test_integer_volume_with_level_on_samples_is_watertight():
    rng = np.random.default_rng(5)
    vol = np.zeros((16, 15, 14), np.uint8)
    vol[1:-1, 1:-1, 1:-1] = rng.integers(0, 3, size=(14, 13, 12))
    s = geom.marching_cubes(vol, level=1, normals_toward="decreasing")
    repeated, open_edges = edge_counts(s.faces)
    assert repeated == 0 and open_edges == 0
    assert len(np.unique(s.vertices, axis=0)) == len(s.vertices)


def test_isosurface_of_a_callable_and_normals():
    s = geom.isosurface(lambda x, y, z: x * x + y * y + z * z - 0.25, ((-1, -1, -1), (1, 1, 1)), 32,
                        compute_normals=True)
    assert s.normals.shape == s.vertices.shape
    dots = np.einsum("ij,ij->i", s.normals, s.vertices / np.linalg.norm(s.vertices, axis=1)[:, None])
    assert dots.min() > 0.95
    assert geom.isosurface(lambda x, y, z: x - 0.5, ((0, 0, 0), (1, 1, 1)), 4).normals is None


def test_empty_and_errors():
    s = geom.marching_cubes(np.zeros((4, 4, 4), np.float32) - 1)
    assert s.faces.shape == (0, 3) and s.vertices.shape == (0, 3)
    vol = sphere_volume(10)
    vol[2, 3, 4] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        geom.marching_cubes(vol)
    with pytest.raises(ValueError):
        geom.marching_cubes(np.zeros((4, 4)))
    with pytest.raises(ValueError):
        geom.marching_cubes(sphere_volume(8), spacing=(1, 0, 1))
    with pytest.raises(ValueError):
        geom.marching_cubes(sphere_volume(8), level=float("inf"))
    with pytest.raises(ValueError):
        geom.marching_cubes(sphere_volume(8), normals_toward="up")
    with pytest.raises(TypeError):
        geom.marching_cubes(sphere_volume(8), smooth=True)
    with pytest.raises(ValueError):
        geom.isosurface(lambda x, y, z: x, ((0, 0, 0), (1, 1, 1)), 1)


def cube_mesh(h=0.5):
    corners = np.array([[(c & 1) * 2 * h - h, (c >> 1 & 1) * 2 * h - h, (c >> 2 & 1) * 2 * h - h]
                        for c in range(8)], float)
    quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    tris = [[q[0], q[1], q[2]] for q in quads] + [[q[0], q[2], q[3]] for q in quads]
    return geom.Mesh(corners, np.array(tris))


def box_sdf(p, h=0.5):
    q = np.abs(p) - h
    return np.linalg.norm(np.maximum(q, 0), axis=-1) + np.minimum(q.max(axis=-1), 0)


def test_signed_distance_grid_of_a_cube_is_exact_and_feeds_marching_cubes():
    volume, spacing, origin, stats = geom.signed_distance_grid(cube_mesh(), 24, exact_everywhere=True)
    assert volume.dtype == np.float32 and volume.shape == (24, 24, 24)
    assert stats["exact_samples"] == stats["samples"] == 24 ** 3
    idx = np.indices(volume.shape).reshape(3, -1).T
    points = np.asarray(origin) + idx * np.asarray(spacing)
    want = box_sdf(points)
    assert np.abs(volume.reshape(-1) - want).max() < 1e-6
    s = geom.marching_cubes(volume, 0.0, spacing, origin)
    repeated, open_edges = edge_counts(s.faces)
    assert repeated == 0 and open_edges == 0
    # Exact on the faces; marching cubes cuts the cube's edges by less than a cell.
    assert np.abs(box_sdf(s.vertices)).max() < 0.5 * spacing[0]


def test_mesh_isosurface_offsets_a_sphere_mesh():
    sphere = geom.isosurface(lambda x, y, z: np.sqrt(x * x + y * y + z * z) - 0.7,
                             ((-1, -1, -1), (1, 1, 1)), 48).to_mesh()
    for level in (0.0, 0.2, -0.2):
        s = geom.mesh_isosurface(sphere, 40, level)
        repeated, open_edges = edge_counts(s.faces)
        assert repeated == 0 and open_edges == 0
        r = np.linalg.norm(s.vertices, axis=1)
        assert np.abs(r - (0.7 + level)).max() < 0.015
        assert s.stats.closed


def test_signed_distance_of_an_open_mesh_is_an_error():
    triangle = geom.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), [[0, 1, 2]])
    with pytest.raises(ValueError, match="closed mesh.*3 boundary edges"):
        geom.signed_distance_grid(triangle, 16)
    with pytest.raises(ValueError, match="resolution"):
        geom.signed_distance_grid(cube_mesh(), 4)


def test_cli_sdf_offset_and_errors(run, meshes, tmp_path):
    out = tmp_path / "offset.ply"
    r = run("isosurface", "--sdf", meshes["tetrahedron"], "--resolution", "40", "--level", "0.1",
            "-o", out, "--json")
    assert r.returncode == 0, r.stderr
    import json
    stats = json.loads(r.stdout)
    assert stats["closed"] and stats["euler_characteristic"] == 2
    assert stats["signed_distance"]["exact_samples"] < stats["signed_distance"]["samples"]
    assert geom.load(out).n_faces == stats["triangles"]
    r = run("isosurface", "--sdf", meshes["triangle"], "--resolution", "16", "-o", tmp_path / "x.ply")
    assert r.returncode == 1
    assert "triangle.obj" in r.stderr and "closed mesh" in r.stderr
    r = run("isosurface", "--sdf", meshes["tetrahedron"], "--implicit", "sphere", "-o", out)
    assert r.returncode == 2


def test_cli_implicit_torus_and_nan_grid(run, tmp_path):
    import json
    r = run("isosurface", "--implicit", "torus", "--resolution", "48", "-o", tmp_path / "t.ply", "--json")
    assert r.returncode == 0, r.stderr
    stats = json.loads(r.stdout)
    assert stats["closed"] and stats["euler_characteristic"] == 0 and "tunnels" in stats
    vol = sphere_volume(8)
    vol[1, 2, 3] = np.nan
    np.save(tmp_path / "nan.npy", vol)
    r = run("isosurface", tmp_path / "nan.npy", "-o", tmp_path / "n.ply")
    assert r.returncode == 1 and "NaN" in r.stderr


def test_cli_empty_grid_is_refused_by_name(run, tmp_path):
    # NumPy writes empty arrays; before, a zero in the shape was mistaken for a short file.
    np.save(tmp_path / "empty.npy", np.zeros((2, 3, 0), dtype="<f4"))
    r = run("isosurface", tmp_path / "empty.npy", "-o", tmp_path / "e.ply")
    assert r.returncode == 1
    assert "empty.npy: the grid is empty (0×3×2 samples)" in r.stderr
    assert not (tmp_path / "e.ply").exists()
