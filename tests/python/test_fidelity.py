"""As given, unless asked: what a file holds comes back out of convert and batch, what info
says a repair would do is what repair does, and what a reader skips is said."""

import json
import warnings

import pytest

import geom
from conftest import ROOT

# Everything build() would change: a degenerate triangle (repeated corner), a zero-area one,
# two copies of one face, a fin (three faces on edge 1-2), an unused vertex, and a concave
# 8-gon (an L shape).
AS_GIVEN_OBJ = """v 0 0 0
v 1 0 0
v 0 1 0
v 0 -1 0
v 0 0 1
v 2 0 0
v 9 9 9
v 3 0 0
v 5 0 0
v 5 1 0
v 4 1 0
v 4 3 0
v 3 3 0
v 3 2 0
v 3 1 0
f 1 2 3
f 2 1 4
f 1 2 5
f 1 2 6
f 1 1 2
f 3 4 5
f 3 4 5
f 8 9 10 11 12 13 14 15
"""


def obj_faces(path):
    return [line.split()[1:] for line in path.read_text().splitlines() if line.startswith("f ")]


@pytest.mark.parametrize("ext", ["obj", "ply", "off"])
def test_convert_writes_every_face_and_vertex_as_read(run, tmp_path, ext):
    src = tmp_path / "given.obj"
    src.write_text(AS_GIVEN_OBJ)
    out = tmp_path / f"out.{ext}"
    r = run("convert", "--json", src, out)
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""
    j = json.loads(r.stdout)
    assert (j["vertices"], j["faces"], j["repairs"]) == (15, 8, None)
    back = tmp_path / "back.obj"
    assert run("convert", out, back).returncode == 0
    assert obj_faces(back) == obj_faces(src)


def test_convert_repairs_only_when_asked_and_says_what_changed(run, tmp_path):
    src = tmp_path / "given.obj"
    src.write_text(AS_GIVEN_OBJ)
    r = run("convert", "--json", "--repair", src, tmp_path / "fixed.obj")
    assert r.returncode == 0, r.stderr
    rep = json.loads(r.stdout)["repairs"]
    # Vertex 6 lay on a degenerate face only: once it is dropped, two vertices are unused.
    assert (rep["dropped_degenerate"], rep["dropped_duplicate"]) == (2, 1)
    assert (rep["split_nonmanifold_edges"], rep["dropped_unreferenced"]) == (1, 2)


def test_info_previews_exactly_what_repair_does(run, tmp_path):
    src = tmp_path / "given.obj"
    src.write_text(AS_GIVEN_OBJ)
    info = json.loads(run("info", "--json", src).stdout)["repairs"]
    r = run("repair", "--json", src, tmp_path / "r.obj")
    assert r.returncode == 0, r.stderr
    done = json.loads(r.stdout)
    for key in ("welded_vertices", "dropped_degenerate", "dropped_duplicate",
                "dropped_unreferenced", "split_nonmanifold_edges", "split_nonmanifold_vertices",
                "flipped_faces", "cut_edges"):
        assert info[key] == done[key], key
    assert info["dropped_unreferenced"] == 2


def test_info_of_a_point_cloud_is_a_manifold_of_genus_zero(run, tmp_path):
    src = tmp_path / "points.obj"
    src.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\n")
    j = json.loads(run("info", "--json", src).stdout)
    assert (j["manifold"], j["orientable"], j["genus"], j["components"]) == (True, True, 0, 0)
    assert "n/a" not in run("info", src).stdout


def batch_record(run, tmp_path, step):
    """The batch report's record of AS_GIVEN_OBJ run through `step`."""
    src = tmp_path / "in"
    src.mkdir()
    (src / "given.obj").write_text(AS_GIVEN_OBJ)
    r = run("batch", src, tmp_path / "out", "--step", step)
    assert r.returncode == 0, r.stderr
    return json.loads((tmp_path / "out" / "batch-report.jsonl").read_text().splitlines()[0])


def test_batch_conversion_keeps_the_file_as_given(run, tmp_path):
    record = batch_record(run, tmp_path, "convert --format ply")
    assert record["after"] == {"vertices": 15, "faces": 8}, record
    assert record["repairs"] == 0


def test_python_load_issues_the_readers_warnings(tmp_path):
    modes = ROOT.parent / "shared" / "corpus" / "gltf-samples" / "Models" / "MeshPrimitiveModes"
    path = modes / "glTF-Embedded" / "MeshPrimitiveModes.gltf"
    if not path.is_file():
        pytest.skip("corpus not found")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = geom.load_with_report(path)
    assert any("point or line primitive was skipped" in str(w.message) for w in caught)
    assert result.warnings and all("skipped" in w for w in result.warnings)


def test_convert_names_what_the_output_format_cannot_hold(run, tmp_path):
    src = tmp_path / "given.obj"
    src.write_text(AS_GIVEN_OBJ)
    r = run("convert", src, tmp_path / "out.stl")
    assert r.returncode == 0, r.stderr
    assert "out.stl: 1 polygon of more than 3 corners is split into 6 triangles" in r.stderr
    assert "1 vertex that no face uses is not stored" in r.stderr
    assert run("convert", "--quiet", src, tmp_path / "q.stl").stderr == ""


def test_python_save_warns_naming_what_the_format_cannot_hold(tmp_path):
    mesh = geom.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        geom.save(mesh, tmp_path / "quad.stl")
        geom.save(mesh, tmp_path / "quad.obj")
    assert [str(w.message) for w in caught] == [
        f"{tmp_path / 'quad.stl'}: 1 polygon of more than 3 corners is split into 2 triangles "
        "(stl holds triangles only)"]


def test_batch_report_names_what_the_output_format_cannot_hold(run, tmp_path):
    record = batch_record(run, tmp_path, "convert --format stl")
    assert any("split into 6 triangles" in w for w in record["warnings"]), record


def test_a_command_that_builds_a_mesh_says_what_the_build_changed(run, tmp_path):
    src = tmp_path / "given.obj"
    src.write_text(AS_GIVEN_OBJ)
    r = run("simplify", src, "-o", tmp_path / "s.obj", "--ratio", "0.9")
    assert r.returncode == 0, r.stderr
    assert "given.obj: building the mesh changed it: dropped degenerate faces: 2" in r.stderr
    assert "dropped duplicate faces: 1" in r.stderr
    clean = tmp_path / "tetra.obj"
    clean.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n")
    assert run("simplify", clean, "-o", tmp_path / "t.obj", "--ratio", "0.9").stderr == ""


# OBJ's names of objects, groups and materials, and its material files.
NAMED_OBJ = """mtllib shop.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
o chair
g seat
usemtl oak
f 1 2 3
f 1 3 4
g legs
usemtl steel
f 2 5 3
"""
NAMES = ["mtllib shop.mtl", "o chair", "g seat", "usemtl oak", "g legs", "usemtl steel"]


def obj_names(path):
    keys = ("mtllib", "o", "g", "usemtl")
    return [line for line in path.read_text().splitlines() if line.split()[:1] and line.split()[0] in keys]


@pytest.mark.parametrize("command", [["convert"], ["convert", "--repair"], ["repair"],
                                     ["subdivide", "--levels", "1"]])
def test_obj_groups_materials_and_libraries_come_back_out(run, tmp_path, command):
    src = tmp_path / "named.obj"
    src.write_text(NAMED_OBJ)
    out = tmp_path / "out.obj"
    r = run(*command[:1], src, out, *command[1:])
    assert r.returncode == 0, r.stderr
    assert obj_names(out) == NAMES


def test_batch_keeps_obj_names_and_other_formats_say_they_drop_them(run, tmp_path):
    folder = tmp_path / "in"
    folder.mkdir()
    (folder / "named.obj").write_text(NAMED_OBJ)
    for step in ("convert --format obj", "repair"):
        out = tmp_path / step.split()[0]
        r = run("batch", folder, out, "--step", step)
        assert r.returncode == 0, r.stderr
        assert obj_names(out / "named.obj") == NAMES
    r = run("convert", folder / "named.obj", tmp_path / "named.ply")
    assert "face names (1 object, 2 groups, 2 materials) are not stored (ply has no place for them)" in r.stderr
    assert "material libraries (mtllib shop.mtl) are not stored" in r.stderr


def test_repair_keeps_the_uv_seams_of_vertices_it_welds(run, tmp_path):
    """Two triangles of one quad, each its own UV chart with its own copies of the shared
    edge's vertices (as PLY and glTF store a seam): welding joins the positions, and the
    texture coordinates move to the corners rather than being lost."""
    src = tmp_path / "seam.ply"
    src.write_text("ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n"
                   "property float z\nproperty float u\nproperty float v\nelement face 2\n"
                   "property list uchar int vertex_indices\nend_header\n"
                   "0 0 0 0 0\n1 0 0 .5 0\n1 1 0 .5 .5\n"
                   "0 0 0 .6 0\n1 1 0 1 .5\n0 1 0 .6 .5\n3 0 1 2\n3 3 4 5\n")
    r = run("repair", src, tmp_path / "out.obj")
    assert r.returncode == 0, r.stderr
    assert "welded vertices: 2" in r.stdout
    assert "texture coordinates or normals differ (kept per face corner, so the seam stays): 2" in r.stdout
    out = (tmp_path / "out.obj").read_text().splitlines()
    assert sum(line.startswith("v ") for line in out) == 4
    assert sum(line.startswith("vt ") for line in out) == 6
    r = run("repair", src, tmp_path / "out.ply")
    assert "texture coordinates per face corner (UV seams) are not stored" in r.stderr


def test_compress_keeps_every_face_of_a_named_obj_with_a_degenerate_face(run, tmp_path):
    src = tmp_path / "named.obj"
    src.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\ng a\nf 1 2 3\nf 1 1 2\ng b\nf 2 4 3\n")
    r = run("compress", src, tmp_path / "n.gmc")
    assert r.returncode == 0, r.stderr
    assert "1 faces a mesh cannot hold" in r.stderr and "not stored" in r.stderr and "f:group name" in r.stderr
    r = run("decompress", tmp_path / "n.gmc", tmp_path / "back.obj")
    assert r.returncode == 0, r.stderr
    faces = sorted(line for line in (tmp_path / "back.obj").read_text().splitlines() if line.startswith("f "))
    assert faces == ["f 1 1 2", "f 1 2 3", "f 3 2 4"]


def test_python_load_and_save_keep_the_material_files(tmp_path):
    src = tmp_path / "named.obj"
    src.write_text(NAMED_OBJ)
    mesh = geom.load(src)
    assert geom.load_with_report(src).material_libraries == ["shop.mtl"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        geom.save(mesh, tmp_path / "same.obj")
    assert obj_names(tmp_path / "same.obj") == NAMES
    # A mesh made from it has the material names but not the files: said, or passed.
    moved = geom.Mesh(mesh.vertices + 1.0, mesh.faces)
    moved_names = geom.subdivide(mesh, levels=0).mesh
    with pytest.warns(UserWarning, match="no material file is known"):
        geom.save(moved_names, tmp_path / "made.obj")
    geom.save(moved_names, tmp_path / "passed.obj", material_libraries=["shop.mtl"])
    assert obj_names(tmp_path / "passed.obj") == NAMES
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        geom.save(moved, tmp_path / "unnamed.obj")  # names no material: nothing to say


def _two_octahedra_sharing_a_vertex():
    """Two octahedra touching at vertex 1 (a non-manifold vertex), as OBJ text."""
    import itertools
    verts, faces = [], []
    for cx in (0.0, 2.0):
        base = len(verts)
        pts = [(cx + 1, 0, 0), (cx - 1, 0, 0), (cx, 1, 0), (cx, -1, 0), (cx, 0, 1), (cx, 0, -1)]
        verts += pts
        for sx, sy, sz in itertools.product((0, 1), (2, 3), (4, 5)):
            tri = [base + sx, base + sy, base + sz]
            a, b, c = (pts[i - base] for i in tri)
            n = ((b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
                 (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
                 (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
            centre = (sum(p[0] for p in (a, b, c)) / 3 - cx, sum(p[1] for p in (a, b, c)) / 3,
                      sum(p[2] for p in (a, b, c)) / 3)
            if sum(x * y for x, y in zip(n, centre)) < 0:
                tri.reverse()
            faces.append(tri)
    # The second octahedron's vertex 1 (at x = 1) is the first one's vertex 0: share it.
    shared, dup = 0, 6 + 1
    faces = [[shared if i == dup else i - (i > dup) for i in f] for f in faces]
    del verts[dup]
    lines = [f"v {x} {y} {z}" for x, y, z in verts]
    lines += ["f " + " ".join(str(i + 1) for i in f) for f in faces]
    return "\n".join(lines) + "\n"


def test_simplify_keeps_a_non_manifold_vertex_one_vertex(run, tmp_path):
    src = tmp_path / "bowtie.obj"
    src.write_text(_two_octahedra_sharing_a_vertex())
    out = tmp_path / "out.obj"
    r = run("simplify", src, out, "--ratio", "0.9")
    assert r.returncode == 0, r.stderr
    assert "joined again (2 copies)" in r.stderr
    lines = out.read_text().splitlines()
    verts = [tuple(map(float, l.split()[1:4])) for l in lines if l.startswith("v ")]
    assert verts.count((1.0, 0.0, 0.0)) == 1  # the shared vertex, once, where it was
    shared = verts.index((1.0, 0.0, 0.0)) + 1
    faces = [[int(t.split("/")[0]) for t in l.split()[1:]] for l in lines if l.startswith("f ")]
    users = [f for f in faces if shared in f]
    # Faces of both octahedra use it: some lie left of x = 1, some right.
    xs = {verts[i - 1][0] > 1.0 for f in users for i in f if i != shared}
    assert xs == {True, False}


def test_batch_simplify_keeps_a_non_manifold_vertex_one_vertex(run, tmp_path):
    folder = tmp_path / "in"
    folder.mkdir()
    (folder / "bowtie.obj").write_text(_two_octahedra_sharing_a_vertex())
    r = run("batch", folder, tmp_path / "out", "--step", "simplify --ratio 0.9")
    assert r.returncode == 0, r.stderr
    lines = (tmp_path / "out" / "bowtie.obj").read_text().splitlines()
    verts = [tuple(map(float, l.split()[1:4])) for l in lines if l.startswith("v ")]
    assert verts.count((1.0, 0.0, 0.0)) == 1
