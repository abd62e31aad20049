"""Dask: jobs rendered on a LocalCluster of two worker processes are the bytes
`glview batch` writes for the same jobs file."""
import os

import pytest

# scripts/test_python.sh installs distributed; only a hand-made venv may lack it, and CI
# must not pass by skipping.
if os.environ.get("CI") == "true":
    import distributed
else:
    distributed = pytest.importorskip("distributed")


def test_local_cluster_equals_glview_batch(tmp_path, bunny, cli):
    import glview.dask

    lines = ["# turntable of the small bunny"]
    for i, yaw in enumerate(range(0, 360, 45)):
        lines.append(f"{bunny} --size 120x90 --yaw {yaw} -o {{dir}}/view{i}.png")
    (tmp_path / "batch").mkdir()
    (tmp_path / "dask").mkdir()
    jobs = tmp_path / "jobs.txt"
    jobs.write_text("\n".join(lines).replace("{dir}", str(tmp_path / "batch")) + "\n")
    cli("batch", jobs)
    dask_lines = [l.replace("{dir}", str(tmp_path / "dask")) for l in lines]
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        paths = glview.dask.render_jobs(client, dask_lines, progress=False)
        workers = client.run(lambda: 1)
    assert len(workers) == 2
    assert len(paths) == 8
    for i in range(8):
        a = (tmp_path / "batch" / f"view{i}.png").read_bytes()
        b = (tmp_path / "dask" / f"view{i}.png").read_bytes()
        assert a == b, f"view{i}.png differs"
