"""geom batch (CLI) and geom.batch (Python, local pool and Dask): every good file processed,
every bad one reported with its message, outputs valid, resume does nothing, an interrupted
run leaves no partial output, and the Dask path reports what the local path reports."""

import json
import os
import pathlib
import signal
import subprocess
import time

import numpy as np
import pytest

import geom
import geom.batch
from conftest import GEOM_BIN, torus_mesh

PIPELINE = {"steps": ["repair", "subdivide --levels 1", "simplify --ratio 0.5",
                      "convert --format ply"]}


def torus(n, m):
    """A closed triangulated torus: n*m vertices, 2*n*m triangles, genus 1."""
    return torus_mesh(n, m, R=2.0, r=0.7, lumps=0.0)

BROKEN = {
    "bad_index.obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
    "truncated.ply": "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n",
    "deep/empty.off": "",
    "garbage.stl": "solid x\n facet normal 0 0 1\n  outer loop\n   vertex 1 2\n",
}


def make_corpus(folder, count, size=(12, 8)):
    exts = [".obj", ".ply", ".off", ".stl", ".glb"]
    for k in range(count):
        sub = folder / f"set{k % 3}"
        sub.mkdir(parents=True, exist_ok=True)
        geom.save(torus(size[0] + k % 5, size[1] + k % 3), str(sub / f"torus{k}{exts[k % 5]}"))
    for name, text in BROKEN.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(text)
    (folder / "readme.txt").write_text("not a mesh")


def read_report(path):
    lines = [json.loads(line) for line in pathlib.Path(path).read_text().splitlines()]
    assert "summary" in lines[-1]
    return {r["input"]: r for r in lines[:-1]}, lines[-1]["summary"]


def batch(*args):
    return subprocess.run([str(GEOM_BIN), "batch", *map(str, args)], capture_output=True,
                          text=True, timeout=300)


def without_times(records):
    return sorted((json.dumps({k: v for k, v in r.items() if k not in ("seconds", "steps")},
                              sort_keys=True) for r in records))


@pytest.fixture
def corpus(tmp_path):
    folder = tmp_path / "in"
    make_corpus(folder, 10)
    pipeline = tmp_path / "pipeline.json"
    pipeline.write_text(json.dumps(PIPELINE))
    return folder, pipeline


def test_every_good_file_is_processed_and_every_bad_one_reported(corpus, tmp_path):
    folder, pipeline = corpus
    out = tmp_path / "out"
    r = batch(folder, out, "--pipeline", pipeline, "--jobs", "2", "--json")
    assert r.returncode == 1, r.stderr  # some files failed; the run still went through all
    records, summary = read_report(out / "batch-report.jsonl")
    assert len(records) == 14 and summary["files"] == 14
    assert summary["ok"] == 10 and summary["failed"] == 4 and summary["skipped"] == 0
    assert json.loads(r.stdout)["ok"] == 10
    for name in BROKEN:
        rec = records[name]
        assert rec["status"] == "failed"
        assert name in rec["error"], rec["error"]  # the message names the file
    for name, rec in records.items():
        if name in BROKEN:
            continue
        assert rec["status"] == "ok", rec
        assert rec["output"] == str(pathlib.PurePosixPath(name).with_suffix(".ply"))
        mesh = geom.load(str(out / rec["output"]))
        assert geom.validate(mesh).ok
        assert mesh.n_faces == rec["after"]["faces"]
        # Catmull-Clark makes 3 quads of each triangle, simplify fans them (x2) and halves.
        assert rec["before"]["faces"] * 3 == mesh.n_faces
        assert [s["step"] for s in rec["steps"]] == ["read", *PIPELINE["steps"], "write"]
    assert not list(out.rglob("*.geom-partial-*"))
    assert not (out / "readme.txt").exists()


def test_resume_does_nothing_the_second_time(corpus, tmp_path):
    folder, pipeline = corpus
    out = tmp_path / "out"
    batch(folder, out, "--pipeline", pipeline, "-j", "2", "--quiet")
    outputs = {p: p.stat().st_mtime_ns for p in out.rglob("*.ply")}
    assert len(outputs) == 10
    r = batch(folder, out, "--pipeline", pipeline, "--resume", "--quiet")
    records, summary = read_report(out / "batch-report.jsonl")
    assert summary["skipped"] == 10 and summary["ok"] == 0 and summary["failed"] == 4
    assert {p: p.stat().st_mtime_ns for p in out.rglob("*.ply")} == outputs
    # Without --resume or --force an existing output is never overwritten.
    r = batch(folder, out, "--pipeline", pipeline, "--quiet")
    records, summary = read_report(out / "batch-report.jsonl")
    assert summary["ok"] == 0 and summary["failed"] == 14
    assert "output exists" in records["set0/torus0.obj"]["error"]
    assert {p: p.stat().st_mtime_ns for p in out.rglob("*.ply")} == outputs


def test_usage_errors(corpus, tmp_path):
    folder, pipeline = corpus
    assert batch(folder, tmp_path / "o").returncode == 2  # no pipeline
    r = batch(folder, tmp_path / "o", "--step", "simplify --rato 0.5")
    assert r.returncode == 1 and "unknown option --rato" in r.stderr
    r = batch(folder, folder, "--step", "repair")
    assert r.returncode == 1 and "output folder is the input folder" in r.stderr
    assert batch(folder, tmp_path / "o", "--step", "repair", "--resume", "--force").returncode == 2


def start_slow_run(tmp_path):
    folder = tmp_path / "big"
    make_corpus(folder, 40, size=(30, 20))
    out = tmp_path / "out"
    proc = subprocess.Popen([str(GEOM_BIN), "batch", str(folder), str(out), "-j", "2", "-q",
                             "--step", "subdivide --levels 2", "--step", "simplify --ratio 0.3"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    report = out / "batch-report.jsonl"
    deadline = time.time() + 120
    while time.time() < deadline and proc.poll() is None:
        if report.exists() and report.read_text().count("\n") >= 2:
            break
        time.sleep(0.05)
    return folder, out, proc


def check_outputs_whole(out):
    written = list(out.rglob("*.*"))
    meshes = [p for p in written if not p.name.startswith(".") and p.suffix != ".jsonl"]
    for p in meshes:
        assert geom.validate(geom.load(str(p))).ok, p
    return meshes


def test_terminating_a_run_leaves_no_partial_output(tmp_path):
    folder, out, proc = start_slow_run(tmp_path)
    assert proc.poll() is None, "the run ended before it could be interrupted"
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=120) == 130
    assert not list(out.rglob("*.geom-partial-*"))
    done = check_outputs_whole(out)
    assert 0 < len(done) < 40
    _, summary = read_report(out / "batch-report.jsonl")
    assert summary["interrupted"] and summary["ok"] == len(done)


def test_a_killed_run_is_completed_by_resume(tmp_path):
    folder, out, proc = start_slow_run(tmp_path)
    proc.kill()  # SIGKILL: no chance to clean up; partial files stay hidden and are not outputs
    proc.wait(timeout=60)
    done = check_outputs_whole(out)
    assert len(done) < 40
    r = batch(folder, out, "-j", "2", "-q", "--resume", "--step", "subdivide --levels 2",
              "--step", "simplify --ratio 0.3")
    _, summary = read_report(out / "batch-report.jsonl")
    assert summary["skipped"] == len(done) and summary["ok"] == 40 - len(done)
    assert not list(out.rglob("*.geom-partial-*"))
    assert len(check_outputs_whole(out)) == 40


def test_python_local_and_dask_paths_give_the_cli_report(corpus, tmp_path):
    folder, pipeline = corpus
    batch(folder, tmp_path / "cli", "--pipeline", pipeline, "--quiet")
    cli_records, _ = read_report(tmp_path / "cli" / "batch-report.jsonl")

    local = geom.batch.run(folder, str(pipeline), out_dir=tmp_path / "local", jobs=2,
                           report=tmp_path / "local.jsonl")
    assert without_times(local) == without_times(cli_records.values())
    assert len((tmp_path / "local.jsonl").read_text().splitlines()) == 14

    import dask.distributed as distributed  # installed by scripts/install-deps: never skipped
    # Worker processes import geom from where this process found it.
    package_dir = str(pathlib.Path(geom.__file__).resolve().parents[1])
    os.environ["PYTHONPATH"] = os.pathsep.join(
        [package_dir] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        remote = geom.batch.run(folder, PIPELINE, client, out_dir=tmp_path / "dask")
    assert without_times(remote) == without_times(local)
    for rec in remote:
        if rec["status"] == "ok":
            assert geom.validate(geom.load(str(tmp_path / "dask" / rec["output"]))).ok


def test_python_errors(corpus, tmp_path):
    folder, _ = corpus
    with pytest.raises(ValueError, match=r"step 2 \(simplify\): unknown option --rato"):
        geom.batch.run(folder, ["repair", "simplify --rato 0.5"], out_dir=tmp_path / "o")
    with pytest.raises(ValueError, match="resume or force"):
        geom.batch.run(folder, ["repair"], out_dir=tmp_path / "o", resume=True, force=True)
    with pytest.raises(TypeError):
        geom.batch.run(folder, 42, out_dir=tmp_path / "o")
    files = [folder / "set0" / "torus0.obj", folder / "set1" / "torus1.ply"]
    records = geom.batch.run(files, ["compress --bits 12"], out_dir=tmp_path / "few", jobs=1)
    assert [r["output"] for r in records] == ["set0/torus0.gmc", "set1/torus1.gmc"]
    assert all(r["status"] == "ok" for r in records)
