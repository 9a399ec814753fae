"""geom.render: numpy images, effects only when asked, scene errors naming the key."""

import json

import numpy as np
import pytest

import geom


def cube():
    v = np.array([[x, y, z] for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)], float)
    f = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    return geom.Mesh(v, f)


def test_render_returns_rgb_array_of_the_requested_size():
    img = geom.render(cube(), size=(64, 48), samples=1)
    assert img.shape == (48, 64, 3)
    assert img.dtype == np.uint8
    assert (img != 255).any(axis=2).sum() > 300  # the cube covers part of a white background


def test_effects_only_when_asked():
    _, plain = geom.render(cube(), size=(32, 32), return_stats=True)
    assert plain.path == "raster" and not plain.bvh_built
    assert plain.shadow_rays == 0 and plain.reflection_rays == 0
    _, shadowed = geom.render(cube(), size=(32, 32), shadows=True, return_stats=True)
    assert shadowed.path == "raytrace" and shadowed.bvh_built and shadowed.shadow_rays > 0
    _, flat = geom.render(cube(), size=(32, 32), flat=True, return_stats=True)
    assert not flat.normals_computed


def test_scene_file_with_instances(tmp_path):
    geom.save(cube(), str(tmp_path / "box.obj"))
    scene = {"image": {"width": 40, "height": 30, "samples": 1},
             "meshes": {"box": "box.obj"},
             "nodes": [{"mesh": "box"}, {"mesh": "box", "translate": [3, 0, 0]}]}
    (tmp_path / "s.json").write_text(json.dumps(scene))
    img, stats = geom.render(str(tmp_path / "s.json"), return_stats=True)
    assert img.shape == (30, 40, 3)
    assert stats.triangles == 24


def test_scene_errors(tmp_path):
    (tmp_path / "bad.json").write_text('{"meshes": {"a": "box.obj"}, "lights": [{"shadow": 1}]}')
    with pytest.raises(OSError):
        geom.render(str(tmp_path / "bad.json"))  # box.obj does not exist
    geom.save(cube(), str(tmp_path / "box.obj"))
    with pytest.raises(ValueError, match=r"lights\[0\]\.shadow"):
        geom.render(str(tmp_path / "bad.json"))
    with pytest.raises(OSError):
        geom.render(str(tmp_path / "missing.json"))
