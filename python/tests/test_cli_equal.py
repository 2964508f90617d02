"""The binding's results equal the command's JSON for the same recording and options."""

from __future__ import annotations

import shutil
import subprocess

import pytest

import hybrid_fdd as hf


def test_baseline_referenced_cwru_record_equals_cli(cwru, run_cli):
    rec, base = cwru / "12k_drive_end" / "130.mat", cwru / "normal" / "97.mat"
    want = run_cli("--input", str(rec), "--bearing", "6205", "--baseline", str(base))
    by_path = hf.diagnose(rec, bearing="6205", baseline=base)
    assert by_path.to_dict() == want
    assert by_path.verdict == want["verdict"] == "outer"
    assert by_path.reference == "baseline"
    assert by_path.baseline_note is not None and "decimated by 4" in by_path.baseline_note
    # the same through read(): Recording in, Recording as baseline, and plain arrays
    r, b = hf.read(rec), hf.read(base)
    assert hf.diagnose(r, baseline=b).to_dict() == want
    assert hf.diagnose(r.samples, fs=r.fs, rpm=r.rpm, baseline=(b.samples, b.fs)).to_dict() \
        == want


def test_self_referenced_with_range_and_alpha_equals_cli(cwru, run_cli):
    rec = cwru / "12k_drive_end" / "105.mat"
    want = run_cli("--input", str(rec), "--bearing", "SKF 6205-2RS", "--rpm-range", "1600-1900",
                   "--alpha", "0.05")
    got = hf.diagnose(rec, bearing="SKF 6205-2RS", rpm_range=(1600, 1900), alpha=0.05)
    assert got.to_dict() == want
    assert got.reference == "self"
    assert got.false_alarm == 0.05
    # the string form of the range, and the Recording form, give the same report
    assert hf.diagnose(hf.read(rec), bearing="6205-2RS", rpm_range="1600-1900",
                       alpha=0.05).to_dict()["verdict"] == want["verdict"]


def test_unknown_bearing_equals_cli(cwru, run_cli):
    rec = cwru / "12k_drive_end" / "197.mat"
    want = run_cli("--input", str(rec), "--bearing", "unknown")
    got = hf.diagnose(hf.read(rec), bearing="unknown")
    assert got.to_dict() == want
    assert got["bearing_guess"] is not None


def test_mfpt_generic_mat_equals_cli(data, run_cli):
    mfpt = data / "mfpt"
    files = sorted(mfpt.glob("*OuterRaceFault*.mat")) if mfpt.is_dir() else []
    if not files:
        pytest.skip(f"no MFPT recording under {mfpt}")
    rec = files[0]
    want = run_cli("--input", str(rec), "--bearing", "n=8,d=0.235in,D=1.245in")
    r = hf.read(rec)
    assert r.rpm_source == "file" and r.rpm is not None
    got = hf.diagnose(r, bearing="n=8,d=0.235in,D=1.245in")
    assert got.to_dict() == want


def test_simulated_csv_with_sidecar_equals_cli(cli, run_cli, tmp_path):
    """No shared data needed: the command's own simulation, a CSV and its JSON sidecar."""
    csv = tmp_path / "sim.csv"
    subprocess.run([str(cli), "simulate", "--fault", "inner", "--rpm", "1797", "--fs", "12000",
                    "--duration", "3", "--seed", "3", "--out", str(csv)], check=True,
                   stdout=subprocess.DEVNULL)
    r = hf.read(csv)
    assert r.fs == pytest.approx(12000.0, rel=1e-6)
    assert r.rpm == 1797.0 and r.rpm_source == "sidecar"
    assert r.unit == "g" and r.bearing == "6205"
    want = run_cli("--input", str(csv), "--bearing", "6205")
    assert hf.diagnose(csv).to_dict() == want
    assert hf.diagnose(r).to_dict() == want
    # a copy without the sidecar stores no speed: the command and the binding both ask for one
    bare = tmp_path / "bare" / "sim.csv"
    bare.parent.mkdir()
    shutil.copy(csv, bare)
    assert hf.read(bare).rpm is None
    with pytest.raises(hf.InputError, match="rpm"):
        hf.diagnose(bare)
    assert hf.diagnose(bare, rpm=1797).to_dict() == want


def test_paths_batch_equals_cli_directory_run(cwru, cli, tmp_path):
    """diagnose_many over a directory = `diagnose --input DIR` (same files, same reports)."""
    d = tmp_path / "in"
    d.mkdir()
    for n in ("105", "118", "130"):
        (d / f"{n}.mat").symlink_to(cwru / "12k_drive_end" / f"{n}.mat")
    out = tmp_path / "out"
    subprocess.run([str(cli), "diagnose", "--input", str(d), "--bearing", "6205", "--report",
                    str(out)], check=True, stdout=subprocess.DEVNULL)
    got = hf.diagnose_many(d, bearing="6205")
    assert [g.source for g in got] == hf.recordings_in(d)
    import json
    for g in got:
        stem = g.source.rsplit("/", 1)[-1].removesuffix(".mat")
        assert g.to_dict() == json.loads((out / f"{stem}.json").read_text())


def test_prepared_baseline_equals_cli_and_is_reused(cwru, run_cli):
    rec, base = cwru / "12k_drive_end" / "130.mat", cwru / "normal" / "97.mat"
    want = run_cli("--input", str(rec), "--bearing", "6205", "--baseline", str(base))
    b = hf.Baseline(base)
    assert "97.mat" in repr(b)
    r = hf.read(rec)
    assert hf.diagnose(r, baseline=b).to_dict() == want
    assert hf.diagnose(r, baseline=b).to_dict() == want  # the cached preparation, same report
    assert hf.diagnose(rec, baseline=b).to_dict() == want
    assert [d.to_dict() for d in hf.diagnose_many([r, r], baseline=b)] == [want, want]
    r97 = hf.read(base)
    assert hf.diagnose(r, baseline=hf.Baseline(r97)).to_dict() == want
    assert hf.diagnose(r, baseline=hf.Baseline(r97.samples, fs=r97.fs)).to_dict() == want


def test_simulate_equals_cli(cli, tmp_path):
    out = tmp_path / "cli.csv"
    subprocess.run([str(cli), "simulate", "--fault", "outer", "--rpm", "1750", "--fs", "12000",
                    "--duration", "1.5", "--seed", "7", "--out", str(out)], check=True,
                   stdout=subprocess.DEVNULL)
    rec, side = hf.simulate(fault="outer", rpm=1750, fs=12000, duration=1.5, seed=7)
    import json
    import numpy as np
    want = hf.read(out)
    assert np.array_equal(rec.samples, want.samples) and rec.fs == want.fs
    assert side == json.loads(out.with_suffix(".json").read_text())
    assert rec.unit == "g" and rec.rpm == 1750 and side["params"] == "calibrated"
    # the bare 5-DOF model (m/s^2), kept at `out`
    kept = tmp_path / "bare" / "b.csv"
    rec2, side2 = hf.simulate(out=kept, fault="inner", params="cwru", duration=0.5, seed=1)
    assert kept.exists() and rec2.unit == "m/s^2" and side2["params"] == "cwru"
    with pytest.raises(hf.InputError, match="unexpected argument"):
        hf.simulate(no_such_flag=1)
    with pytest.raises(hf.InputError, match="rpm"):
        hf.simulate(rpm=-5)
