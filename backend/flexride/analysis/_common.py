"""Input checks and JSON conversion shared by the analysis modules (private).

Every public analysis function validates its input here so that bad input (empty arrays, NaN,
too short a record, a sample rate too low for the band) raises one clear
:class:`~flexride.errors.AnalysisError` instead of a NumPy warning or a silent NaN.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from flexride.errors import AnalysisError


def check_rate(fs: float) -> float:
    """Return ``fs`` as float after checking it is a finite positive sample rate (Hz)."""
    try:
        fs = float(fs)
    except (TypeError, ValueError):
        raise AnalysisError(f"sample rate must be a number in Hz, got {fs!r}") from None
    if not (math.isfinite(fs) and fs > 0.0):
        raise AnalysisError(f"sample rate must be finite and positive (Hz), got {fs!r}")
    return fs


def check_signal(
    x: Any,
    fs: float | None = None,
    *,
    name: str = "signal",
    min_duration: float | None = None,
    min_samples: int = 2,
    method: str = "this method",
    ndim: tuple[int, ...] = (1, 2),
) -> np.ndarray:
    """Validate a signal array (samples along the last axis) and return it as float64.

    Parameters
    ----------
    x : array_like
        Signal, shape ``(n,)`` or ``(m, n)`` (samples along the last axis).
    fs : float, optional
        Sample rate in Hz, needed for ``min_duration``.
    name : str
        Name used in error messages.
    min_duration : float, optional
        Shortest record the method accepts (s).
    min_samples : int
        Fewest samples the method accepts.
    method : str
        Name of the method, for the error message.
    ndim : tuple of int
        Allowed numbers of dimensions.

    Raises
    ------
    AnalysisError
        Empty input, NaN or infinite values, wrong shape, or too short a record.
    """
    try:
        arr = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise AnalysisError(f"{name}: cannot convert to a float array ({exc})") from None
    if arr.ndim not in ndim:
        raise AnalysisError(
            f"{name}: expected an array with {' or '.join(map(str, ndim))} dimension(s) "
            f"(samples along the last axis), got shape {arr.shape}"
        )
    if arr.size == 0 or arr.shape[-1] == 0:
        raise AnalysisError(f"{name}: empty array")
    if not np.all(np.isfinite(arr)):
        bad = int(np.count_nonzero(~np.isfinite(arr)))
        raise AnalysisError(f"{name}: contains {bad} NaN or infinite value(s)")
    n = arr.shape[-1]
    if n < min_samples:
        raise AnalysisError(f"{name}: {method} needs at least {min_samples} samples, got {n}")
    if min_duration is not None:
        if fs is None:
            raise AnalysisError(f"{name}: a sample rate is needed to check the record length")
        duration = n / fs
        if duration + 0.5 / fs < min_duration:
            raise AnalysisError(
                f"{name}: record of {duration:.3g} s is too short for {method}, "
                f"which needs at least {min_duration:.3g} s"
            )
    return arr


def check_nyquist(fs: float, f_max: float, what: str, factor: float = 2.0) -> None:
    """Raise if ``fs`` is below ``factor`` × ``f_max`` (the band or filter needs it)."""
    if fs < factor * f_max:
        raise AnalysisError(
            f"sample rate {fs:g} Hz is too low for {what}: it needs at least "
            f"{factor * f_max:g} Hz ({factor:g} × {f_max:g} Hz)"
        )


def jsonable(obj: Any) -> Any:
    """Convert results (dataclasses, arrays, NumPy scalars) to plain JSON-compatible values.

    Non-finite floats become ``None`` (JSON has no NaN); tuples become lists. Dataclass fields
    declared with ``metadata={"json": False}`` (large intermediate arrays) are left out.
    """
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: jsonable(getattr(obj, f.name)) for f in dataclasses.fields(obj)
                if f.metadata.get("json", True)}
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        if obj.dtype.kind in "fc":
            arr = obj.astype(np.float64) if obj.dtype.kind == "f" else np.abs(obj)
            out = arr.tolist()
            if not np.all(np.isfinite(arr)):
                return _nan_to_none(out)
            return out
        return obj.tolist()
    if isinstance(obj, np.bool_ | bool):
        return bool(obj)
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, float | np.floating):
        v = float(obj)
        return v if math.isfinite(v) else None
    return obj


def _nan_to_none(values: Any) -> Any:
    if isinstance(values, list):
        return [_nan_to_none(v) for v in values]
    if isinstance(values, float) and not math.isfinite(values):
        return None
    return values
