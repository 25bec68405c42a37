"""The claims registry: every table entry and stated finding of the paper, in the paper's
order, each with its value or words, how flexride's value is computed from the study, and how
it is judged (:class:`~flexride.paper.claims.base.Claim`).

``evaluate_all(data)`` judges them all.
"""

from __future__ import annotations

from flexride.paper.claims.base import Claim, ClaimResult, evaluate
from flexride.paper.claims.conclusions import conclusions
from flexride.paper.claims.defects import section6, section7
from flexride.paper.claims.precalculation import precalculation
from flexride.paper.claims.section5 import section5
from flexride.paper.claims.section8 import section8
from flexride.paper.claims.tables import section3, table1, table2
from flexride.paper.data import StudyData

__all__ = ["CLAIMS", "Claim", "ClaimResult", "evaluate", "evaluate_all"]


def _registry() -> tuple[Claim, ...]:
    claims = (*precalculation(), *table1(), *table2(), *section3(), *section5(), *section6(),
              *section7(), *section8(), *conclusions())
    ids = [c.id for c in claims]
    dup = sorted({i for i in ids if ids.count(i) > 1})
    if dup:
        raise RuntimeError(f"duplicate claim ids: {dup}")
    return claims


CLAIMS: tuple[Claim, ...] = _registry()
"""Every claim, in the paper's order."""


def evaluate_all(data: StudyData) -> list[ClaimResult]:
    """Judge every claim of :data:`CLAIMS` on the study's results."""
    return [evaluate(c, data) for c in CLAIMS]
