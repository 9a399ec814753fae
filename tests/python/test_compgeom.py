"""geom.delaunay / geom.voronoi / geom.convex_hull and the delaunay, voronoi, hull subcommands."""

import json

import numpy as np
import pytest

import geom


def _grid(n):
    x, y = np.meshgrid(np.arange(n, dtype=float), np.arange(n, dtype=float))
    return np.column_stack([x.ravel(), y.ravel()])


def test_delaunay_grid_and_duplicates():
    p = np.vstack([_grid(10), [[3.0, 4.0]]])
    r = geom.delaunay(p)
    assert r.triangles.shape == (2 * 9 * 9, 3)
    assert r.duplicates == 1
    assert r.vertex_of[-1] == 43
    a = p[r.triangles]
    area = (a[:, 1, 0] - a[:, 0, 0]) * (a[:, 2, 1] - a[:, 0, 1]) - \
           (a[:, 1, 1] - a[:, 0, 1]) * (a[:, 2, 0] - a[:, 0, 0])
    assert np.all(area > 0)


def test_delaunay_collinear_constraints_and_errors():
    r = geom.delaunay(np.array([[0, 0], [2, 2], [1, 1.0]]))
    assert r.collinear and list(r.chain) == [0, 2, 1]
    p = np.array([[0, 0], [1, 1], [0, 1], [1, 0], [0.5, 0.2]], float)
    r = geom.delaunay(p, segments=[[2, 3]])
    assert r.constrained_edges.shape == (1, 2)
    with pytest.raises(ValueError, match="segment 1"):
        geom.delaunay(p, segments=[[0, 1], [2, 3]])
    with pytest.raises(ValueError, match="point 1"):
        geom.delaunay(np.array([[0, 0], [np.nan, 1], [1, 0]]))
    with pytest.raises(TypeError):
        geom.delaunay(p, exactly=True)


def test_voronoi_cells_tile_the_clip_box():
    rng = np.random.default_rng(1)
    p = rng.random((300, 2))
    r = geom.voronoi(p, clip=(-1, -1, 2, 2))

    def area(c):
        x, y = c[:, 0], c[:, 1]
        return 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)

    assert sum(area(c) for c in r.cells) == pytest.approx(9.0, rel=1e-9)


def test_convex_hull_2d_and_3d():
    h2 = geom.convex_hull(_grid(5))
    assert sorted(h2.vertices) == [0, 4, 20, 24]
    cube = np.array([[x, y, z] for x in range(3) for y in range(3) for z in range(3)], float)
    h3 = geom.convex_hull(cube)
    assert len(h3.vertices) == 8 and h3.triangles.shape == (12, 3)
    flat = np.column_stack([_grid(4), np.zeros(16)])
    assert geom.convex_hull(flat).planar
    with pytest.raises(ValueError):
        geom.convex_hull(np.zeros((3, 4)))


def test_cli_delaunay_voronoi_hull(run, tmp_path):
    pts = tmp_path / "points.txt"
    pts.write_text("# grid\n" + "\n".join(f"{x},{y}" for x in range(4) for y in range(4)) + "\n")
    out = run("delaunay", pts, "-o", tmp_path / "tri.obj", "--json")
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["triangles"] == 18
    assert (tmp_path / "tri.obj").read_text().count("\nf ") + \
        (tmp_path / "tri.obj").read_text().startswith("f ") == 18
    out = run("voronoi", pts, "-o", tmp_path / "cells.svg", "--clip", "-1,-1,4,4")
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "cells.svg").read_text().count("<polygon") == 17
    assert run("voronoi", pts, "--clip", "1,2,3").returncode == 2
    p3 = tmp_path / "cube.xyz"
    p3.write_text("\n".join(f"{x} {y} {z}" for x in range(3) for y in range(3) for z in range(3)))
    out = run("hull", p3, "-o", tmp_path / "hull.obj", "--json")
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["hull_vertices"] == 8
    bad = tmp_path / "bad.txt"
    bad.write_text("0 0\n1 x\n")
    assert run("delaunay", bad).returncode == 1
