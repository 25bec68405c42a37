"""A claim of the paper: what it says, how flexride's value is computed from the study, how it
is judged, and why flexride may differ; and its evaluation into a verdict.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from flexride.paper.data import NotComparable, StudyData
from flexride.paper.judge import NOT_COMPARABLE, NOT_REPRODUCED, REPRODUCED, Judge, Value

__all__ = ["Claim", "ClaimResult", "evaluate"]

Compute = Callable[[StudyData], Value]
"""flexride's value of a claim from the study's results; raises NotComparable when the study
lacks what it needs."""


@dataclass(frozen=True)
class Claim:
    """One table entry or stated finding of the paper.

    Attributes
    ----------
    id : str
        Stable identifier, e.g. ``table1.mode1``, ``s7.fig21.linear``.
    source : str
        Where the paper says it (table, section, figure).
    statement : str
        What the paper says (its words, shortened).
    paper : Any
        The paper's value: a number (unit in ``unit``) or its words.
    rule : str
        The tolerance rule that decides "reproduced".
    compute : callable
        flexride's value from the study (:data:`Compute`).
    judge : callable
        ``judge(paper, value) -> bool`` (:mod:`flexride.paper.judge`).
    reason : str
        Why flexride may differ: an input the paper does not give, or a modelling difference,
        with flexride's documented measurements. Shown when not reproduced.
    agree : str
        Remark shown when reproduced (e.g. "an input of the model, not a prediction").
    figure : str or None
        Id of the report figure that shows it.
    unit : str
        Unit of a numeric paper value.
    """

    id: str
    source: str
    statement: str
    paper: Any
    rule: str
    compute: Compute
    judge: Judge
    reason: str = ""
    agree: str = ""
    figure: str | None = None
    unit: str = ""


@dataclass
class ClaimResult:
    """A judged claim, as written to ``summary.json`` (:meth:`to_dict`)."""

    claim: Claim
    value: Value | None
    verdict: str
    note: str

    def to_dict(self) -> dict[str, Any]:
        """``{"id", "source", "paper", "flexride", "verdict", "note", "statement", "rule"}``."""
        c = self.claim
        paper: Any = c.paper if not c.unit else {"value": c.paper, "unit": c.unit}
        return {"id": c.id, "source": c.source, "paper": paper,
                "flexride": None if self.value is None else self.value.to_dict(),
                "verdict": self.verdict, "note": self.note, "statement": c.statement,
                "rule": c.rule}


def evaluate(claim: Claim, data: StudyData) -> ClaimResult:
    """Compute flexride's value of ``claim`` and judge it.

    Verdicts: ``reproduced`` (the rule holds), ``not reproduced`` (it does not; the note gives
    the claim's reason), ``not comparable`` (the study lacks the data, or the paper's value
    cannot be compared; the note says why).
    """
    try:
        value = claim.compute(data)
    except NotComparable as exc:
        return ClaimResult(claim, None, NOT_COMPARABLE, str(exc))
    except Exception as exc:  # a bug must not cost the whole report; the note says so
        return ClaimResult(claim, None, NOT_COMPARABLE,
                           f"evaluation failed ({type(exc).__name__}: {exc}); a flexride bug")
    if not value.comparable:
        return ClaimResult(claim, value, NOT_COMPARABLE, value.why)
    if claim.judge(claim.paper, value):
        return ClaimResult(claim, value, REPRODUCED, claim.agree)
    return ClaimResult(claim, value, NOT_REPRODUCED, claim.reason)
