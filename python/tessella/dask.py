"""Refining many mesh files on a Dask cluster (``pip install tessella[dask]``).

:func:`refine_files` is :func:`tessella.batch` on Dask, a few files per task: the same
outputs, the same manifest rows, the same skipping of outputs that exist. A worker that dies
while it refines a file has its task retried on another worker (Dask reschedules the tasks of
lost workers); outputs get their names only when they are whole (on Linux a half-written file
has no name at all; elsewhere its temporary file is removed when the run ends), so nothing
partial is left. Outputs are flushed to the disk once at the end, by every worker
(``syncfs``), not one ``fsync`` per file; ``sync_each=True`` flushes each file instead.

On one machine, ``client=None`` makes a ``LocalCluster``. On a real cluster, start a scheduler
and workers (``dask scheduler`` on one machine, ``dask worker tcp://HOST:8786`` on each of the
others, with tessella installed everywhere) and pass ``distributed.Client("tcp://HOST:8786")``;
the input and output paths must then name a file system every worker sees (or use
:func:`refine_partition` with a bag of ``(name, bytes)`` pairs)::

    from distributed import Client
    import tessella.dask
    client = Client("tcp://scheduler.example.org:8786")
    rows = tessella.dask.refine_files(["/shared/meshes"], "/shared/refined", client, level=4)
    failed = [r for r in rows if r["status"] == "failed"]

:func:`refine_partition` fits ``dask.bag`` pipelines::

    import dask.bag as db
    rows = db.from_sequence(paths, npartitions=8).map_partitions(
        tessella.dask.refine_partition, "/shared/refined", level=4).compute()
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import Any, Dict, Iterable, List, Optional, Tuple, Union

from ._batch import (
    MANIFEST,
    PathLike,
    _row,
    _split_options,
    expand,
    refine_row,
    remove_stale_temporaries,
    skipped_row,
    sync_folder,
)
from ._errors import OptionError, need

__all__ = ["refine_files", "refine_partition"]


def _distributed() -> Any:
    return need("distributed", "tessella.dask needs Dask's distributed scheduler: pip install 'tessella[dask]'")


def refine_files(
    paths: Iterable[PathLike],
    out_dir: PathLike,
    client: Any = None,
    *,
    retries: int = 2,
    sync_each: bool = False,
    files_per_task: Optional[int] = None,
    **options: Any,
) -> List[Dict[str, Any]]:
    """Refines every mesh file named by ``paths`` (files, folders, glob patterns) into
    ``out_dir`` on the Dask cluster of ``client`` (default: the current client, else a new
    ``LocalCluster``), with the options of :func:`tessella.refine_to_file` (and ``format``,
    ``force`` as for :func:`tessella.batch`). Returns the manifest rows, also written to
    ``out_dir/manifest.jsonl`` as results arrive.

    A file whose task fails for another reason than a bad file (a worker lost ``retries``
    times over and more, per Dask's ``allowed-failures``) gets a ``"failed"`` row naming the
    cause; files that cannot be refined get their error, as in :func:`tessella.batch`.

    Files go to the workers ``files_per_task`` at a time, since a Dask task costs a few
    milliseconds, more than a small file's refinement. The default gives each worker thread
    one to four tasks, more when the estimated output (the inputs' size times the level
    squared) is large enough that each task still writes about 16 MB; ``files_per_task=1``
    gives one task per file. A task retried after a lost worker refines
    all its files again (each output is replaced whole).
    """
    if files_per_task is not None and (not isinstance(files_per_task, int) or files_per_task < 1):
        raise OptionError(f"files_per_task={files_per_task!r}: give a whole number of 1 or more")
    distributed = _distributed()
    ext, force, options = _split_options(options, sync_each)
    pairs = expand(paths, out_dir, ext)
    os.makedirs(os.fspath(out_dir), exist_ok=True)
    remove_stale_temporaries(out_dir)
    own_cluster = None
    if client is None:
        try:
            client = distributed.get_client()
        except ValueError:
            own_cluster = distributed.LocalCluster(processes=True)
            client = distributed.Client(own_cluster)
    try:
        rows = [skipped_row(i, o) for i, o in pairs if not force and os.path.exists(o)]
        todo = [(i, o) for i, o in pairs if force or not os.path.exists(o)]
        with open(Path(os.fspath(out_dir)) / MANIFEST, "w", encoding="utf-8") as manifest:
            for row in rows:
                manifest.write(json.dumps(row) + "\n")
            manifest.flush()
            per_task = files_per_task or _files_per_task(client, todo, options.get("level", 8))
            chunks = [todo[k : k + per_task] for k in range(0, len(todo), per_task)]
            futures = client.map(_refine_rows, chunks, pure=False, retries=retries, **options)
            chunk_of = {f.key: c for f, c in zip(futures, chunks)}
            for future in distributed.as_completed(futures):
                try:
                    done = future.result()
                except Exception as e:  # the task itself failed: a lost worker, a dead cluster
                    done = [_row(*pair, "failed") for pair in chunk_of[future.key]]
                    for row in done:
                        row["error"] = f"{type(e).__name__}: {e}"
                for row in done:
                    manifest.write(json.dumps(row) + "\n")
                rows.extend(done)
                manifest.flush()
        if not sync_each:
            # Each worker flushes what it wrote (on a shared file system, its own cache).
            client.run(sync_folder, os.fspath(out_dir))
    finally:
        if own_cluster is not None:
            client.close()
            own_cluster.close()
    # Every task has ended: what is left of temporary files was a lost worker's.
    remove_stale_temporaries(out_dir)
    return rows


def _refine_rows(pairs: List[Tuple[str, str]], **options: Any) -> List[Dict[str, Any]]:
    """One task: the rows of refining each ``(input, output)`` pair in turn."""
    return [refine_row(i, o, **options) for i, o in pairs]


#: The output a task should have to write at least, estimated: a Dask task costs a few
#: milliseconds, and 16 MB takes tens of milliseconds to refine and write, so a smaller task
#: would be mostly Dask's cost.
TASK_BYTES = 16 << 20


def _files_per_task(client: Any, todo: List[Tuple[str, str]], level: Any) -> int:
    """Files per task: one task per worker thread at least, four at most (so that a slow or
    lost worker's share stays small), and within that as many as keep each task's output
    near :data:`TASK_BYTES`, estimated from the inputs' sizes: a refined file is about its
    input's size times the level squared (each coarse triangle becomes level² of them)."""
    threads = sum(client.nthreads().values()) or 1
    inputs = 0
    for input, _ in todo:
        try:
            inputs += os.path.getsize(input)
        except OSError:
            pass  # refining it will say why
    try:
        scale = max(float(level), 1.0) ** 2
    except (TypeError, ValueError):
        scale = 64.0  # refining will refuse the level
    tasks = max(threads, min(4 * threads, int(inputs * scale // TASK_BYTES)))
    return max(1, -(-len(todo) // tasks))


def refine_partition(
    items: Iterable[Union[PathLike, Tuple[str, bytes]]],
    out_dir: PathLike,
    *,
    sync_each: bool = False,
    **options: Any,
) -> List[Dict[str, Any]]:
    """Refines one partition of a ``dask.bag`` into ``out_dir`` and returns its manifest rows
    (``bag.map_partitions(refine_partition, out_dir, level=4)``). Items are paths, or
    ``(name, bytes)`` pairs: a file's name (its extension says its format) and contents, for
    workers that do not see the inputs' file system. Outputs that exist are skipped unless
    ``force=True``. The partition's outputs are flushed to the disk together at its end
    (``sync_each=True``: each one as it is written)."""
    ext, force, options = _split_options(options, sync_each)
    rows: List[Dict[str, Any]] = []
    for item in items:
        if isinstance(item, tuple):
            name, data = item
            output = str(Path(os.fspath(out_dir)) / Path(name).with_suffix("." + ext).name)
            if not force and os.path.exists(output):
                rows.append(skipped_row(name, output))
                continue
            with tempfile.TemporaryDirectory(prefix="tessella-") as tmp:
                path = os.path.join(tmp, Path(name).name)
                with open(path, "wb") as f:
                    f.write(data)
                row = refine_row(path, output, **options)
            row["input"] = name
            rows.append(row)
        else:
            ((input, output),) = expand([item], out_dir, ext)
            if not force and os.path.exists(output):
                rows.append(skipped_row(input, output))
            else:
                rows.append(refine_row(input, output, **options))
    if not sync_each and any(r["status"] == "ok" for r in rows):
        sync_folder(out_dir)
    return rows
