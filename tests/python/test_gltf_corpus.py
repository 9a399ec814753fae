"""Every glTF sample model in ../shared/corpus (the Khronos sample models in all their variants:
plain, binary, embedded, Draco, quantized) reads, or is refused for a reason the corpus
explains (an external buffer of 4 MiB or more was not kept). The counts geom reads agree with
an independent reader written here from the specification (it reads only the JSON: accessor
counts, primitive modes, the node tree); a read -> write (OBJ, PLY, GLB) -> read round trip
keeps the topology; meshopt-compressed and quantized files made by gltfpack read to the same
shape as their source. Skipped when the corpus is absent."""

import json
import os
import pathlib
import struct
import subprocess
import urllib.parse

import pytest

from conftest import GEOM_BIN, ROOT

CORPUS = pathlib.Path(os.environ.get("GEOM_CORPUS_DIR", ROOT.parent / "shared" / "corpus"))
MODELS = CORPUS / "gltf-samples" / "Models"


def gltf_files():
    if not MODELS.is_dir():
        return []
    files = sorted(p for p in MODELS.rglob("*") if p.suffix in (".gltf", ".glb"))
    return [pytest.param(p, id=str(p.relative_to(MODELS))) for p in files]


def one_variant_per_model():
    """The GLB of each model (else its .gltf): the round-trip test's inputs."""
    chosen = {}
    for param in gltf_files():
        path = param.values[0]
        model = path.relative_to(MODELS).parts[0]
        rank = {"glTF-Binary": 0, "glTF": 1, "glTF-Embedded": 2}.get(path.parent.name)
        if rank is not None and (model not in chosen or rank < chosen[model][0]):
            chosen[model] = (rank, path)
    return [pytest.param(p, id=m) for m, (_, p) in sorted(chosen.items())]


def read_json(path):
    data = path.read_bytes()
    if data[:4] == b"glTF":
        length, = struct.unpack_from("<I", data, 12)
        return json.loads(data[20:20 + length])
    return json.loads(data)


def independent_counts(doc):
    """(vertices, triangles) of the default scene flattened, as geom flattens it: every mesh
    instance, triangle primitives only (strips and fans make n - 2 triangles)."""
    accessors, meshes, nodes = doc.get("accessors", []), doc.get("meshes", []), doc.get("nodes", [])

    def mesh_counts(m):
        v = t = 0
        for prim in meshes[m]["primitives"]:
            mode = prim.get("mode", 4)
            if mode < 4:
                continue
            nv = accessors[prim["attributes"]["POSITION"]]["count"]
            n = accessors[prim["indices"]]["count"] if "indices" in prim else nv
            v += nv
            t += n // 3 if mode == 4 else max(n - 2, 0)
        return v, t

    def visit(i):
        node = nodes[i]
        v, t = mesh_counts(node["mesh"]) if "mesh" in node else (0, 0)
        for c in node.get("children", []):
            cv, ct = visit(c)
            v, t = v + cv, t + ct
        return v, t

    if doc.get("scenes"):
        roots = doc["scenes"][doc.get("scene", 0)].get("nodes", [])
    else:
        children = {c for n in nodes for c in n.get("children", [])}
        roots = [i for i in range(len(nodes)) if i not in children]
    totals = [visit(r) for r in roots]
    return sum(v for v, _ in totals), sum(t for _, t in totals)


def missing_external_buffer(path, doc):
    for b in doc.get("buffers", []):
        uri = b.get("uri", "")
        if uri and not uri.startswith("data:"):
            if not (path.parent / urllib.parse.unquote(uri)).is_file():
                return uri
    return None


def geom(*args, cwd=None):
    return subprocess.run([str(GEOM_BIN), *map(str, args)], capture_output=True, text=True,
                          timeout=300, cwd=cwd)


@pytest.mark.skipif(not MODELS.is_dir(), reason="../shared/corpus not found")
@pytest.mark.parametrize("path", gltf_files())
def test_every_sample_reads_with_the_counts_of_an_independent_reader(path, tmp_path):
    doc = read_json(path)
    r = geom("convert", "--json", path, tmp_path / "out.obj")
    missing = missing_external_buffer(path, doc)
    if missing:
        assert r.returncode == 1 and "cannot open external buffer" in r.stderr, r.stderr
        return
    assert r.returncode == 0, r.stderr
    got = json.loads(r.stdout)
    assert (got["vertices"], got["faces"]) == independent_counts(doc)
    modes = {p.get("mode", 4) for m in doc.get("meshes", []) for p in m["primitives"]}
    assert ("point or line primitive" in r.stderr) == bool(modes & {0, 1, 2, 3}), r.stderr
    appearance = [e for e in doc.get("extensionsRequired", [])
                  if e.startswith("KHR_materials_") or e == "KHR_texture_transform"]
    for ext in appearance:
        assert ext in r.stderr


@pytest.mark.skipif(not MODELS.is_dir(), reason="../shared/corpus not found")
def test_a_gltf_named_without_a_folder_finds_its_buffers():
    folder = MODELS / "Duck" / "glTF"
    r = geom("info", "--json", "Duck.gltf", cwd=folder)
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["faces"] == 4212


def topology(path):
    r = geom("info", "--json", path)
    assert r.returncode == 0, r.stderr
    j = json.loads(r.stdout)
    return {k: j[k] for k in ("vertices", "faces", "components", "boundary_loops", "genus")}


@pytest.mark.skipif(not MODELS.is_dir(), reason="../shared/corpus not found")
@pytest.mark.parametrize("path", one_variant_per_model())
def test_round_trip_through_obj_ply_glb_keeps_topology(path, tmp_path):
    doc = read_json(path)
    if missing_external_buffer(path, doc):
        pytest.skip("external buffer not in the corpus (4 MiB or more)")
    if independent_counts(doc)[1] == 0:
        pytest.skip("no triangles")
    given = topology(path)
    for ext in ("obj", "ply", "glb"):
        out = tmp_path / f"out.{ext}"
        r = geom("convert", path, out)
        assert r.returncode == 0, r.stderr
        assert topology(out) == given, ext


GLTFPACK_MODELS = ["Duck/glTF-Binary/Duck.glb", "BoxTextured/glTF-Binary/BoxTextured.glb",
                   "CesiumMilkTruck/glTF-Binary/CesiumMilkTruck.glb",
                   "BoxVertexColors/glTF-Binary/BoxVertexColors.glb"]


def bounds(path):
    r = geom("info", "--json", path)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)["bounds"]


@pytest.mark.skipif(not MODELS.is_dir(), reason="../shared/corpus not found")
@pytest.mark.parametrize("flags", [["-c"], ["-cc"], ["-noq"], ["-c", "-noq"]],
                         ids=["meshopt+quantized", "meshopt-filters", "plain", "meshopt"])
@pytest.mark.parametrize("model", GLTFPACK_MODELS)
def test_gltfpack_output_reads_to_the_shape_of_its_source(model, flags, tmp_path):
    src = MODELS / model
    if not src.is_file():
        pytest.skip(f"{model} not in the corpus")
    out = tmp_path / "packed.glb"
    r = subprocess.run(["gltfpack", "-i", str(src), "-o", str(out), *flags], capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    packed = read_json(out)
    used = set(packed.get("extensionsUsed", []))
    if "-c" in flags or "-cc" in flags:
        assert "EXT_meshopt_compression" in used
    if "-noq" not in flags:
        assert "KHR_mesh_quantization" in used
    r = geom("convert", "--json", out, tmp_path / "packed.obj")
    assert r.returncode == 0, r.stderr
    got = json.loads(r.stdout)
    assert (got["vertices"], got["faces"]) == independent_counts(packed)
    # gltfpack welds and reorders, but the shape stays: same bounds to its 14-bit quantisation.
    a, b = bounds(src), bounds(tmp_path / "packed.obj")
    size = max(hi - lo for lo, hi in zip(a["min"], a["max"]))
    for k in ("min", "max"):
        for x, y in zip(a[k], b[k]):
            assert abs(x - y) <= 2e-4 * size, (k, a, b)
    out.unlink()  # gltfpack's file, not geom's: the validator hook checks what geom writes
