"""Batch processing: one pipeline over many mesh files, on local processes or a Dask cluster.

    >>> import geom.batch
    >>> records = geom.batch.run("assets/", ["repair", "simplify --ratio 0.25",
    ...                                       "compress --bits 12"], out_dir="out/")
    >>> sum(r["status"] == "ok" for r in records)

On a cluster (Debian's python3-distributed), hand run() a client; workers read and write the
files themselves (so they need the same paths, e.g. a shared file system, and `geom` on their
PYTHONPATH), and only paths and the small report records travel through the scheduler:

    >>> from dask.distributed import Client
    >>> client = Client("tcp://scheduler:8786")          # or Client(LocalCluster(...))
    >>> records = geom.batch.run(paths, "pipeline.json", client, out_dir="/shared/out")

The pipeline is the same as `geom batch --pipeline` reads (geom/batch/PIPELINE.md): a dict
{"steps": [...]}, a list of steps, JSON text, or the path of a JSON file. Each record is one
line of `geom batch`'s report, as a dict: input, output, status ("ok", "failed",
"skipped"), before/after counts, repairs, bytes, error, per-step seconds.
"""

import functools
import json
import os
import uuid

from . import _geom

__all__ = []  # reached as geom.batch.run, not re-exported at the top level


def run(paths, pipeline, client=None, *, out_dir, root=None, jobs=None, resume=False,
        force=False, report=None):
    """Apply `pipeline` to every mesh in `paths` and write the outputs under `out_dir`.

    paths: a folder (searched recursively by extension, as `geom batch` does) or a list of
    files. Outputs keep each file's path relative to `root` (default: the folder, or the
    files' common folder). client: None runs `jobs` local processes (default: all cores);
    a dask.distributed.Client maps the same per-file function over its workers. resume skips
    files whose output is newer than the input; force replaces existing outputs; otherwise
    an existing output makes that file fail. report: a path to write the JSON-lines report.
    Returns the records in input order. A bad file never stops the run: its record says why.
    """
    if resume and force:
        raise ValueError("give resume or force, not both")
    pipeline_json = _geom._batch_pipeline(_pipeline_text(pipeline))
    root, files = _inputs(paths, root, out_dir)
    os.makedirs(out_dir, exist_ok=True)
    tasks = _geom._batch_plan(pipeline_json, root, files, out_dir)
    _geom._batch_remove_partial_outputs(out_dir)
    work = functools.partial(_process, pipeline_json,
                             "skip" if resume else "overwrite" if force else "fail")
    if client is None:
        records = _run_local(work, tasks, jobs)
    else:
        records = _run_dask(work, tasks, client)
    if report is not None:
        with open(report, "w") as f:
            f.writelines(json.dumps(r, sort_keys=True) + "\n" for r in records)
    return records


def _process(pipeline_json, existing, task):
    # Module level, so that process pools and Dask pickle it by reference.
    return json.loads(_geom._batch_process(pipeline_json, existing, tuple(task)))


def _pipeline_text(pipeline):
    if isinstance(pipeline, dict):
        return json.dumps(pipeline)
    if isinstance(pipeline, (list, tuple)):
        return json.dumps({"steps": list(pipeline)})
    if isinstance(pipeline, (str, os.PathLike)):
        text = os.fspath(pipeline)
        if text.lstrip().startswith("{"):
            return text
        with open(text) as f:
            return f.read()
    raise TypeError("pipeline must be a dict, a list of steps, JSON text or a file path")


def _inputs(paths, root, out_dir):
    if isinstance(paths, (str, os.PathLike)):
        folder = os.fspath(paths)
        files = [str(p) for p in _geom._batch_find(folder, os.fspath(out_dir))]
        return (os.fspath(root) if root is not None else folder), files
    files = [os.fspath(p) for p in paths]
    if root is None:
        root = os.path.commonpath([os.path.dirname(os.path.abspath(f)) for f in files]) \
            if files else "."
    return os.fspath(root), files


def _run_local(work, tasks, jobs):
    jobs = jobs or os.cpu_count() or 1
    if jobs == 1 or len(tasks) <= 1:
        return [work(t) for t in tasks]
    import concurrent.futures
    import multiprocessing
    # spawn, not fork: the parent may hold TBB's worker threads, which a fork does not copy.
    ctx = multiprocessing.get_context("spawn")
    with concurrent.futures.ProcessPoolExecutor(jobs, mp_context=ctx) as pool:
        return list(pool.map(work, tasks, chunksize=1))


def _run_dask(work, tasks, client):
    from dask.distributed import as_completed
    # A bounded window of futures in flight keeps the client's memory flat on 100k files.
    window = max(4, 4 * max(1, len(client.scheduler_info().get("workers", {}))))
    records = [None] * len(tasks)
    pending = iter(enumerate(tasks))
    index = {}
    run_id = uuid.uuid4().hex

    def submit(n):
        for i, task in pending:
            fut = client.submit(work, task, pure=False, key=f"geom-batch-{run_id}-{i}")
            index[fut.key] = i
            futures.add(fut)
            n -= 1
            if n == 0:
                return

    futures = as_completed()
    submit(window)
    for fut in futures:
        records[index.pop(fut.key)] = fut.result()
        fut.release()
        submit(1)
    return records
