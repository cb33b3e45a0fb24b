"""The examples of python/examples run as users run them."""

import os
import runpy
import shutil
from pathlib import Path

import numpy as np
import pytest

import subsurf

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
MESHES = Path(__file__).resolve().parents[2] / "examples" / "meshes"


def test_notebook_tour_runs(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    env = runpy.run_path(str(EXAMPLES / "refine_evaluate_plot.py"), run_name="tour")
    h = env["mean_curvature"]
    assert h.shape == (201,) and np.isfinite(h).all()
    # Largest at the crease (v = 0).
    assert abs(h[0]) == np.abs(h).max()
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return
    assert (tmp_path / "limit-curvature.png").stat().st_size > 0


def test_refine_directory_on_a_local_dask_cluster(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    src = tmp_path / "in"
    src.mkdir()
    for name in ("cube.obj", "cube-crease.obj", "torus.obj"):
        shutil.copy(MESHES / name, src / name)
    (src / "notes.txt").write_text("not a mesh")
    example = runpy.run_path(str(EXAMPLES / "refine_directory.py"), run_name="example")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        results = example["refine_directory"](src, tmp_path / "out", 2, client)
    assert [Path(r["input"]).name for r in results] == ["cube-crease.obj", "cube.obj", "torus.obj"]
    for r in results:
        assert r["refined_faces"] == 16 * r["faces"]
        local = subsurf.read(r["input"]).subdivide(2)
        assert np.array_equal(subsurf.read(r["output"]).points, local.points)
