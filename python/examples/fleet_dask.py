"""A fleet of recordings diagnosed on a Dask distributed cluster.

    python python/examples/fleet_dask.py DIR_OR_FILES... [--workers 2] [--batch-size 8]
        [--bearing 6205] [--baseline healthy.mat] [--rpm 1797] [--out report.csv] [--bench]

The recordings (a directory, as ``hybrid-fdd diagnose --input DIR`` lists it, or files) are cut
into batches; each batch is one Dask task, which runs ``hybrid_fdd.diagnose_many`` on its worker
(the files are read there: only paths travel, and only a row per recording comes back). The
rows are gathered as a pandas DataFrame in input order: file, verdict, reference, speed used,
p under healthy, each fault's score, the band, and the error of a recording that failed.

Without ``--scheduler`` it starts a ``LocalCluster`` of ``--workers`` processes with one thread
each (a task's ``diagnose_many`` then runs on ``--threads-per-task`` rayon threads, 1 by default,
so workers do not oversubscribe the cores). With ``--bench`` it also times the same recordings
one at a time in this process and with one ``diagnose_many`` call, and prints recordings per
second for each.

For Spark the same function serves ``mapInArrow`` (python/README.md).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from typing import Any, Dict, Iterable, Iterator, List, Optional, Sequence

import hybrid_fdd as hf

#: The columns of the report table.
COLUMNS = [
    "file", "verdict", "reference", "rpm_used", "p_healthy", "score_inner_db", "score_outer_db",
    "score_ball_db", "band_low_hz", "band_high_hz", "error",
]


def row(path: str, d: Any) -> Dict[str, Any]:
    """One recording's row: its diagnosis, or the error it raised."""
    if isinstance(d, Exception):
        r = {c: None for c in COLUMNS}
        r.update(file=path, error=f"{type(d).__name__}: {d}")
        return r
    s = d["scores"]
    return {
        "file": path,
        "verdict": d.verdict,
        "reference": d.reference,
        "rpm_used": d.rpm_used,
        "p_healthy": d.p_healthy,
        "score_inner_db": s["inner"],
        "score_outer_db": s["outer"],
        "score_ball_db": s["ball"],
        "band_low_hz": d.band["low_hz"],
        "band_high_hz": d.band["high_hz"],
        "error": None,
    }


def diagnose_batch(paths: Sequence[str], options: Dict[str, Any],
                   threads: Optional[int] = 1) -> List[Dict[str, Any]]:
    """The task: diagnose one batch of files where it runs, one row each, failures as rows."""
    out = hf.diagnose_many(list(paths), errors="return", threads=threads, **options)
    return [row(p, d) for p, d in zip(paths, out)]


def batches(items: Sequence[str], size: int) -> Iterator[List[str]]:
    """``items`` in consecutive batches of ``size`` (the last may be shorter)."""
    for i in range(0, len(items), size):
        yield list(items[i:i + size])


def expand(inputs: Iterable[str]) -> List[str]:
    """Directories expanded as ``hybrid-fdd diagnose --input DIR`` lists them; files kept."""
    paths: List[str] = []
    for i in inputs:
        paths.extend(hf.recordings_in(i) if os.path.isdir(i) else [os.fspath(i)])
    return paths


def run(client: Any, paths: Sequence[str], options: Dict[str, Any], batch_size: int = 8,
        threads_per_task: Optional[int] = 1) -> "Any":
    """Diagnose ``paths`` on the cluster of ``client``, one task per batch; the report table as
    a pandas DataFrame in input order."""
    import pandas as pd

    task = _task(client)
    futures = [client.submit(task, b, options, threads_per_task, pure=False)
               for b in batches(list(paths), batch_size)]
    rows = [r for batch in client.gather(futures) for r in batch]
    return pd.DataFrame(rows, columns=COLUMNS)


def local_cluster(workers: int = 2) -> Any:
    """A ``LocalCluster`` of ``workers`` processes with one thread each, and its client."""
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           dashboard_address=":0")
    return Client(cluster)


def _task(client: Any) -> Any:
    """:func:`diagnose_batch` as the workers can import it: this file is sent to them
    (``Client.upload_file``), and the function is taken from the module ``fleet_dask`` (also
    when this file runs as ``__main__``, whose functions a worker cannot import)."""
    here = os.path.abspath(__file__)
    client.upload_file(here)
    if __name__ != "fleet_dask":
        sys.path.insert(0, os.path.dirname(here))
        import fleet_dask  # noqa: PLC0415 - this very file, under its module name

        return fleet_dask.diagnose_batch
    return diagnose_batch


def main(argv: Optional[Sequence[str]] = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("inputs", nargs="+", help="directories and/or recording files")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--scheduler", help="address of a running Dask scheduler (else a LocalCluster)")
    p.add_argument("--batch-size", type=int, default=8)
    p.add_argument("--threads-per-task", type=int, default=1)
    p.add_argument("--bearing", default="6205")
    p.add_argument("--baseline")
    p.add_argument("--rpm", type=float)
    p.add_argument("--fs", type=float)
    p.add_argument("--channel")
    p.add_argument("--out", help="write the table (.csv or .parquet)")
    p.add_argument("--bench", action="store_true",
                   help="also time one process (one at a time, and diagnose_many)")
    a = p.parse_args(argv)
    paths = expand(a.inputs)
    options = {k: v for k, v in dict(bearing=a.bearing, baseline=a.baseline, rpm=a.rpm,
                                     fs=a.fs, channel=a.channel).items() if v is not None}
    if a.scheduler:
        from distributed import Client
        client = Client(a.scheduler)
    else:
        client = local_cluster(a.workers)
    with client:
        client.run(lambda: __import__("hybrid_fdd"))  # workers import the package before timing
        t0 = time.perf_counter()
        table = run(client, paths, options, a.batch_size, a.threads_per_task)
        t_cluster = time.perf_counter() - t0
    print(table.to_string(index=False, max_colwidth=60))
    print(f"cluster: {len(paths)} recordings in {t_cluster:.2f} s = "
          f"{len(paths) / t_cluster:.2f} recordings/s ({a.workers} workers)")
    if a.bench:
        t0, c0 = time.perf_counter(), time.process_time()
        for path in paths:
            try:
                hf.diagnose(path, **options)
            except (hf.InputError, hf.DataError):
                pass
        t_one, c_one = time.perf_counter() - t0, time.process_time() - c0
        t0 = time.perf_counter()
        hf.diagnose_many(paths, errors="return", **options)
        t_many = time.perf_counter() - t0
        print(f"one process, one at a time: {len(paths) / t_one:.2f} recordings/s "
              f"({c_one / len(paths):.3f} CPU s per recording); "
              f"diagnose_many: {len(paths) / t_many:.2f} recordings/s; load average "
              f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    if a.out:
        (table.to_parquet if a.out.endswith(".parquet") else table.to_csv)(a.out, index=False)
    return 1 if table["error"].notna().any() else 0


if __name__ == "__main__":
    sys.exit(main())
