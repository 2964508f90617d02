"""A recording whose speed sweeps, diagnosed from Python with its tachometer channel (``tach``,
as ``hybrid-fdd diagnose --tach``): order tracked, the fault named, the tracking in the report;
and the errors of a tachometer given where it cannot be read."""

from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

import hybrid_fdd as hf

FS = 20_000.0
SECS = 8.0
PPR = 60
BEARING = "n=12,d=7.94mm,D=38.5mm,angle=0deg"


def sweep_csv(path, f0=25.0, f1=15.0, outer=True, seed=3):
    """A coast-down from f0 to f1 Hz: noise, a 1x line, outer-race impacts at the bearing's
    BPFO of the shaft's angle ringing 3 kHz (1 % jitter accumulating), and a tachometer of PPR
    square pulses a turn; written as ``accel,tach``."""
    rng = np.random.default_rng(seed)
    n = int(FS * SECS)
    t = np.arange(n) / FS
    theta = f0 * t + 0.5 * (f1 - f0) / SECS * t * t
    x = 0.2 * np.sin(2 * np.pi * theta + 0.3) + 0.5 * rng.standard_normal(n)
    if outer:
        r = 7.94 / 38.5
        step = 1.0 / (6.0 * (1.0 - r))
        angles = np.cumsum(step * (1.0 + 0.01 * rng.standard_normal(int(theta[-1] / step) + 10)))
        angles = angles[angles < theta[-1]]
        k0 = np.searchsorted(theta, angles)
        kt = np.arange(int(0.0064 * FS)) / FS
        kernel = np.exp(-kt / 0.0008) * np.sin(2 * np.pi * 3000.0 * kt)
        for k in k0:
            m = min(len(kernel), n - k)
            x[k:k + m] += kernel[:m]
    tach = np.where(np.mod(theta * PPR, 1.0) < 0.5, 5.0, 0.0)
    np.savetxt(path, np.column_stack([x, tach]), delimiter=",", header="accel,tach",
               comments="", fmt="%.6f")
    return path


def test_a_coast_down_is_named_with_its_tachometer(tmp_path, cli):
    csv = sweep_csv(tmp_path / "coast.csv")
    d = hf.diagnose(csv, fs=FS, bearing=BEARING, channel="accel", tach="tach",
                    pulses_per_rev=PPR)
    assert d.verdict == "outer", d
    t = d.order_tracking
    assert t is not None and t["source"]["kind"] == "tachometer"
    assert abs(t["min_rpm"] - 900) < 10 and abs(t["max_rpm"] - 1500) < 10, t
    # the same file at one speed: the lines smear over the sweep
    flat = hf.diagnose(csv, fs=FS, rpm=1200, bearing=BEARING, channel="accel")
    assert flat.verdict == "normal" and flat.order_tracking is None
    # the command's report, key for key
    out = tmp_path / "cli.json"
    subprocess.run([str(cli), "diagnose", "--input", str(csv), "--fs", str(FS), "--channel",
                    "accel", "--bearing", BEARING, "--tach", "tach", "--pulses-per-rev",
                    str(PPR), "--report", str(out)], check=True, capture_output=True)
    assert json.loads(out.read_text()) == d.to_dict()


def test_arrays_are_tracked_as_the_file_is(tmp_path):
    csv = sweep_csv(tmp_path / "coast.csv")
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    x, tach = data[:, 0], data[:, 1]
    samples, info = hf.order_track(x, tach, FS, PPR)
    assert abs(info["mean_rpm"] - 1200) < 5 and info["source"]["kind"] == "tachometer"
    assert len(samples) == pytest.approx(info["turns"] * info["samples_per_rev"], rel=0.03)
    d = hf.diagnose(x, fs=FS, bearing=BEARING, tach=tach, pulses_per_rev=PPR)
    f = hf.diagnose(csv, fs=FS, bearing=BEARING, channel="accel", tach="tach",
                    pulses_per_rev=PPR)
    assert d.verdict == f.verdict == "outer"
    assert d.p_healthy == f.p_healthy
    assert d.order_tracking == f.order_tracking
    with pytest.raises(hf.InputError, match="pulse"):
        hf.order_track(x, np.zeros_like(x), FS, PPR)


def test_a_tachometer_where_it_cannot_be_read_is_an_input_error(tmp_path):
    csv = sweep_csv(tmp_path / "coast.csv", outer=False)
    with pytest.raises(hf.InputError, match="leave out rpm"):
        hf.diagnose(csv, fs=FS, rpm=1200, bearing=BEARING, channel="accel", tach="tach")
    with pytest.raises(hf.InputError, match="give x as a path"):
        hf.diagnose(np.zeros(40_000), fs=FS, bearing=BEARING, tach="tach")
    with pytest.raises(hf.InputError, match="leave out rpm"):
        hf.diagnose(np.zeros(40_000), fs=FS, rpm=1200, bearing=BEARING, tach=np.zeros(40_000))
    with pytest.raises(hf.InputError, match="channel"):
        hf.diagnose(csv, fs=FS, bearing=BEARING, channel="accel", tach=np.zeros(3))
    with pytest.raises(hf.DataError, match="tachometer"):
        hf.diagnose(csv, fs=FS, bearing=BEARING, channel="accel", tach="tach",
                    pulses_per_rev=6000)


def comb_sweep(f0=25.0, f1=15.0, seed=5):
    """A coast-down from f0 to f1 Hz with a shaft comb (orders 1-12 at 1/k) over noise, and no
    tachometer: the recording's own comb gives its speed."""
    rng = np.random.default_rng(seed)
    n = int(FS * SECS)
    t = np.arange(n) / FS
    theta = f0 * t + 0.5 * (f1 - f0) / SECS * t * t
    x = 0.3 * rng.standard_normal(n)
    for k in range(1, 13):
        x += (1.0 / k) * np.sin(2 * np.pi * k * theta + 0.7 * k)
    return x


def test_steady_speed_reads_a_sweep_at_one_speed(tmp_path, cli):
    x = comb_sweep()
    tracked = hf.diagnose(x, fs=FS, rpm=1200, bearing=BEARING)
    assert tracked.order_tracking is not None, tracked
    assert tracked.order_tracking["source"]["kind"] == "shaft_comb"
    one = hf.diagnose(x, fs=FS, rpm=1200, bearing=BEARING, steady_speed=True)
    assert one.order_tracking is None and "order_tracking" not in one.to_dict()
    many = hf.diagnose_many([x, x], fs=FS, rpm=1200, bearing=BEARING, steady_speed=True)
    assert [m.order_tracking for m in many] == [None, None]
    # the command's --steady-speed, key for key
    csv = tmp_path / "comb.csv"
    np.savetxt(csv, x[:, None], delimiter=",", header="accel", comments="", fmt="%.9f")
    out = tmp_path / "cli.json"
    subprocess.run([str(cli), "diagnose", "--input", str(csv), "--fs", str(FS), "--channel",
                    "accel", "--rpm", "1200", "--bearing", BEARING, "--steady-speed",
                    "--report", str(out)], check=True, capture_output=True)
    f = hf.diagnose(csv, fs=FS, rpm=1200, bearing=BEARING, channel="accel", steady_speed=True)
    assert json.loads(out.read_text()) == f.to_dict()
    assert f.order_tracking is None
    with pytest.raises(hf.InputError, match="steady_speed"):
        hf.diagnose(x, fs=FS, bearing=BEARING, tach=np.zeros_like(x), steady_speed=True)
    with pytest.raises(hf.InputError, match="steady_speed"):
        hf.diagnose(x, fs=FS, rpm=1200, bearing=BEARING, steady_speed="yes")
