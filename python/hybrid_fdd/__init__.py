"""hybrid_fdd: training-free, model-based bearing-fault diagnosis from vibration, in Python.

The numbers are computed by the Rust workspace of hybrid-fdd (the very code the ``hybrid-fdd``
command runs); this module is a thin layer over its native part ``hybrid_fdd._native``::

    import hybrid_fdd as hf
    rec = hf.read("cwru/12k_drive_end/130.mat")        # samples, fs, rpm, unit, source
    d = hf.diagnose(rec, bearing="6205", baseline="cwru/normal/97.mat")
    d.verdict                                           # 'outer'
    d.evidence["outer"].p_healthy                       # the detector's probability under healthy
    d.to_dict()                                         # the command's JSON report, key for key
    hf.diagnose_many("cwru/12k_drive_end/")             # a directory, in parallel, input order
    t = hf.trend("ims/1st_test", bearing="ZA-2115", rpm=2000)   # a machine over time
    t.alarm, t.thresholds, t.to_pandas(), t.plot()      # the onset alarm, fault named, severity

Errors are :class:`InputError` (a ``ValueError``: input the diagnosis refuses),
:class:`DataError` (an ``OSError``: a file that cannot be read) and :class:`InternalError` (a
``RuntimeError``: a bug, the Rust code panicked); each carries the Rust message on one line.
"""

from __future__ import annotations

import copy
import json
import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._native import DataError, InputError, InternalError

__all__ = [
    "DEFAULT_FALSE_ALARM",
    "DataError",
    "Diagnosis",
    "Effect",
    "Baseline",
    "Evidence",
    "InputError",
    "InternalError",
    "Ledger",
    "MachineModel",
    "Recording",
    "bearing",
    "calibrate",
    "close_loop",
    "diagnose",
    "diagnose_many",
    "order_track",
    "read",
    "recordings_in",
    "simulate",
    "Threshold",
    "Trend",
    "TrendAlarm",
    "TrendRow",
    "trend",
]

__version__ = "0.1.0"

#: The false-alarm probability per recording used when ``alpha`` is not given (1 %).
DEFAULT_FALSE_ALARM: float = _native.DEFAULT_FALSE_ALARM

PathLike = Union[str, "os.PathLike[str]"]

_ERRORS = {"InputError": InputError, "DataError": DataError, "InternalError": InternalError}


@dataclass(frozen=True)
class Recording:
    """A recording read by :func:`read`: what ``hybrid-fdd diagnose --input`` reads.

    Attributes:
        samples: the chosen channel, a 1-D float64 array.
        fs: sampling rate, Hz (the file's own where it stores one).
        rpm: the speed ``diagnose`` would declare (the file's own, e.g. a CWRU record's stored
            speed or MFPT's ``rate``, or a ``simulate`` sidecar's); ``None`` when the file stores
            none (then give ``rpm`` or ``rpm_range`` to :func:`diagnose`).
        rpm_source: ``"file"``, ``"sidecar"`` or ``None``.
        unit: ``"g"``, ``"m/s^2"`` or ``"unknown"``.
        unit_statement: what the reports say about the unit.
        fault_size_in: a CWRU record's catalogued fault diameter, inches.
        bearing: the bearing a ``simulate`` sidecar records, else ``None``.
        path: the file read.
        channel: the channel asked for.
        notes: what the loader said (e.g. a speed taken from a sidecar).
    """

    samples: np.ndarray
    fs: float
    rpm: Optional[float]
    rpm_source: Optional[str]
    unit: str
    unit_statement: str
    fault_size_in: Optional[float]
    bearing: Optional[str]
    path: str
    channel: str
    notes: Tuple[str, ...] = field(default=())

    @property
    def duration_s(self) -> float:
        """Length of the recording, seconds."""
        return len(self.samples) / self.fs

    def __len__(self) -> int:
        return len(self.samples)

    def __repr__(self) -> str:
        rpm = "None" if self.rpm is None else f"{self.rpm:g}"
        return (
            f"Recording({self.path!r}, channel={self.channel!r}, {len(self.samples)} samples, "
            f"fs={self.fs:g} Hz, rpm={rpm}, unit={self.unit!r})"
        )


def read(path: PathLike, channel: Optional[str] = None, fs: Optional[float] = None) -> Recording:
    """Read a recording as ``hybrid-fdd diagnose --input PATH [--channel C] [--fs FS]`` reads it.

    Every format the command reads: a CWRU ``.mat`` record (``channel`` ``DE`` (default), ``FE``
    or ``BA``), any other MAT-file v5-v7 (the signal found inside structs and cells, e.g. MFPT's
    ``bearing.gs`` with its stored ``sr`` and ``rate``; Paderborn's ``channel="vibration_1"``),
    CSV/TSV/text from a logger (``channel`` a column name or 1-based number; a ``simulate`` CSV's
    ``accel`` with fs from ``time_s`` and unit and speed from its JSON sidecar) and IMS's
    date-named text files.

    Args:
        path: the file.
        channel: which channel or column (default as the command: ``DE``).
        fs: sampling rate for files that store none; a file's own rate wins, and a ``fs`` that
            disagrees with it is an error, as for the command.

    Returns:
        A :class:`Recording`.

    Raises:
        DataError: the file cannot be read, holds no such channel, stores no rate and none was
            given, or stores a rate ``fs`` disagrees with.
    """
    r = _native.read(os.fspath(path), channel, None if fs is None else float(fs))
    return Recording(
        samples=r["samples"],
        fs=r["fs"],
        rpm=r["rpm"],
        rpm_source=r["rpm_source"],
        unit=r["unit"],
        unit_statement=r["unit_statement"],
        fault_size_in=r["fault_size_in"],
        bearing=r["bearing"],
        path=os.fspath(r["path"]),
        channel=r["channel"],
        notes=tuple(r["notes"]),
    )


class Evidence:
    """The evidence for one fault hypothesis (``inner``, ``outer`` or ``ball``) of a diagnosis.

    A view over the report's ``evidence`` entry (:meth:`to_dict` gives it whole).

    Attributes:
        hypothesis: ``"inner"``, ``"outer"`` or ``"ball"``.
        detected: whether the fault is part of the verdict.
        fault_hz: the kinematic fault frequency at the speed used, Hz.
        band_hz: the demodulation band it reads strongest in, ``(low, high)`` Hz.
        score_db: the detector's statistic, dB.
        p_healthy: how often a healthy machine shows evidence this strong (``None`` when the
            detector did not read this hypothesis).
        modulation_depth: the modulation depth of its harmonics (``None`` likewise).
        explained_by: the stronger fault whose lines explain this one's, or ``None``.
        harmonics: its harmonic lines (dicts: ``label``, ``expected_hz``, ``found_hz``,
            ``prominence_db``, ``evidence_db``, ...).
        sidebands: its distinguishing sidebands (BPFI +/- fr, BSF +/- FTF), same form.
    """

    def __init__(self, entry: Dict[str, Any]):
        self._e = entry
        sig = entry.get("significance") or {}
        self.hypothesis: str = entry["hypothesis"]
        self.detected: bool = bool(entry["detected"])
        self.fault_hz: float = entry["fault_hz"]
        self.band_hz: Tuple[float, float] = tuple(entry["band_hz"])  # type: ignore[assignment]
        self.score_db: float = entry["score_db"]
        self.p_healthy: Optional[float] = sig.get("p_healthy")
        self.modulation_depth: Optional[float] = sig.get("modulation_depth")
        self.explained_by: Optional[str] = sig.get("explained_by")
        self.harmonics: List[Dict[str, Any]] = entry["harmonics"]
        self.sidebands: List[Dict[str, Any]] = entry["sidebands"]

    def to_dict(self) -> Dict[str, Any]:
        """The report's entry for this hypothesis (a copy)."""
        return copy.deepcopy(self._e)

    def __repr__(self) -> str:
        p = "-" if self.p_healthy is None else f"{self.p_healthy:.2g}"
        return (
            f"Evidence({self.hypothesis!r}, detected={self.detected}, p_healthy={p}, "
            f"score_db={self.score_db:.1f})"
        )


class Diagnosis:
    """One recording's diagnosis: the verdict and every number that led to it.

    :meth:`to_dict` is the JSON report ``hybrid-fdd diagnose`` writes for the same recording and
    options (``--report x.json``), key for key: both are ``serde_json`` of the same Rust struct.
    (A trained classifier's ``"classifier"`` entry, which ``diagnose --classifier`` adds, is not
    bound.)

    Attributes:
        verdict: ``"normal"``, ``"inner"``, ``"outer"``, ``"ball"``, a ``+``-joined combination,
            or ``"uncertain"`` (then :attr:`candidates` names the faults).
        detected: the faults of the verdict.
        candidates: the faults an ``uncertain`` verdict could not tell apart.
        p_healthy: how often a healthy machine shows evidence this strong for some fault.
        false_alarm: the false-alarm probability per recording the verdict was made at.
        reference: ``"baseline"`` or ``"self"``.
        rpm_used: the speed used, rpm (found in the recording's shaft comb, or the declared one).
        shaft_hz: the shaft rate used, Hz.
        frequencies_hz: the fault frequencies used, Hz (``bpfo``, ``bpfi``, ``ball_defect`` = CWRU's
            BSF, ``ftf``, ``ball_spin``).
        band: the demodulation band chosen (``low_hz``, ``high_hz``, ...).
        evidence: per hypothesis, ``{"inner": Evidence, "outer": ..., "ball": ...}``.
        baseline_note: how the baseline was used (``None``: self-referenced).
        unit: the unit of the samples (``"g"``, ``"m/s^2"``, ``"unknown"``).
        source: the file diagnosed, when it was one.
        notes: what the loader said.
        envelope: the chosen band's squared envelope spectrum, which the command draws but does
            not write in its JSON: ``band_hz``, ``resolution_hz``, ``power`` (a float64 array,
            one value per bin), ``spectral_kurtosis``, ``segments``.
        rust_seconds: the time the Rust diagnosis itself took (no reading, copying or JSON), s.
        order_tracking: how a recording whose speed changed was resampled at equal shaft angles
            before it was diagnosed (``source`` — ``{"kind": "tachometer", ...}`` or
            ``{"kind": "shaft_comb", ...}`` —, ``min_rpm``, ``max_rpm``, ``mean_rpm``,
            ``samples_per_rev``, ``max_order``, ...); ``None`` for a steady speed.
    """

    def __init__(
        self,
        report: Dict[str, Any],
        baseline_note: Optional[str] = None,
        unit: str = "unknown",
        unit_statement: str = "",
        source: Optional[str] = None,
        notes: Sequence[str] = (),
        envelope: Optional[Dict[str, Any]] = None,
        rust_seconds: Optional[float] = None,
    ):
        self._r = report
        self.envelope = envelope
        self.rust_seconds = rust_seconds
        op = report["operating_point"]
        self.verdict: str = report["verdict"]
        self.detected: List[str] = list(report["detected"])
        self.candidates: List[str] = list(report.get("candidates", []))
        self.p_healthy: float = report["p_healthy"]
        self.false_alarm: float = report["false_alarm"]
        self.reference: str = report["reference"]
        self.rpm_used: float = op["rpm_used"]
        self.shaft_hz: float = op["shaft_hz"]
        self.frequencies_hz: Dict[str, float] = dict(op["frequencies_hz"])
        self.band: Dict[str, Any] = dict(report["band"])
        self.evidence: Dict[str, Evidence] = {
            e["hypothesis"]: Evidence(e) for e in report["evidence"]
        }
        self.baseline_note = baseline_note
        self.unit = unit
        self.unit_statement = unit_statement
        self.source = source
        self.notes: Tuple[str, ...] = tuple(notes)
        tracking = report.get("order_tracking")
        self.order_tracking: Optional[Dict[str, Any]] = (
            None if tracking is None else dict(tracking))

    @classmethod
    def _from_native(cls, d: Dict[str, Any], source: Optional[str] = None) -> "Diagnosis":
        return cls(
            json.loads(d["json"]),
            baseline_note=d["baseline_note"],
            unit=d["unit"],
            unit_statement=d["unit_statement"],
            source=source,
            notes=d["notes"],
            envelope=d.get("envelope"),
            rust_seconds=d.get("rust_seconds"),
        )

    @property
    def is_faulty(self) -> bool:
        """Whether the verdict names a fault (or faults it cannot tell apart)."""
        return self.verdict != "normal"

    def to_dict(self) -> Dict[str, Any]:
        """The command's JSON report for this recording, as a dict (a copy)."""
        return copy.deepcopy(self._r)

    def to_json(self, **kwargs: Any) -> str:
        """:meth:`to_dict` as JSON text (``json.dumps`` keyword arguments pass through)."""
        kwargs.setdefault("indent", 2)
        return json.dumps(self._r, **kwargs)

    def __getitem__(self, key: str) -> Any:
        """A top-level entry of the report (``d["statistics"]``), as stored."""
        return self._r[key]

    def __repr__(self) -> str:
        src = f" {os.path.basename(self.source)!r}" if self.source else ""
        return (
            f"<Diagnosis{src}: {self.verdict} (p_healthy {self.p_healthy:.2g}, "
            f"{self.reference} reference, {self.rpm_used:.1f} rpm)>"
        )

    def plot(self, ax: Any = None) -> Any:
        """Draw the report's overlay figure with matplotlib: the residual's squared envelope
        spectrum in the chosen band (dB over its median) with the BPFO, BPFI, BSF, FTF and shaft
        harmonics and the distinguishing sidebands (BPFI +/- fr, BSF +/- FTF) marked, and the
        lines each hypothesis found as dots.

        Args:
            ax: a matplotlib ``Axes``; a new figure's when ``None``.

        Returns:
            The ``Axes``.

        Raises:
            ImportError: matplotlib is not installed (``pip install matplotlib``).
        """
        try:
            import matplotlib.pyplot as plt
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("Diagnosis.plot needs matplotlib: pip install matplotlib") from e
        if ax is None:
            _, ax = plt.subplots(figsize=(9, 4.8))
        env = self.envelope
        if env is None:
            raise ValueError("this Diagnosis holds no envelope spectrum to draw")
        f = self.frequencies_hz
        fr = self.shaft_hz
        top = 3.4 * max(f["bpfo"], f["bpfi"], f["ball_defect"]) + fr
        power = np.asarray(env["power"], dtype=float)
        hz = np.arange(len(power)) * env["resolution_hz"]
        keep = (hz > 0) & (hz <= top)
        hz, power = hz[keep], power[keep]
        pos = power[power > 0]
        median = float(np.median(pos)) if len(pos) else 1.0
        db = 10 * np.log10(np.maximum(power, 1e-300) / median)
        colours = {"fr": "0.6", "BPFO": "C0", "BPFI": "C3", "BSF": "C2", "FTF": "C4"}
        rates = {"fr": fr, "BPFO": f["bpfo"], "BPFI": f["bpfi"], "BSF": f["ball_defect"],
                 "FTF": f["ftf"]}
        for name, rate in rates.items():
            for k in (1, 2, 3):
                x = k * rate
                if 0 < x < top:
                    ax.axvline(x, color=colours[name], lw=0.8, alpha=0.8)
                    ax.annotate(f"{name}×{k}", (x, 1.0), xycoords=("data", "axes fraction"),
                                rotation=90, va="top", ha="right", fontsize=7,
                                color=colours[name])
        for s in (-1, 1):
            for x, c in ((f["bpfi"] + s * fr, "C3"), (f["ball_defect"] + s * f["ftf"], "C2")):
                if 0 < x < top:
                    ax.axvline(x, color=c, lw=0.8, ls="--", alpha=0.45)
        ax.plot(hz, db, color="k", lw=0.8)
        dots = {"inner": "C3", "outer": "C0", "ball": "C2"}
        for e in sorted(self.evidence.values(), key=lambda e: e.detected):
            for line in e.harmonics + e.sidebands:
                if line.get("shaft_order") is None and line.get("evidence_db", 0) > 0:
                    y = np.interp(line["found_hz"], hz, db) if len(hz) else 0.0
                    ax.plot(line["found_hz"], y, "o", ms=5 if e.detected else 3,
                            color=dots.get(e.hypothesis, "k"))
        b = self.band
        title = os.path.basename(self.source) + ": " if self.source else ""
        ax.set_title(
            f"{title}{self.verdict} — squared envelope spectrum of the residual, band "
            f"{b['low_hz']:.0f}–{b['high_hz']:.0f} Hz ({self.reference} reference)",
            fontsize=9,
        )
        ax.set_xlabel("envelope frequency (Hz)")
        ax.set_ylabel("power re median (dB)")
        ax.set_xlim(0, top)
        return ax


class Baseline:
    """A healthy baseline read once and prepared once per recording rate (and, for a machine
    model, per speed), then reused by every :func:`diagnose` / :func:`diagnose_many` call it is
    passed to (a path, array or :class:`Recording` given as ``baseline=`` is read and prepared
    again by each call).

    Args:
        source: a path (a recording, or a machine-model JSON), a :class:`Recording`, a
            :class:`MachineModel`, or an array (with ``fs``).
        fs: the rate of an array, or of a text file that stores none.
        channel: the channel or column of a file (default ``DE``).

    Raises:
        DataError: an unreadable file. InputError: a bad array or machine model.
    """

    def __init__(self, source: Any, fs: Optional[float] = None, channel: Optional[str] = None):
        ch = "DE" if channel is None else str(channel)
        if _is_path(source):
            self._native = _native.PreparedBaseline(path=os.fspath(source),
                                                    fs=_num(fs, "fs"), channel=ch)
        elif isinstance(source, MachineModel):
            self._native = _native.PreparedBaseline(machine=source.to_json())
        elif isinstance(source, Recording):
            self._native = _native.PreparedBaseline(samples=source.samples, fs=source.fs)
        else:
            if fs is None:
                raise InputError("fs (the sampling rate, Hz) is required for an array baseline")
            self._native = _native.PreparedBaseline(samples=_signal(source, "baseline"),
                                                    fs=_num(fs, "fs"))

    def __repr__(self) -> str:
        return f"Baseline({os.fspath(self._native.path)!r})"


def _signal(x: Any, what: str = "x") -> np.ndarray:
    """A 1-D contiguous float64 copy or view of ``x``; refuses what is not a real 1-D signal."""
    try:
        a = np.asarray(x)
    except Exception as e:  # noqa: BLE001 - any conversion failure is bad input
        raise InputError(f"{what} is not an array: {e}") from None
    if a.ndim != 1:
        raise InputError(f"{what} must be a 1-D signal, got an array of shape {a.shape}")
    if a.dtype.kind not in "fiub":
        raise InputError(f"{what} must hold real numbers, got dtype {a.dtype}")
    if a.size == 0:
        raise InputError(f"{what} is empty")
    return np.ascontiguousarray(a, dtype=np.float64)


def _num(v: Any, what: str) -> Optional[float]:
    if v is None:
        return None
    try:
        return float(v)
    except (TypeError, ValueError):
        raise InputError(f"{what} must be a number, got {v!r}") from None


def _range(r: Any) -> Optional[Tuple[float, float]]:
    if r is None:
        return None
    if isinstance(r, str):
        lo, sep, hi = r.partition("-")
        if not sep:
            raise InputError(f"rpm_range {r!r}: give (low, high) or 'LOW-HIGH' in rpm")
        r = (lo, hi)
    try:
        lo, hi = r
    except (TypeError, ValueError):
        raise InputError(f"rpm_range must be (low, high) in rpm, got {r!r}") from None
    return (_num(lo, "rpm_range low"), _num(hi, "rpm_range high"))  # type: ignore[return-value]


def _is_path(x: Any) -> bool:
    return isinstance(x, (str, os.PathLike))


def _baseline(baseline: Any, fs: Optional[float]) -> Dict[str, Any]:
    """The baseline arguments of the native calls: a file, a Recording or an array (at ``fs``)."""
    if baseline is None:
        return {}
    if _is_path(baseline):
        return {"baseline_path": os.fspath(baseline)}
    if isinstance(baseline, MachineModel):
        return {"baseline_machine": baseline.to_json()}
    if isinstance(baseline, Baseline):
        return {"baseline_prepared": baseline._native}
    if isinstance(baseline, Recording):
        return {"baseline_samples": baseline.samples, "baseline_fs": baseline.fs}
    if isinstance(baseline, tuple) and len(baseline) == 2 and not np.isscalar(baseline[0]):
        return {"baseline_samples": _signal(baseline[0], "baseline"),
                "baseline_fs": _num(baseline[1], "baseline fs")}
    return {"baseline_samples": _signal(baseline, "baseline"), "baseline_fs": fs}


def _unpack(results: List[Tuple[str, Any]], sources: Sequence[Optional[str]],
            errors: str) -> List[Any]:
    out: List[Any] = []
    for i, ((status, value), src) in enumerate(zip(results, sources)):
        if status == "ok":
            out.append(Diagnosis._from_native(value, source=src))
            continue
        exc = _ERRORS[status](value)
        if errors == "raise":
            where = f"item {i}" + (f" ({src})" if src else "")
            raise _ERRORS[status](f"{where}: {value}") if len(results) > 1 else exc
        out.append(exc)
    return out


def _flag(v: Any, what: str) -> bool:
    if not isinstance(v, (bool, np.bool_)):
        raise InputError(f"{what} must be True or False, got {v!r}")
    return bool(v)


def _tach(tach: Any, pulses_per_rev: Any) -> Dict[str, Any]:
    if tach is None:
        return {}
    if not isinstance(tach, str):
        raise InputError("for a path, tach is the name or number of the file's tachometer "
                         "channel")
    return dict(tach=tach, pulses_per_rev=_num(pulses_per_rev, "pulses_per_rev"))


def diagnose(
    x: Any,
    fs: Optional[float] = None,
    rpm: Optional[float] = None,
    bearing: str = "6205",
    rpm_range: Any = None,
    alpha: Optional[float] = None,
    baseline: Any = None,
    *,
    channel: Optional[str] = None,
    unit: Optional[str] = None,
    tach: Any = None,
    pulses_per_rev: float = 1.0,
    steady_speed: bool = False,
) -> Diagnosis:
    """Diagnose one recording: ``normal``, ``inner``, ``outer``, ``ball``, a combination or
    ``uncertain``, training-free (``hybrid-fdd diagnose``).

    Args:
        x: a 1-D array of samples (any real dtype and strides: converted to contiguous float64;
            NaN or infinite samples are refused), a :class:`Recording`, or a path (read exactly
            as ``hybrid-fdd diagnose --input PATH``).
        fs: sampling rate, Hz (required for an array; a Recording's own otherwise; for a path, as
            ``--fs``).
        rpm: declared shaft speed, rpm; the running speed is searched within +/- 10 % of it.
            Default: a Recording's or file's stored speed.
        bearing: a catalogue designation (``"6205"``, ``"SKF 6205-2RS"``, ``"UC204"``; see
            :func:`bearing`), a geometry ``"n=9,d=0.3126in,D=1.537in"``, the four multiples, or
            ``"unknown"``.
        rpm_range: ``(low, high)`` rpm (or ``"300-3600"``) to search the speed in, instead of
            +/- 10 % of ``rpm`` or without any.
        alpha: false-alarm probability per recording (default :data:`DEFAULT_FALSE_ALARM`).
        baseline: a healthy recording of the same machine: a path (a recording, or a machine
            model JSON from ``hybrid-fdd calibrate``), a :class:`Baseline` (prepared once, reused
            across calls), a :class:`MachineModel`, a :class:`Recording`, an array (at ``fs``) or
            ``(array, fs)``. Without one the evidence is self-referenced.
        channel: channel or column of a path ``x`` and of a baseline file (default ``DE``).
        unit: unit of an array's samples (``"g"``, ``"m/s^2"``); checked against a machine-model
            baseline's.
        tach: a tachometer channel of the same file (for a path ``x``), as ``--tach``, or the
            tachometer's samples (an array beside an array ``x``, at ``fs``): the recording is
            resampled at equal shaft angles from its pulses (:func:`order_track`) and diagnosed
            at their mean speed (give no ``rpm``, ``rpm_range`` or ``baseline``). Without one, a self-referenced
            recording whose speed changes is tracked along its own shaft comb where it can be
            (:attr:`Diagnosis.order_tracking` says how).
        pulses_per_rev: the tachometer's pulses a shaft turn (an encoder's lines; 1 for a key).
        steady_speed: read the recording at one speed only, never tracked along its own shaft
            comb (``--steady-speed``): for a machine known to run at one speed, or to compare.

    Returns:
        A :class:`Diagnosis`.

    Raises:
        InputError: bad samples, an unknown bearing, a speed, rate, range or ``alpha`` out of
            range, no speed and no range, a baseline at an incompatible rate.
        DataError: a file (recording or baseline) that cannot be read.
    """
    base = _baseline(baseline, None)
    common = dict(
        bearing=str(bearing),
        rpm_range=_range(rpm_range),
        alpha=_num(alpha, "alpha"),
        channel="DE" if channel is None else str(channel),
        steady_speed=_flag(steady_speed, "steady_speed"),
    )
    if tach is not None and steady_speed:
        raise InputError("tach with steady_speed: the tachometer's order tracking is asked for; "
                         "leave one of them out")
    if _is_path(x):
        res = _native.diagnose_files(
            [os.fspath(x)], fs=_num(fs, "fs"), rpm=_num(rpm, "rpm"), one_file=True,
            **base, **common, **_tach(tach, pulses_per_rev))
        return _unpack(res, [os.fspath(x)], "raise")[0]
    tracking = None
    if tach is not None:
        if isinstance(tach, str):
            raise InputError("tach names a channel of a file: give x as a path (or tach as an "
                             "array of the tachometer's samples)")
        if rpm is not None or rpm_range is not None or baseline is not None:
            raise InputError("tach measures the speed: leave out rpm, rpm_range and baseline")
    if isinstance(x, Recording):
        fs = x.fs if fs is None else fs
        rpm = x.rpm if rpm is None else rpm
        unit = x.unit if unit is None else unit
        src: Optional[str] = x.path
        samples = x.samples
    else:
        src = None
        samples = _signal(x)
    if fs is None:
        raise InputError("fs (the sampling rate, Hz) is required for an array")
    if tach is not None:
        samples, tracking = order_track(samples, tach, fs, pulses_per_rev)
        fs, rpm = tracking["equivalent_fs_hz"], tracking["mean_rpm"]
    if "baseline_samples" in base and base.get("baseline_fs") is None:
        base["baseline_fs"] = _num(fs, "fs")
    res = _native.diagnose_arrays(
        [samples], [_num(fs, "fs")], [_num(rpm, "rpm")], [unit], **base, **common)
    d = _unpack(res, [src], "raise")[0]
    if tracking is not None:
        d._r["order_tracking"] = tracking
        d.order_tracking = dict(tracking)
    return d


def _per_item(v: Any, n: int, what: str) -> List[Any]:
    if v is None or np.isscalar(v):
        return [v] * n
    v = list(v)
    if len(v) != n:
        raise InputError(f"{what}: {len(v)} values for {n} signals")
    return v


def diagnose_many(
    signals: Any,
    fs: Any = None,
    rpm: Any = None,
    bearing: str = "6205",
    rpm_range: Any = None,
    alpha: Optional[float] = None,
    baseline: Any = None,
    *,
    channel: Optional[str] = None,
    unit: Any = None,
    threads: Optional[int] = None,
    errors: str = "raise",
    tach: Optional[str] = None,
    pulses_per_rev: float = 1.0,
    steady_speed: bool = False,
) -> List[Any]:
    """Diagnose many recordings in parallel on all cores, with the interpreter released.

    Args:
        signals: a directory (every recording in it, as ``hybrid-fdd diagnose --input DIR``
            lists them), a list of paths, or a list of arrays / :class:`Recording` objects.
        fs: sampling rate(s), Hz: one for all or one per signal (for paths: for files that store
            none, as ``--fs`` in a directory batch).
        rpm: declared speed(s), rpm: one for all or one per signal (default: each recording's
            own; for paths one value, as ``--rpm``).
        bearing, rpm_range, alpha, baseline, channel: as :func:`diagnose`; one baseline for all,
            prepared once per rate as the command's batch does.
        unit: unit(s) of array samples.
        threads: worker threads (default: all cores).
        errors: ``"raise"`` (default) raises the first failure in input order, its message
            prefixed with the item; ``"return"`` puts the exception object in that item's place.
        tach, pulses_per_rev: as :func:`diagnose` (paths only): each file's tachometer channel.
        steady_speed: as :func:`diagnose`.

    Returns:
        One :class:`Diagnosis` per signal, in input order.

    Raises:
        InputError, DataError: as :func:`diagnose` (with ``errors="raise"``).
    """
    if errors not in ("raise", "return"):
        raise InputError(f"errors must be 'raise' or 'return', got {errors!r}")
    if threads is not None and (not isinstance(threads, int) or threads < 1):
        raise InputError(f"threads must be a positive integer or None, got {threads!r}")
    common = dict(
        bearing=str(bearing),
        rpm_range=_range(rpm_range),
        alpha=_num(alpha, "alpha"),
        channel="DE" if channel is None else str(channel),
        threads=threads,
        steady_speed=_flag(steady_speed, "steady_speed"),
    )
    if _is_path(signals):
        if not os.path.isdir(signals):
            raise DataError(f"{os.fspath(signals)} is not a directory (diagnose one file with "
                            "diagnose)")
        signals = recordings_in(signals)
    items = list(signals)
    if not items:
        return []
    if all(_is_path(s) for s in items):
        if fs is not None and not np.isscalar(fs) or rpm is not None and not np.isscalar(rpm):
            raise InputError("for paths, fs and rpm are one value for all (as --fs and --rpm)")
        paths = [os.fspath(s) for s in items]
        res = _native.diagnose_files(
            paths, fs=_num(fs, "fs"), rpm=_num(rpm, "rpm"), one_file=False,
            **_baseline(baseline, None), **common, **_tach(tach, pulses_per_rev))
        return _unpack(res, paths, errors)
    if tach is not None:
        raise InputError("tach names a channel of a file: give paths")
    if any(_is_path(s) for s in items):
        raise InputError("signals mixes paths and arrays: give one kind")
    n = len(items)
    fss, rpms, units = _per_item(fs, n, "fs"), _per_item(rpm, n, "rpm"), _per_item(unit, n, "unit")
    arrays, sources = [], []
    for i, s in enumerate(items):
        if isinstance(s, Recording):
            arrays.append(s.samples)
            fss[i] = s.fs if fss[i] is None else fss[i]
            rpms[i] = s.rpm if rpms[i] is None else rpms[i]
            units[i] = s.unit if units[i] is None else units[i]
            sources.append(s.path)
        else:
            arrays.append(_signal(s, f"signals[{i}]"))
            sources.append(None)
    for i, f in enumerate(fss):
        if f is None:
            raise InputError(f"signals[{i}]: fs (the sampling rate, Hz) is required for an array")
    base = _baseline(baseline, None)
    if "baseline_samples" in base and base.get("baseline_fs") is None:
        base["baseline_fs"] = _num(fss[0], "fs")
    res = _native.diagnose_arrays(
        arrays, [_num(f, "fs") for f in fss], [_num(r, "rpm") for r in rpms],
        [None if u is None else str(u) for u in units], **base, **common)
    return _unpack(res, sources, errors)


def recordings_in(directory: PathLike) -> List[str]:
    """The recordings ``hybrid-fdd diagnose --input DIR`` would diagnose, sorted: ``.mat``,
    ``.csv``, ``.tsv``, and MAT or text files named without an extension or with an all-digit
    one (IMS).

    Raises:
        DataError: not a directory, or one holding no recording.
    """
    return [os.fspath(p) for p in _native.recordings_in(os.fspath(directory))]


def order_track(
    x: Any, tach: Any, fs: float, pulses_per_rev: float = 1.0
) -> Tuple["np.ndarray", Dict[str, Any]]:
    """Resample ``x`` (at ``fs`` Hz) at equal shaft angles from the tachometer ``tach`` recorded
    beside it (same length; ``pulses_per_rev`` pulses a turn: an encoder's lines, 1 for a key),
    as ``hybrid-fdd diagnose --tach`` does (computed order tracking).

    Returns:
        ``(samples, info)``: the resampled samples, ``info["samples_per_rev"]`` a turn, to be read
        as a recording at ``info["equivalent_fs_hz"]`` and ``info["mean_rpm"]``; ``info`` also
        holds ``min_rpm``, ``max_rpm``, ``max_order`` (the order band kept), ``turns`` and
        ``source``.

    Raises:
        InputError: channels of different lengths, too few pulses, a missed or spurious pulse,
            a rate too low for the fastest turn.
    """
    samples, info = _native.order_track(
        _signal(x), _signal(tach), _num(fs, "fs"), _num(pulses_per_rev, "pulses_per_rev"))
    return samples, json.loads(info)


def bearing(spec: str) -> Dict[str, Any]:
    """The bearing ``spec`` names, as ``--bearing`` parses it: ``name``, ``given``, ``geometry``
    (``n_balls``, ``ball_diameter_m``, ``pitch_diameter_m``, ``contact_angle_rad``; ``None`` for
    the four multiples) and ``orders`` (x shaft rate: ``bpfo``, ``bpfi``, ``ftf``, ``ball_spin``,
    ``ball_defect`` = CWRU's BSF).

    Raises:
        InputError: an unknown designation (the message lists the nearest ones) or a bad spec.
    """
    return json.loads(_native.bearing(str(spec)))


class MachineModel:
    """A calibrated machine model (``hybrid-fdd calibrate``): structural path and modes, lines,
    floor, speed ratio, units. :meth:`save` writes, and :meth:`load` reads, the same JSON as the
    command's ``--out``; pass it as ``baseline=`` to :func:`diagnose` or ``machine=`` to
    :func:`close_loop`.

    Attributes:
        ledger: the calibration loop's :class:`Ledger` (``None`` for a model loaded from a file).
    """

    def __init__(self, text: str, ledger: "Optional[Ledger]" = None):
        self._text = _native.machine_model(text)
        self._d = json.loads(self._text)
        self.ledger = ledger

    @classmethod
    def load(cls, path: PathLike) -> "MachineModel":
        """Read and validate a machine model file (``calibrate --out``).

        Raises:
            DataError: the file cannot be read. InputError: it is not a valid machine model.
        """
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise DataError(f"reading {os.fspath(path)}: {e.strerror or e}") from None
        return cls(text)

    def save(self, path: PathLike) -> None:
        """Write the model as ``hybrid-fdd calibrate --out`` writes it."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self._text + "\n")

    def to_json(self) -> str:
        """The model's JSON text (as saved, without the final newline)."""
        return self._text

    def to_dict(self) -> Dict[str, Any]:
        """The model as a dict (a copy)."""
        return copy.deepcopy(self._d)

    @property
    def units(self) -> str:
        """The units the model was calibrated in (``"g"``, ``"m/s^2"``, ``"unknown"``)."""
        return self._d.get("units", "unknown")

    @property
    def fs(self) -> float:
        """The sampling rate the model was calibrated at, Hz."""
        return self._d["fs_hz"]

    def __repr__(self) -> str:
        return (f"<MachineModel {self._d.get('provenance', {}).get('recording', '')!r}: "
                f"{self.fs:g} Hz, {len(self._d.get('lines', []))} lines, units {self.units}>")


class Effect:
    """One effect the closed loop added: what it is, where it went, what it explained.

    Attributes:
        kind: ``structural_path``, ``tone``, ``shaft_harmonic``, ``bearing_fault``, ...
        frequency_hz: its frequency (``None`` for ``speed_offset`` and ``slip``).
        parameters: its parameters (dict).
        placement: ``"physics"`` or ``"measurement"``.
        error_before, error_after: the held-out error before and after adding it.
        accepted_on: the test it passed.
    """

    def __init__(self, entry: Dict[str, Any]):
        self._e = entry
        self.kind: str = entry["kind"]
        self.frequency_hz: Optional[float] = entry.get("frequency_hz")
        self.parameters: Dict[str, Any] = entry.get("parameters", {})
        self.placement: Optional[str] = entry.get("placement")
        self.error_before: float = entry["error_before"]
        self.error_after: float = entry["error_after"]
        self.accepted_on: Optional[str] = entry.get("accepted_on")

    def to_dict(self) -> Dict[str, Any]:
        """The ledger's entry (a copy)."""
        return copy.deepcopy(self._e)

    def __repr__(self) -> str:
        f = "" if self.frequency_hz is None else f" {self.frequency_hz:.1f} Hz"
        return f"Effect({self.kind!r}{f}: {self.error_before:.3f} -> {self.error_after:.3f})"


class Ledger:
    """The closed loop's ledger: the error before and after, the effects added in order.

    :meth:`to_dict` is the JSON report ``hybrid-fdd close-loop --report`` writes, key for key.

    Attributes:
        error_metric: the error's name (``floor_regularised_lsd_db``).
        error_before, error_after: the held-out error of the declared model and after all
            accepted effects.
        effects: the accepted :class:`Effect` objects, in the order they were added.
        machine: the augmented model as a :class:`MachineModel`.
    """

    def __init__(self, report: Dict[str, Any], machine: Optional[MachineModel] = None):
        self._r = report
        self.error_metric: str = report["error_metric"]
        self.error_before: float = report["error_before"]
        self.error_after: float = report["error_after"]
        self.effects: List[Effect] = [Effect(e) for e in report["effects"]]
        self.machine = machine

    def to_dict(self) -> Dict[str, Any]:
        """The command's JSON report (a copy)."""
        return copy.deepcopy(self._r)

    def __getitem__(self, key: str) -> Any:
        return self._r[key]

    def __repr__(self) -> str:
        return (f"<Ledger {self.error_metric} {self.error_before:.3f} -> {self.error_after:.3f}, "
                f"{len(self.effects)} effect(s)>")


def calibrate(
    path: PathLike,
    rpm: Optional[float] = None,
    bearing: Optional[str] = None,
    *,
    channel: str = "DE",
    fs: Optional[float] = None,
    decimate: int = 1,
    model: str = "physics",
    units: Optional[str] = None,
    line_frequency: float = 60.0,
    max_effects: Optional[int] = None,
    report: Optional[PathLike] = None,
) -> MachineModel:
    """Calibrate a machine model on a healthy recording: ``hybrid-fdd calibrate --input PATH``.

    Only files are taken (the loop reads its recording as the command does). Arguments are the
    command's flags (``decimate=4`` takes CWRU's 48 kHz normal record to 12 kHz); ``report`` keeps
    the loop's JSON/Markdown/PNG report at that path (the command writes it as
    ``<out>.report.json``).

    Returns:
        A :class:`MachineModel` (its ``ledger`` the calibration loop's).

    Raises:
        InputError: bad options or a recording the loop refuses. DataError: unreadable file.
    """
    machine, ledger = _native.calibrate(
        os.fspath(path), rpm=_num(rpm, "rpm"), bearing=bearing, channel=channel,
        fs=_num(fs, "fs"), decimate=int(decimate), model=model, units=units,
        line_frequency=float(line_frequency), max_effects=max_effects,
        report=None if report is None else os.fspath(report))
    m = MachineModel(machine)
    m.ledger = Ledger(json.loads(ledger), m)
    return m


def close_loop(
    path: PathLike,
    fault: Optional[str] = None,
    machine: Union[MachineModel, PathLike, None] = None,
    rpm: Optional[float] = None,
    bearing: Optional[str] = None,
    *,
    channel: str = "DE",
    fs: Optional[float] = None,
    decimate: int = 1,
    model: str = "physics",
    units: Optional[str] = None,
    line_frequency: float = 60.0,
    max_effects: int = 8,
    seconds: Optional[float] = None,
    fault_size_in: Optional[float] = None,
    report: Optional[PathLike] = None,
) -> Ledger:
    """Close the loop on a recording: ``hybrid-fdd close-loop --input PATH``.

    The declared model (or ``machine``, a calibrated :class:`MachineModel` or its file) is run
    against the recording; what the residual holds that the model misses is traced to effects,
    added, and the held-out error measured before and after.

    Args:
        path: the recording (a file).
        fault: the declared fault (``none``, ``outer``, ``inner``, ``ball``, ``inner+outer``...).
        machine: start from this machine model instead of the bare declared model.
        rpm, bearing, channel, fs, decimate, model, units, line_frequency, max_effects, seconds,
            fault_size_in: the command's flags.
        report: keep the JSON/Markdown/PNG report at this path (default: not kept).

    Returns:
        The :class:`Ledger` (its ``machine`` the augmented model).

    Raises:
        InputError: bad options, a machine model that does not match. DataError: a machine
            model file that cannot be read.
    """
    if machine is not None and not isinstance(machine, MachineModel):
        machine = MachineModel.load(machine)
    m, ledger = _native.close_loop_file(
        os.fspath(path), fault="none" if fault is None else str(fault),
        machine=None if machine is None else machine.to_json(), rpm=_num(rpm, "rpm"),
        bearing=bearing, channel=channel, fs=_num(fs, "fs"), decimate=int(decimate),
        model=model, units=units, line_frequency=float(line_frequency),
        max_effects=int(max_effects), seconds=_num(seconds, "seconds"),
        fault_size_in=_num(fault_size_in, "fault_size_in"),
        report=None if report is None else os.fspath(report))
    return Ledger(json.loads(ledger), MachineModel(m))


def simulate(out: Optional[PathLike] = None, **flags: Any) -> Tuple[Recording, Dict[str, Any]]:
    """Simulate a recording: ``hybrid-fdd simulate`` (at CWRU conditions, 6205 at 12 kHz, the
    calibrated CWRU rig, in g; else the bare 5-DOF model, in m/s^2).

    Keyword arguments are the command's flags with ``_`` for ``-`` (``fault="outer"``,
    ``rpm=1797``, ``fs=12000``, ``duration=2``, ``seed=1``, ``fault_size=0.1778``,
    ``params="cwru"``, ``outer_clock=3``, ``bearing="6203"``, ``states=True``, ...). The command
    writes its CSV and JSON sidecar (at ``out``, else in a temporary directory removed
    afterwards) and prints its lines on standard output; the CSV is read back by :func:`read`, so
    the samples are exactly what the command's file holds.

    Returns:
        ``(Recording, sidecar)``: the recording (its ``rpm``, ``bearing`` and ``unit`` from the
        sidecar) and the sidecar's parameters as a dict.

    Raises:
        InputError: an unknown flag or a value the command refuses.
    """
    import shutil
    import tempfile

    argv: List[str] = []
    for k, v in flags.items():
        flag = "--" + k.replace("_", "-")
        if v is True:
            argv.append(flag)
        elif v is False or v is None:
            continue
        else:
            argv += [flag, str(v)]
    tmp = None if out is not None else tempfile.mkdtemp(prefix="hybrid-fdd-simulate-")
    path = os.fspath(out) if out is not None else os.path.join(tmp, "simulated.csv")  # type: ignore[arg-type]
    try:
        _native.simulate_to(argv, path)
        rec = read(path)
        with open(os.path.splitext(path)[0] + ".json", encoding="utf-8") as f:
            side = json.load(f)
        return rec, side
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)


# hybrid_fdd.trend (issue 57): imported last, it uses Recording and the helpers above
from ._trend import Threshold, Trend, TrendAlarm, TrendRow, trend  # noqa: E402
