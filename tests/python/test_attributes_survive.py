"""Attributes survive: simplify, lod and batch keep the texture coordinates and normals a mesh
holds without being asked (attribute-aware collapses), and what is not kept is named — the
progressive stream, which holds positions only, says so."""

import json
import os
import pathlib
import warnings

import numpy as np
import pytest

import geom
from conftest import ROOT

DATA = pathlib.Path(os.environ.get("GEOM_DATA_DIR", ROOT.parent / "shared" / "meshes"))


def textured_grid(path, n=12):
    """An n×n-quad wavy grid, triangulated, with a texture coordinate and a normal per corner
    (OBJ v/vt/vn): 2n² faces, (n+1)² vt lines."""
    lines = []
    for i in range(n + 1):
        for j in range(n + 1):
            lines.append(f"v {i / n} {j / n} {0.1 * np.sin(3 * i / n) * np.cos(2 * j / n):.6f}")
    for i in range(n + 1):
        for j in range(n + 1):
            lines.append(f"vt {i / n} {j / n}")
    lines.append("vn 0 0 1")
    at = lambda i, j: i * (n + 1) + j + 1  # noqa: E731
    for i in range(n):
        for j in range(n):
            a, b, c, d = at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)
            lines.append(f"f {a}/{a}/1 {b}/{b}/1 {c}/{c}/1")
            lines.append(f"f {a}/{a}/1 {c}/{c}/1 {d}/{d}/1")
    path.write_text("\n".join(lines) + "\n")
    return path


def count(path, prefix):
    return sum(1 for line in path.read_text().splitlines() if line.startswith(prefix))


def test_cli_simplify_keeps_uvs_and_normals_unless_told(run, tmp_path):
    src = textured_grid(tmp_path / "grid.obj")
    r = run("simplify", src, tmp_path / "s.obj", "--ratio", "0.3", "--json")
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""
    report = json.loads(r.stdout)
    assert report["attributes"] == ["normals", "uv"] and report["dropped_properties"] == []
    out = tmp_path / "s.obj"
    assert count(out, "f ") < 0.35 * 288
    assert count(out, "vt ") > 0 and count(out, "vn ") > 0
    assert all(line.count("/") == 6 for line in out.read_text().splitlines() if line.startswith("f "))

    r = run("simplify", src, tmp_path / "bare.obj", "--ratio", "0.3", "--attributes", "none")
    assert r.returncode == 0, r.stderr
    # (OBJ's vt/vn load per corner, and per vertex too where a vertex's corners agree.)
    assert "not carried to the output: v:normal, v:texcoord, h:texcoord, h:normal" in r.stderr
    assert count(tmp_path / "bare.obj", "vt ") == 0
    r = run("simplify", src, tmp_path / "x.obj", "--ratio", "0.3", "--attributes", "none,uv")
    assert r.returncode == 2 and "none cannot be combined" in r.stderr


def test_cli_lod_levels_keep_uvs_and_progressive_names_what_it_drops(run, tmp_path):
    src = textured_grid(tmp_path / "grid.obj")
    r = run("lod", src, tmp_path / "levels", "--levels", "2", "--format", "obj")
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""
    levels = sorted((tmp_path / "levels").glob("*.obj"))
    assert len(levels) == 2
    faces = [count(p, "f ") for p in levels]
    assert faces[0] > faces[1] and all(count(p, "vt ") > 0 for p in levels)

    r = run("progressive", src, tmp_path / "g.gpm")
    assert r.returncode == 0, r.stderr
    assert "a .gpm stream holds positions only; not stored: v:normal, v:texcoord, h:texcoord, h:normal" in r.stderr


def test_batch_simplify_keeps_uvs(run, tmp_path):
    folder = tmp_path / "in"
    folder.mkdir()
    textured_grid(folder / "grid.obj")
    r = run("batch", folder, tmp_path / "out", "--step", "simplify --ratio 0.3")
    assert r.returncode == 0, r.stderr
    assert count(tmp_path / "out" / "grid.obj", "vt ") > 0
    record = json.loads((tmp_path / "out" / "batch-report.jsonl").read_text().splitlines()[0])
    assert "warnings" not in record, record


def test_python_simplify_keeps_uvs_and_warns_naming_what_it_drops(tmp_path):
    mesh = geom.load(textured_grid(tmp_path / "grid.obj"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        kept = geom.simplify(mesh, ratio=0.3)
    assert kept.dropped_properties == []
    assert geom.present_attributes(kept.mesh) == ["normals", "uv"]
    with pytest.warns(UserWarning, match="not carried to the output: v:normal, v:texcoord, h:texcoord, h:normal"):
        bare = geom.simplify(mesh, ratio=0.3, attributes=())
    assert bare.dropped_properties == ["v:normal", "v:texcoord", "h:texcoord", "h:normal"]
    with pytest.warns(UserWarning, match="not carried to the output: v:normal, h:normal$"):
        geom.simplify(mesh, ratio=0.3, attributes=["uv"])
    with pytest.warns(UserWarning, match="ProgressiveMesh holds positions only; not kept: v:normal, v:texcoord, h:texcoord, h:normal"):
        geom.ProgressiveMesh(mesh)


@pytest.mark.skipif(not (DATA / "spot_triangulated.obj").is_file(), reason="GEOM_DATA_DIR not found")
def test_the_textured_spot_keeps_its_uvs_and_seams(run, tmp_path):
    """The issue's case: the 3,225-vt spot came out of simplify with none."""
    src = DATA / "spot_triangulated.obj"
    r = run("simplify", src, tmp_path / "spot.obj", "--ratio", "0.25")
    assert r.returncode == 0, r.stderr
    out = tmp_path / "spot.obj"
    vt = count(out, "vt ")
    # Seam vertices keep both sides: more texture coordinates than vertices, as in the input.
    assert vt > count(out, "v ") and 0.2 * 3225 < vt < 0.5 * 3225
    mesh = geom.load(out)
    assert geom.present_attributes(mesh) == ["uv"]
