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
