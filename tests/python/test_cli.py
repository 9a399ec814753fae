"""The `geom` command-line tool: exit codes, --help, JSON output, the overwrite rule, the tour
and every malformed file in tests/corpus."""

import hashlib
import json

import pytest

from conftest import CORPUS, SAMPLE

# The foundation's subcommands; every subcommand `geom --help` lists gets its --help checked too.
COMMANDS = ["info", "convert", "validate", "repair", "tour", "batch"]

SAMPLE_COUNTS = {"vertices": 1536, "edges": 3168, "faces": 1632, "boundary_loops": 0,
                 "components": 1, "euler_characteristic": 0, "genus": 1}


def digest(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


def one_line(stderr):
    lines = [line for line in stderr.splitlines() if line.strip()]
    assert len(lines) == 1, f"expected one line on stderr, got: {stderr!r}"
    return lines[0]


def corpus_files():
    if not CORPUS.is_dir():
        return []
    return sorted(p for p in CORPUS.rglob("*")
                  if p.is_file() and p.suffix.lower() not in (".md", ".txt")
                  and not p.name.startswith((".", "README")))


# ---- parser ------------------------------------------------------------------------------

def test_help_lists_every_subcommand(run):
    r = run("--help")
    assert r.returncode == 0
    for command in COMMANDS:
        assert command in r.stdout


def listed_subcommands(run):
    text = run("--help").stdout
    listed = text[text.index("Subcommands:"):].splitlines()[1:]
    return [line.split()[0] for line in listed if line.startswith("  ") and line.strip()]


def test_every_subcommand_has_help(run):
    commands = listed_subcommands(run)
    assert set(COMMANDS) <= set(commands)
    for command in commands:
        r = run(command, "--help")
        assert r.returncode == 0, (command, r.stderr)
        assert "Usage" in r.stdout and command in r.stdout, command
        assert run(command, "--no-such-option").returncode == 2, command


def test_version(run):
    r = run("--version")
    assert r.returncode == 0 and "geom" in r.stdout


@pytest.mark.parametrize("args", [[], ["nonsense"], ["info"], ["info", "--no-such-option", "x"],
                                  ["convert", "only-one.obj"],
                                  ["convert", "a.obj", "b.ply", "--binary", "--ascii"],
                                  ["convert", "a.obj", "b.obj", "--drc-bits", "99"],
                                  ["validate", "a.obj", "--manifold=maybe"]])
def test_usage_errors_exit_2(run, args):
    assert run(*args).returncode == 2


# ---- info --------------------------------------------------------------------------------

def test_info_text(run):
    r = run("info", SAMPLE)
    assert r.returncode == 0, r.stderr
    assert "genus" in r.stdout and "1536" in r.stdout and r.stderr == ""


def test_info_json_sample(run):
    r = run("info", "--json", SAMPLE)
    assert r.returncode == 0, r.stderr
    j = json.loads(r.stdout)
    for key, value in SAMPLE_COUNTS.items():
        assert j[key] == value, key
    assert j["manifold"] and j["closed"] and j["orientable"]
    assert j["face_sizes"] == {"3": 216, "4": 1392, "5": 24}
    assert j["repairs"]["changed"] is False
    assert len(j["bounds"]["min"]) == 3 and len(j["bounds"]["max"]) == 3
    assert all(lo < hi for lo, hi in zip(j["bounds"]["min"], j["bounds"]["max"]))


def test_info_json_keys_and_null_genus(run, meshes):
    j = json.loads(run("info", "--json", meshes["fin"]).stdout)
    for key in ["vertices", "edges", "faces", "boundary_loops", "components",
                "euler_characteristic", "genus", "manifold", "closed", "orientable", "repairs",
                "face_sizes", "bounds"]:
        assert key in j
    assert j["manifold"] is False and j["genus"] is None
    assert j["repairs"]["split_nonmanifold_edges"] >= 1


def test_info_open_disk(run, meshes):
    j = json.loads(run("info", "--json", meshes["triangle"]).stdout)
    assert (j["vertices"], j["edges"], j["faces"], j["boundary_loops"]) == (3, 3, 1, 1)
    assert j["euler_characteristic"] == 1 and j["genus"] == 0 and j["closed"] is False


def test_info_reports_repairs(run, meshes):
    j = json.loads(run("info", "--json", meshes["flipped"]).stdout)
    assert j["repairs"]["flipped_faces"] == 1
    assert j["repairs"]["messages"]


def test_info_stdin(run):
    r = run("info", "--json", "-", stdin=SAMPLE.read_text())
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["faces"] == 1632


def test_info_quiet(run):
    r = run("info", "--quiet", SAMPLE)
    assert r.returncode == 0 and r.stdout == ""


@pytest.mark.parametrize("name", ["missing.obj", "missing.ply"])
def test_info_missing_file(run, tmp_path, name):
    r = run("info", tmp_path / name)
    assert r.returncode == 1
    assert name in one_line(r.stderr)


def test_info_unknown_format(run, tmp_path):
    path = tmp_path / "mesh.xyz"
    path.write_text("hello, world\n")
    r = run("info", path)
    assert r.returncode == 1
    assert "mesh.xyz" in one_line(r.stderr)


NO_GEOMETRY = {
    "notes.obj": "# exported by nothing\nmtllib scene.mtl\ng empty\n",
    "blank.obj": "",
    "empty.ply": "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                 "property float z\nend_header\n",
}


@pytest.mark.parametrize("name", NO_GEOMETRY)
def test_file_without_geometry_fails_naming_it(run, tmp_path, name):
    path = tmp_path / name
    path.write_text(NO_GEOMETRY[name])
    out = tmp_path / "out.ply"
    for args in (["info", path], ["convert", path, out]):
        r = run(*args)
        assert r.returncode == 1, f"{args[0]}: exit {r.returncode}; stdout {r.stdout!r}"
        line = one_line(r.stderr)
        assert name in line and "no geometry" in line, line
    assert not out.exists()


def test_batch_counts_a_file_without_geometry_as_failed(run, meshes, tmp_path):
    folder = tmp_path / "in"
    folder.mkdir()
    (folder / "good.obj").write_text(meshes["tetrahedron"].read_text())
    (folder / "notes.obj").write_text(NO_GEOMETRY["notes.obj"])
    r = run("batch", folder, tmp_path / "out", "--step", "validate", "--json", "--quiet")
    assert r.returncode == 1, r.stderr
    summary = json.loads(r.stdout)
    assert summary["ok"] == 1 and summary["failed"] == 1
    report = (tmp_path / "out" / "batch-report.jsonl").read_text().splitlines()
    failed = [rec for rec in map(json.loads, report) if rec.get("status") == "failed"]
    assert len(failed) == 1 and "notes.obj" in failed[0]["input"]
    assert "no geometry" in failed[0]["error"]


def test_corpus_is_present():
    assert corpus_files(), f"no malformed files in {CORPUS}"


@pytest.mark.parametrize("path", corpus_files(), ids=lambda p: str(p.relative_to(CORPUS)))
def test_info_rejects_malformed_file(run, path):
    r = run("info", path)
    assert r.returncode == 1, f"exit {r.returncode}; stdout {r.stdout[:200]!r}"
    assert path.name in one_line(r.stderr)


# A 240-byte Draco 2.0 point cloud (found by fuzz_compgeom) whose header declares 16.8M
# points: libdraco allocates 3.7 GB for them before it reads the data. Kept out of the corpus,
# which is read without a memory limit.
DRC_CLAIMS_16M_POINTS = (
    "RFJBQ08CAAAAMAEBAQEBAQEBAS0BAQEBAQEBAQEBAQEBAQEBAQ0AAAABAQEBAQEcDAEBAQEBAQEBAQEBAQEBAQEBAQEB"
    "AQEBAQEBAQEBAQEBAQEBAQEBAQEBAQEBAQEBDAwMAQEBAQEBAQEBAQEBAQEBAQEMDAwMDAxDQ0NDQ0NDQ0NDQ0NDQ0ND"
    "Q0NDQ0NDQ0NDQ0NDQ0NDQ0NDQ0NDQ0NDQ0NDQ0NDQ0NDQ0NDQ0NDQ0NDQ0NDQ0NDQ0MxIAo0GS4BAQEBAQEBAQEBAQEB"
    "AQEBAQUBAQEBAQEBAQEBAQwMDAwMDDEgCjQZLjAK")


def test_info_names_the_drc_file_whose_counts_exhaust_memory(geom_bin, tmp_path):
    import base64
    import resource
    import subprocess
    path = tmp_path / "claims_16m_points.drc"
    path.write_bytes(base64.b64decode(DRC_CLAIMS_16M_POINTS))
    gib = 1 << 30

    def limit_memory():
        resource.setrlimit(resource.RLIMIT_AS, (gib, gib))

    r = subprocess.run([str(geom_bin), "info", str(path)], capture_output=True, text=True,
                       timeout=120, preexec_fn=limit_memory)
    assert r.returncode == 1, r.stderr
    line = one_line(r.stderr)
    assert path.name in line and "ran out of memory" in line, line


# ---- convert -------------------------------------------------------------------------------

@pytest.mark.parametrize("name,extra,faces", [
    ("out.obj", [], 1632), ("out.ply", [], 1632), ("out_ascii.ply", ["--ascii"], 1632),
    ("out.off", [], 1632), ("out.stl", [], 3072), ("out_ascii.stl", ["--ascii"], 3072),
    ("out.drc", [], None), ("out.glb", [], 3072), ("out.gltf", [], 3072)])
def test_convert_every_format(run, tmp_path, name, extra, faces):
    out = tmp_path / name
    r = run("convert", SAMPLE, out, *extra)
    assert r.returncode == 0, r.stderr
    j = json.loads(run("info", "--json", out).stdout)
    assert j["vertices"] == 1536
    if faces is not None:
        assert j["faces"] == faces
    assert j["genus"] == 1 and j["closed"]


@pytest.mark.parametrize("name,unstored", [("out.stl", 1), ("out.drc", 1), ("out.glb", 0),
                                           ("out.obj", 0), ("out.ply", 0), ("out.off", 0)])
def test_convert_warns_about_vertices_the_format_cannot_store(run, tmp_path, name, unstored):
    # STL holds triangles only and a Draco mesh the vertices of its faces; glTF keeps a vertex
    # no face uses beside triangles.
    src = tmp_path / "isolated.obj"
    src.write_text("v 0 0 0\nv 5 5 5\nv 1 0 0\nv 0 1 0\nf 1 3 4\n")
    r = run("convert", src, tmp_path / name)
    assert r.returncode == 0, r.stderr
    if unstored:
        assert f"{name}: 1 vertex that no face uses is not stored" in one_line(r.stderr)
    else:
        assert r.stderr.strip() == ""
        assert json.loads(run("info", "--json", tmp_path / name).stdout)["vertices"] == 4
    assert run("convert", "--quiet", src, tmp_path / ("q" + name)).stderr.strip() == ""


def test_convert_points_only_to_gltf_warns_that_nothing_is_stored(run, tmp_path):
    src = tmp_path / "points.obj"
    src.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\n")
    r = run("convert", src, tmp_path / "points.glb")
    assert r.returncode == 0, r.stderr
    assert "3 vertices that no face uses are not stored (glb" in one_line(r.stderr)
    # A glTF without meshes holds no geometry, which is an error to read.
    r = run("info", "--json", tmp_path / "points.glb")
    assert r.returncode == 1 and "points.glb: no geometry" in one_line(r.stderr)


def test_convert_ascii_and_binary_differ(run, tmp_path):
    run("convert", SAMPLE, tmp_path / "a.ply", "--ascii")
    run("convert", SAMPLE, tmp_path / "b.ply", "--binary")
    assert b"format ascii" in (tmp_path / "a.ply").read_bytes()[:200]
    assert b"format binary" in (tmp_path / "b.ply").read_bytes()[:200]


def test_convert_json(run, tmp_path):
    r = run("convert", "--json", SAMPLE, tmp_path / "x.off")
    assert r.returncode == 0
    j = json.loads(r.stdout)
    assert j["vertices"] == 1536 and j["faces"] == 1632


def test_convert_weld(run, meshes, tmp_path):
    out = tmp_path / "welded.obj"
    assert run("convert", meshes["duplicated"], out).returncode == 0
    assert json.loads(run("info", "--json", out).stdout)["vertices"] == 6
    for weld in (["--weld", "0"], ["--weld"], ["--weld=1e-9"]):
        assert run("convert", meshes["duplicated"], out, *weld).returncode == 0
        j = json.loads(run("info", "--json", out).stdout)
        assert j["vertices"] == 4 and j["boundary_loops"] == 1, weld
    assert run("convert", "--weld", meshes["duplicated"], out).returncode == 0
    assert json.loads(run("info", "--json", out).stdout)["vertices"] == 4


def test_convert_to_stdout(run):
    r = run("convert", SAMPLE, "-", "--format", "off")
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("OFF")


def test_convert_to_stdout_needs_format(run):
    r = run("convert", SAMPLE, "-")
    assert r.returncode == 2
    assert "--format" in r.stderr


def test_convert_stdin_to_file(run, tmp_path):
    out = tmp_path / "from_stdin.ply"
    r = run("convert", "-", out, stdin=SAMPLE.read_text())
    assert r.returncode == 0, r.stderr
    assert json.loads(run("info", "--json", out).stdout)["faces"] == 1632


def test_convert_never_overwrites_input(run, tmp_path):
    src = tmp_path / "in.obj"
    src.write_text(SAMPLE.read_text())
    before = digest(src)
    for target in (src, tmp_path / "." / "in.obj"):
        r = run("convert", src, target)
        assert r.returncode == 2
        assert "--force" in r.stderr
        assert digest(src) == before


def test_convert_force_overwrites(run, tmp_path):
    src = tmp_path / "in.obj"
    src.write_text(SAMPLE.read_text())
    assert run("convert", src, src, "--force").returncode == 0
    assert json.loads(run("info", "--json", src).stdout)["faces"] == 1632


def test_convert_unwritable_output(run, tmp_path):
    r = run("convert", SAMPLE, tmp_path / "no" / "such" / "dir" / "x.ply")
    assert r.returncode == 1
    one_line(r.stderr)


# ---- output names --------------------------------------------------------------------------

POINTS_2D = "0 0\n1 0\n0 1\n1 1\n0.3 0.6\n"


@pytest.mark.parametrize("args,option,bad", [
    (["render", SAMPLE, "-o", "{tmp}/y.obj"], "-o/--output", "y.obj"),
    (["render", SAMPLE, "-o", "-"], "-o/--output", "'-'"),
    (["montage", SAMPLE, "-o", "{tmp}/m.jpg"], "-o/--output", "m.jpg"),
    (["compress", SAMPLE, "{tmp}/out.obj"], "output", "out.obj"),
    (["progressive", SAMPLE, "{tmp}/out.ply"], "output", "out.ply"),
    (["voronoi", "{tmp}/p.txt", "-o", "{tmp}/cells.png"], "-o/--output", "cells.png"),
    (["delaunay", "{tmp}/p.txt", "-o", "{tmp}/tri.png"], "-o/--output", "tri.png"),
    (["hull", "{tmp}/p.txt", "-o", "{tmp}/hull.txt"], "-o/--output", "hull.txt"),
    (["lod", SAMPLE, "{tmp}/levels", "--gltf", "{tmp}/chain.obj"], "--gltf", "chain.obj"),
    (["batch", "{tmp}/in", "{tmp}/out", "--step", "validate", "--report", "{tmp}/r.obj"],
     "--report", "r.obj"),
])
def test_output_name_must_say_what_is_written(run, tmp_path, args, option, bad):
    # Exit 2 before any work: render used to put PNG bytes into y.obj.
    (tmp_path / "p.txt").write_text(POINTS_2D)
    (tmp_path / "in").mkdir()
    before = set(tmp_path.rglob("*"))
    r = run(*[str(a).replace("{tmp}", str(tmp_path)) for a in args])
    assert r.returncode == 2, r.stderr
    line = one_line(r.stderr)
    assert option in line and bad in line and "must end in" in line, line
    assert set(tmp_path.rglob("*")) == before


def test_output_name_extension_is_case_insensitive(run, tmp_path):
    (tmp_path / "p.txt").write_text(POINTS_2D)
    assert run("compress", SAMPLE, tmp_path / "OUT.GMC", "--quiet").returncode == 0
    cells = tmp_path / "cells.SVG"
    assert run("voronoi", tmp_path / "p.txt", "-o", cells, "--quiet").returncode == 0


def test_mesh_output_with_unknown_extension_is_refused(run, tmp_path):
    # format_from_path decides mesh outputs: an unknown extension is refused naming the file.
    r = run("convert", SAMPLE, tmp_path / "out.png")
    assert r.returncode == 1
    assert "out.png" in one_line(r.stderr)
    assert not (tmp_path / "out.png").exists()


# ---- validate ------------------------------------------------------------------------------

def test_validate_sample_all(run):
    r = run("validate", SAMPLE, "--manifold", "--closed", "--oriented")
    assert r.returncode == 0, r.stdout + r.stderr
    assert run("validate", SAMPLE, "--all").returncode == 0


def test_validate_without_flags_accepts_open_mesh(run, meshes):
    assert run("validate", meshes["triangle"]).returncode == 0


def test_validate_closed_fails_on_open_mesh(run, meshes):
    r = run("validate", meshes["triangle"], "--closed")
    assert r.returncode == 1
    assert "not closed" in r.stdout and "1 boundary loops" in r.stdout


def test_validate_manifold_fails_on_fin(run, meshes):
    r = run("validate", meshes["fin"], "--manifold")
    assert r.returncode == 1
    assert "not manifold" in r.stdout


def test_validate_oriented_fails_on_flipped(run, meshes):
    r = run("validate", meshes["flipped"], "--oriented")
    assert r.returncode == 1
    assert "disagree" in r.stdout
    assert run("validate", meshes["flipped"], "--manifold").returncode == 0


def test_validate_json(run, meshes):
    r = run("validate", "--json", meshes["triangle"], "--closed", "--manifold")
    assert r.returncode == 1
    j = json.loads(r.stdout)
    assert j["ok"] is False and len(j["problems"]) == 1


def test_validate_bad_file(run, tmp_path):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 zero\nf 1 2 3\n")
    r = run("validate", bad)
    assert r.returncode == 1
    assert "bad.obj" in one_line(r.stderr)


# ---- repair --------------------------------------------------------------------------------

def test_repair_orients(run, meshes, tmp_path):
    out = tmp_path / "fixed.ply"
    r = run("repair", meshes["flipped"], out)
    assert r.returncode == 0, r.stderr
    assert "flip" in r.stdout.lower() or "orient" in r.stdout.lower()
    assert run("validate", out, "--oriented").returncode == 0


def test_repair_welds_and_reports_json(run, meshes, tmp_path):
    out = tmp_path / "fixed.obj"
    r = run("repair", "--json", meshes["duplicated"], "-o", out)
    assert r.returncode == 0, r.stderr
    j = json.loads(r.stdout)
    assert j["welded_vertices"] == 2 and j["vertices"] == 4


def test_repair_splits_nonmanifold(run, meshes, tmp_path):
    out = tmp_path / "fixed.obj"
    assert run("repair", meshes["fin"], out).returncode == 0
    assert run("validate", out, "--manifold").returncode == 0


def test_repair_needs_output(run, meshes):
    assert run("repair", meshes["flipped"]).returncode == 2


def test_repair_never_overwrites_input(run, meshes):
    before = digest(meshes["flipped"])
    r = run("repair", meshes["flipped"], meshes["flipped"])
    assert r.returncode == 2
    assert digest(meshes["flipped"]) == before


# ---- tour ----------------------------------------------------------------------------------

def test_tour_default_sample(run, tmp_path):
    out = tmp_path / "out"
    r = run("tour", "-o", out)
    assert r.returncode == 0, r.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["ok"] is True
    assert set(summary["steps"]) >= {"core", "io"}
    assert all(step["ok"] for step in summary["steps"].values())
    assert (out / "summary.md").read_text().startswith("# geom tour")
    for f in summary["files"]:
        assert (out / f["path"]).is_file(), f
    assert summary["steps"]["core"]["input"]["genus"] == 1
    # What the compression page claims: the decoded surface stays within the vertex bound
    # (it did not while polygons lost their first corner: 0.031 against 8.3e-5 at 14 bits).
    for run_ in summary["steps"]["compress"]["runs"]:
        assert run_["hausdorff"] <= run_["error_bound"], run_
    # Non-manifold input refined as given: V + E + F vertices at level 1, nothing split apart.
    fin = summary["steps"]["subdivision"]["as_given"]
    assert (fin["nonmanifold_edges"], fin["level1_vertices"], fin["level2_vertices"]) == (1, 21, 65)


def test_tour_given_file_and_json(run, meshes, tmp_path):
    out = tmp_path / "t"
    r = run("tour", meshes["tetrahedron"], "-o", out, "--json", "--quiet")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["steps"]["core"]["input"]["euler_characteristic"] == 2
    assert (out / "tetrahedron.ply").is_file()


def test_tour_default_output_folder(run, tmp_path):
    assert run("tour", "--quiet", cwd=tmp_path).returncode == 0
    assert (tmp_path / "out" / "summary.md").is_file()


def test_tour_does_not_overwrite_input(run, tmp_path):
    src = tmp_path / "sample.obj"
    src.write_text(SAMPLE.read_text())
    before = digest(src)
    r = run("tour", src, "-o", tmp_path, "--quiet")
    assert r.returncode != 0
    assert digest(src) == before


def test_tour_bad_input(run, tmp_path):
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n")
    r = run("tour", bad, "-o", tmp_path / "o")
    assert r.returncode == 1
    assert "bad.off" in one_line(r.stderr)


# ---- progress ------------------------------------------------------------------------------

def run_with_terminal_stderr(geom_bin, *args):
    """Runs geom with stderr on a pseudo-terminal; returns (process, what stderr showed)."""
    import os
    import pty
    import subprocess

    master, slave = pty.openpty()
    try:
        r = subprocess.run([str(geom_bin), *map(str, args)], stdout=subprocess.PIPE,
                           stderr=slave, timeout=120)
    finally:
        os.close(slave)
    chunks = []
    try:
        while True:
            try:
                data = os.read(master, 4096)
            except OSError:  # EIO: the terminal's other side is closed
                break
            if not data:
                break
            chunks.append(data)
    finally:
        os.close(master)
    return r, b"".join(chunks).decode(errors="replace")


def test_progress_only_on_a_terminal(geom_bin, run):
    r, shown = run_with_terminal_stderr(geom_bin, "info", "--json", SAMPLE)
    assert r.returncode == 0
    assert json.loads(r.stdout)["faces"] == 1632  # stdout untouched by the bar
    assert "sample.obj" in shown and "reading" in shown
    assert run("info", SAMPLE).stderr == ""  # not a terminal: no bar
    r, shown = run_with_terminal_stderr(geom_bin, "info", "--quiet", SAMPLE)
    assert r.returncode == 0 and shown == ""


def test_lod_writes_an_msft_lod_gltf_chain(run, tmp_path):
    import json
    out = tmp_path / "chain.gltf"
    r = run("lod", str(SAMPLE), str(tmp_path / "levels"), "--levels", "2", "--gltf", str(out))
    assert r.returncode == 0, r.stderr
    doc = json.loads(out.read_text())
    assert doc["extensionsUsed"] == ["MSFT_lod"]
    assert doc["nodes"][0]["extensions"]["MSFT_lod"]["ids"] == [1, 2]
    assert len(doc["meshes"]) == 3
