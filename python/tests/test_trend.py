"""``hybrid_fdd.trend``: equal to ``hybrid-fdd trend`` on the IMS- and XJTU-SY-layout fixtures
(``fixtures/trend/``), right on recordings made here, and one-line typed errors on bad input."""

from __future__ import annotations

import datetime as dt
import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import hybrid_fdd as hf
from conftest import REPO, synthetic

FIXTURES = REPO / "fixtures" / "trend"
IMS_ARGS = dict(bearing="ZA-2115", rpm=2000, baseline_count=5, unit="g",
                machine_group="group2-rigid")
IMS_FLAGS = ["--bearing", "ZA-2115", "--rpm", "2000", "--baseline-count", "5", "--unit", "g",
             "--machine-group", "group2-rigid"]


@pytest.fixture(scope="session")
def run_trend(cli: Path, tmp_path_factory: pytest.TempPathFactory):
    """Run ``hybrid-fdd trend ARGS --report <tmp>`` and return the report directory."""
    counter = iter(range(10**6))

    def run(*args: str) -> Path:
        out = tmp_path_factory.mktemp(f"trend{next(counter)}")
        subprocess.run([str(cli), "trend", *args, "--report", str(out)], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        return out

    return run


def _same_files(a: Path, b: Path) -> None:
    for f in ("trend.json", "trend.csv", "summary.md", "trend.png"):
        assert (a / f).read_bytes() == (b / f).read_bytes(), f


def test_ims_fixture_equals_cli(run_trend, tmp_path):
    src = str(FIXTURES / "ims")
    want_dir = run_trend("--input", src, *IMS_FLAGS, "--no-observers")
    want = json.loads((want_dir / "trend.json").read_text())
    got = hf.trend(src, **IMS_ARGS, observers=False)
    assert got.to_dict() == want
    assert got["layout"] == "IMS (tab-separated, no header)"
    assert got.indicators == [i["name"] for i in want["indicators"]]
    assert "kurtosis" in got.indicators
    assert len(got.rows) == len(got) == 10
    assert got.rows[0].name == "2004.02.12.10.32.39"
    assert got.rows[0].time_text == "2004-02-12T10:32:39"
    assert got.rows[1].time - got.rows[0].time == 600.0
    assert all(r.baseline == (i < 5) for i, r in enumerate(got.rows))
    assert all(r.zone is not None for r in got.rows)
    # the impacts begin in the 7th file: 3 of 4 fires at the 9th at the earliest
    a = got.alarm
    assert a is not None and a.index == want["alarm"]["index"] == 8
    assert a.time_text == "2004-02-12T11:52:39" and a.name == "2004.02.12.11.52.39"
    assert "kurtosis" in a.indicators and a.fault == "not diagnosed"
    assert set(a.severity) == set(a.indicators)
    th = got.thresholds["kurtosis"]
    assert th is not None and th.k == 5.0 and th.baselines == 5
    assert th.value == want["thresholds"][got.indicators.index("kurtosis")]["value"]
    assert got.rows[8].above["kurtosis"] and got.rows[8].normalised["kurtosis"] > th.value
    # write() gives the command's four files, byte for byte
    got.write(tmp_path / "w")
    _same_files(tmp_path / "w", want_dir)
    # report= writes them too
    hf.trend(src, **IMS_ARGS, observers=False, report=tmp_path / "r")
    _same_files(tmp_path / "r", want_dir)


def test_xjtu_fixture_with_observers_equals_cli(run_trend):
    src = str(FIXTURES / "xjtu")
    want = json.loads((run_trend("--input", src, "--bearing", "UER204", "--rpm", "2100",
                                 "--baseline-count", "5") / "trend.json").read_text())
    got = hf.trend(src, bearing="UER204", rpm=2100, baseline_count=5)
    assert got.to_dict() == want
    assert got.axis == "index"
    assert [r.name for r in got.rows] == [f"{k}.csv" for k in range(1, 11)]
    assert got["channel"] == "Horizontal_vibration_signals"
    assert "hostsmo_ms" in got.indicators and "afsmo_ratio" in got.indicators
    assert got.alarm is not None and got.alarm.index >= 8
    # the vertical channel stays healthy: no alarm on it
    v = hf.trend(src, bearing="UER204", rpm=2100, baseline_count=5, observers=False,
                 channel="Vertical_vibration_signals")
    assert v.alarm is None and v["channel"] == "Vertical_vibration_signals"


def test_options_reach_the_command(run_trend):
    src = str(FIXTURES / "ims")
    flags = ["--input", src, *IMS_FLAGS, "--no-observers", "--alarm", "2/3", "--k", "4",
             "--alarm-on", "kurtosis,crest", "--speed-exponent", "1", "--channel", "2"]
    want = json.loads((run_trend(*flags) / "trend.json").read_text())
    got = hf.trend(src, **IMS_ARGS, observers=False, alarm="2/3", k=4, alarm_on=["kurtosis", "crest"],
                   speed_exponent=1, channel="2")
    assert got.to_dict() == want
    assert got["config"]["m"] == 2 and got["config"]["k"] == 4.0
    assert got["alarm_on"] == ["kurtosis", "crest"]


def test_index_csv_equals_cli(run_trend, tmp_path):
    idx = tmp_path / "index.csv"
    rows = [f"{(FIXTURES / 'xjtu' / f'{k}.csv').as_posix()},{k}" for k in range(10, 0, -1)]
    idx.write_text("file,time\n" + "\n".join(rows) + "\n")
    want = json.loads((run_trend("--index", str(idx), "--bearing", "UER204", "--rpm", "2100",
                                 "--baseline-count", "5", "--no-observers") / "trend.json")
                      .read_text())
    got = hf.trend(index=idx, bearing="UER204", rpm=2100, baseline_count=5, observers=False)
    assert got.to_dict() == want
    assert got.rows[0].name.endswith("/1.csv")


def test_to_pandas_and_plot():
    t = hf.trend(FIXTURES / "ims", **IMS_ARGS, observers=False)
    pd = pytest.importorskip("pandas")
    df = t.to_pandas()
    assert isinstance(df, pd.DataFrame) and len(df) == 10
    header = t.to_csv().splitlines()[0].split(",")
    assert list(df.columns) == header
    assert df["kurtosis"].tolist() == [r.values["kurtosis"] for r in t.rows]
    assert df["above_kurtosis"].iloc[8]
    assert df["evidence_outer"].isna().all()  # too short for the diagnosis
    pytest.importorskip("matplotlib")
    import matplotlib
    matplotlib.use("Agg")
    fig = t.plot()
    visible = [ax for ax in fig.axes if ax.get_visible()]
    assert len(visible) == len(t.indicators)
    fig2 = t.plot(indicators=["kurtosis"])
    assert len([ax for ax in fig2.axes if ax.get_visible()]) == 1
    with pytest.raises(hf.InputError, match="no indicator 'nope'"):
        t.plot(indicators=["nope"])


def test_to_pandas_without_pandas_is_a_clear_import_error(monkeypatch):
    t = hf.trend(FIXTURES / "ims", **IMS_ARGS, observers=False)
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match="pip install pandas"):
        t.to_pandas()


FS, RPM = 12_000.0, 1797.0
T0 = dt.datetime(2024, 3, 1, 8, 0, 0)


def _life(onset: int, n: int = 20, gain_from: int | None = None) -> list:
    """n one-second recordings an hour apart: healthy, then outer-race impacts from ``onset``;
    from ``gain_from`` on, healthy ones multiplied by 3 (a sensor-gain step)."""
    items = []
    for i in range(n):
        x = synthetic("outer" if i >= onset else "none", seconds=1.0, fs=FS, rpm=RPM, seed=i)
        if gain_from is not None and i >= gain_from:
            x = 3.0 * x
        items.append((T0 + dt.timedelta(hours=i), x, FS))
    return items


def test_arrays_alarm_after_the_onset_and_not_before():
    onset = 14
    items = _life(onset)
    t = hf.trend(items[::-1], bearing="6205", rpm=RPM, observers=False)  # any order
    assert t.axis == "seconds"
    assert [r.time_text for r in t.rows][:2] == ["2024-03-01T08:00:00", "2024-03-01T09:00:00"]
    a = t.alarm
    assert a is not None
    assert onset <= a.index <= onset + 3, a
    assert a.fault == "outer"
    assert "kurtosis" in a.indicators
    # nothing above any threshold before the onset, after the baseline
    for r in t.rows[10:onset]:
        assert not any(r.above.values()), r
    for o in t["onsets"]:
        if o is not None:
            assert o["first_exceedance_index"] >= onset
    assert [r.verdict for r in t.rows[onset:]] == ["outer"] * (20 - onset)


def test_arrays_healthy_run_has_no_alarm():
    t = hf.trend(_life(onset=99), bearing="6205", rpm=RPM, observers=False)
    assert t.alarm is None
    assert "No alarm" in t.summary


def test_arrays_gain_step_does_not_fire_crest_or_kurtosis():
    t = hf.trend(_life(onset=99, gain_from=14), bearing="6205", rpm=RPM, observers=False)
    onsets = {o["indicator"]: o for o in t["onsets"] if o is not None}
    assert "rms" in onsets  # the gain step is seen where it should be...
    for immune in ("crest", "kurtosis", "evidence_outer", "evidence_inner"):
        assert immune not in onsets, onsets[immune]  # ...and not where it should not
    assert t.alarm is None or not {"crest", "kurtosis"} & set(t.alarm.indicators)


def test_arrays_forms_agree_and_numbers_are_positions(tmp_path):
    items = _life(onset=14, n=14)
    by_tuple = hf.trend([(i, x, FS) for i, (_, x, _) in enumerate(items)], bearing="6205",
                        rpm=RPM, observers=False, baseline_count=10)
    by_fs = hf.trend([(i, x) for i, (_, x, _) in enumerate(items)], bearing="6205", rpm=RPM,
                     fs=FS, observers=False, baseline_count=10)
    by_rpm = hf.trend([(i, x, FS, RPM) for i, (_, x, _) in enumerate(items)], bearing="6205",
                      observers=False, baseline_count=10)
    assert by_tuple.axis == "index"
    assert by_tuple.to_dict() == by_fs.to_dict() == by_rpm.to_dict()
    recs = []
    for i, (_, x, _) in enumerate(items):
        p = tmp_path / f"{i}.csv"
        np.savetxt(p, x, header="accel", comments="", fmt="%.17g")
        recs.append((np.datetime64("2024-03-01T08:00:00") + np.timedelta64(i, "h"),
                     hf.read(p, fs=FS)))
    by_rec = hf.trend(recs, bearing="6205", rpm=RPM, observers=False)
    assert by_rec.axis == "seconds" and by_rec.rows[3].name == "3.csv"
    assert [r.values for r in by_rec.rows] == [r.values for r in by_tuple.rows]


def test_arrays_write_the_four_files(tmp_path):
    t = hf.trend(_life(onset=14, n=16), bearing="6205", rpm=RPM, observers=False,
                 report=tmp_path / "r")
    for f in ("trend.csv", "trend.json", "summary.md", "trend.png"):
        assert (tmp_path / "r" / f).stat().st_size > 0, f
    assert json.loads((tmp_path / "r" / "trend.json").read_text()) == t.to_dict()
    assert (tmp_path / "r" / "summary.md").read_text() == t.summary


# bad input: one line, the typed error, the file named


def _ims_copies(d: Path, names: list) -> Path:
    d.mkdir()
    files = sorted((FIXTURES / "ims").iterdir())
    for n, f in zip(names, files * 2):
        shutil.copy(f, d / n)
    return d


IMS_NAMES = [f"2004.02.12.1{h}.{m}2.39" for h, m in
             [(0, 3), (0, 4), (0, 5), (1, 0), (1, 1), (1, 2)]]


def _one_line(e: pytest.ExceptionInfo) -> str:
    msg = str(e.value)
    assert "\n" not in msg, msg
    return msg


def test_duplicate_timestamps_are_data_errors_naming_the_file(tmp_path):
    d = _ims_copies(tmp_path / "dup", IMS_NAMES + ["2004-02-12T10:42:39.csv"])
    with pytest.raises(hf.DataError) as e:
        hf.trend(d, **IMS_ARGS, observers=False)
    msg = _one_line(e)
    assert "duplicate timestamp 2004-02-12T10:42:39" in msg and "2004-02-12T10:42:39.csv" in msg
    d = _ims_copies(tmp_path / "unparsed", IMS_NAMES + ["readings_final.csv"])
    with pytest.raises(hf.DataError, match=r"^readings_final.csv: no timestamp"):
        hf.trend(d, **IMS_ARGS, observers=False)


def test_duplicate_times_in_memory_are_input_errors():
    items = _life(onset=99, n=12)
    items[7] = (items[3][0], items[7][1], FS)
    with pytest.raises(hf.InputError) as e:
        hf.trend(items, bearing="6205", rpm=RPM, observers=False)
    assert "item 7: duplicate timestamp 2024-03-01T11:00:00 (also item 3)" in _one_line(e)
    mixed = [(T0 + dt.timedelta(hours=i), x, FS) for i, (_, x, _) in enumerate(items)]
    mixed[4] = (4, mixed[4][1], FS)
    with pytest.raises(hf.InputError, match=r"^item 4: named by a number, but item 0 is named "
                                            r"by a timestamp"):
        hf.trend(mixed, bearing="6205", rpm=RPM, baseline_count=5, observers=False)


def test_too_few_baselines_and_recordings_are_input_errors(tmp_path):
    d = _ims_copies(tmp_path / "few", IMS_NAMES)
    args = {**IMS_ARGS, "observers": False}
    with pytest.raises(hf.InputError,
                       match=r"3 baseline recording\(s\), the thresholds need at least 5"):
        hf.trend(d, **{**args, "baseline_count": 3})
    with pytest.raises(hf.InputError, match=r"6 recording\(s\), fewer than the 8 baseline"):
        hf.trend(d, **{**args, "baseline_count": 8})
    with pytest.raises(hf.InputError, match=r"12 recording\(s\), fewer than the 15 baseline"):
        hf.trend(_life(onset=99, n=12), bearing="6205", rpm=RPM, baseline_count=15,
                 observers=False)


def test_mixed_rates_and_channel_counts_are_errors_naming_the_recording(tmp_path):
    items = _life(onset=99, n=12)
    items[6] = (items[6][0], items[6][1], 10_000.0)
    with pytest.raises(hf.InputError) as e:
        hf.trend(items, bearing="6205", rpm=RPM, observers=False)
    assert _one_line(e).startswith(
        "item 6: sampled at 10000 Hz, the first recording (item 0) at 12000 Hz")
    # files: CSV with a time column, the 6th at another rate
    d = tmp_path / "rates"
    d.mkdir()
    for k in range(1, 7):
        fs = 10_000.0 if k == 6 else 12_000.0
        x = np.random.default_rng(k).normal(size=3000)
        np.savetxt(d / f"{k}.csv", np.column_stack([np.arange(3000) / fs, x]), delimiter=",",
                   header="time_s,accel", comments="", fmt="%.9f")
    with pytest.raises(hf.DataError, match=r"^6.csv: sampled at 10000 Hz, the first recording "
                                           r"\(1.csv\) at 12000 Hz"):
        hf.trend(d, bearing="6205", rpm=RPM, baseline_count=5, observers=False)
    # an 8-column IMS file among 4-column ones
    d = _ims_copies(tmp_path / "cols", IMS_NAMES)
    row = "\t".join(["0.1"] * 8) + "\n"
    (d / "2004.02.12.11.32.39").write_text(row * 2000)
    with pytest.raises(hf.DataError,
                       match=r"^2004.02.12.11.32.39: 8 columns, but 2004.02.12.10.32.39 has 4"):
        hf.trend(d, **IMS_ARGS, observers=False)


def test_bad_options_are_input_errors(tmp_path):
    src = FIXTURES / "ims"
    with pytest.raises(hf.InputError, match="--alarm 3of4: expected M/N"):
        hf.trend(src, **IMS_ARGS, alarm="3of4")
    with pytest.raises(hf.InputError, match="machine group `group9`"):
        hf.trend(src, **{**IMS_ARGS, "machine_group": "group9"})
    with pytest.raises(hf.InputError, match="unknown bearing|bearing"):
        hf.trend(src, **{**IMS_ARGS, "bearing": "no-such-bearing"})
    with pytest.raises(hf.DataError, match="is not a directory"):
        hf.trend(tmp_path / "absent", **IMS_ARGS)
    with pytest.raises(hf.InputError, match="not both"):
        hf.trend(src, index=tmp_path / "i.csv", **IMS_ARGS)
    with pytest.raises(hf.InputError, match="no sampling rate"):
        hf.trend([(0, np.ones(10))], bearing="6205", rpm=RPM)
    with pytest.raises(hf.InputError, match="report .* is the input directory"):
        hf.trend(src, **IMS_ARGS, report=src)


def test_the_interpreter_is_released_during_the_call():
    """Another Python thread keeps running while a trend is computed (``py.detach``): held, the
    main thread's ticks would stop for the whole call."""
    import threading
    import time

    done, out = threading.Event(), {}

    def work() -> None:
        out["t"] = hf.trend(FIXTURES / "xjtu", bearing="UER204", rpm=2100, baseline_count=5)
        done.set()

    ticks = [time.perf_counter()]
    th = threading.Thread(target=work)
    th.start()
    while not done.is_set():
        time.sleep(0.005)
        ticks.append(time.perf_counter())
    th.join()
    total = ticks[-1] - ticks[0]
    assert out["t"].alarm is not None
    assert total > 0.3, f"the call took {total:.3f} s: too short to tell"
    assert max(np.diff(ticks)) < 0.4 * total, (max(np.diff(ticks)), total)
