"""Refining meshes into files: :func:`refine_to_file` (one mesh, written piece by piece, so the
output may be far larger than memory) and :func:`batch` (many files, on all cores, resumable,
with a manifest). :mod:`tessella.dask` runs the same per-file work on a Dask cluster.

The manifest (``manifest.jsonl`` in the output folder) has one JSON row per input, with the
keys of the ``tessella batch`` command: ``input``, ``output``, ``status`` (``"ok"``,
``"skipped"``: the output existed, or ``"failed"``), ``input_triangles``, ``vertices``,
``triangles``, ``seconds``, ``streamed`` and ``error`` (the message, for failures).
"""

from __future__ import annotations

import glob
import json
import os
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any, Dict, Iterable, List, Optional, Tuple, Union

from . import _tessella
from ._errors import OptionError

PathLike = Union[str, "os.PathLike[str]"]

#: The manifest's file name in the output folder.
MANIFEST = "manifest.jsonl"
#: Extensions of the mesh files a folder is searched for.
MESH_EXTENSIONS = (".obj", ".ply", ".gltf", ".glb", ".stl")
#: The options :func:`refine_to_file`, :func:`batch` and :mod:`tessella.dask` pass on.
OPTIONS = (
    "scheme", "level", "alpha", "normals_mode", "weld", "ply_ascii", "max_memory", "sync", "origin",
    "spacing", "lod",
)


def refine_to_file(
    vertices: Any,
    faces: Any,
    path: PathLike,
    normals: Any = None,
    *,
    point_data: Optional[Dict[str, Any]] = None,
    **options: Any,
) -> Dict[str, Any]:
    """Refines a mesh straight into the file ``path`` (``.ply``, ``.obj``, ``.glb``,
    ``.gltf``, ``.stl``) and returns its counts (``vertices``, ``triangles``,
    ``input_triangles``, ``streamed``, ``seconds``).

    The refinement (uniform or adaptive levels, welded or soup: ``weld=False``) is written
    piece by piece:
    memory holds a few pieces of about ``max_memory / 8`` bytes (default ``max_memory`` 1 GiB)
    whatever the level, and the file has the bytes the whole refinement gets in memory, in any
    format (``.gltf`` gets its buffer base64-encoded as it comes). The free disk space is
    checked first (``OSError``: "needs 41.2 GB, the disk has 12.0 GB free"), and the file is
    written to a file without a name that gets ``path``'s only when it is whole (Linux;
    elsewhere a temporary file renamed into place), so a failed or killed run leaves nothing
    at ``path``.

    ``point_data`` (name to one value per coarse vertex, shape ``(n,)``) is carried to every
    refined vertex as :func:`tessella.refine` carries it (linear on each face) and written as
    PLY vertex properties or glTF ``_NAME`` attributes, piece by piece too; other formats
    refuse it (``FileFormatError``), as they refuse ``origin=True``, which writes each
    vertex's coarse face and barycentrics (PLY ``face``, ``bary1..3``).

    Options: ``scheme`` (``"pn"``), ``level`` (8), ``alpha`` (0.75), ``normals_mode``,
    ``weld`` (True), ``ply_ascii`` (False), ``max_memory`` (bytes), ``sync`` (True: the file
    is flushed to the disk before it gets its name; False leaves that to the system, or to one
    :func:`sync_folder` after many files, as :func:`batch` does), ``origin`` (False),
    ``spacing`` (``"grid"``; ``"equal"``, ``"fractional-odd"``, ``"fractional-even"``: the
    hardware tessellator's, where ``level`` may be fractional, as a fractional grid level
    may) and ``lod`` (``"tolerance:D"``: a level per edge, as :func:`tessella.refine`). Raises
    ``MeshError`` for a bad mesh or field, ``OptionError`` for bad options, ``OSError`` for
    what the system refused.
    """
    _check_options(options)
    fields = []
    if point_data:
        from ._fields import _field_rows
        from ._errors import MeshError
        import numpy as np

        count = len(np.asarray(vertices))
        for name, values in dict(point_data).items():
            rows = _field_rows(name, values, count, "vertex")
            if rows.shape[1] != 1:
                raise MeshError(
                    f"field {name!r} has {rows.shape[1]} components; a file holds one value a "
                    f"vertex per field: pass each component as a field of its own"
                )
            fields.append((str(name), np.ascontiguousarray(rows[:, 0])))
    return _tessella._refine_to_file((vertices, faces, normals, fields), os.fspath(path), **options)


def refine_file(input: PathLike, output: PathLike, **options: Any) -> Dict[str, Any]:
    """Refines the mesh file ``input`` into ``output`` as :func:`refine_to_file` does, with the
    file's per-vertex fields (PLY vertex properties, glTF ``_NAME`` attributes) carried into
    outputs that hold them (PLY, glTF), as ``tessella refine`` does; raises
    ``FileFormatError`` for a malformed file and ``OSError`` for a missing one."""
    _check_options(options)
    return _tessella._refine_to_file(os.fspath(input), os.fspath(output), **options)


def sync_folder(path: PathLike) -> None:
    """Flushes every file of the file system that holds ``path`` to the disk (Linux's
    ``syncfs``): the one flush after many files written with ``sync=False``."""
    _tessella._sync_folder(os.fspath(path))


def _check_options(options: Dict[str, Any]) -> None:
    unknown = sorted(set(options) - set(OPTIONS))
    if unknown:
        raise OptionError(
            f"unknown option(s) {', '.join(unknown)}; the options are {', '.join(OPTIONS)}"
        )


def expand(paths: Iterable[PathLike], out_dir: PathLike, ext: str = "ply") -> List[Tuple[str, str]]:
    """``(input, output)`` for every mesh file named by ``paths`` (files, folders searched
    recursively, glob patterns), as ``tessella batch`` pairs them: a folder's files keep their
    paths below the folder, the others their names; the extension becomes ``ext``. Raises
    ``OptionError`` for a path that names nothing and for two inputs with one output."""
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    found: List[Tuple[Path, Path]] = []
    for item in paths:
        path = Path(os.fspath(item))
        if path.is_dir():
            for file in sorted(p for p in path.rglob("*") if p.is_file()):
                if file.suffix.lower() in MESH_EXTENSIONS:
                    found.append((file, file.relative_to(path)))
        elif path.exists():
            found.append((path, Path(path.name)))
        elif any(c in str(path) for c in "*?["):
            matches = sorted(Path(p) for p in glob.glob(str(path)) if Path(p).is_file())
            if not matches:
                raise OptionError(f"the pattern {str(path)!r} matches no file")
            found.extend((m, Path(m.name)) for m in matches)
        else:
            raise OptionError(f"{path}: no such file or folder")
    if not found:
        raise OptionError("no mesh files among the inputs")
    jobs: List[Tuple[str, str]] = []
    owner: Dict[str, str] = {}
    for file, relative in found:
        output = str(Path(os.fspath(out_dir)) / relative.with_suffix("." + ext))
        if output in owner:
            raise OptionError(
                f"{owner[output]} and {file} would both be written to {output}; "
                "batch them into separate folders"
            )
        owner[output] = str(file)
        jobs.append((str(file), output))
    return jobs


#: A manifest row's keys, in order.
ROW_KEYS = ("input", "output", "status", "input_triangles", "vertices", "triangles", "seconds", "streamed", "error")


def _row(input: str, output: str, status: str) -> Dict[str, Any]:
    row: Dict[str, Any] = dict.fromkeys(ROW_KEYS)
    row.update(input=input, output=output, status=status)
    return row


def refine_row(input: str, output: str, **options: Any) -> Dict[str, Any]:
    """One manifest row: ``input`` refined into ``output``; a failure becomes the row's error
    (the batch goes on)."""
    row = _row(input, output, "ok")
    try:
        os.makedirs(os.path.dirname(output) or ".", exist_ok=True)
        done = refine_file(input, output, **options)
        row.update({k: done[k] for k in ROW_KEYS[3:8]})
    except (ValueError, OSError) as e:  # TessellaError is a ValueError
        row.update(status="failed", error=f"{type(e).__name__}: {e}")
    return row


def skipped_row(input: str, output: str) -> Dict[str, Any]:
    """The row of an input whose output exists (complete: outputs get their names whole)."""
    return _row(input, output, "skipped")


def remove_stale_temporaries(out_dir: PathLike) -> None:
    """Removes the temporary files (``.tessella-*.tmp``) that killed runs left below
    ``out_dir``. One batch at a time per output folder: another's files in progress would go
    too."""
    for path in Path(os.fspath(out_dir)).rglob(".tessella-*.tmp"):
        try:
            path.unlink()
        except FileNotFoundError:
            pass  # its writer finished (renamed it) or removed it meanwhile


def _split_options(
    options: Dict[str, Any], sync_each: bool
) -> Tuple[str, bool, Dict[str, Any]]:
    """The output format, ``force`` and the per-file options of a batch's ``**options``; the
    per-file ``sync`` is the batch's ``sync_each`` (a batch flushes its files itself)."""
    options = dict(options)
    ext = str(options.pop("format", "ply")).lstrip(".").lower()
    force = bool(options.pop("force", False))
    if "." + ext not in MESH_EXTENSIONS:
        raise OptionError(f"format={ext!r}: give ply, obj, glb, gltf or stl")
    if "sync" in options:
        raise OptionError(
            "sync= is refine_to_file's; a batch flushes its files together at the end, or "
            "each one as it is written with sync_each=True"
        )
    _check_options(options)
    options["sync"] = bool(sync_each)
    return ext, force, options


def batch(
    paths: Iterable[PathLike],
    out_dir: PathLike,
    *,
    jobs: Optional[int] = None,
    sync_each: bool = False,
    **options: Any,
) -> List[Dict[str, Any]]:
    """Refines every mesh file named by ``paths`` (files, folders, glob patterns) into
    ``out_dir`` with the options of :func:`refine_to_file`, ``jobs`` files at once (default:
    one per core), and returns the manifest rows (also written, as they finish, to
    ``out_dir/manifest.jsonl``).

    ``format="ply"`` picks the outputs' format; outputs that exist are skipped unless
    ``force=True``, so a killed batch resumes where it stopped. A file that fails gets a
    ``"failed"`` row with its error and the batch goes on. The outputs are flushed to the disk
    together when the batch ends (``sync_each=True``: each one before it gets its name); a
    killed batch leaves whole files either way. Raises ``OptionError`` for bad inputs or
    options before anything is refined.
    """
    ext, force, options = _split_options(options, sync_each)
    pairs = expand(paths, out_dir, ext)
    os.makedirs(os.fspath(out_dir), exist_ok=True)
    remove_stale_temporaries(out_dir)
    manifest = Path(os.fspath(out_dir)) / MANIFEST
    rows = [skipped_row(i, o) for i, o in pairs if not force and os.path.exists(o)]
    todo = [(i, o) for i, o in pairs if force or not os.path.exists(o)]
    lock = threading.Lock()
    with open(manifest, "w", encoding="utf-8") as out:
        for row in rows:
            out.write(json.dumps(row) + "\n")
        out.flush()

        def one(pair: Tuple[str, str]) -> Dict[str, Any]:
            row = refine_row(pair[0], pair[1], **options)
            with lock:
                out.write(json.dumps(row) + "\n")
                out.flush()
            return row

        # The refinement releases the GIL: threads run files side by side.
        with ThreadPoolExecutor(max_workers=jobs or os.cpu_count() or 1) as pool:
            rows.extend(pool.map(one, todo))
    if not sync_each:
        sync_folder(out_dir)
    return rows
