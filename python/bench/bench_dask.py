"""One Dask worker's throughput, and two workers' on this machine: 48 jobs of the Stanford
bunny at 640×480 with glview's defaults (three lights, the key light's shadow), PNG files out,
on a `LocalCluster` of 1 and then 2 worker processes (one thread each); pictures per second,
median of 3 timed rounds after a warm-up round (which makes each worker's renderer).

    target/pyvenv/bin/python python/bench/bench_dask.py     # after `pip install ./python`

A benchmark, not a test: CI does not run it (the Dask test checks the pictures).
"""
import os
import statistics
import sys
import tempfile
import time

JOBS, ROUNDS = 48, 3


def main() -> None:
    from dask.distributed import Client, LocalCluster

    import glview.dask

    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.dirname(os.path.dirname(here))
    model = os.path.join(repo, "..", "shared", "models", "stanford-bunny", "stanford-bunny.obj")
    out = tempfile.mkdtemp(prefix="glview-dask-bench-")
    lines = [
        f"{model} --size 640x480 --yaw {360 * i / JOBS:.1f} -o {out}/{i:03}.png"
        for i in range(JOBS)
    ]
    print(f"bunny, {JOBS} jobs, 640x480, glview's defaults, PNG files; pictures/s (median of {ROUNDS})")
    for workers in (1, 2):
        with LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster, Client(cluster) as client:
            glview.dask.render_jobs(client, lines, progress=False)
            rates = []
            for _ in range(ROUNDS):
                t = time.perf_counter()
                glview.dask.render_jobs(client, lines, progress=False)
                rates.append(JOBS / (time.perf_counter() - t))
        print(f"| {workers} worker process{'es' if workers > 1 else ''} | {statistics.median(rates):.1f} |")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
