"""`geom info --json` on every shared mesh agrees with MANIFEST.md, whose columns were counted
by an independent checker script (not by geom). Skipped when GEOM_DATA_DIR is absent."""

import json
import os
import pathlib
import subprocess

import pytest

from conftest import GEOM_BIN

REPO = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(os.environ.get("GEOM_DATA_DIR", REPO.parent / "shared" / "meshes"))


def manifest_rows():
    manifest = DATA / "MANIFEST.md"
    if not manifest.is_file():
        return []
    rows = []
    for line in manifest.read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 16 or not cells[0].startswith("`"):
            continue
        name = cells[0].strip("`")
        rows.append(pytest.param(name, cells, id=name))
    return rows


def total_genus(cell):
    """'1' -> 1, '0,0,0' -> 0, '0x29 1x1 6x1' -> 7, 'n/a …' -> None."""
    if cell.startswith("n/a"):
        return None
    total = 0
    for part in cell.replace(",", " ").split():
        genus, _, count = part.partition("x")
        total += int(genus) * (int(count) if count else 1)
    return total


@pytest.mark.skipif(not (DATA / "MANIFEST.md").is_file(), reason="GEOM_DATA_DIR not found")
@pytest.mark.parametrize("name,cells", manifest_rows())
def test_info_matches_manifest(name, cells):
    (vertices, faces, _polygons, closed, manifold, oriented, components, loops,
     genus) = cells[6:15]
    r = subprocess.run([str(GEOM_BIN), "info", "--json", str(DATA / name)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    info = json.loads(r.stdout)
    assert info["vertices"] == int(vertices)
    assert info["faces"] == int(faces)
    assert info["closed"] == (closed == "yes")
    assert info["manifold"] == (manifold.lower() == "yes")
    assert info["consistently_oriented"] == (oriented == "yes")
    assert info["components"] == int(components)
    assert info["boundary_loops"] == int(loops)
    assert info["genus"] == total_genus(genus)
    # χ of the surface (unreferenced vertices are not part of it) is what the surface form
    # says: 2(C − G) − H.
    if info["genus"] is not None:
        assert info["euler_characteristic"] == 2 * (info["components"] - info["genus"]) \
            - info["boundary_loops"]
