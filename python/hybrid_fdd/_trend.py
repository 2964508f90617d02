"""``hybrid_fdd.trend``: watch a machine over time (issue 57), over ``hybrid-fdd trend``.

The computation is the command's own (``hybrid_fdd_cli::trend::compute`` for a directory or an
index CSV, ``compute_in_memory`` for arrays, both calling ``trend::analyse``); this module turns
its ``trend.json`` into Python objects and draws it.
"""

from __future__ import annotations

import datetime as _dt
import json
import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._native import InputError

PathLike = Union[str, "os.PathLike[str]"]

#: k of the thresholds median + k * 1.4826 * MAD when not given (the command's ``--k``).
TREND_DEFAULT_K: float = _native.TREND_DEFAULT_K
#: Exponent p of the speed normalisation when not given (the command's ``--speed-exponent``).
TREND_DEFAULT_SPEED_EXPONENT: float = _native.TREND_DEFAULT_SPEED_EXPONENT


@dataclass(frozen=True)
class TrendRow:
    """One recording of a trend (a row of ``trend.csv``).

    Attributes:
        name: the file name (or the in-memory item's name).
        time: its time: seconds since 1970-01-01 (the names' clock) or a position (numbers).
        time_text: the time as the outputs print it (``2004-02-12T10:32:39``, or the number).
        baseline: whether it is one of the first ``baseline_count`` (the healthy baseline).
        rpm: the speed used (the one the diagnosis found, else the declared one).
        verdict: the diagnosis' verdict, ``None`` when it could not run.
        p_healthy: the diagnosis' probability under healthy.
        zone: the ISO 20816-3 zone of the velocity (``"A"`` … ``"D"``), when unit and group are
            known.
        values: each indicator as measured (``None`` when not computed).
        normalised: each indicator normalised to the reference speed (what is thresholded).
        above: whether each indicator's normalised value is above its threshold.
        modulation_depth: the diagnosis' modulation depth per hypothesis.
        notes: what could not be computed, and why.
    """

    name: str
    time: float
    time_text: str
    baseline: bool
    rpm: float
    verdict: Optional[str]
    p_healthy: Optional[float]
    zone: Optional[str]
    values: Dict[str, Optional[float]]
    normalised: Dict[str, Optional[float]]
    above: Dict[str, bool]
    modulation_depth: Dict[str, float]
    notes: Tuple[str, ...] = field(default=())


@dataclass(frozen=True)
class Threshold:
    """An indicator's threshold from the baseline recordings: ``median + k * spread`` (in log10
    for positive indicators, linear for the evidence), ``value`` in the indicator's own unit."""

    indicator: str
    value: float
    median: float
    spread: float
    spread_floored: bool
    k: float
    domain: str
    baselines: int


@dataclass(frozen=True)
class TrendAlarm:
    """The run's first alarm.

    Attributes:
        index: its row (0-based).
        name: the recording's name.
        time: its time (as :attr:`TrendRow.time`); ``time_text`` as printed.
        indicators: the indicators that fired there (m of n consecutive above).
        fault: the fault the diagnosis names at the alarm (or ``"not diagnosed"``).
        verdicts: the verdicts of the alarm window's recordings.
        severity: per indicator, the severity trend after the alarm (slope, level, time to it).
    """

    index: int
    name: str
    time: float
    time_text: str
    indicators: Tuple[str, ...]
    fault: str
    verdicts: Tuple[str, ...]
    severity: Dict[str, Dict[str, Any]]


class Trend:
    """A machine watched over time: the result of :func:`trend` (``hybrid-fdd trend``'s).

    ``to_dict()`` is the command's ``trend.json`` key for key; :meth:`write` writes its four
    files; :attr:`rows`, :attr:`thresholds` and :attr:`alarm` are the same numbers as objects.
    """

    def __init__(self, native: Any):
        self._native = native
        self._dict: Dict[str, Any] = json.loads(native.json())
        d = self._dict
        texts = native.time_texts()
        names = [i["name"] for i in d["indicators"]]
        self._indicators = names
        self._rows = [
            TrendRow(
                name=r["name"], time=r["time"], time_text=t, baseline=r["baseline"],
                rpm=r["rpm"], verdict=r.get("verdict"), p_healthy=r.get("p_healthy"),
                zone=r.get("zone"), values=dict(zip(names, r["values"])),
                normalised=dict(zip(names, r["normalised"])), above=dict(zip(names, r["above"])),
                modulation_depth=dict(r.get("modulation_depth") or {}),
                notes=tuple(r.get("notes") or ()),
            )
            for r, t in zip(d["rows"], texts)
        ]
        self._thresholds = {
            n: None if t is None else Threshold(
                indicator=n, value=t["value"], median=t["median"], spread=t["spread"],
                spread_floored=t["spread_floored"], k=t["k"], domain=str(t["domain"]),
                baselines=t["baselines"])
            for n, t in zip(names, d["thresholds"])
        }
        a = d.get("alarm")
        self._alarm = None if a is None else TrendAlarm(
            index=a["index"], name=a["name"], time=a["time"], time_text=texts[a["index"]],
            indicators=tuple(a["indicators"]), fault=a["fault"],
            verdicts=tuple(a.get("verdicts") or ()),
            severity=dict(zip(a["indicators"], a.get("severity") or [])),
        )

    def to_dict(self) -> Dict[str, Any]:
        """The command's ``trend.json`` (a deep copy), key for key."""
        return json.loads(self._native.json())

    def to_json(self) -> str:
        """``trend.json``'s text, as the command writes it."""
        return str(self._native.json())

    def to_csv(self) -> str:
        """``trend.csv``'s text."""
        return str(self._native.csv())

    @property
    def summary(self) -> str:
        """``summary.md``'s text: the alarm, the thresholds table, the observers, what is not
        seen."""
        return str(self._native.summary())

    @property
    def indicators(self) -> List[str]:
        """The indicators' names, in the table's order."""
        return list(self._indicators)

    @property
    def rows(self) -> List[TrendRow]:
        """One :class:`TrendRow` per recording, in time order."""
        return list(self._rows)

    @property
    def thresholds(self) -> Dict[str, Optional[Threshold]]:
        """Each indicator's :class:`Threshold` (``None`` where the baseline gives none)."""
        return dict(self._thresholds)

    @property
    def alarm(self) -> Optional[TrendAlarm]:
        """The first alarm, or ``None`` when no indicator stayed above long enough."""
        return self._alarm

    @property
    def axis(self) -> str:
        """``"seconds"`` (calendar times) or ``"index"`` (numbers: positions)."""
        return str(self._dict["axis"])

    def __getitem__(self, key: str) -> Any:
        return self._dict[key]

    def __len__(self) -> int:
        return len(self._rows)

    def __repr__(self) -> str:
        a = self._alarm
        what = "no alarm" if a is None else (
            f"alarm at {a.name} ({a.time_text}) on {', '.join(a.indicators)}: {a.fault}")
        return f"<Trend of {len(self._rows)} recordings, {len(self._indicators)} indicators: {what}>"

    def write(self, directory: PathLike) -> None:
        """Write the command's four files into ``directory`` (created): ``trend.csv``,
        ``trend.json``, ``summary.md``, ``trend.png``.

        Raises:
            DataError: the directory or a file cannot be written.
        """
        self._native.write(os.fspath(directory))

    def to_pandas(self) -> Any:
        """A ``pandas.DataFrame``, one row per recording, with ``trend.csv``'s columns (``time``,
        ``time_text``, ``file``, ``baseline``, ``rpm``, ``verdict``, ``p_healthy``, ``zone``, each
        indicator as measured, ``above_<indicator>``, ``depth_inner|outer|ball``) at full
        precision.

        Raises:
            ImportError: pandas is not installed (``pip install pandas``).
        """
        try:
            import pandas as pd
        except ImportError as e:
            raise ImportError("Trend.to_pandas needs pandas: pip install pandas") from e
        cols: Dict[str, List[Any]] = {
            "time": [r.time for r in self._rows],
            "time_text": [r.time_text for r in self._rows],
            "file": [r.name for r in self._rows],
            "baseline": [r.baseline for r in self._rows],
            "rpm": [r.rpm for r in self._rows],
            "verdict": [r.verdict for r in self._rows],
            "p_healthy": [r.p_healthy for r in self._rows],
            "zone": [r.zone for r in self._rows],
        }
        for n in self._indicators:
            cols[n] = [np.nan if r.values[n] is None else r.values[n] for r in self._rows]
        for n in self._indicators:
            cols[f"above_{n}"] = [r.above[n] for r in self._rows]
        for h in ("inner", "outer", "ball"):
            cols[f"depth_{h}"] = [r.modulation_depth.get(h, np.nan) for r in self._rows]
        return pd.DataFrame(cols)

    def plot(self, indicators: Optional[Sequence[str]] = None, cols: int = 3) -> Any:
        """Small multiples as the command's ``trend.png``: each indicator (speed-normalised)
        over time divided by its threshold (the threshold is the red line at 1), the baseline
        shaded, points above the threshold red, the alarm an orange line.

        Args:
            indicators: the ones to draw (default: all).
            cols: panels per row.

        Returns:
            The matplotlib ``Figure``.

        Raises:
            ImportError: matplotlib is not installed (``pip install matplotlib``).
        """
        try:
            import matplotlib.pyplot as plt
        except ImportError as e:
            raise ImportError("Trend.plot needs matplotlib: pip install matplotlib") from e
        names = list(self._indicators if indicators is None else indicators)
        unknown = [n for n in names if n not in self._thresholds]
        if unknown:
            raise InputError(f"no indicator {unknown[0]!r}; the trend has {self._indicators}")
        k = max(len(names), 1)
        cols = max(1, min(cols, k))
        nrows = -(-k // cols)
        fig, axes = plt.subplots(nrows, cols, figsize=(4 * cols, 2.2 * nrows), squeeze=False)
        seconds = self.axis == "seconds"
        t0 = self._rows[0].time if self._rows else 0.0
        per = 1.0 / 3600.0 if seconds else 1.0
        x = [(r.time - t0) * per for r in self._rows]
        nb = self._dict["config"]["baseline_count"]
        units = {i["name"]: i["unit"] for i in self._dict["indicators"]}
        for j, ax in enumerate(axes.flat):
            if j >= k:
                ax.set_visible(False)
                continue
            n = names[j]
            th = self._thresholds[n]
            scale = th.value if th is not None and th.value > 0 else None
            pts = [(xi, r.normalised[n] / scale if scale else r.normalised[n], r.above[n])
                   for xi, r in zip(x, self._rows) if r.normalised[n] is not None]
            if 0 < nb <= len(self._rows):
                ax.axvspan(0.0, x[nb - 1], color="0.8", alpha=0.35, lw=0)
            if scale:
                ax.axhline(1.0, color="tab:red", lw=1)
            if self._alarm is not None:
                ax.axvline(x[self._alarm.index], color="tab:orange", lw=2)
            if pts:
                px, py, above = zip(*pts)
                ax.plot(px, py, color="tab:blue", lw=1)
                ax.scatter(px, py, s=8, zorder=3,
                           c=["tab:red" if a else "tab:blue" for a in above])
            ax.set_title(f"{n} / threshold" if scale else f"{n} ({units[n]}; no threshold)",
                         fontsize=9)
            ax.set_xlim(0.0, max(x[-1] if x else 0.0, 1e-9) * 1.02)
            ax.tick_params(labelsize=7)
            ax.set_xlabel("hours since the first recording" if seconds
                          else "recordings since the first", fontsize=7)
        fig.tight_layout()
        return fig


def _time(t: Any, what: str) -> Union[float, str]:
    """A time for the native layer: a number (a position) or an ISO date-time string."""
    if isinstance(t, bool):
        raise InputError(f"{what}: a time must be a number, a datetime or an ISO string, not a bool")
    if isinstance(t, _dt.datetime):
        return t.replace(tzinfo=None, microsecond=0).isoformat(timespec="seconds")
    if isinstance(t, _dt.date):
        return f"{t.isoformat()}T00:00:00"
    if isinstance(t, np.datetime64):
        return str(t.astype("datetime64[s]"))
    if isinstance(t, str):
        return t
    if isinstance(t, (int, float, np.integer, np.floating)):
        return float(t)
    raise InputError(f"{what}: a time must be a number, a datetime or an ISO string, got {t!r}")


def _in_memory(items: Sequence[Any], fs: Optional[float]) -> Dict[str, List[Any]]:
    """The native arguments of recordings in memory: ``(time, Recording)``, ``(time, samples)``
    (at ``fs``), ``(time, samples, fs)`` or ``(time, samples, fs, rpm)``."""
    from . import Recording, _num, _signal

    out: Dict[str, List[Any]] = {"names": [], "times": [], "signals": [], "fs": [], "rpm": [],
                                 "units": []}
    for i, item in enumerate(items):
        what = f"item {i}"
        if isinstance(item, Recording) or not isinstance(item, (tuple, list)) or \
                not 2 <= len(item) <= 4:
            raise InputError(
                f"{what}: give (time, Recording), (time, samples[, fs[, rpm]]); got "
                f"{type(item).__name__}")
        t, rest = item[0], tuple(item[1:])
        if isinstance(rest[0], Recording):
            if len(rest) != 1:
                raise InputError(f"{what}: give (time, Recording) alone")
            r = rest[0]
            name = os.path.basename(os.fspath(r.path)) or what
            x, f, rpm, unit = r.samples, r.fs, r.rpm, r.unit
        else:
            name = what
            x = _signal(rest[0], what)
            f = _num(rest[1], f"{what} fs") if len(rest) > 1 else fs
            rpm = _num(rest[2], f"{what} rpm") if len(rest) > 2 else None
            unit = None
            if f is None:
                raise InputError(f"{what}: no sampling rate: give (time, samples, fs) or fs=")
        out["names"].append(name)
        out["times"].append(_time(t, what))
        out["signals"].append(_signal(x, what))
        out["fs"].append(float(f))
        out["rpm"].append(rpm)
        out["units"].append(unit)
    return out


def trend(
    input: Union[PathLike, Sequence[Any], None] = None,
    *,
    bearing: str,
    rpm: Optional[float] = None,
    fs: Optional[float] = None,
    channel: Optional[str] = None,
    baseline_count: int = 10,
    unit: Optional[str] = None,
    machine_group: Optional[str] = None,
    alarm: str = "3/4",
    k: float = TREND_DEFAULT_K,
    alarm_on: Optional[Sequence[str]] = None,
    speed_exponent: float = TREND_DEFAULT_SPEED_EXPONENT,
    observers: bool = True,
    decimate_to: Optional[float] = None,
    index: Optional[PathLike] = None,
    report: Optional[PathLike] = None,
    progress: bool = False,
) -> Trend:
    """Watch a machine over time, as ``hybrid-fdd trend`` does: per recording, RMS, peak, crest
    factor, kurtosis, band velocity RMS, mean square, the diagnosis' evidence per hypothesis and
    the observers' residual energies; thresholds from the first ``baseline_count`` recordings
    (median + k * 1.4826 * MAD); the M-of-N onset alarm, the fault named at it and the severity
    trend after it.

    Args:
        input: a directory of recordings of one machine, ordered by the times in their names
            (IMS's ``2004.02.12.10.32.39``, ISO dates, or numbers as XJTU-SY's ``1.csv``), read
            in IMS, XJTU-SY, CSV or ``.mat`` layouts as the command reads them; or recordings in
            memory: a list of ``(time, Recording)``, ``(time, samples)`` (at ``fs``),
            ``(time, samples, fs)`` or ``(time, samples, fs, rpm)`` in any order, ``time`` a
            ``datetime``/``numpy.datetime64``/ISO string (calendar time, slopes per hour) or a
            number (a position, slopes per unit of it). ``None`` with ``index``.
        bearing: a catalogue designation, a geometry ``n=…,d=…,D=…[,angle=…]``, or ``unknown``
            (``--bearing``).
        rpm: declared shaft speed for every recording (``--rpm``; else each file's or item's own).
        fs: sampling rate of files that store none (``--fs``; default 20 000 for IMS files,
            25 600 for XJTU-SY); for arrays, the rate of ``(time, samples)`` items.
        channel: a column name or number of a text file, DE/FE/BA of a CWRU ``.mat``
            (``--channel``; files only).
        baseline_count: the first N recordings are the healthy baseline (``--baseline-count``).
        unit: ``g`` or ``m/s2`` (``--unit``; default: what the files state, else unknown).
        machine_group: ISO 20816-3 group for the velocity's zone (``--machine-group``).
        alarm: the rule ``"M/N"`` (``--alarm``).
        k: k of the thresholds (``--k``).
        alarm_on: the indicators whose onset makes the alarm (``--alarm-on``; default: the
            gain-immune ones, crest, kurtosis, the evidence and the observers' ``*_ratio``;
            ``"all"`` for every indicator).
        speed_exponent: exponent of the speed normalisation (``--speed-exponent``).
        observers: run the dissertation's observers (``False`` = ``--no-observers``).
        decimate_to: decimate recordings at an integer multiple of this rate to it
            (``--decimate-to``).
        index: an index CSV ``file,time[,start_s,duration_s]`` instead of ``input`` (``--index``).
        report: a directory to write the command's four files into (``--report``); by default
            nothing is written (see :meth:`Trend.write`).
        progress: show the command's progress bar on standard error.

    Returns:
        A :class:`Trend`.

    Raises:
        InputError: bad options (bearing, alarm rule, k, unit, group), too few recordings for
            the baseline or too few baselines; for arrays, also duplicate or mixed times, mixed
            rates, non-finite samples.
        DataError: a file that cannot be read, a name without a time, duplicate or mixed times,
            a bad index, mixed sampling rates, layouts or channel counts in a directory.
        InternalError: a bug (the Rust code panicked).
    """
    from . import _num

    common = dict(
        bearing=str(bearing), baseline_count=_count(baseline_count),
        unit=None if unit is None else str(unit),
        machine_group=None if machine_group is None else str(machine_group), alarm=str(alarm),
        k=_num(k, "k"),
        alarm_on=None if alarm_on is None else [str(a) for a in ([alarm_on] if isinstance(
            alarm_on, str) else alarm_on)],
        speed_exponent=_num(speed_exponent, "speed_exponent"), observers=bool(observers),
        decimate_to=_num(decimate_to, "decimate_to"),
        report=None if report is None else os.fspath(report), progress=bool(progress),
    )
    if input is not None and not isinstance(input, (str, os.PathLike)):
        if index is not None or channel is not None:
            raise InputError("index and channel are for files, not recordings in memory")
        a = _in_memory(list(input), _num(fs, "fs"))
        return Trend(_native.trend_arrays(**a, **common, default_rpm=_num(rpm, "rpm")))
    return Trend(_native.trend_files(
        None if input is None else os.fspath(input),
        None if index is None else os.fspath(index),
        rpm=_num(rpm, "rpm"), fs=_num(fs, "fs"), channel=None if channel is None else str(channel),
        **common))


def _count(n: Any) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
        raise InputError(f"baseline_count must be a non-negative integer, got {n!r}")
    return int(n)
