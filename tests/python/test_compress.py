"""geom.compress / geom.decompress (geom/compress through the binding)."""

import json

import numpy as np
import pytest

import geom
from conftest import torus_mesh as torus


def quad_grid(n=6):
    """An open wavy square of n² quads (one boundary loop)."""
    u, v = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1), indexing="ij")
    vertices = np.stack([u, v, 0.1 * np.sin(4 * u) * np.cos(3 * v)], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    at = lambda i, j: i * (n + 1) + j  # noqa: E731
    faces = np.stack([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)], -1).reshape(-1, 4)
    return geom.Mesh(vertices, faces)


def cyclic(face):
    """A face's corner cycle, rotated to start at its smallest index (orientation kept)."""
    face = list(face)
    k = face.index(min(face))
    return tuple(face[k:] + face[:k])


def test_round_trip_within_quantisation_bound_and_permutation_maps_back():
    mesh = torus()
    data, perm = geom.compress(mesh, bits=11, return_permutation=True)
    assert isinstance(data, bytes) and data[:3] == b"GMC"
    out, order = geom.decompress(data)
    assert order is None  # the order is not in the stream; the encoder's permutation maps back
    assert (out.n_vertices, out.n_faces) == (mesh.n_vertices, mesh.n_faces) == (288, 576)
    assert sorted(perm.vertices) == list(range(288)) and sorted(perm.faces) == list(range(576))
    v_in, v_out = mesh.vertices, out.vertices
    extent = (v_in.max(axis=0) - v_in.min(axis=0)).max()
    bound = 0.5 * extent / (2 ** 11 - 1)
    err = np.abs(v_out - v_in[perm.vertices]).max()
    assert 0 < err <= bound * (1 + 1e-9)
    # Decoded face f is input face perm.faces[f] with its vertices renamed (same cycle).
    f_in, f_out = np.asarray(mesh.faces), np.asarray(out.faces)
    for f in range(576):
        assert cyclic(perm.vertices[f_out[f]]) == cyclic(f_in[perm.faces[f]])
    topo = out.analyze()
    assert (topo.genus, topo.boundary_loops, topo.components) == (1, 0, 1)


def test_preserve_order_gives_the_input_back_in_order():
    mesh = quad_grid()
    data = geom.compress(mesh, bits=14, preserve_order=True)
    out, perm = geom.decompress(data)
    assert list(perm.vertices) == list(range(49)) and list(perm.faces) == list(range(36))
    assert np.array_equal(np.asarray(out.faces), np.asarray(mesh.faces))  # quads, first corners kept
    bound = 0.5 * 1.0 / (2 ** 14 - 1)
    assert np.abs(out.vertices - mesh.vertices).max() <= bound * (1 + 1e-9)


def test_precision_bounds_the_error_and_levels_are_monotonic():
    mesh = torus()
    data, perm = geom.compress(mesh, precision=1e-3, return_permutation=True)
    out, _ = geom.decompress(data)
    assert np.abs(out.vertices - mesh.vertices[perm.vertices]).max() <= 1e-3 * (1 + 1e-9)
    sizes = [len(geom.compress(mesh, level=level)) for level in range(10)]
    assert all(b <= a for a, b in zip(sizes, sizes[1:])), sizes


def test_corrupted_and_truncated_streams_raise_naming_the_offset():
    data = geom.compress(torus())
    with pytest.raises(geom.DecodeError, match=r"^byte 0: .*bad magic"):
        geom.decompress(b"XMC" + data[3:])
    with pytest.raises(geom.DecodeError, match=r"^byte 4: unsupported stream version 9"):
        geom.decompress(data[:4] + b"\x09" + data[5:])
    with pytest.raises(ValueError, match=r"^byte \d+: "):
        geom.decompress(data[: len(data) // 2])
    # Every single-bit flip in the payload is an error or a valid mesh, never a crash.
    errors = 0
    for i in range(40, len(data), max(1, len(data) // 60)):
        flipped = bytearray(data)
        flipped[i] ^= 0x10
        try:
            geom.decompress(bytes(flipped))
        except geom.DecodeError as e:
            assert str(e).startswith("byte ")
            errors += 1
    assert errors > 0


def test_bad_options_raise():
    mesh = torus()
    with pytest.raises(ValueError, match="level"):
        geom.compress(mesh, level=10)
    with pytest.raises(ValueError, match="bits"):
        geom.compress(mesh, bits=31)
    with pytest.raises(ValueError, match="precision"):
        geom.compress(mesh, precision=-1.0)
    with pytest.raises(TypeError):
        geom.decompress("not bytes")


def test_large_meshes_split_into_chunks_that_decode_to_the_same_mesh(run, tmp_path):
    mesh = torus(200, 100, R=3.0, r=1.0)  # 40000 triangles: 2 chunks of at least 16384
    data, perm, stats = geom.compress(mesh, bits=14, chunk_triangles=16384,
                                      return_permutation=True, return_stats=True)
    assert data[4] == 3 and stats.chunks == 2
    one, one_perm, one_stats = geom.compress(mesh, bits=14, chunk_triangles=0,
                                             return_permutation=True, return_stats=True)
    assert one[4] != 3 and one_stats.chunks == 1
    out, _ = geom.decompress(data)
    ref, _ = geom.decompress(one)
    # One grid for every chunk: each input vertex decodes to the same point either way.
    v_out = np.empty_like(out.vertices)
    v_out[perm.vertices] = out.vertices
    v_ref = np.empty_like(ref.vertices)
    v_ref[one_perm.vertices] = ref.vertices
    assert np.array_equal(v_out, v_ref)
    f_in, f_out = np.asarray(mesh.faces), np.asarray(out.faces)
    assert sorted(cyclic(perm.vertices[f]) for f in f_out) == sorted(cyclic(f) for f in f_in)
    assert out.analyze().genus == 1
    with pytest.raises(ValueError, match="chunk_triangles"):
        geom.compress(mesh, chunk_triangles=100)
    src, gmc = tmp_path / "t.ply", tmp_path / "t.gmc"
    geom.save(mesh, src)
    r = run("compress", src, gmc, "--chunk-triangles", "16384", "--bits", "14", "--json")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["chunks"] == 2


def test_empty_mesh_round_trips():
    out, perm = geom.decompress(geom.compress(geom.Mesh(np.zeros((0, 3)), np.zeros((0, 3), int)),
                                              preserve_order=True))
    assert (out.n_vertices, out.n_faces) == (0, 0)
    assert len(perm.vertices) == 0


def test_cli_round_trips_non_manifold_input_joining_the_split_vertices(run, meshes, tmp_path):
    gmc, back = tmp_path / "fin.gmc", tmp_path / "fin_back.obj"
    r = run("compress", meshes["fin"], gmc, "--preserve-order", "--bits", "16", "--json")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["split_vertices"] > 0
    assert "non-manifold input" in r.stderr, r.stderr
    r = run("decompress", gmc, back, "--json")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["vertices"] == 5
    src, src_faces = read_obj(meshes["fin"])
    out, out_faces = read_obj(back)
    assert out_faces == src_faces  # the edge with three faces is back
    assert np.abs(out["v"] - src["v"]).max() <= 0.5 * 2 / 65535 + 1e-12  # extent 2, 16 bits


def test_api_records_split_vertices_given_the_build_report(meshes):
    loaded = geom.load_with_report(meshes["fin"])
    mesh, origin = loaded.mesh, np.asarray(loaded.report.vertex_origin)
    assert mesh.n_vertices > 5
    data, perm = geom.compress(mesh, vertex_origin=origin, return_permutation=True)
    out, none, rep = geom.decompress(data, return_representative=True)
    assert none is None and len(rep) == out.n_vertices
    # Two decoded vertices are joined exactly when they came from one source vertex.
    src = origin[perm.vertices]
    assert np.array_equal(src[:, None] == src[None, :], rep[:, None] == rep[None, :])
    assert len(np.unique(rep)) == 5
    assert geom.decompress(geom.compress(mesh), return_representative=True)[2] is None
    # In preserved order the groups come back in input numbering: the source vertex (build()
    # numbers the copies after it) stands for each.
    out, perm, rep = geom.decompress(geom.compress(mesh, vertex_origin=origin, preserve_order=True),
                                     return_representative=True)
    assert perm is not None and np.array_equal(rep, np.array([origin.tolist().index(o) for o in origin]))
    assert np.array_equal(np.unique(rep[np.asarray(out.faces)]), np.arange(5))
    # The arrays path joins the groups itself: the source's 5 vertices, the fin's three
    # triangles on one edge (which no half-edge mesh can hold).
    arrays = geom.decompress_arrays(geom.compress(mesh, vertex_origin=origin))
    assert arrays.positions.shape == (5, 3) and arrays.triangles.shape == (mesh.n_faces, 3)
    edges = [tuple(sorted((int(t[i]), int(t[(i + 1) % 3])))) for t in arrays.triangles for i in range(3)]
    assert max(edges.count(e) for e in edges) == 3
    with pytest.raises(ValueError, match="vertex_origin"):
        geom.compress(mesh, vertex_origin=[0, 1])


def test_cli_round_trip_with_json(run, meshes, tmp_path):
    gmc, back = tmp_path / "t.gmc", tmp_path / "t.obj"
    r = run("compress", meshes["tetrahedron"], gmc, "--bits", "12", "--preserve-order", "--json")
    assert r.returncode == 0, r.stderr
    r = run("decompress", gmc, back)
    assert r.returncode == 0, r.stderr
    mesh = geom.load(back)
    assert (mesh.n_vertices, mesh.n_faces) == (4, 4)
    assert np.abs(mesh.vertices - geom.load(meshes["tetrahedron"]).vertices).max() <= 0.5 / 4095 + 1e-12


def read_obj(path):
    """Positions, texture coordinates, normals and faces (vertex indices, 0-based) of an OBJ."""
    rows = {"v": [], "vt": [], "vn": []}
    faces = []
    for line in path.read_text().splitlines():
        words = line.split()
        if words and words[0] in rows:
            rows[words[0]].append([float(x) for x in words[1:]])
        elif words and words[0] == "f":
            faces.append([int(w.split("/")[0]) - 1 for w in words[1:]])
    return {k: np.array(v) for k, v in rows.items()}, faces


def _torus_ply_with_normals_and_uvs(path):
    """A torus written as PLY with per-vertex normals (not unit length) and UVs; returns the
    mesh, the unit normals and the UVs."""
    mesh = torus(16, 8)
    v = mesh.vertices
    n = v - np.c_[v[:, :2] / np.linalg.norm(v[:, :2], axis=1)[:, None], np.zeros(len(v))]
    uv = np.c_[np.arctan2(v[:, 1], v[:, 0]), 2 * v[:, 2]]
    header = ["ply", "format ascii 1.0", f"element vertex {len(v)}"] + [
        f"property double {c}" for c in ("x", "y", "z", "nx", "ny", "nz", "s", "t")] + [
        f"element face {mesh.n_faces}", "property list uchar int vertex_indices", "end_header"]
    body = [" ".join(repr(float(x)) for x in row) for row in np.c_[v, n, uv]]
    body += ["3 " + " ".join(str(i) for i in f) for f in np.asarray(mesh.faces)]
    path.write_text("\n".join(header + body) + "\n")
    return mesh, n / np.linalg.norm(n, axis=1)[:, None], uv


def test_cli_normals_and_texcoords_round_trip_in_order(run, tmp_path):
    src = tmp_path / "t.ply"
    mesh, n_in, uv = _torus_ply_with_normals_and_uvs(src)
    v = mesh.vertices
    gmc, back = tmp_path / "t.gmc", tmp_path / "back.obj"
    r = run("compress", src, gmc, "--preserve-order", "--normal-bits", "12", "--json")
    assert r.returncode == 0, r.stderr
    assert '"normal_bits_per_vertex"' in r.stdout
    r = run("decompress", gmc, back)
    assert r.returncode == 0, r.stderr
    rows, faces = read_obj(back)
    assert faces == [list(f) for f in np.asarray(mesh.faces)]
    assert rows["vn"].shape == (len(v), 3) and rows["vt"].shape == (len(v), 2)
    cos = np.clip((n_in * rows["vn"]).sum(axis=1), -1, 1)
    assert np.arccos(cos).max() <= 4.5 / 2 ** 12
    uv_bound = 0.5 * (uv.max(axis=0) - uv.min(axis=0)).max() / (2 ** 12 - 1)
    assert np.abs(rows["vt"] - uv).max() <= uv_bound * (1 + 1e-9)


def _seamed_band_obj(path, nu=12):
    """A cylinder band of nu quads with coloured vertices and UVs cut where u wraps (u = 1 on
    the last column's right edge, 0 on the first column's left): per-corner UVs with a seam.
    Returns the corner UVs face by face and the colours."""
    theta = 2 * np.pi * np.arange(nu) / nu
    v = np.r_[np.c_[np.cos(theta), np.sin(theta), np.zeros(nu)],
              np.c_[np.cos(theta), np.sin(theta), np.ones(nu)]]
    color = np.c_[np.linspace(0, 1, 2 * nu), np.full(2 * nu, 0.5), np.linspace(1, 0.2, 2 * nu)]
    lines = ["v " + " ".join(repr(float(x)) for x in row) for row in np.c_[v, color]]
    lines += [f"vt {i / nu!r} {j!r}" for j in (0.0, 1.0) for i in range(nu + 1)]
    corners = []
    for i in range(nu):
        quad = [(i, i, 0), ((i + 1) % nu, i + 1, 0), ((i + 1) % nu + nu, i + 1, 1), (i + nu, i, 1)]
        lines.append("f " + " ".join(f"{vi + 1}/{j * (nu + 1) + ti + 1}" for vi, ti, j in quad))
        corners.append([(ti / nu, float(j)) for _, ti, j in quad])
    path.write_text("\n".join(lines) + "\n")
    return np.array(corners), color


def _corner_uvs(path):
    """Per-corner vt of an OBJ, face by face."""
    vt, faces = [], []
    for line in path.read_text().splitlines():
        words = line.split()
        if words and words[0] == "vt":
            vt.append([float(x) for x in words[1:3]])
        elif words and words[0] == "f":
            faces.append([vt[int(w.split("/")[1]) - 1] for w in words[1:]])
    return np.array(faces)


def test_corner_uvs_with_a_seam_and_colours_round_trip(tmp_path):
    src, back = tmp_path / "band.obj", tmp_path / "back.obj"
    uv, color = _seamed_band_obj(src)
    mesh = geom.load(src)
    data, stats = geom.compress(mesh, preserve_order=True, return_stats=True)
    assert stats.dropped_properties == []
    coded = {a.name: a for a in stats.attributes}
    assert set(coded) == {"h:texcoord", "v:color"}
    out, perm = geom.decompress(data)
    assert perm is not None
    geom.save(out, back)
    uv_out = _corner_uvs(back)
    assert uv_out.shape == uv.shape
    assert np.abs(uv_out - uv).max() <= coded["h:texcoord"].max_error * (1 + 1e-9)
    # The seam survives: the last quad's right corners sit at u = 1, the first's left at 0.
    assert uv_out[-1, 1, 0] > 0.99 and uv_out[0, 0, 0] < 0.01
    # The arrays path: each triangle corner's UV, at both sides of the seam. A flat corner
    # matches a source corner at its position (the band's vertices lie 30 degrees apart).
    arrays = geom.decompress_arrays(data)
    assert arrays.corner_normals is None and arrays.corner_texcoords.shape == (len(uv) * 2, 3, 2)
    src_v = np.asarray(mesh.vertices)
    src_pos = np.array([[src_v[vi] for vi in f] for f in np.asarray(mesh.faces)]).reshape(-1, 3)
    src_uv = uv.reshape(-1, 2)
    bound = coded["h:texcoord"].max_error * (1 + 1e-6) + 1e-6  # + float32 rounding
    for tri, uvs in zip(arrays.triangles, arrays.corner_texcoords):
        for v, t in zip(tri, uvs):
            at = np.linalg.norm(src_pos - arrays.positions[v], axis=1) < 1e-2
            assert np.abs(src_uv[at] - t).max(axis=1).min() <= bound, (v, t)
    # Across the seam one vertex carries u = 1 in one triangle and u = 0 in another.
    u_of = {}
    for tri, uvs in zip(arrays.triangles, arrays.corner_texcoords):
        for v, t in zip(tri, uvs):
            u_of.setdefault(int(v), set()).add(round(float(t[0]), 3))
    assert sum(1 for us in u_of.values() if 0.0 in us and 1.0 in us) == 2
    rows, _ = read_obj(back)
    bound = 0.5 * (color.max(axis=0) - color.min(axis=0)) / (2 ** 12 - 1)
    assert np.all(np.abs(rows["v"][:, 3:] - color) <= bound * (1 + 1e-9) + 1e-15)


def test_cli_names_the_properties_it_cannot_store(run, tmp_path):
    src, gmc = tmp_path / "q.ply", tmp_path / "q.gmc"
    src.write_text("\n".join([
        "ply", "format ascii 1.0", "element vertex 4", "property float x", "property float y",
        "property float z", "element face 2", "property list uchar int vertex_indices",
        "property float quality", "end_header",
        "0 0 0", "1 0 0", "1 1 0", "0 1 0", "3 0 1 2 0.5", "3 0 2 3 0.25"]) + "\n")
    r = run("compress", src, gmc, "--json", "--attribute-bits", "10")
    assert r.returncode == 0, r.stderr
    assert "warning" in r.stderr and "f:quality" in r.stderr
    assert json.loads(r.stdout)["dropped_properties"] == ["f:quality"]
    r = run("compress", src, gmc, "--force", "--quiet")
    assert r.returncode == 0 and r.stderr == ""


def test_decompress_arrays_match_the_mesh_decode():
    # One stream, two chunks and a polygon mesh: the arrays are the mesh decode's vertices
    # (as float32) and faces, in the same order; a polygon comes back as triangles of its own.
    for mesh, kwargs in ((torus(), {}), (torus(200, 100, R=3.0, r=1.0), {"chunk_triangles": 16384}),
                         (quad_grid(), {})):
        data = geom.compress(mesh, bits=12, **kwargs)
        out, _ = geom.decompress(data)
        arrays = geom.decompress_arrays(data)
        assert arrays.positions.dtype == np.float32 and arrays.triangles.dtype == np.uint32
        assert np.array_equal(arrays.positions, out.vertices.astype(np.float32))
        faces = [list(f) for f in out.faces]
        if all(len(f) == 3 for f in faces):
            assert np.array_equal(arrays.triangles, np.asarray(faces))
        else:
            assert len(arrays.triangles) == sum(len(f) - 2 for f in faces)
            corners = [set(f) for f in faces]
            assert all(any(set(t) <= c for c in corners) for t in arrays.triangles.tolist())
        assert arrays.normals is None and arrays.texcoords is None
    with pytest.raises(geom.DecodeError, match=r"^byte \d+: "):
        geom.decompress_arrays(data[: len(data) // 2])


def test_decompress_arrays_return_normals_and_texcoords(tmp_path):
    src = tmp_path / "t.ply"
    mesh, n, uv = _torus_ply_with_normals_and_uvs(src)
    v = mesh.vertices
    data, perm = geom.compress(geom.load(src), normal_bits=12, return_permutation=True)
    arrays = geom.decompress_arrays(data)
    assert arrays.normals.shape == (len(v), 3) and arrays.texcoords.shape == (len(v), 2)
    cos = np.clip((n[perm.vertices] * arrays.normals).sum(axis=1), -1, 1)
    assert np.arccos(cos).max() <= 4.5 / 2 ** 12 + 1e-6  # + float32 rounding
    uv_bound = 0.5 * (uv.max(axis=0) - uv.min(axis=0)).max() / (2 ** 12 - 1)
    assert np.abs(arrays.texcoords - uv[perm.vertices]).max() <= uv_bound + 1e-6


def test_polygons_keep_their_first_corner_by_default():
    mesh = quad_grid(8)
    data, perm, stats = geom.compress(mesh, bits=14, return_permutation=True, return_stats=True)
    assert stats.rotation_bytes > 0
    out, _ = geom.decompress(data)
    f_in, f_out = np.asarray(mesh.faces), np.asarray(out.faces)
    for f in range(len(f_out)):  # the same corners from the same first corner
        assert list(perm.vertices[f_out[f]]) == list(f_in[perm.faces[f]])
    small = geom.compress(mesh, bits=14, keep_corner_order=False)
    assert len(small) < len(data)


def test_loose_faces_travel_beside_the_mesh():
    mesh = quad_grid(3)
    loose = [[0, 0, 1], [0, 1, 2]]  # a repeated index; three collinear corners
    data, perm = geom.compress(mesh, loose_faces=loose, return_permutation=True)
    out, _, back = geom.decompress(data, return_loose_faces=True)
    assert [list(perm.vertices[f]) for f in back] == loose


def test_cli_writes_back_degenerate_and_duplicate_faces(run, tmp_path):
    src, gmc, back = tmp_path / "bad.obj", tmp_path / "bad.gmc", tmp_path / "back.obj"
    src.write_text("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0.5\nv 1 1 0\nv 2 1 0.3\n"
                   "f 1 2 5 4\nf 2 3 6 5\nf 1 1 2\nf 1 2 3\nf 4 5 2 1\n")
    r = run("compress", src, gmc, "--json")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["loose_faces"] == 3
    r = run("decompress", gmc, back, "--json")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["faces"] == 5
    _, faces = read_obj(back)
    assert sorted(len(f) for f in faces) == [3, 3, 4, 4, 4]
    r = run("compress", "--help")
    assert "--any-corner-order" in r.stdout
