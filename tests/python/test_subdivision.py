"""geom.subdivide / geom.limit_positions from Python."""

import json

import numpy as np
import pytest

import geom
from conftest import SAMPLE

CUBE_V = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                   [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], float)
CUBE_F = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]


def cube():
    return geom.Mesh(CUBE_V, CUBE_F)


def test_catmull_clark_counts_and_limit():
    r = geom.subdivide(cube(), levels=2)
    assert r.mesh.n_faces == 96
    assert r.mesh.n_vertices == 98
    assert [c.faces for c in r.per_level] == [6, 24, 96]
    pushed = geom.subdivide(cube(), levels=2, limit=True)
    assert pushed.limit_max_distance > 0
    lim = geom.limit_positions(r.mesh, normals=True)
    np.testing.assert_allclose(lim.positions, pushed.mesh.vertices, atol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(lim.normals, axis=1), 1.0)


def test_creases_as_arrays_keep_sharp_edges():
    # Every cube edge infinitely sharp: the corners stay put.
    edges = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4),
             (0, 4), (1, 5), (2, 6), (3, 7)]
    creases = [(a, b, 10.0) for a, b in edges]
    r = geom.subdivide(cube(), creases=creases, levels=2)
    v = r.mesh.vertices
    for corner in CUBE_V:
        assert np.min(np.linalg.norm(v - corner, axis=1)) == 0.0
    smooth = geom.subdivide(cube(), corners=[(0, 10.0)], levels=1)
    assert np.min(np.linalg.norm(smooth.mesh.vertices - CUBE_V[0], axis=1)) == 0.0


def test_loop_and_options():
    tet = geom.Mesh(np.array([[1, 1, 1], [-1, -1, 1], [-1, 1, -1], [1, -1, -1]], float),
                    [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])
    r = geom.subdivide(tet, scheme="loop", levels=3, boundary="corners", crease_method="chaikin")
    assert r.mesh.n_faces == 4 * 64
    assert geom.subdivide(cube(), crease_angle=60.0).angle_creased_edges == 12


def test_errors():
    with pytest.raises(ValueError):
        geom.subdivide(cube(), scheme="loop")
    with pytest.raises(ValueError):
        geom.subdivide(cube(), scheme="butterfly")
    with pytest.raises(ValueError):
        geom.subdivide(cube(), levels=11)
    with pytest.raises(ValueError):
        geom.subdivide(cube(), creases=[(0, 6, 1.0)])  # a diagonal, not an edge
    with pytest.raises(ValueError):
        geom.subdivide(cube(), creases=[(0, 99, 1.0)])
    with pytest.raises(TypeError):
        geom.subdivide(cube(), level=2)


def test_cli_subdivide(run, tmp_path):
    out = tmp_path / "smooth.obj"
    r = run("subdivide", SAMPLE, "-o", out, "--levels", "1", "--limit", "--json")
    assert r.returncode == 0, r.stderr
    j = json.loads(r.stdout)
    assert j["levels"] == 1 and j["faces"] > j["faces_before"]
    assert j["limit_max_distance"] >= j["limit_rms_distance"] > 0
    assert geom.load(str(out)).n_faces == j["faces"]
    assert run("subdivide", SAMPLE, "-o", tmp_path / "x.obj", "--scheme", "butterfly").returncode == 2
    assert run("subdivide", SAMPLE, "-o", tmp_path / "x.obj", "--levels", "11").returncode == 2
    assert run("subdivide", tmp_path / "missing.obj", "-o", tmp_path / "y.obj").returncode == 1


def _write_uv_cube(path):
    """The cube with one UV per vertex, an affine function of its position (no seams)."""
    uv = lambda p: (0.5 * p[0] + 0.25 * p[1] + 0.1, p[2] - 0.3 * p[0])
    lines = [f"v {x} {y} {z}" for x, y, z in CUBE_V]
    lines += ["vt %.17g %.17g" % uv(p) for p in CUBE_V]
    lines += ["f " + " ".join(f"{i + 1}/{i + 1}" for i in face) for face in CUBE_F]
    path.write_text("\n".join(lines) + "\n")
    return uv


def _corner_uv_error(path, uv):
    """Largest |vt - uv(v)| over the face corners of an OBJ file."""
    v, vt, worst = [], [], 0.0
    for line in path.read_text().splitlines():
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            v.append([float(x) for x in w[1:4]])
        elif w[0] == "vt":
            vt.append([float(x) for x in w[1:3]])
        elif w[0] == "f":
            for corner in w[1:]:
                i, t = (int(x) - 1 for x in corner.split("/")[:2])
                worst = max(worst, float(np.linalg.norm(np.subtract(vt[t], uv(v[i])))))
    assert vt, "no texture coordinates written"
    return worst


def test_smooth_face_varying_uvs_follow_the_vertices(run, tmp_path):
    # Subdivision is affine-invariant: seamless UVs that are an affine function of position
    # stay that function of the refined positions when refined smoothly, not when linearly.
    src = tmp_path / "uv_cube.obj"
    uv = _write_uv_cube(src)
    smooth, linear = tmp_path / "smooth.obj", tmp_path / "linear.obj"
    assert run("subdivide", src, "-o", smooth, "--levels", "2", "--uv", "smooth").returncode == 0
    assert run("subdivide", src, "-o", linear, "--levels", "2").returncode == 0
    assert _corner_uv_error(smooth, uv) < 1e-12
    assert _corner_uv_error(linear, uv) > 1e-3
    assert run("subdivide", src, "-o", linear, "--uv", "cubic").returncode == 2

    r = geom.subdivide(geom.load(str(src)), levels=2, face_varying="smooth")
    out = tmp_path / "py.obj"
    geom.save(r.mesh, str(out))
    assert _corner_uv_error(out, uv) < 1e-12

    # --limit takes smooth UVs to the limit with the vertices, so they still agree; from the
    # unrefined control mesh that is refused rather than left half done.
    pushed = tmp_path / "pushed.obj"
    args = ("subdivide", src, "-o", pushed, "--uv", "smooth", "--limit")
    assert run(*args, "--levels", "2").returncode == 0
    assert _corner_uv_error(pushed, uv) < 1e-12
    refused = run(*args, "--levels", "0")
    assert refused.returncode != 0 and "levels >= 1" in refused.stderr
    r = geom.subdivide(geom.load(str(src)), levels=1, face_varying="smooth", limit=True)
    geom.save(r.mesh, str(out))
    assert _corner_uv_error(out, uv) < 1e-12
    with pytest.raises(ValueError):
        geom.subdivide(cube(), face_varying="cubic")


FIN = np.array([[0, 0, 0], [0, 1, 0], [1, 0, 0.1], [1, 1, 0], [-1, 0, 0], [-1, 1, 0.2],
                [0, 0, 1], [0, 1, 1.1]], dtype=float)
FIN_FACES = np.array([[0, 1, 3, 2], [1, 0, 4, 5], [0, 1, 7, 6]])  # three quads on edge 0-1


def test_non_manifold_faces_are_refined_as_given():
    r = geom.subdivide(FIN, FIN_FACES, levels=2)
    # OpenSubdiv's counts: V + E + F at level 1 (8 + 10 + 3), then 21 + 32 + 12.
    assert [c.vertices for c in r.per_level] == [8, 21, 65]
    assert r.vertices.shape == (65, 3) and r.faces.shape == (48, 4)
    assert (r.nonmanifold_edges, r.nonmanifold_vertices, r.opened_edges) == (1, 2, 0)
    assert r.split_vertices > 0
    # The fin's edge is infinitely sharp: its ends stay put, its midpoint is a midpoint.
    level1 = geom.subdivide(FIN, FIN_FACES, levels=1)
    np.testing.assert_allclose(level1.vertices[3 + 10 + 0], FIN[0])
    np.testing.assert_allclose(level1.vertices[3 + 10 + 1], FIN[1])
    # Every input vertex's vertex-point comes out once: nothing was split apart.
    assert len(np.unique(level1.faces)) == 21


def test_as_given_faces_with_repeats_and_lists():
    faces = [[0, 1, 1, 2], [1, 4, 5, 2], [0, 2, 3, 0, 2]]
    pts = [[0, 0, 0], [1, 0, 0], [1, 1, 0.3], [0, 1, 0], [2, 0, 0], [2, 1, 0.5]]
    r = geom.subdivide(pts, faces, levels=1, creases=[(1, 4, 2.0)])
    assert r.faces.shape == (13, 4) and r.degenerate_edges >= 1
    with pytest.raises(ValueError, match="face 0"):
        geom.subdivide(pts, [[0, 1, 9]])


def test_cli_subdivide_keeps_a_fin_as_given(run, tmp_path):
    src = tmp_path / "fin.obj"
    src.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in FIN) +
                   "".join("f " + " ".join(str(i + 1) for i in f) + "\n" for f in FIN_FACES))
    out = tmp_path / "out.obj"
    r = run("subdivide", src, out, "--json")
    assert r.returncode == 0, r.stderr
    j = json.loads(r.stdout)
    assert (j["vertices"], j["faces"], j["nonmanifold_edges"], j["opened_edges"]) == (21, 12, 1, 0)
    text = out.read_text().splitlines()
    assert sum(line.startswith("v ") for line in text) == 21
    assert sum(line.startswith("f ") for line in text) == 12
    # A batch of subdivide steps takes the same path: the fin keeps its 21 vertices.
    folder = tmp_path / "in"
    folder.mkdir()
    (folder / "fin.obj").write_text(src.read_text())
    r = run("batch", folder, tmp_path / "b", "--step", "subdivide --levels 1")
    assert r.returncode == 0, r.stderr
    batch_text = (tmp_path / "b" / "fin.obj").read_text().splitlines()
    assert sum(line.startswith("v ") for line in batch_text) == 21
