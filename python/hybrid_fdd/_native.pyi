"""Type stub of the native module ``hybrid_fdd._native`` (python/src/lib.rs).

The public API is ``hybrid_fdd`` (``__init__.py``); these are the calls it makes. Each diagnosis
result is ``("ok", {"json": str, "baseline_note": str | None, "unit": str,
"unit_statement": str, "notes": list[str]})`` or ``(error class name, message)``.
"""

from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

DEFAULT_FALSE_ALARM: float

class InputError(ValueError):
    """Input the diagnosis refuses (one-line Rust message)."""

class DataError(OSError):
    """A file that cannot be read or parsed (one-line Rust message)."""

class InternalError(RuntimeError):
    """The Rust code panicked: a bug."""

_Result = Tuple[str, Any]

class PreparedBaseline:
    """A baseline read once; its preparations cached across calls."""

    def __init__(
        self,
        path: Optional[str] = None,
        samples: Optional[npt.NDArray[np.float64]] = None,
        fs: Optional[float] = None,
        machine: Optional[str] = None,
        channel: str = "DE",
    ) -> None: ...
    @property
    def path(self) -> Any: ...

def read(path: str, channel: Optional[str] = None, fs: Optional[float] = None) -> Dict[str, Any]: ...
def diagnose_arrays(
    signals: Sequence[npt.NDArray[np.float64]],
    fs: Sequence[float],
    rpm: Sequence[Optional[float]],
    unit: Sequence[Optional[str]],
    bearing: str,
    rpm_range: Optional[Tuple[float, float]] = None,
    alpha: Optional[float] = None,
    baseline_path: Optional[str] = None,
    baseline_samples: Optional[npt.NDArray[np.float64]] = None,
    baseline_fs: Optional[float] = None,
    baseline_machine: Optional[str] = None,
    baseline_prepared: Optional[PreparedBaseline] = None,
    channel: str = "DE",
    threads: Optional[int] = None,
    steady_speed: bool = False,
) -> List[_Result]: ...
def diagnose_files(
    paths: Sequence[str],
    bearing: str,
    channel: str = "DE",
    fs: Optional[float] = None,
    rpm: Optional[float] = None,
    rpm_range: Optional[Tuple[float, float]] = None,
    alpha: Optional[float] = None,
    baseline_path: Optional[str] = None,
    baseline_samples: Optional[npt.NDArray[np.float64]] = None,
    baseline_fs: Optional[float] = None,
    baseline_machine: Optional[str] = None,
    baseline_prepared: Optional[PreparedBaseline] = None,
    one_file: bool = False,
    threads: Optional[int] = None,
    tach: Optional[str] = None,
    pulses_per_rev: float = 1.0,
    steady_speed: bool = False,
) -> List[_Result]: ...
def recordings_in(directory: str) -> List[str]: ...
def bearing(spec: str) -> str: ...
def order_track(
    x: npt.NDArray[np.float64],
    tach: npt.NDArray[np.float64],
    fs: float,
    pulses_per_rev: float,
) -> Tuple[npt.NDArray[np.float64], str]: ...
def calibrate(
    path: str,
    rpm: Optional[float] = None,
    bearing: Optional[str] = None,
    channel: str = "DE",
    fs: Optional[float] = None,
    decimate: int = 1,
    model: str = "physics",
    units: Optional[str] = None,
    line_frequency: float = 60.0,
    max_effects: Optional[int] = None,
    report: Optional[str] = None,
) -> Tuple[str, str]: ...
def close_loop_file(
    path: str,
    fault: str = "none",
    machine: Optional[str] = None,
    rpm: Optional[float] = None,
    bearing: Optional[str] = None,
    channel: str = "DE",
    fs: Optional[float] = None,
    decimate: int = 1,
    model: str = "physics",
    units: Optional[str] = None,
    line_frequency: float = 60.0,
    max_effects: int = 8,
    seconds: Optional[float] = None,
    fault_size_in: Optional[float] = None,
    report: Optional[str] = None,
) -> Tuple[str, str]: ...
def machine_model(text: str) -> str: ...
def simulate_to(flags: Sequence[str], out: str) -> None: ...

TREND_DEFAULT_K: float
TREND_DEFAULT_SPEED_EXPONENT: float

class TrendResult:
    """``hybrid-fdd trend``'s result, kept in Rust (``hybrid_fdd_cli::trend::Trend``)."""

    def json(self) -> str:
        """``trend.json``'s text, as the command writes it."""
    def csv(self) -> str:
        """``trend.csv``'s text."""
    def summary(self) -> str:
        """``summary.md``'s text."""
    def time_texts(self) -> List[str]:
        """Each row's time as the outputs print it."""
    def write(self, dir: str) -> None:
        """Write trend.csv, trend.json, summary.md and trend.png into ``dir`` (created)."""

def trend_files(
    input: Optional[str],
    index: Optional[str],
    bearing: str,
    rpm: Optional[float],
    fs: Optional[float],
    channel: Optional[str],
    baseline_count: int,
    unit: Optional[str],
    machine_group: Optional[str],
    alarm: str,
    k: float,
    alarm_on: Optional[Sequence[str]],
    speed_exponent: float,
    observers: bool,
    decimate_to: Optional[float],
    report: Optional[str],
    progress: bool,
) -> TrendResult:
    """``hybrid-fdd trend --input DIR | --index FILE``: the command's reading and analysis."""
def trend_arrays(
    names: Sequence[str],
    times: Sequence[Union[float, str]],
    signals: Sequence[npt.NDArray[np.float64]],
    fs: Sequence[float],
    rpm: Sequence[Optional[float]],
    units: Sequence[Optional[str]],
    bearing: str,
    baseline_count: int,
    unit: Optional[str],
    machine_group: Optional[str],
    alarm: str,
    k: float,
    alarm_on: Optional[Sequence[str]],
    speed_exponent: float,
    observers: bool,
    decimate_to: Optional[float],
    report: Optional[str],
    progress: bool,
    default_rpm: Optional[float],
) -> TrendResult:
    """The command's analysis on recordings in memory (times: numbers = positions, strings =
    calendar times)."""
