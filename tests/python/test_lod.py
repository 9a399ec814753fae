"""geom.simplify, geom.compare and geom.ProgressiveMesh (geom/lod through the binding)."""

import json

import numpy as np
import pytest

import geom
from conftest import torus_mesh as torus


def grid(n=12):
    """A wavy open square (one boundary loop) of 2·n² triangles."""
    u, v = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1), indexing="ij")
    vertices = np.stack([u, v, 0.1 * np.sin(4 * u) * np.cos(3 * v)], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    at = lambda i, j: i * (n + 1) + j  # noqa: E731
    faces = np.concatenate([
        np.stack([at(i, j), at(i + 1, j), at(i + 1, j + 1)], -1).reshape(-1, 3),
        np.stack([at(i, j), at(i + 1, j + 1), at(i, j + 1)], -1).reshape(-1, 3)])
    return geom.Mesh(vertices, faces)


def test_simplify_ratio_keeps_topology():
    mesh = torus()
    r = geom.simplify(mesh, ratio=0.25)
    assert r.faces_before == 576
    # A closed mesh loses exactly two triangles per collapse, so the target is met exactly.
    assert r.faces_after == 144 == r.mesh.n_faces
    assert r.collapses == 216
    assert r.stop == "target reached"
    topo = r.mesh.analyze()
    assert (topo.genus, topo.boundary_loops, topo.components) == (1, 0, 1)
    assert topo.manifold and r.mesh.validate().ok
    # Every output vertex sits on an input vertex's index; kept ones are bit-exact or moved.
    assert r.vertex_origin.shape == (r.mesh.n_vertices,)
    assert len(set(r.vertex_origin.tolist())) == r.mesh.n_vertices
    d = geom.compare(mesh, r.mesh, samples=20000)
    assert 0 < d.hausdorff < 0.05 * d.diagonal
    assert d.rms <= d.hausdorff


def test_simplify_faces_and_max_error():
    mesh = torus()
    assert geom.simplify(mesh, faces=100).faces_after == 100
    assert geom.simplify(mesh, target_faces=100).faces_after == 100
    bound = 0.02
    r = geom.simplify(mesh, max_error=bound)
    assert r.max_quadric_error <= bound
    assert r.faces_after < 576
    assert r.stop == "every remaining collapse exceeds max_error"
    # A tighter bound can only keep more faces.
    assert geom.simplify(mesh, max_error=bound / 10).faces_after >= r.faces_after


def test_keep_boundary_keeps_every_boundary_vertex():
    mesh = grid()
    before = mesh.vertices
    boundary = {tuple(p) for p in before.tolist() if 0 in p[:2] or 1 in p[:2]}
    r = geom.simplify(mesh, ratio=0.2, keep_boundary=True)
    after = {tuple(p) for p in r.mesh.vertices.tolist()}
    assert boundary <= after
    assert r.mesh.analyze().boundary_loops == 1


def test_simplify_bad_arguments():
    mesh = torus()
    with pytest.raises(ValueError, match="ratio"):
        geom.simplify(mesh, ratio=1.5)
    with pytest.raises(ValueError, match="not both"):
        geom.simplify(mesh, ratio=0.5, faces=10)
    with pytest.raises(ValueError, match="max_error"):
        geom.simplify(mesh, max_error=-1.0)
    with pytest.raises(TypeError, match="unknown option"):
        geom.simplify(mesh, speed=3)
    with pytest.raises(ValueError):
        geom.compare(mesh, geom.Mesh(np.zeros((0, 3)), np.zeros((0, 3), int)))


def test_refit_lowers_the_error_and_keeps_the_topology():
    mesh = torus()
    plain = geom.simplify(mesh, ratio=0.1, refit=0)
    fitted = geom.simplify(mesh, ratio=0.1, refit=1)
    # The refit moves vertices only: same connectivity, same count.
    assert fitted.faces_after == plain.faces_after
    assert np.array_equal(fitted.mesh.faces, plain.mesh.faces)
    assert not np.array_equal(fitted.mesh.vertices, plain.mesh.vertices)
    topo = fitted.mesh.analyze()
    assert (topo.genus, topo.boundary_loops, topo.components) == (1, 0, 1)
    assert fitted.mesh.validate().ok
    d0 = geom.compare(mesh, plain.mesh, samples=20000)
    d1 = geom.compare(mesh, fitted.mesh, samples=20000)
    assert d1.rms < 0.95 * d0.rms
    assert (plain.refit_rounds, fitted.refit_rounds, geom.simplify(mesh, ratio=0.1).refit_rounds) == (0, 1, 1)
    with pytest.raises(ValueError, match="refit_iterations"):
        geom.simplify(mesh, ratio=0.1, refit=-2)
    # Vertex splits replay single collapses; a refit of one level cannot be replayed.
    with pytest.raises(ValueError, match="refit_iterations"):
        geom.ProgressiveMesh(mesh, refit=1)


def test_cli_simplify_refit(tmp_path, run):
    src = tmp_path / "t.obj"
    geom.save(torus(), str(src))
    out = tmp_path / "out.obj"
    plain = run("simplify", src, out, "--ratio", "0.1", "--refit", "0", "--measure", "--json")
    fitted = run("simplify", src, out, "--ratio", "0.1", "--refit", "1", "--measure", "--json", "--force")
    assert plain.returncode == 0 and fitted.returncode == 0, fitted.stderr
    assert json.loads(fitted.stdout)["rms"] < json.loads(plain.stdout)["rms"]
    assert (json.loads(plain.stdout)["refit_rounds"], json.loads(fitted.stdout)["refit_rounds"]) == (0, 1)
    auto = run("simplify", src, out, "--ratio", "0.1", "--json", "--force")
    assert json.loads(auto.stdout)["refit_rounds"] == 1
    assert "--refit" in run("simplify", "--help").stdout
    assert run("simplify", src, tmp_path / "x.obj", "--ratio", "0.1", "--refit", "-2").returncode == 2


def test_progressive_mesh_reconstructs_exactly():
    mesh = torus()
    pm = geom.ProgressiveMesh(mesh)
    assert pm.n_vertices == pm.max_vertices == mesh.n_vertices
    assert pm.n_faces == pm.max_faces == 576
    original_v, original_f = mesh.vertices, mesh.faces
    pm.coarsen_to(pm.base_vertices)
    assert pm.n_faces == pm.base_faces < 576
    assert pm.positions.shape == (pm.base_vertices, 3)
    assert pm.faces.shape == (pm.base_faces, 3)
    middle = (pm.base_vertices + pm.max_vertices) // 2
    pm.refine_to(middle)
    assert pm.n_vertices == middle and pm.n_faces == pm.faces_at(middle)
    pm.refine_to(pm.max_vertices)
    origin = pm.vertex_origin
    # Positions bit-exact and faces identical up to the returned permutation.
    assert np.array_equal(pm.positions, original_v[origin])
    assert np.array_equal(origin[pm.faces], original_f[pm.face_origin])
    assert sorted(pm.face_origin.tolist()) == list(range(576))


def test_progressive_base_from_options():
    pm = geom.ProgressiveMesh(torus(), faces=200)
    assert pm.base_faces == 200
    assert pm.vertices_for_faces(200) == pm.base_vertices


def test_geomorph_endpoints_equal_the_levels():
    pm = geom.ProgressiveMesh(torus())
    coarse = pm.base_vertices + 20
    fine = pm.base_vertices + 120
    pm.set_level(fine)
    fine_positions, fine_faces = pm.positions, pm.faces
    pm.set_level(coarse)
    coarse_positions, coarse_faces = pm.positions, pm.faces

    p1, f1 = pm.geomorph(coarse, fine, 1.0)
    assert np.array_equal(p1, fine_positions) and np.array_equal(f1, fine_faces)
    assert pm.n_vertices == fine

    p0, f0 = pm.geomorph(coarse, fine, 0.0)
    assert np.array_equal(f0, fine_faces)
    assert np.array_equal(p0[:coarse], coarse_positions)
    # At t=0 the fine faces collapse onto the coarse ones: the non-degenerate triangles are
    # exactly the coarse level's, as coordinate triples.
    def triangles(p, f):
        return {tuple(sorted(map(tuple, p[t].tolist()))) for t in f if len({tuple(x) for x in p[t].tolist()}) == 3}
    assert triangles(p0, f0) == triangles(coarse_positions, coarse_faces)

    half, _ = pm.geomorph(coarse, fine, 0.5)
    assert np.allclose(half, 0.5 * (p0 + p1))


def test_progressive_bad_arguments():
    pm = geom.ProgressiveMesh(torus())
    with pytest.raises(ValueError, match="refine_to"):
        pm.refine_to(pm.max_vertices + 1)
    with pytest.raises(ValueError, match="coarsen_to"):
        pm.coarsen_to(pm.base_vertices - 1)
    pm.set_level(pm.base_vertices)
    with pytest.raises(ValueError, match="use refine_to"):
        pm.coarsen_to(pm.base_vertices + 1)
    with pytest.raises(ValueError, match="geomorph"):
        pm.geomorph(pm.base_vertices + 5, pm.base_vertices + 1, 0.5)
    with pytest.raises(ValueError, match="t must be"):
        pm.geomorph(pm.base_vertices, pm.max_vertices, 1.5)
    with pytest.raises(ValueError, match="ratio"):
        geom.ProgressiveMesh(torus(), ratio=-0.5)


def test_stream_round_trip_and_corruption(tmp_path):
    pm = geom.ProgressiveMesh(torus())
    path = tmp_path / "torus.gpm"
    pm.save(str(path))
    back = geom.ProgressiveMesh.load(str(path))
    assert isinstance(back, geom.ProgressiveMesh)
    assert (back.base_vertices, back.max_vertices, back.max_faces) == \
        (pm.base_vertices, pm.max_vertices, pm.max_faces)
    assert np.array_equal(back.positions, pm.positions)
    assert np.array_equal(back.faces, pm.faces)

    data = pm.encode()
    assert data == path.read_bytes()
    cut = data[: len(data) * 3 // 4]
    with pytest.raises(geom.DecodeError):
        geom.ProgressiveMesh.decode(cut)
    partial = geom.ProgressiveMesh.decode(cut, allow_partial=True)
    assert pm.base_vertices <= partial.n_vertices < pm.max_vertices
    with pytest.raises(geom.DecodeError):
        geom.ProgressiveMesh.decode(b"not a stream at all")
    with pytest.raises(OSError):
        geom.ProgressiveMesh.load(str(tmp_path / "missing.gpm"))


def uv_sphere_obj(n_lat=12, n_lon=24):
    """OBJ text of a unit UV sphere: vt cut along longitude 0 (u = 0 and u = 1 meet there),
    vn per vertex."""
    lines, vts = [], {}
    pos = [(0.0, 0.0, 1.0)] + [
        (np.sin(np.pi * i / n_lat) * np.cos(2 * np.pi * j / n_lon),
         np.sin(np.pi * i / n_lat) * np.sin(2 * np.pi * j / n_lon), np.cos(np.pi * i / n_lat))
        for i in range(1, n_lat) for j in range(n_lon)] + [(0.0, 0.0, -1.0)]
    lines += [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in pos]
    lines += [f"vn {x:.17g} {y:.17g} {z:.17g}" for x, y, z in pos]

    def vt(u, v):
        if (u, v) not in vts:
            vts[(u, v)] = len(vts) + 1
            lines.append(f"vt {u:.17g} {v:.17g}")
        return vts[(u, v)]

    ring = lambda i, j: 2 + (i - 1) * n_lon + j % n_lon  # noqa: E731
    corner = lambda i, j: f"{ring(i, j)}/{vt(j / n_lon, i / n_lat)}/{ring(i, j)}"  # noqa: E731
    faces = []
    for j in range(n_lon):
        pole_n, pole_s = vt((j + 0.5) / n_lon, 0.0), vt((j + 0.5) / n_lon, 1.0)
        faces.append(f"f 1/{pole_n}/1 {corner(1, j)} {corner(1, j + 1)}")
        s = len(pos)
        faces.append(f"f {s}/{pole_s}/{s} {corner(n_lat - 1, j + 1)} {corner(n_lat - 1, j)}")
        for i in range(1, n_lat - 1):
            faces.append(f"f {corner(i, j)} {corner(i + 1, j)} {corner(i + 1, j + 1)}")
            faces.append(f"f {corner(i, j)} {corner(i + 1, j + 1)} {corner(i, j + 1)}")
    return "\n".join(lines + faces) + "\n"


def obj_counts(text):
    kinds = [line.split()[0] for line in text.splitlines() if line.strip()]
    return {k: kinds.count(k) for k in ("v", "vt", "vn", "f")}


def test_simplify_with_attributes_carries_uvs_and_normals(tmp_path):
    src = tmp_path / "sphere.obj"
    src.write_text(uv_sphere_obj())
    mesh = geom.load(str(src))
    r = geom.simplify(mesh, ratio=0.3, attributes=("normals", "uv"), attribute_weights={"uv": 2.0})
    assert r.stop == "target reached" and r.mesh.validate().ok
    out = tmp_path / "out.obj"
    geom.save(r.mesh, str(out))
    counts = obj_counts(out.read_text())
    assert counts["f"] == r.faces_after
    # UVs come out per corner, with the seam's two sides as separate vt entries.
    assert counts["vt"] > counts["v"]
    assert counts["vn"] >= counts["v"]
    for line in out.read_text().splitlines():
        if line.startswith("vt "):
            u, v = map(float, line.split()[1:3])
            assert -1e-9 <= u <= 1 + 1e-9 and -1e-9 <= v <= 1 + 1e-9
        if line.startswith("vn "):
            assert abs(np.linalg.norm([float(x) for x in line.split()[1:4]]) - 1) < 1e-6

    # Asked for none, the output has none (and says so); by default it keeps them all.
    plain = tmp_path / "plain.obj"
    with pytest.warns(UserWarning, match="not carried to the output"):
        geom.save(geom.simplify(mesh, ratio=0.3, attributes=()).mesh, str(plain))
    assert obj_counts(plain.read_text())["vt"] == 0
    kept = tmp_path / "kept.obj"
    geom.save(geom.simplify(mesh, ratio=0.3).mesh, str(kept))
    assert obj_counts(kept.read_text())["vt"] > obj_counts(kept.read_text())["v"]

    opts = geom.SimplifyOptions()
    opts.attributes = {"uv": 0.5}
    assert opts.attributes == {"uv": 0.5}
    with pytest.raises(ValueError, match="unknown attribute"):
        geom.simplify(mesh, attributes=("uv", "tangents"))
    with pytest.raises(ValueError, match="texcoord"):
        geom.simplify(torus(), attributes=("uv",))
    with pytest.raises(ValueError, match="weight"):
        geom.simplify(mesh, attributes=("uv",), attribute_weights=-1.0)
    with pytest.raises(ValueError, match="not asked for"):
        geom.simplify(mesh, attributes=("uv",), attribute_weights={"color": 1.0})


def test_cli_simplify_attributes(tmp_path, run):
    src = tmp_path / "sphere.obj"
    src.write_text(uv_sphere_obj())
    out = tmp_path / "out.obj"
    r = run("simplify", src, out, "--ratio", "0.3", "--attributes", "normals,uv", "--attribute-weight", "2",
            "--json")
    assert r.returncode == 0, r.stderr
    counts = obj_counts(out.read_text())
    assert counts["vt"] > counts["v"] and counts["vn"] >= counts["v"]
    assert "--attributes" in run("simplify", "--help").stdout
    assert run("simplify", src, tmp_path / "x.obj", "--ratio", "0.3", "--attributes", "tangents").returncode == 2
    bad = run("simplify", src, tmp_path / "y.obj", "--ratio", "0.3", "--attributes", "color")
    assert bad.returncode == 1 and "v:color" in bad.stderr
