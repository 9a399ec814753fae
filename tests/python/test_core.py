"""geom.Mesh, geom.build, analyze and validate from Python, including every error path."""

import copy
import threading

import numpy as np
import pytest

import geom
from conftest import SAMPLE

TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
TET_F = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])

CUBE_V = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=float)
CUBE_F = np.array([[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2],
                   [1, 3, 7, 5]])


def torus(n=8, m=6, big=2.0, small=0.5):
    u = np.arange(n) * 2 * np.pi / n
    v = np.arange(m) * 2 * np.pi / m
    uu, vv = np.meshgrid(u, v, indexing="ij")
    pts = np.stack([(big + small * np.cos(vv)) * np.cos(uu),
                    (big + small * np.cos(vv)) * np.sin(uu), small * np.sin(vv)], -1)
    faces = [[i * m + j, ((i + 1) % n) * m + j, ((i + 1) % n) * m + (j + 1) % m,
              i * m + (j + 1) % m] for i in range(n) for j in range(m)]
    return pts.reshape(-1, 3), np.array(faces)


def mobius(n=8):
    """A strip of n quads whose ends are glued with a half twist."""
    v = []
    for i in range(n):
        t = np.pi * i / n
        a = 2 * t
        for s in (-0.3, 0.3):
            v.append([(1 + s * np.cos(t)) * np.cos(a), (1 + s * np.cos(t)) * np.sin(a),
                      s * np.sin(t)])
    faces = [[2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1] for i in range(n - 1)]
    faces.append([2 * (n - 1), 1, 0, 2 * (n - 1) + 1])  # the twisted seam
    return np.array(v), faces


# ---- construction ----------------------------------------------------------------------------

def test_empty_mesh():
    m = geom.Mesh()
    assert (m.n_vertices, m.n_edges, m.n_faces) == (0, 0, 0)
    assert m.is_empty
    assert m.vertices.shape == (0, 3) and m.faces.shape == (0, 3)


def test_mesh_from_arrays_round_trip():
    m = geom.Mesh(TET_V, TET_F)
    assert (m.n_vertices, m.n_edges, m.n_faces, m.n_halfedges) == (4, 6, 4, 12)
    assert m.vertices.dtype == np.float64 and m.faces.dtype == np.int64
    np.testing.assert_array_equal(m.vertices, TET_V)
    np.testing.assert_array_equal(m.faces, TET_F)
    assert m.is_triangle_mesh() and not m.is_quad_mesh()


def test_mesh_accepts_lists_and_other_dtypes():
    m = geom.Mesh(TET_V.astype(np.float32).tolist(), TET_F.astype(np.uint16).tolist())
    np.testing.assert_array_equal(m.faces, TET_F)
    m = geom.Mesh(TET_V.astype(np.int32), TET_F.astype(np.int32))
    assert m.n_faces == 4


def test_mixed_polygons_come_back_as_lists():
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], float)
    faces = [[0, 1, 2, 3], [1, 4, 2]]
    m = geom.Mesh(v, faces)
    assert m.faces == faces
    assert m.analyze().face_sizes == {3: 1, 4: 1}


def test_quad_mesh():
    m = geom.Mesh(CUBE_V, CUBE_F)
    assert m.is_quad_mesh() and m.faces.shape == (6, 4)


def test_copy_is_independent():
    m = geom.Mesh(TET_V, TET_F)
    for c in (m.copy(), copy.copy(m), copy.deepcopy(m)):
        assert c is not m and c.n_faces == 4
    assert "4 vertices" in repr(m)


# ---- construction errors ---------------------------------------------------------------------

@pytest.mark.parametrize("vertices,message", [
    (np.zeros((4, 2)), "V×3"),
    (np.zeros((4, 3, 1)), "V×3"),
    ("abc", "vertices"),
    (np.array([[0, 0, np.nan], [1, 0, 0], [0, 1, 0], [0, 0, 1]]), "non-finite"),
    (np.array([[0, 0, np.inf], [1, 0, 0], [0, 1, 0], [0, 0, 1]]), "non-finite"),
])
def test_bad_vertices(vertices, message):
    with pytest.raises(ValueError, match=message):
        geom.Mesh(vertices, TET_F)


@pytest.mark.parametrize("faces,message", [
    (np.array([[0, 1, 4]]), "face 0 has index 4"),
    (np.array([[0, 1, 2], [0, -1, 2]]), "face 1 has index -1"),
    ([[0, 1, 2], [0, 1, 7]], "face 1 has index 7"),
    (np.array([[0, 1]]), "at least 3"),
    ([[0, 1, 2], [1, 2]], "face 1 has 2 corners"),
    (np.array([[0.0, 1.0, 2.0]]), "integer"),
    ([[0, 1.5, 2]], "non-integer"),
    ([[0, 1, "2"]], "non-integer"),
    ([5], "not a sequence"),
    (42, "faces"),
    ("012", "faces"),
    (np.zeros((2, 3, 3), dtype=int), "dimensions"),
])
def test_bad_faces(faces, message):
    with pytest.raises(ValueError, match=message) as info:
        geom.Mesh(TET_V, faces)
    assert isinstance(info.value, geom.InvalidArgument)


def test_unknown_build_option():
    with pytest.raises(TypeError, match="unknown option 'weld'"):
        geom.Mesh(TET_V, TET_F, weld=0.1)
    with pytest.raises(TypeError, match="unknown option"):
        geom.build(TET_V, TET_F, colour="red")


def test_bad_policy():
    with pytest.raises(ValueError, match="policy"):
        geom.build(TET_V, TET_F, policy="lenient")


# ---- build -----------------------------------------------------------------------------------

def test_build_reports_nothing_on_clean_input():
    result = geom.build(TET_V, TET_F)
    assert result.mesh.n_faces == 4
    assert not result.report.changed()
    np.testing.assert_array_equal(result.report.face_origin, [0, 1, 2, 3])


def test_build_welds_duplicates():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    f = [[0, 1, 2], [3, 5, 4]]
    assert geom.build(v, f).mesh.n_vertices == 6
    r = geom.build(v, f, weld_tolerance=0.0)
    assert r.report.welded_vertices == 2 and r.mesh.n_vertices == 4
    assert r.report.changed() and r.report.messages
    assert r.report.vertex_map.tolist()[3] == r.report.vertex_map.tolist()[1]


def test_build_flips_and_strict_raises():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    f = [[0, 1, 2], [1, 2, 3]]
    assert geom.build(v, f).report.flipped_faces == 1
    with pytest.raises(geom.TopologyError, match="face"):
        geom.build(v, f, policy="strict")


def test_build_splits_nonmanifold_edge():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]], float)
    f = [[0, 1, 2], [1, 0, 3], [0, 1, 4]]
    r = geom.build(v, f)
    assert r.report.split_nonmanifold_edges >= 1
    assert r.mesh.validate().ok
    with pytest.raises(ValueError):
        geom.build(v, f, policy="strict")


def test_build_options_object():
    o = geom.BuildOptions()
    assert (o.policy, o.weld_tolerance, o.orient, o.drop_unreferenced) == ("repair", -1.0, True,
                                                                           False)


# ---- analyze ---------------------------------------------------------------------------------

def test_analyze_tetrahedron():
    t = geom.Mesh(TET_V, TET_F).analyze()
    assert (t.vertices, t.edges, t.faces) == (4, 6, 4)
    assert t.euler_characteristic == 2 and t.genus == 0 and t.components == 1
    assert t.closed and t.manifold and t.orientable and t.boundary_loops == 0
    assert t.face_sizes == {3: 4}
    lo, hi = t.bounds
    np.testing.assert_array_equal(lo, [0, 0, 0])
    np.testing.assert_array_equal(hi, [1, 1, 1])
    assert len(t.per_component) == 1 and t.per_component[0].genus == 0
    assert "chi=2" in repr(t)


def test_analyze_cube_and_function_form():
    t = geom.analyze(geom.Mesh(CUBE_V, CUBE_F))
    assert (t.vertices, t.edges, t.faces, t.euler_characteristic, t.genus) == (8, 12, 6, 2, 0)


def test_analyze_single_triangle():
    t = geom.Mesh(TET_V[:3], [[0, 1, 2]]).analyze()
    assert (t.euler_characteristic, t.boundary_loops, t.components, t.genus) == (1, 1, 1, 0)
    assert not t.closed and t.boundary_edges == 3


def test_analyze_torus():
    v, f = torus()
    t = geom.Mesh(v, f).analyze()
    assert (t.euler_characteristic, t.genus, t.boundary_loops) == (0, 1, 0)


def test_analyze_two_components():
    v = np.vstack([TET_V, TET_V + 5])
    f = np.vstack([TET_F, TET_F + 4])
    t = geom.Mesh(v, f).analyze()
    assert t.components == 2 and t.euler_characteristic == 4 and t.genus == 0
    assert len(t.per_component) == 2


def test_analyze_mobius_is_not_orientable():
    v, f = mobius()
    given = geom.analyze(v, f)  # the polygons as given
    assert given.orientable is False and given.genus is None
    assert (given.vertices, given.edges, given.faces) == (16, 24, 8)
    assert given.boundary_loops == 1 and given.euler_characteristic == 0
    # A half-edge mesh is oriented, so building cuts the strip open and says so.
    result = geom.build(v, f)
    assert result.report.orientable is False
    assert result.mesh.validate().ok and result.mesh.analyze().orientable


def test_analyze_arrays_as_given():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]], float)
    t = geom.analyze(v, [[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    assert t.nonmanifold_edges == 1 and not t.manifold and t.genus is None
    with pytest.raises(ValueError, match="face 0 has index 9"):
        geom.analyze(v, [[0, 1, 9]])


def test_analyze_empty_mesh():
    t = geom.Mesh().analyze()
    assert (t.vertices, t.faces, t.components) == (0, 0, 0) and t.bounds is None


def test_sample_mesh_topology():
    t = geom.load(SAMPLE).analyze()
    assert (t.vertices, t.edges, t.faces, t.genus) == (1536, 3168, 1632, 1)
    assert t.face_sizes == {3: 216, 4: 1392, 5: 24}


# ---- validate --------------------------------------------------------------------------------

def test_validate():
    r = geom.validate(geom.Mesh(TET_V, TET_F))
    assert r.ok and bool(r) and r.problems == [] and "ok" in repr(r)
    assert geom.Mesh(CUBE_V, CUBE_F).validate(max_problems=5).ok


# ---- threads (the GIL is released in long work) ----------------------------------------------

def test_concurrent_analysis_from_threads():
    v, f = torus(60, 40)
    mesh = geom.Mesh(v, f)
    results = []

    def work():
        for _ in range(5):
            results.append(mesh.analyze().genus)

    threads = [threading.Thread(target=work) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert results == [1] * 20
