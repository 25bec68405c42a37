"""Browser tests of studies with irregularity realisations (``seeds``) and of the paper report
kind of study, in Chromium and Firefox, against a real ``flexride serve`` (fixtures of
tests/frontend/conftest.py):

* the study page draws the 95 % confidence intervals of the means as error bars, with the
  values the API gives;
* a paper report study's page says what the report waits for and offers "Open report" once it
  is built. The report's state is the server's study answer with its ``report`` replaced
  (``page.route``): a real report study runs the quick plan's 16 runs with the 0.2 m car body,
  minutes of computing (tests/api/test_studies_report.py builds a real one).
"""

from __future__ import annotations

import json
import re
from typing import Any, get_args

from flexride.scenario.fidelity import CUTOFF_RULE_LABELS, CutoffRule
from flexride.study.sections import SECTION_RULE_LABELS, SectionRule

try:
    from playwright.sync_api import expect
except ImportError:  # the browser fixture skips these tests (or fails them in CI)
    expect = None

RUN_S = 5.5  # the spectral Sperling index needs at least 5 s
SHARED: dict[str, Any] = {}  # made once per session; both browsers read it


def _seeds_study(server: Any) -> dict:
    """Random irregularity at two speeds, two realisations each: four jobs."""
    if "seeds" not in SHARED:
        st = server.api("/studies", {
            "name": "ui-seeds", "base": {"preset": "paper-metro"},
            "conditions": ["random-straight"], "speeds_kmh": [60, 80], "seeds": 2,
            "overrides": {"duration_s": RUN_S, "distance_m": None}})
        assert st["n_jobs"] == 4
        for job in st["jobs"]:
            assert server.wait_job(job["id"], timeout=400)["status"] == "succeeded"
        SHARED["seeds"] = server.api(f"/studies/{st['id']}")
    return SHARED["seeds"]


def test_study_with_seeds_draws_error_bars(page, server, shot, wait_plot):
    st = _seeds_study(server)
    row = next(r for r in st["tables"]["sperling_vs_speed"]
               if r["point"] == "PC" and r["direction"] == "z")
    assert row["n"] == [2, 2] and all(c is not None and c > 0 for c in row["ci95"])
    page.goto(f"/#/studies/{st['id']}")
    wait_plot(page, "#plot-sperling-speed")
    traces = page.eval_on_selector("#plot-sperling-speed .plot", """e => e.data
        .filter(t => t.name === 'PC' && t.error_y)
        .map(t => ({axis: t.xaxis, y: t.y, bars: t.error_y.array, visible: t.error_y.visible}))""")
    assert len(traces) == 2  # vertical and lateral panels
    vertical = next(t for t in traces if t["axis"] == "x")
    assert vertical["visible"] and vertical["bars"] == row["ci95"]
    assert vertical["y"] == row["value"]
    # drawn: the error-bar paths are in the SVG
    assert page.locator("#plot-sperling-speed g.errorbar").count() >= 4
    note = page.locator("#plot-sperling-speed .plot-note").inner_text()
    assert "means over 2 irregularity realisations" in note and "95 %" in note
    # every index's section is stated: 5.5 s runs are too short for 30 m on (whole run)
    page.locator("#study-sections summary").click()
    cells = page.locator("#study-sections tbody tr").all_inner_texts()
    assert len(cells) == 2 and all("whole run" in c for c in cells)
    assert row["sections"] == ["whole run", "whole run"]
    shot(page, "40-study-seeds-error-bars")
    page.get_by_role("tab", name="Peak vs speed").click()
    wait_plot(page, "#plot-peak-speed")
    assert page.eval_on_selector("#plot-peak-speed .plot",
                                 "e => e.data.some(t => t.error_y && t.error_y.visible)")


def test_report_study_offers_open_report_once_built(page, server):
    st = _seeds_study(server)
    state = {"report": {"state": "waiting", "message": "3 of 4 runs finished; the report is "
                        "built when all have", "progress": 0.0, "counts": {}, "links": {}}}

    def handle(route):
        if route.request.method != "GET":
            route.fallback()
            return
        body = route.fetch().json()
        route.fulfill(json={**body, "preset": "paper-report", "report": state["report"]})

    page.route(re.compile(rf".*/api/v1/studies/{st['id']}$"), handle)
    try:
        page.goto(f"/#/studies/{st['id']}")
        expect(page.locator("#study-report-state")).to_contain_text("3 of 4 runs finished")
        assert page.locator("#open-report").count() == 0
        links = {"html": f"/api/v1/studies/{st['id']}/report",
                 "summary": f"/api/v1/studies/{st['id']}/report/summary"}
        state["report"] = {"state": "ready", "message": "the report is ready", "progress": 1.0,
                           "counts": {"reproduced": 37, "not reproduced": 29,
                                      "not comparable": 2}, "links": links}
        link = page.get_by_role("link", name="Open report")
        expect(link).to_be_visible(timeout=15_000)  # the page polls while the report builds
        assert link.get_attribute("href") == links["html"]
        assert page.locator("#report-summary").get_attribute("href") == links["summary"]
        assert "37 reproduced" in page.locator("#study-report-state").inner_text()
    finally:
        page.unroute_all(behavior="wait")


def test_new_study_form_takes_seeds_section_and_offers_the_report(page, server):
    page.goto("/#/studies/new")
    page.get_by_role("button", name="Fill the form with paper-table2", exact=True).click()
    assert page.locator("#study-count").inner_text() == "2"
    page.fill("#study-seeds", "3")
    page.locator("#study-seeds").dispatch_event("input")
    expect(page.locator("#study-count")).to_have_text("6")
    assert "3 irregularity realisations" in page.locator("#study-count-info").inner_text()
    assert page.locator("#study-section").input_value() == "paper"
    assert "circular arc" in page.locator("#study-section-help").inner_text()
    # the choices are the service's (GET /openapi.json), in its order with its labels
    for select, rule, labels in (("#study-section", SectionRule, SECTION_RULE_LABELS),
                                 ("#study-cutoff", CutoffRule, CUTOFF_RULE_LABELS)):
        shown = page.locator(f"{select} option").evaluate_all(
            "os => os.map(o => [o.value, o.textContent])")
        assert shown == [[v, labels[v]] for v in get_args(rule)]
    page.fill("#study-seeds", "21")
    page.click("#submit-study")
    assert "1 to 20" in page.locator("#study-seeds-err").inner_text()
    # the paper report: quick or full, its runs fixed by the plan
    assert page.locator("#run-report-quick").inner_text() == "Run quick report"
    # 16 + 16 · 5 seeds, and the element-size pre-calculation's 2 tracks × 6 meshes
    assert "108 jobs" in page.locator("#run-report-full").inner_text()


def test_the_cut_off_choice_reaches_the_study(page, server):
    """'As given' in the form is the request's cutoff (the default, 'follow', is left out).
    The request is answered here with a refusal, so that no flexible study is run; its body is
    read in the page (Firefox's interception does not give it)."""
    page.console_log.allow(r"status of 422")  # the stand-in answer below
    page.route("**/api/v1/studies", lambda route: route.fulfill(
        status=422, content_type="application/json", body=json.dumps(
            {"detail": [{"loc": ["body", "name"], "msg": "stopped by the test", "type": "x"}],
             "message": "stopped by the test"}))
        if route.request.method == "POST" else route.continue_())
    page.goto("/#/studies/new")
    page.evaluate("""() => {
        const f = window.fetch; window.__studyBodies = [];
        window.fetch = (u, o) => {
            if (String(u).endsWith('/api/v1/studies') && o && o.method === 'POST')
                window.__studyBodies.push(JSON.parse(o.body));
            return f(u, o);
        };
    }""")
    page.get_by_role("button", name="Fill the form with paper-table3", exact=True).click()
    assert page.locator("#study-cutoff").input_value() == "follow"
    page.click("#submit-study")
    page.wait_for_function("() => window.__studyBodies.length === 1")
    page.select_option("#study-cutoff", "as_given")
    page.click("#submit-study")
    page.wait_for_function("() => window.__studyBodies.length === 2")
    first, second = page.evaluate("() => window.__studyBodies")
    assert first["body_models"] == ["flexible"] and "cutoff" not in first
    assert second["cutoff"] == "as_given"
