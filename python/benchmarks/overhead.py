"""The binding's overhead over the Rust diagnosis on a 10 s record (reported, not asserted).

    python python/benchmarks/overhead.py [RECORDING] [--runs 15]

Times ``hybrid_fdd.diagnose(x, fs, rpm)`` end to end in Python (copy of the array, the Rust
diagnosis with the interpreter released, its report as JSON, ``json.loads``, the Diagnosis
object) against ``Diagnosis.rust_seconds``, the time the Rust diagnosis itself took inside the
same call (``hybrid_fdd_cli::diagnose::diagnose_loaded_with``, timed in Rust). Default recording:
CWRU 130.mat (10.2 s at 12 kHz) from ``HYBRID_FDD_DATA`` or ../shared/data; without it, 10 s of
synthetic signal.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time
from pathlib import Path

import numpy as np

import hybrid_fdd as hf


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("recording", nargs="?")
    p.add_argument("--runs", type=int, default=15)
    a = p.parse_args()
    data = Path(os.environ.get("HYBRID_FDD_DATA",
                               Path(__file__).resolve().parents[2].parent / "shared" / "data"))
    path = a.recording or data / "cwru" / "12k_drive_end" / "130.mat"
    if Path(path).exists():
        r = hf.read(path)
        x, fs, rpm, what = r.samples, r.fs, r.rpm, f"{Path(path).name}, {r.duration_s:.1f} s"
    else:
        rng = np.random.default_rng(0)
        x, fs, rpm, what = rng.normal(size=120_000), 12_000.0, 1797.0, "synthetic, 10.0 s"
    hf.diagnose(x, fs=fs, rpm=rpm)
    walls, rusts, parses = [], [], []
    for _ in range(a.runs):
        t0 = time.perf_counter()
        d = hf.diagnose(x, fs=fs, rpm=rpm)
        walls.append(time.perf_counter() - t0)
        rusts.append(d.rust_seconds)
        text = d.to_json(indent=None)
        t0 = time.perf_counter()
        json.loads(text)
        parses.append(time.perf_counter() - t0)
    wall, rust = statistics.median(walls), statistics.median(rusts)
    over = [w - r for w, r in zip(walls, rusts)]
    print(f"OVERHEAD ({what}, {a.runs} runs, medians): diagnose() {wall * 1e3:.1f} ms, of which "
          f"the Rust diagnosis {rust * 1e3:.1f} ms; binding overhead "
          f"{statistics.median(over) * 1e3:.1f} ms = {100 * statistics.median(over) / rust:.2f} % "
          f"(json.loads of the report alone {statistics.median(parses) * 1e3:.1f} ms)")


if __name__ == "__main__":
    main()
