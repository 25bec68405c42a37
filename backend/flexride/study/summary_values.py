"""One number from a stored analysis summary (:meth:`flexride.analysis.Summary.to_dict`): the
reader the study tables and the paper report share.
"""

from __future__ import annotations

import math
from typing import Any

__all__ = ["summary_value"]

_FIRST_WEIGHTING = {"z": "Wb", "y": "Wd", "x": "Wd"}


def summary_value(summary: dict[str, Any] | None, point: str, direction: str,
                  quantity: str) -> float | None:
    """One number of a summary dict: ``sperling``, ``peak`` (max |a|), ``rms`` or ``a_w``
    (ISO 2631 weighted rms, Wb for z, Wd for y); None when absent.
    """
    try:
        d = summary["points"][point]["directions"][direction]  # type: ignore[index]
        if quantity == "sperling":
            v = d["sperling"]["value"] if d.get("sperling") else None
        elif quantity == "peak":
            v = d["peaks"]["max_abs"]
        elif quantity == "rms":
            v = d["peaks"]["rms"]
        elif quantity == "a_w":
            v = d["iso2631"][_FIRST_WEIGHTING[direction]]["a_w"]
        else:
            raise ValueError(f"unknown quantity {quantity!r}")
    except (KeyError, TypeError):
        return None
    if v is None:
        return None
    v = float(v)
    return v if math.isfinite(v) else None
