"""How a claim is judged: flexride's value against the paper's, by the rule the claim states.

A judge is a function ``judge(paper, value) -> bool`` (True: reproduced). Numbers are compared
through their mean over irregularity realisations; trends and orderings carry their own
``holds``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from flexride.paper.measures import Estimate

__all__ = [
    "NOT_COMPARABLE",
    "NOT_REPRODUCED",
    "REPRODUCED",
    "VERDICTS",
    "Judge",
    "Value",
    "holds",
    "within",
    "within_abs",
]

REPRODUCED = "reproduced"
NOT_REPRODUCED = "not reproduced"
NOT_COMPARABLE = "not comparable"
VERDICTS = (REPRODUCED, NOT_REPRODUCED, NOT_COMPARABLE)


@dataclass(frozen=True)
class Value:
    """flexride's side of a claim.

    Attributes
    ----------
    estimate : Estimate or None
        The number compared with the paper's (mean ± 95 % CI over seeds).
    holds : bool or None
        Whether a stated trend or ordering holds in flexride's results.
    values : dict
        The numbers it was decided on (JSON-ready).
    words : str
        flexride's result in words.
    comparable : bool
        False when the paper's value cannot be compared (e.g. no unit); ``why`` says why.
    why : str
        Reason it is not comparable.
    unit : str
        Unit of ``estimate``.
    """

    estimate: Estimate | None = None
    holds: bool | None = None
    values: dict[str, Any] = field(default_factory=dict)
    words: str = ""
    comparable: bool = True
    why: str = ""
    unit: str = ""

    def to_dict(self) -> dict[str, Any]:
        """JSON form: ``value``/``ci95``/``n`` of the estimate, ``holds``, the deciding
        numbers and the words.
        """
        out: dict[str, Any] = {}
        if self.estimate is not None:
            out.update(self.estimate.to_dict())
            if self.unit:
                out["unit"] = self.unit
        if self.holds is not None:
            out["holds"] = self.holds
        if self.values:
            out["values"] = _rounded(self.values)
        if self.words:
            out["words"] = self.words
        return out


def _rounded(obj: Any) -> Any:
    """Floats to 4 significant digits (non-finite → None), recursively."""
    if isinstance(obj, dict):
        return {str(k): _rounded(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_rounded(v) for v in obj]
    if isinstance(obj, bool) or obj is None or isinstance(obj, int | str):
        return obj
    try:
        v = float(obj)
    except (TypeError, ValueError):
        return str(obj)
    return float(f"{v:.4g}") if math.isfinite(v) else None


Judge = Callable[[Any, Value], bool]
"""``judge(paper, value) -> bool``: True when flexride reproduces the paper."""


def within(rel: float) -> Judge:
    """Judge: the mean is within ``rel`` (a fraction) of the paper's number."""
    def judge(paper: Any, value: Value) -> bool:
        if value.estimate is None:
            return False
        return abs(value.estimate.mean / float(paper) - 1.0) <= rel + 1e-12

    judge.__doc__ = f"within {rel:.0%} of the paper's value"
    return judge


def within_abs(tol: float) -> Judge:
    """Judge: the mean is within ``tol`` (in the value's unit) of the paper's number."""
    def judge(paper: Any, value: Value) -> bool:
        if value.estimate is None:
            return False
        return abs(value.estimate.mean - float(paper)) <= tol + 1e-12

    judge.__doc__ = f"within ±{tol:g} of the paper's value"
    return judge


def holds(paper: Any, value: Value) -> bool:
    """Judge: the stated trend or ordering holds in flexride's results."""
    return bool(value.holds)
