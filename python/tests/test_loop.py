"""calibrate and close_loop equal the command's files; a MachineModel saves what `calibrate
--out` writes and serves as a diagnosis baseline."""

from __future__ import annotations

import json
import subprocess

import pytest

import hybrid_fdd as hf


@pytest.fixture(scope="module")
def rig(cwru, cli, tmp_path_factory):
    """97.mat calibrated at 12 kHz by the command and by the binding."""
    out = tmp_path_factory.mktemp("rig") / "rig.json"
    subprocess.run([str(cli), "calibrate", "--input", str(cwru / "normal" / "97.mat"),
                    "--decimate", "4", "--out", str(out)], check=True, stdout=subprocess.DEVNULL)
    mine = hf.calibrate(cwru / "normal" / "97.mat", decimate=4)
    return out, mine


def test_calibrate_equals_cli(rig, tmp_path):
    out, mine = rig
    assert mine.to_dict() == json.loads(out.read_text())
    assert mine.ledger.to_dict() == json.loads(out.with_name("rig.report.json").read_text())
    assert mine.fs == 12_000.0 and mine.units == "g"
    saved = tmp_path / "mine.json"
    mine.save(saved)
    assert saved.read_text() == out.read_text()
    assert hf.MachineModel.load(saved).to_dict() == mine.to_dict()


def test_machine_model_baseline_equals_cli(rig, cwru, run_cli):
    out, mine = rig
    rec = cwru / "12k_drive_end" / "130.mat"
    want = run_cli("--input", str(rec), "--bearing", "6205", "--baseline", str(out))
    assert hf.diagnose(rec, baseline=mine).to_dict() == want
    assert hf.diagnose(rec, baseline=out).to_dict() == want


def test_close_loop_equals_cli(rig, cwru, cli, tmp_path):
    out, mine = rig
    rec = cwru / "12k_drive_end" / "130.mat"
    report = tmp_path / "loop.json"
    subprocess.run([str(cli), "close-loop", "--input", str(rec), "--fault", "outer", "--machine",
                    str(out), "--seconds", "4", "--report", str(report)], check=True,
                   stdout=subprocess.DEVNULL)
    kept = tmp_path / "kept" / "loop.json"
    ledger = hf.close_loop(rec, fault="outer", machine=mine, seconds=4, report=kept)
    assert ledger.to_dict() == json.loads(report.read_text())
    assert kept.exists() and kept.with_suffix(".md").exists()
    assert ledger.error_after <= ledger.error_before
    assert all(isinstance(e, hf.Effect) for e in ledger.effects)
    assert isinstance(ledger.machine, hf.MachineModel)


def test_loop_errors(tmp_path):
    with pytest.raises(hf.DataError) as e:
        hf.calibrate(tmp_path / "none.mat")
    assert "\n" not in str(e.value)
    bad = tmp_path / "bad.json"
    bad.write_text('{"not": "a machine model"}')
    with pytest.raises(hf.InputError):
        hf.MachineModel.load(bad)
    with pytest.raises(hf.DataError):
        hf.MachineModel.load(tmp_path / "missing.json")
