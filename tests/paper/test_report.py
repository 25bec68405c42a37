"""The report of a tiny study: a valid summary.json, a self-contained index.html with Plotly
inlined, and a re-run that reuses every cached run."""

from __future__ import annotations

import json
import re

from flexride.paper import run_report
from flexride.paper.claims import CLAIMS
from flexride.paper.judge import VERDICTS
from paper.conftest import tiny_options


def test_summary_json_lists_every_claim_with_a_verdict(tiny_report):
    directory, result = tiny_report
    claims = json.loads((directory / "summary.json").read_text(encoding="utf-8"))
    assert isinstance(claims, list) and [c["id"] for c in claims] == [c.id for c in CLAIMS]
    for c in claims:
        assert {"id", "source", "paper", "flexride", "verdict", "note"} <= set(c)
        assert c["verdict"] in VERDICTS
        assert "evaluation failed" not in c["note"], c
        assert c["verdict"] == "reproduced" or c["note"], c["id"]
    verdicts = {c["id"]: c["verdict"] for c in claims}
    assert verdicts["table1.mode1"] in ("reproduced", "not reproduced")
    assert verdicts["s5.2.fig15.vertical"] == "not comparable"  # no curve in this study
    # Table 3's 4 runs and the pre-calculation's 2 tracks x 3 meshes
    assert result.outcome.computed + result.outcome.reused == 10 and not result.outcome.failures
    # Fig. 4 on 0.7/0.6/0.5 m: the smooth track's air springs carry their static load on every
    # mesh (nothing grows); 0.2 m is not among the sizes (adequacy not comparable)
    grows = next(c for c in claims if c["id"] == "s2.fig4.grows")
    assert grows["verdict"] == "not reproduced" and grows["flexride"]["holds"] is False
    assert verdicts["s2.fig4.adequate"] == "not comparable"
    sperling = next(c for c in claims if c["id"] == "table2.sperling_z.flexible")["flexride"]
    assert 0.5 < sperling["value"] < 5.0


def test_index_html_is_self_contained_and_embeds_plotly(tiny_report):
    directory, _ = tiny_report
    page = (directory / "index.html").read_text(encoding="utf-8")
    assert not re.search(r"<script[^>]*\bsrc\s*=\s*['\"]?https?://", page, flags=re.I)
    assert not re.search(r"<link[^>]*href\s*=\s*['\"]?https?://", page, flags=re.I)
    assert "Plotly.newPlot" in page and len(page) > 3_000_000  # plotly.js inlined
    data = re.search(r"<script type='application/json' id='figure-data'>(.*?)</script>",
                     page, flags=re.S)
    figures = json.loads(data.group(1))
    assert {"fig4", "fig6", "fig7", "fig10", "fig24", "fig26"} <= {f["id"] for f in figures}
    fig4 = next(f for f in figures if f["id"] == "fig4")
    assert len(fig4["panels"]) == 4 and not fig4["note"]  # 2 tracks x (largest value, rms)
    meshes = next(t for t in fig4["panels"][0]["data"] if t["mode"] == "lines+markers")
    assert meshes["x"] == [0.5, 0.6, 0.7]
    assert "Shortened study" in page and "Model overrides" in page
    assert "s8.fig26.pr-lag" in page


def test_a_rerun_reuses_the_cached_runs(tiny_report):
    directory, first = tiny_report
    again = run_report(directory, tiny_options(jobs=1))
    assert again.outcome.reused == 10 and again.outcome.computed == 0
    assert [c["verdict"] for c in again.claims] == [c["verdict"] for c in first.claims]


def test_the_report_states_the_sperling_settings_it_used(tiny_report):
    """The settings line comes from the pinned defaults (a changed default changes it)."""
    from flexride.analysis.sperling import SPERLING_DEFAULTS, spectral_form_text

    page = (tiny_report[0] / "index.html").read_text(encoding="utf-8")
    assert spectral_form_text() in page
    assert f"{SPERLING_DEFAULTS['segment_s']:g} s Hann segments with 50% overlap" in page
    assert "wall time" in page and "the service's jobs" not in page  # runs ran in the command
