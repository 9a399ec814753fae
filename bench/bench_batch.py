#!/usr/bin/python3
"""Batch throughput: ~1000 meshes through one pipeline, on 1 and 2 cores and on Dask.

usage (from the repository root, after ./scripts/build):
    PYTHONPATH=build/python GEOM_BIN=build/cli/geom bench/bench_batch.py [--count 1000]

The corpus holds generated tori (marching cubes, 560 to 24k triangles, in OBJ, PLY, OFF,
STL and GLB) plus the meshes at the top of $GEOM_DATA_DIR (default ../shared/meshes), linked
in. The pipeline is "repair -> simplify --ratio 0.5 -> compress --bits 12". The runs are:
  - `geom batch` with --jobs 1 and --jobs 2 (threads in one process);
  - geom.batch.run with a local process pool of 2;
  - geom.batch.run on a Dask LocalCluster with 2 single-threaded worker processes.
For each run it prints meshes/s, triangles/s and the overhead per task: the workers' wall
time not spent inside the per-file function, spread over the tasks. The per-task figures
also give an estimate of how long a 100k-asset corpus would take on N workers. The table
goes to $GEOM_BENCH_OUT/batch.csv (default bench-out/).
"""
import argparse
import csv
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

import geom
import geom.batch

ROOT = pathlib.Path(__file__).resolve().parents[1]
PIPELINE = ["repair", "simplify --ratio 0.5", "compress --bits 12"]


def torus(resolution, R=2.0, r=0.7):
    """A closed torus from marching cubes: 560 triangles at resolution 8, 24k at 45."""
    f = lambda x, y, z: (np.sqrt(x * x + y * y) - R) ** 2 + z * z - r * r
    b = R + r + 0.1
    return geom.isosurface(f, ((-b, -b, -r - 0.1), (b, b, r + 0.1)), resolution).to_mesh()


def make_corpus(folder, count):
    rng = np.random.default_rng(1)
    exts = [".obj", ".ply", ".off", ".stl", ".glb"]
    data = pathlib.Path(os.environ.get("GEOM_DATA_DIR", ROOT.parent / "shared" / "meshes"))
    shared = sorted(p for p in data.glob("*") if p.suffix.lower() in (".obj", ".ply", ".off", ".stl"))
    if not shared:
        print(f"note: no meshes in {data}; the corpus is generated meshes only")
    for p in shared:
        (folder / "shared").mkdir(parents=True, exist_ok=True)
        os.symlink(p.resolve(), folder / "shared" / p.name)
    for k in range(max(0, count - len(shared))):
        sub = folder / f"gen{k % 10}"
        sub.mkdir(parents=True, exist_ok=True)
        geom.save(torus(int(rng.integers(8, 45))), str(sub / f"t{k}{exts[k % 5]}"))


def overhead_per_task(wall, workers, records):
    inside = sum(r["seconds"] for r in records)
    return max(0.0, (wall * workers - inside) / max(1, len(records)))


def summarise(name, workers, wall, records):
    ok = [r for r in records if r["status"] == "ok"]
    for r in records:
        if r["status"] == "failed":
            print(f"{name}: {r['input']}: {r['error']}")
    tris = sum(r["before"]["faces"] for r in ok)
    return {"run": name, "workers": workers, "seconds": wall, "files": len(records),
            "ok": len(ok), "meshes_per_s": len(ok) / wall, "triangles_per_s": tris / wall,
            "task_ms": 1e3 * sum(r["seconds"] for r in records) / max(1, len(records)),
            "overhead_ms": 1e3 * overhead_per_task(wall, workers, records)}


def run_cli(geom_bin, folder, out, jobs):
    t0 = time.perf_counter()
    subprocess.run([geom_bin, "batch", folder, out, "-j", str(jobs), "-q", "--force",
                    *sum((["--step", s] for s in PIPELINE), [])], check=False)
    wall = time.perf_counter() - t0
    lines = (pathlib.Path(out) / "batch-report.jsonl").read_text().splitlines()
    return wall, [json.loads(line) for line in lines[:-1]]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--count", type=int, default=1000)
    args = ap.parse_args()
    geom_bin = os.environ.get("GEOM_BIN", str(ROOT / "build" / "cli" / "geom"))
    work = pathlib.Path(tempfile.mkdtemp(prefix="geom_bench_batch_"))
    try:
        folder = work / "in"
        make_corpus(folder, args.count)
        rows = []
        for jobs in (1, 2):
            wall, recs = run_cli(geom_bin, str(folder), str(work / f"cli{jobs}"), jobs)
            rows.append(summarise(f"geom batch -j {jobs}", jobs, wall, recs))
        t0 = time.perf_counter()
        recs = geom.batch.run(folder, PIPELINE, out_dir=work / "pool", jobs=2)
        rows.append(summarise("geom.batch.run, 2 processes", 2, time.perf_counter() - t0, recs))
        rows += dask_rows(folder, work)
        report(rows)
    finally:
        shutil.rmtree(work, ignore_errors=True)


def dask_rows(folder, work):
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        print("note: dask.distributed not installed; Dask rows skipped")
        return []
    package_dir = str(pathlib.Path(geom.__file__).resolve().parents[1])
    os.environ["PYTHONPATH"] = os.pathsep.join([package_dir, os.environ.get("PYTHONPATH", "")])
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        t0 = time.perf_counter()
        recs = geom.batch.run(folder, PIPELINE, client, out_dir=work / "dask")
        return [summarise("geom.batch.run, Dask LocalCluster 2 workers", 2,
                          time.perf_counter() - t0, recs)]


def report(rows):
    base = rows[0]["seconds"]
    print(f"{'run':46} {'s':>7} {'files':>6} {'ok':>5} {'meshes/s':>9} {'Mtris/s':>8} "
          f"{'task ms':>8} {'overhead ms':>11} {'speed-up':>8}")
    for r in rows:
        print(f"{r['run']:46} {r['seconds']:7.2f} {r['files']:6d} {r['ok']:5d} "
              f"{r['meshes_per_s']:9.1f} {r['triangles_per_s'] / 1e6:8.3f} {r['task_ms']:8.2f} "
              f"{r['overhead_ms']:11.2f} {base / r['seconds']:7.2f}x")
    for r in rows:
        per_task = (r["task_ms"] + r["overhead_ms"]) / 1e3
        est = ", ".join(f"{n} workers {100_000 * per_task / n / 60:.1f} min" for n in (2, 16, 64, 256))
        print(f"100k assets like these, {r['run']}: {est}")
    out = pathlib.Path(os.environ.get("GEOM_BENCH_OUT", "bench-out"))
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "batch.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"CSV: {out / 'batch.csv'}")


if __name__ == "__main__":
    sys.exit(main())
