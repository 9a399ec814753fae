"""Every glTF sample model in ../shared/corpus (the Khronos sample models in all their variants:
plain, binary, embedded, Draco, quantized) reads, or is refused for a reason the corpus
explains (an external buffer of 4 MiB or more was not kept). The counts geom reads agree with
an independent reader written here from the specification (it reads only the JSON: accessor
counts, primitive modes, the node tree); a read -> write (OBJ, PLY, GLB) -> read round trip
keeps the topology; meshopt-compressed and quantized files made by gltfpack read to the same
shape as their source. Skipped when the corpus is absent."""

import base64
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


COMPONENTS = {5120: ("b", 127.0), 5121: ("B", 255.0), 5122: ("h", 32767.0),
              5123: ("H", 65535.0), 5125: ("I", None), 5126: ("f", None)}
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


class Buffers:
    """Plain accessors of a .gltf or .glb, decoded from the specification: buffer views,
    offsets, strides, normalized integers, sparse substitution. Draco and meshopt streams are
    not decoded (decodable() says so)."""

    def __init__(self, path, doc):
        self.doc, self.data = doc, []
        raw = path.read_bytes()
        for b in doc.get("buffers", []):
            uri = b.get("uri")
            if uri is None:  # the GLB's BIN chunk
                json_len, = struct.unpack_from("<I", raw, 12)
                self.data.append(raw[20 + json_len + 8:])
            elif uri.startswith("data:"):
                self.data.append(base64.b64decode(uri.split(",", 1)[1]))
            else:
                self.data.append((path.parent / urllib.parse.unquote(uri)).read_bytes())

    def decodable(self, prim):
        if "KHR_draco_mesh_compression" in prim.get("extensions", {}):
            return False
        views = self.doc.get("bufferViews", [])
        accs = [self.doc["accessors"][a] for a in prim["attributes"].values()]
        return all("EXT_meshopt_compression" not in views[a["bufferView"]].get("extensions", {})
                   for a in accs if "bufferView" in a)

    def accessor(self, a):
        acc = self.doc["accessors"][a]
        fmt, scale = COMPONENTS[acc["componentType"]]
        n, count = WIDTH[acc["type"]], acc["count"]
        size = struct.calcsize(fmt)

        def norm(x):
            if not acc.get("normalized") or scale is None:
                return float(x)
            return max(x / scale, -1.0)

        out = [[0.0] * n for _ in range(count)]
        if "bufferView" in acc:
            view = self.doc["bufferViews"][acc["bufferView"]]
            data = self.data[view["buffer"]]
            stride = view.get("byteStride") or size * n
            base = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
            for i in range(count):
                out[i] = [norm(x) for x in struct.unpack_from("<" + fmt * n, data, base + i * stride)]
        if "sparse" in acc:
            sp = acc["sparse"]
            iv = self.doc["bufferViews"][sp["indices"]["bufferView"]]
            ifmt = COMPONENTS[sp["indices"]["componentType"]][0]
            at = struct.unpack_from("<" + ifmt * sp["count"], self.data[iv["buffer"]],
                                    iv.get("byteOffset", 0) + sp["indices"].get("byteOffset", 0))
            vv = self.doc["bufferViews"][sp["values"]["bufferView"]]
            vals = struct.unpack_from("<" + fmt * (n * sp["count"]), self.data[vv["buffer"]],
                                      vv.get("byteOffset", 0) + sp["values"].get("byteOffset", 0))
            for k, i in enumerate(at):
                out[i] = [norm(x) for x in vals[k * n:(k + 1) * n]]
        return out


def independent_counts(doc, path=None):
    """(vertices, triangles) of the default scene flattened, as geom flattens it: every mesh
    instance, triangle primitives only (strips and fans make n - 2 triangles). A mesh is one
    welded mesh: its vertices are its distinct (position, colour) pairs (colour when every
    triangle primitive has COLOR_0), counted by decoding the accessors when `path` is given
    and the data is plain; otherwise vertices is None and only triangles are compared."""
    accessors, meshes, nodes = doc.get("accessors", []), doc.get("meshes", []), doc.get("nodes", [])
    buffers = Buffers(path, doc) if path else None

    def mesh_counts(m):
        keys, t, plain = set(), 0, buffers is not None
        prims = [p for p in meshes[m]["primitives"] if p.get("mode", 4) >= 4]
        colours = all("COLOR_0" in p["attributes"] for p in prims)
        for prim in prims:
            nv = accessors[prim["attributes"]["POSITION"]]["count"]
            n = accessors[prim["indices"]]["count"] if "indices" in prim else nv
            t += n // 3 if prim.get("mode", 4) == 4 else max(n - 2, 0)
            plain = plain and buffers.decodable(prim)
            if plain:
                pos = buffers.accessor(prim["attributes"]["POSITION"])
                col = buffers.accessor(prim["attributes"]["COLOR_0"]) if colours else [[0.0] * 3] * nv
                for p, c in zip(pos, col):  # + 0.0: -0 and +0 alike
                    keys.add((p[0] + 0.0, p[1] + 0.0, p[2] + 0.0, *c[:3]))
        return (len(keys) if plain else None), t

    def visit(i):
        node = nodes[i]
        v, t = mesh_counts(node["mesh"]) if "mesh" in node else (0, 0)
        for c in node.get("children", []):
            cv, ct = visit(c)
            v = None if v is None or cv is None else v + cv
            t += ct
        return v, t

    if doc.get("scenes"):
        roots = doc["scenes"][doc.get("scene", 0)].get("nodes", [])
    else:
        children = {c for n in nodes for c in n.get("children", [])}
        roots = [i for i in range(len(nodes)) if i not in children]
    totals = [visit(r) for r in roots]
    vertices = [v for v, _ in totals]
    return (None if None in vertices else sum(vertices)), sum(t for _, t in totals)


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
    vertices, triangles = independent_counts(doc, path)
    assert got["faces"] == triangles
    if vertices is not None:  # Draco and meshopt data are not decoded here
        assert got["vertices"] == vertices
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
    vertices, triangles = independent_counts(packed, out)
    assert got["faces"] == triangles
    if vertices is not None:
        assert got["vertices"] == vertices
    # gltfpack welds and reorders, but the shape stays: same bounds to its 14-bit quantisation.
    a, b = bounds(src), bounds(tmp_path / "packed.obj")
    size = max(hi - lo for lo, hi in zip(a["min"], a["max"]))
    for k in ("min", "max"):
        for x, y in zip(a[k], b[k]):
            assert abs(x - y) <= 2e-4 * size, (k, a, b)
    out.unlink()  # gltfpack's file, not geom's: the validator hook checks what geom writes
