"""The paper reproduced in one command: its study (Table 3's conditions × rigid and flexible
car body, Table 1's modal analysis) run with flexride, every table entry and stated finding
judged against flexride's result, and a self-contained report written beside it.

``flexride paper report -o DIR`` (:mod:`flexride.cli.paper`) or, from Python,
:func:`~flexride.paper.report.run_report`. The claims registry is
:data:`flexride.paper.claims.CLAIMS`; docs/paper.md describes the verdicts.
"""

from __future__ import annotations

from flexride.paper.plan import ReportError, ReportOptions
from flexride.paper.report import ReportResult, run_report

__all__ = ["ReportError", "ReportOptions", "ReportResult", "run_report"]
