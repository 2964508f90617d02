"""examples/fleet_dask.py on a LocalCluster of two workers: every verdict equals the one-process
one, in input order, failures as rows."""

from __future__ import annotations

import importlib.util
import time
from pathlib import Path

import pytest

import hybrid_fdd as hf

pytest.importorskip("distributed", reason="dask.distributed not installed (pip install "
                    "'dask[distributed]' pandas)")
pytest.importorskip("pandas", reason="pandas not installed")

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "fleet_dask.py"


def load_example():
    spec = importlib.util.spec_from_file_location("fleet_dask", EXAMPLE)
    mod = importlib.util.module_from_spec(spec)
    import sys
    sys.modules["fleet_dask"] = mod
    spec.loader.exec_module(mod)
    return mod


def test_fleet_on_a_local_cluster_equals_one_process(cwru, tmp_path):
    fleet = load_example()
    paths = [str(cwru / "12k_drive_end" / f"{n}.mat") for n in (105, 118, 130, 169, 185, 197, 209)]
    junk = tmp_path / "junk.csv"
    junk.write_text("not,a\nrecording,here\n")
    paths.append(str(junk))
    options = {"bearing": "6205", "baseline": str(cwru / "normal" / "97.mat")}
    client = fleet.local_cluster(2)
    try:
        assert len(client.scheduler_info()["workers"]) == 2
        client.run(lambda: __import__("hybrid_fdd"))
        t0 = time.perf_counter()
        table = fleet.run(client, paths, options, batch_size=3)
        elapsed = time.perf_counter() - t0
    finally:
        client.close()
        client.cluster.close()
    print(f"\nFLEET LocalCluster(2 workers): {len(paths)} items in {elapsed:.2f} s = "
          f"{len(paths) / elapsed:.2f} recordings/s (3 tasks of <= 3)")
    assert list(table["file"]) == paths
    for path, got in zip(paths[:-1], table.itertuples()):
        want = hf.diagnose(path, **options)
        assert got.verdict == want.verdict, path
        assert got.p_healthy == want.p_healthy and got.rpm_used == want.rpm_used
        assert not isinstance(got.error, str)  # None (NaN in a pandas column)
    last = table.iloc[-1]
    import pandas as pd
    assert pd.isna(last["verdict"]) and last["error"].startswith("DataError: ")


def test_quickstart_runs_top_to_bottom(data, tmp_path):
    import subprocess
    import sys
    script = EXAMPLE.with_name("quickstart.py")
    r = subprocess.run([sys.executable, str(script), str(data), "--out", str(tmp_path)],
                       check=True, capture_output=True, text=True)
    assert "outer" in r.stdout and "recordings in" in r.stdout
    assert (tmp_path / "rig.json").exists()
    assert hf.MachineModel.load(tmp_path / "rig.json").fs == 12_000.0
