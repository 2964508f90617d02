"""Every error path: a Python exception of the right class with the Rust message on one line,
never a panic (InternalError) and never a crash."""

from __future__ import annotations

import numpy as np
import pytest

import hybrid_fdd as hf
from conftest import synthetic

FS = 12_000.0
X = synthetic("outer")


def one_line(e: pytest.ExceptionInfo) -> str:
    msg = str(e.value)
    assert "\n" not in msg and msg.strip(), msg
    assert not isinstance(e.value, hf.InternalError)
    return msg


def test_exception_classes():
    assert issubclass(hf.InputError, ValueError)
    assert issubclass(hf.DataError, OSError)
    assert issubclass(hf.InternalError, RuntimeError)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(bearing="6299-XYZ"), "not in the catalogue"),
        (dict(bearing="n=9,d=-1in,D=2in"), "must be positive"),  # a bad geometry
        (dict(rpm=5.0), "out of range"),  # below MIN_RPM
        (dict(rpm=1e9), "out of range"),
        (dict(rpm=float("nan")), "NaN rpm out of range"),
        (dict(fs=100.0), "sampling rate"),  # below MIN_FS_HZ
        (dict(fs=float("inf")), "inf Hz out of range"),
        (dict(rpm=None), "rpm"),  # no speed and no range
        (dict(rpm_range=(1900, 1600)), "empty or inverted"),
        (dict(rpm_range="fast"), "LOW-HIGH"),
        (dict(rpm_range=(1, 2, 3)), "low, high"),
        (dict(rpm_range=("a", 2)), "number"),
        (dict(alpha=0.0), "0.2"),
        (dict(alpha=0.5), "0.2"),
        (dict(alpha="often"), "number"),
    ],
)
def test_bad_options_are_input_errors(kwargs, match):
    args = dict(fs=FS, rpm=1797.0, bearing="6205")
    args.update(kwargs)
    with pytest.raises(hf.InputError, match=match) as e:
        hf.diagnose(X, **args)
    one_line(e)


@pytest.mark.parametrize(
    "x, match",
    [
        (np.where(np.arange(len(X)) == 100, np.nan, X), "non-finite"),
        (np.where(np.arange(len(X)) == 7, np.inf, X), "non-finite"),
        (X[:500], "too short"),
        (np.zeros((2, 1000)), "1-D"),
        (X.astype(complex), "real"),
        (np.array(["a", "b"]), "real"),
        (np.array([]), "empty"),
    ],
)
def test_bad_arrays_are_input_errors(x, match):
    with pytest.raises(hf.InputError, match=match) as e:
        hf.diagnose(x, fs=FS, rpm=1797.0)
    one_line(e)


def test_array_needs_fs():
    with pytest.raises(hf.InputError, match="fs") as e:
        hf.diagnose(X, rpm=1797.0)
    one_line(e)


def test_baseline_errors():
    # a baseline at a rate no integer factor joins to the recording's
    with pytest.raises(hf.InputError, match="Hz") as e:
        hf.diagnose(X, fs=FS, rpm=1797.0, baseline=(synthetic("none", fs=7000.0), 7000.0))
    one_line(e)
    with pytest.raises(hf.InputError, match="non-finite") as e:
        hf.diagnose(X, fs=FS, rpm=1797.0, baseline=np.full(len(X), np.nan))
    one_line(e)
    with pytest.raises(hf.DataError, match="missing-baseline.mat") as e:
        hf.diagnose(X, fs=FS, rpm=1797.0, baseline="missing-baseline.mat")
    one_line(e)


def test_unreadable_files_are_data_errors(tmp_path):
    missing = tmp_path / "nope.mat"
    for call in (lambda: hf.read(missing), lambda: hf.diagnose(missing)):
        with pytest.raises(hf.DataError, match="nope.mat") as e:
            call()
        one_line(e)
        assert isinstance(e.value, OSError)
    junk = tmp_path / "junk.bin"
    junk.write_bytes(bytes(range(256)) * 8)
    with pytest.raises(hf.DataError, match="neither a MAT-file nor text") as e:
        hf.read(junk)
    one_line(e)
    fake = tmp_path / "130.mat"
    fake.write_bytes(b"MATLAB 5.0 MAT-file, truncated")
    with pytest.raises(hf.DataError) as e:
        hf.read(fake)
    one_line(e)
    csv = tmp_path / "x.csv"
    csv.write_text("a,b\n1,2\n3,4\n")
    with pytest.raises(hf.DataError) as e:
        hf.read(csv, channel="nope")
    one_line(e)
    with pytest.raises(hf.DataError, match="not a directory") as e:
        hf.diagnose_many(tmp_path / "no-such-dir")
    one_line(e)
    with pytest.raises(hf.DataError) as e:
        hf.recordings_in(tmp_path / "no-such-dir")
    one_line(e)


def test_fs_disagreeing_with_a_files_rate(tmp_path):
    csv = tmp_path / "t.csv"
    t = np.arange(48_000) / 12_000.0
    np.savetxt(csv, np.c_[t, X[: len(t)]], delimiter=",", header="time_s,accel", comments="")
    assert hf.read(csv).fs == pytest.approx(12_000.0)
    with pytest.raises(hf.DataError, match="disagrees") as e:
        hf.read(csv, fs=10_000.0)
    one_line(e)


def test_diagnose_many_errors_raise_or_return():
    good, bad = X, np.where(np.arange(len(X)) == 3, np.nan, X)
    with pytest.raises(hf.InputError, match=r"^item 1: .*non-finite") as e:
        hf.diagnose_many([good, bad, good], fs=FS, rpm=1797.0)
    one_line(e)
    out = hf.diagnose_many([good, bad, X[:300]], fs=FS, rpm=1797.0, errors="return")
    assert isinstance(out[0], hf.Diagnosis)
    assert isinstance(out[1], hf.InputError) and "non-finite" in str(out[1])
    assert isinstance(out[2], hf.InputError) and "too short" in str(out[2])
    for kwargs, match in [
        (dict(errors="ignore"), "errors"),
        (dict(threads=0), "threads"),
        (dict(fs=[FS, FS]), "2 values for 3"),
        (dict(rpm=[1797.0]), "1 values for 3"),
    ]:
        args = dict(fs=FS, rpm=1797.0)
        args.update(kwargs)
        with pytest.raises(hf.InputError, match=match) as e:
            hf.diagnose_many([good, good, good], **args)
        one_line(e)
    with pytest.raises(hf.InputError, match="mixes") as e:
        hf.diagnose_many([good, "a.mat"], fs=FS, rpm=1797.0)
    one_line(e)


def test_unknown_bearing():
    with pytest.raises(hf.InputError, match="unknown bearing") as e:
        hf.bearing("6299-XYZ")
    one_line(e)


def test_prepared_baseline_errors(tmp_path):
    with pytest.raises(hf.DataError, match="gone.mat") as e:
        hf.Baseline(tmp_path / "gone.mat")
    one_line(e)
    with pytest.raises(hf.InputError, match="fs") as e:
        hf.Baseline(np.ones(1000))
    one_line(e)
    with pytest.raises(hf.InputError, match="one baseline") as e:
        hf._native.diagnose_arrays([X], [FS], [1797.0], [None], "6205",
                                   baseline_path="a.mat",
                                   baseline_prepared=hf.Baseline(X, fs=FS)._native)
    one_line(e)
