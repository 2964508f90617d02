"""Shared fixtures: the data directory (the project's one setting) and the ``hybrid-fdd`` binary.

Data: ``HYBRID_FDD_DATA``, else ``../shared/data`` beside the workspace, as the Rust side finds
it (README, "Pointing it at data"). Tests that need the recordings skip with a message when they
are absent, and fail under ``CI=true``, as the Rust tests do.
"""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]


def data_dir() -> Path | None:
    env = os.environ.get("HYBRID_FDD_DATA")
    d = Path(env) if env else REPO.parent / "shared" / "data"
    return d if (d / "cwru").is_dir() else None


def _ci() -> bool:
    return os.environ.get("CI", "").lower() in ("1", "true", "yes")


@pytest.fixture(scope="session")
def data() -> Path:
    """The data directory holding ``cwru/`` (skip, or fail under CI=true, when absent)."""
    d = data_dir()
    if d is None:
        msg = ("real recordings absent: set HYBRID_FDD_DATA to the directory holding cwru/ "
               "(or put it at ../shared/data beside the workspace)")
        if _ci():
            pytest.fail(msg + " -- CI=true requires them")
        pytest.skip(msg)
    return d


@pytest.fixture(scope="session")
def cwru(data: Path) -> Path:
    return data / "cwru"


@pytest.fixture(scope="session")
def cli() -> Path:
    """The ``hybrid-fdd`` executable: ``HYBRID_FDD_BIN``, else built (or found up to date) by
    ``cargo build -p hybrid-fdd-cli --bin hybrid-fdd`` in the workspace (dev profile: what
    ``cargo test --workspace`` has already built in CI; optimisation levels do not change
    results)."""
    env = os.environ.get("HYBRID_FDD_BIN")
    if env:
        return Path(env)
    out = subprocess.run(
        ["cargo", "build", "-p", "hybrid-fdd-cli", "--bin", "hybrid-fdd",
         "--message-format=json-render-diagnostics"],
        cwd=REPO, check=True, stdout=subprocess.PIPE, text=True,
    ).stdout
    for line in out.splitlines():
        try:
            m = json.loads(line)
        except json.JSONDecodeError:
            continue
        if m.get("reason") == "compiler-artifact" and m.get("executable") and \
                m["target"]["name"] == "hybrid-fdd":
            return Path(m["executable"])
    raise RuntimeError("cargo build did not report the hybrid-fdd executable")


@pytest.fixture(scope="session")
def run_cli(cli: Path, tmp_path_factory: pytest.TempPathFactory):
    """Run ``hybrid-fdd diagnose ARGS --report <tmp>/r.json`` and return the JSON report."""
    counter = iter(range(10**6))

    def run(*args: str) -> dict:
        out = tmp_path_factory.mktemp(f"cli{next(counter)}") / "r.json"
        subprocess.run([str(cli), "diagnose", *args, "--report", str(out)], check=True,
                       stdout=subprocess.DEVNULL)
        return json.loads(out.read_text())

    return run


def synthetic(kind: str = "outer", seconds: float = 4.0, fs: float = 12_000.0,
              rpm: float = 1797.0, seed: int = 0) -> np.ndarray:
    """A signal made here (no data needed): white noise plus, for a fault, decaying 3 kHz bursts
    at the 6205's fault rate (BPFO 3.5848 x fr, BPFI 5.4152 x fr)."""
    rng = np.random.default_rng(seed)
    n = int(seconds * fs)
    x = rng.normal(0.0, 1.0, n)
    order = {"outer": 3.5848, "inner": 5.4152}.get(kind)
    if order is not None:
        rate = order * rpm / 60.0
        t = np.arange(int(0.01 * fs)) / fs
        burst = np.exp(-t * 800.0) * np.sin(2 * np.pi * 3000.0 * t) * 8.0
        for k in np.arange(0.0, seconds, 1.0 / rate):
            i = int(k * fs)
            seg = x[i:i + len(burst)]
            seg += burst[:len(seg)]
    return x
