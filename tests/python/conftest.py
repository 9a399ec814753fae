"""Shared fixtures for the Python tests.

The compiled module and the CLI come from a build tree: GEOM_BIN (default build/cli/geom) and
PYTHONPATH (default build/python, added here when `import geom` would otherwise fail), relative
to the repository root:

    PYTHONPATH=build/python GEOM_BIN=build/cli/geom /usr/bin/python3 -m pytest tests/python
"""

import os
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "data" / "sample.obj"
CORPUS = ROOT / "tests" / "corpus"


def _path_from_env(name, default):
    value = os.environ.get(name)
    path = pathlib.Path(value) if value else ROOT / default
    return path if path.is_absolute() else (pathlib.Path.cwd() / path).resolve()


GEOM_BIN = _path_from_env("GEOM_BIN", "build/cli/geom")

try:
    import geom  # noqa: F401
except ImportError:
    sys.path.insert(0, str(_path_from_env("GEOM_PYTHON_DIR", "build/python")))


def torus_mesh(nu=24, nv=12, R=1.0, r=0.35, lumps=0.05):
    """A closed genus-1 triangle mesh of 2·nu·nv faces (nu·nv vertices, i-major), on a torus
    made lumpy by `lumps` so that it is nowhere flat. Shared by the Python tests."""
    import numpy as np
    import geom
    a = 2 * np.pi * np.arange(nu) / nu
    b = 2 * np.pi * np.arange(nv) / nv
    A, B = np.meshgrid(a, b, indexing="ij")
    rr = r + lumps * np.sin(3 * A) * np.cos(2 * B)
    vertices = np.stack([(R + rr * np.cos(B)) * np.cos(A), (R + rr * np.cos(B)) * np.sin(A),
                         rr * np.sin(B)], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    at = lambda i, j: (i % nu) * nv + (j % nv)  # noqa: E731
    faces = np.concatenate([
        np.stack([at(i, j), at(i + 1, j), at(i + 1, j + 1)], -1).reshape(-1, 3),
        np.stack([at(i, j), at(i + 1, j + 1), at(i, j + 1)], -1).reshape(-1, 3)])
    return geom.Mesh(vertices, faces)


# Small meshes as OBJ text, shared by the CLI and io tests.
TETRAHEDRON_OBJ = """v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1
f 1 3 2
f 1 2 4
f 2 3 4
f 1 4 3
"""
# One triangle: an open disk (H = 1, chi = 1).
TRIANGLE_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
# Two triangles sharing an edge whose vertices are written twice (welding merges 2).
DUPLICATED_OBJ = """v 0 0 0
v 1 0 0
v 0 1 0
v 1 0 0
v 0 1 0
v 1 1 0
f 1 2 3
f 4 6 5
"""
# Two triangles that disagree on orientation across their shared edge.
FLIPPED_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 3 4\n"
# Three triangles on one edge (1-2): a non-manifold edge.
FIN_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n"


VALIDATOR = ROOT / "scripts" / "gltf-validate.mjs"


def pytest_configure(config):
    config.addinivalue_line("markers", "invalid_gltf: the test writes an invalid glTF on purpose")


def gltf_validator_errors(paths):
    """Run the Khronos glTF-Validator on `paths`; returns {path: [error lines]} for the files
    with errors (an empty dict when all are valid)."""
    import json
    r = subprocess.run(["node", str(VALIDATOR), *map(str, paths)], capture_output=True,
                       text=True, timeout=600)
    if r.returncode == 2 or (r.returncode and not r.stdout):
        pytest.fail(f"glTF-Validator did not run: {r.stderr.strip()}")
    bad = {}
    for line in r.stdout.splitlines():
        report = json.loads(line)
        if report["errors"]:
            bad[report["file"]] = report["messages"]
    return bad


@pytest.fixture(autouse=True)
def gltf_written_by_the_test_is_valid(request):
    """Every .gltf/.glb a test leaves in its tmp_path passes the Khronos glTF-Validator with
    no error (a test that writes an invalid one on purpose marks itself invalid_gltf)."""
    checked = ("tmp_path" in request.fixturenames
               and not request.node.get_closest_marker("invalid_gltf"))
    tmp = request.getfixturevalue("tmp_path") if checked else None  # before it is torn down
    yield
    if not checked:
        return
    written = sorted(p for p in tmp.rglob("*") if p.suffix.lower() in (".gltf", ".glb"))
    if written:
        bad = gltf_validator_errors(written)
        assert not bad, f"glTF-Validator errors: {bad}"


@pytest.fixture(scope="session")
def geom_bin():
    if not GEOM_BIN.is_file():
        pytest.fail(f"the geom binary is not built: {GEOM_BIN} (set GEOM_BIN)")
    return GEOM_BIN


@pytest.fixture
def run(geom_bin):
    """run(*args, stdin=None) -> CompletedProcess with text stdout/stderr (bytes with binary=True)."""

    def _run(*args, stdin=None, binary=False, cwd=None):
        return subprocess.run([str(geom_bin), *map(str, args)], input=stdin,
                              capture_output=True, text=not binary, timeout=300, cwd=cwd)

    return _run


@pytest.fixture
def meshes(tmp_path):
    """The small OBJ meshes above, written into a temporary folder: name -> path."""
    out = {}
    for name, text in [("tetrahedron", TETRAHEDRON_OBJ), ("triangle", TRIANGLE_OBJ),
                       ("duplicated", DUPLICATED_OBJ), ("flipped", FLIPPED_OBJ),
                       ("fin", FIN_OBJ)]:
        path = tmp_path / f"{name}.obj"
        path.write_text(text)
        out[name] = path
    return out
