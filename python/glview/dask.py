"""Rendering a large list of jobs on a Dask cluster (``distributed``).

Each job is a line of a ``glview batch`` jobs file (a model and options, with ``--output``);
each worker process keeps one :class:`glview.Renderer` per worker thread for all the jobs it
gets, so the GL context, compiled shaders and the uploaded model are reused exactly as in
``glview batch``, and the PNG files written are the bytes ``glview batch`` writes::

    from dask.distributed import Client, LocalCluster
    import glview.dask

    with LocalCluster(n_workers=2, threads_per_worker=1) as cluster, Client(cluster) as client:
        paths = glview.dask.render_jobs(client, open("jobs.txt").read().splitlines())

On a real cluster only the ``Client`` changes (``Client("tcp://scheduler:8786")``, or a
``dask_jobqueue``/``dask_kubernetes`` cluster object); the workers need glview installed and
the models and output folder on a shared file system (or ``to="arrays"`` to get the PNG bytes
back instead of files).
"""
from __future__ import annotations

import os
import shlex
import threading
from typing import Any, Iterable, List, Optional, Tuple, Union

_local = threading.local()


def parse_line(line: str) -> Optional[Tuple[List[str], Optional[str]]]:
    """A jobs-file line as (option words without the output, output path); None for a blank
    or comment line, as ``glview batch`` reads them."""
    line = line.strip()
    if not line or line.startswith("#"):
        return None
    words = shlex.split(line)
    out: Optional[str] = None
    kept: List[str] = []
    it = iter(words)
    for w in it:
        if w in ("-o", "--output"):
            out = next(it, None)
        elif w.startswith("--output="):
            out = w.split("=", 1)[1]
        elif w.startswith("-o") and len(w) > 2:
            out = w[2:]
        else:
            kept.append(w)
    return kept, out


def _renderer() -> Any:
    """This worker thread's renderer, made on its first job and kept."""
    r = getattr(_local, "renderer", None)
    if r is None:
        from . import Renderer

        r = Renderer(16, 16)
        _local.renderer = r
    return r


def render_job(words: List[str], output: Optional[str]) -> Union[str, bytes]:
    """Renders one job on this worker: writes ``output`` and returns its path, or returns
    the PNG bytes when ``output`` is None."""
    png = _renderer()._get().render_words(list(words))
    if output is None:
        return png
    with open(output, "wb") as f:
        f.write(png)
    return output


def render_jobs(
    client: Any, lines: Iterable[str], *, to: str = "files", progress: bool = True
) -> List[Union[str, bytes]]:
    """Renders every job line on the cluster of ``client``; returns the written paths (or
    with ``to="arrays"`` the PNG bytes) in the order of the lines. ``progress`` shows Dask's
    progress bar (in a notebook, a widget); the dashboard shows per-worker progress too."""
    jobs = [j for j in (parse_line(l) for l in lines) if j is not None]
    if to not in ("files", "arrays"):
        raise ValueError("to must be 'files' or 'arrays'")
    futures = [
        client.submit(render_job, words, out if to == "files" else None, pure=False)
        for words, out in jobs
    ]
    if progress:
        from dask.distributed import progress as show

        show(futures)
    return client.gather(futures)


def decode(png: bytes) -> Any:
    """A PNG's bytes (``to="arrays"``) as an H×W×4 uint8 NumPy array."""
    import tempfile

    from ._glview import decode_png

    with tempfile.NamedTemporaryFile(suffix=".png", delete=False) as f:
        f.write(png)
    try:
        return decode_png(f.name)
    finally:
        os.unlink(f.name)
