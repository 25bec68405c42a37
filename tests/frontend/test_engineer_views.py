"""Browser tests of the dashboard as a railway engineer reads it, in Chromium and Firefox
(fixtures of tests/frontend/conftest.py), against a real ``flexride serve``:

* orientation: the drawing of the car body with the paper's and the user's points, and the
  description and position of a point wherever its name appears (from the recorded points);
* honest progress: "compiling the solver (first run only, about N s)" while the service's health
  says so (mocked with ``page.route``), the FE build's progress bar and estimate, a study at
  100 % only when every job has finished, the jobs pager counting the filtered rows;
* figures as in the paper: Sperling against speed as small multiples (one panel per condition and
  direction, one colour per point in every chart), flexible against rigid as a chart in percent
  beside the table, compare with the reference the user chooses;
* one force convention (EN 14363: Q vertical, Y lateral, Y/Q, ΔQ/Q, ΣY; GB 5599's names in the
  help), every wheelset in the running-safety table with the governing value marked;
* forms and tables: the Δt fix button gone after Submit, the job name following the edits, job
  details with preset, body models and contact model, the comfort table within 1280 px (or a
  scroll cue), a unit and a complete help text on every field of the scenario form.

No test leaves a console error (checked by the ``page`` fixture). Screenshots:
tests/frontend/artifacts/<browser>/.
"""

from __future__ import annotations

import re
from typing import Any

import pytest

try:
    from playwright.sync_api import expect
except ImportError:  # the browser fixture skips these tests (or fails them in CI)
    expect = None

RUN_S = 5.5  # the spectral Sperling index needs at least 5 s
SEAT = {"name": "SEAT12", "x": 3.0, "y": 0.8, "z": 1.6}
SHARED: dict[str, Any] = {}  # jobs and studies both browsers read (made once per session)


def _job(server: Any, key: str, **overrides: Any) -> str:
    """A finished job of the session (made once; both browsers read it)."""
    if key not in SHARED:
        ov = {"duration_s": RUN_S, "distance_m": None, **overrides}
        job = server.api("/jobs", {"preset": "paper-random-straight-80", "overrides": ov})
        assert server.wait_job(job["id"], timeout=240)["status"] == "succeeded"
        SHARED[key] = job["id"]
    return SHARED[key]


def _study(server: Any, key: str, body: dict[str, Any], timeout: float = 400) -> dict:
    """A finished study of the session (made once)."""
    if key not in SHARED:
        st = server.api("/studies", body)
        for job in st["jobs"]:
            assert server.wait_job(job["id"], timeout=timeout)["status"] == "succeeded"
        SHARED[key] = server.api(f"/studies/{st['id']}")
    return SHARED[key]


def _seat_job(server: Any) -> str:
    return _job(server, "seat", **{"output.points": [SEAT]})


def _conditions_study(server: Any) -> dict:
    """Two conditions at two speeds: four jobs, two panels per direction."""
    return _study(server, "conditions", {
        "name": "ui-conditions", "base": {"preset": "paper-metro"},
        "conditions": ["random-straight", "settlement"], "speeds_kmh": [60, 80],
        "overrides": {"duration_s": RUN_S, "distance_m": None}})


def _table2_study(server: Any) -> dict:
    """Rigid against flexible (a coarse car body and frames, built in seconds)."""
    return _study(server, "table2", {
        "name": "ui-table2", "base": {"preset": "paper-metro"}, "conditions": ["random-straight"],
        "speeds_kmh": [80], "body_models": ["rigid", "flexible"],
        "overrides": {"duration_s": RUN_S, "distance_m": None,
                      "bodies.carbody.element_size_m": 0.5, "bodies.frames.element_size_m": 0.3}},
        timeout=600)


def _route_json(page: Any, pattern: Any, change) -> dict[str, bool]:
    """Answer GET requests matching ``pattern`` with the server's JSON changed by ``change``
    while the returned switch's ``on`` is true (unrouting races requests in flight)."""
    switch = {"on": True}

    def handle(route):
        if route.request.method != "GET" or not switch["on"]:
            route.fallback()
            return
        resp = route.fetch()
        route.fulfill(response=resp, json=change(resp.json()))
    page.route(pattern, handle)
    return switch


@pytest.fixture
def routed(page: Any):
    """The page, whose routes are removed after the test once their handlers have finished."""
    yield page
    page.unroute_all(behavior="wait")


def _compiling(body: dict) -> dict:
    return {**body, "solver": {"state": "compiling", "estimate_s": 45}}


# -- orientation ----------------------------------------------------------------------------------


def test_points_are_drawn_and_explained_wherever_they_appear(page, server, shot):
    job_id = _seat_job(server)
    points = {p["name"]: p for p in server.api(f"/jobs/{job_id}/channels")["points"]
              if p["body"] == "carbody"}
    paper = server.api("/schemas/points")
    page.goto(f"/#/jobs/{job_id}")
    page.locator("#summary-cards").wait_for(timeout=60_000)
    # the drawing: side and plan view, each of the paper's points and the user's point
    card = page.locator("#points-card")
    expect(card.locator("svg.pt-drawing")).to_be_visible()
    marks = card.locator("svg .pt-mark")
    names = set(marks.evaluate_all("ms => ms.map(m => m.dataset.point)"))
    assert names == {p["name"] for p in paper} | {"SEAT12"}
    assert marks.count() == 2 * len(names)  # side and plan view
    assert card.locator('svg rect.pt-mark[data-point="SEAT12"]').count() == 2  # user: square
    # the legend: description and position from the recorded points
    row = card.locator('tr[data-point="PLA"]').inner_text()
    assert "left air spring" in row and "-6.3" in row and "0.95" in row
    # a point name anywhere: its description and position as tooltip
    for where in ("#summary-cards", ".comfort-table"):
        tip = page.locator(f'{where} abbr.pt[data-point="PC"]').first.get_attribute("title")
        pc = points["PC"]
        assert tip.startswith("PC: floor at the car-body centre")
        assert f"z {pc['z']:g} m" in tip
    seat_tip = page.locator('.comfort-table abbr.pt[data-point="SEAT12"]').get_attribute("title")
    assert "user point" in seat_tip and "x 3 m, y 0.8 m, z 1.6 m" in seat_tip
    shot(page, "30-job-summary-points")
    # channel lists and point selects say it too
    page.get_by_role("tab", name="Time histories").click()
    opt = page.locator('#time-channels option[value="carbody.PRA.acc.z"]')
    assert "right air spring" in opt.get_attribute("title")
    page.get_by_role("tab", name="Correlation").click()
    labels = page.locator("#corr-ref option").all_inner_texts()
    assert any(t.startswith("PLA: floor above the rear bogie's left air spring") for t in labels)


def test_the_same_point_has_the_same_colour_in_every_chart(page, server, wait_plot):
    job_id = _seat_job(server)
    st = _conditions_study(server)
    page.goto(f"/#/jobs/{job_id}?tab=time")
    wait_plot(page, "#plot-time")
    colours = page.eval_on_selector("#plot-time .plot", """e => Object.fromEntries(e.data.map(
        t => [t.name.split(' ')[2], t.line.color]))""")
    page.goto(f"/#/studies/{st['id']}")
    wait_plot(page, "#plot-sperling-speed")
    study = page.eval_on_selector("#plot-sperling-speed .plot", """e => Object.fromEntries(
        e.data.filter(t => !t.name.startsWith('fit')).map(t => [t.name, t.marker.color]))""")
    for point, colour in colours.items():
        assert study[point] == colour, point


# -- honest progress ------------------------------------------------------------------------------


def test_submission_and_queue_say_the_solver_compiles(routed, server, shot):
    page = routed
    held: list[Any] = []
    health = _route_json(page, "**/api/v1/health", _compiling)
    page.route("**/api/v1/jobs", lambda route: held.append(route)
               if route.request.method == "POST" else route.continue_())
    page.goto("/#/new?preset=paper-random-straight-80")
    page.fill("#f-duration_s", "1")
    page.fill("#f-distance_m", "")
    page.click("#submit-job")
    note = page.locator("#submit-compiling")
    note.wait_for(timeout=15_000)
    assert "compiling the solver (first run only, about 45 s)" in note.inner_text()
    assert "Submitting…" in page.locator("#submit-message").inner_text()
    shot(page, "31-submit-compiling", full_page=False)
    assert held, "the submission is held until the test lets it go"
    # the job page while it waits: the same words
    _route_json(page, re.compile(r".*/api/v1/jobs/[0-9a-f]+$"),
                lambda j: {**j, "status": "queued", "progress": 0.0, "message": "queued"})
    held[0].continue_()
    page.wait_for_url(re.compile(r"#/jobs/[0-9a-f]+$"))
    queued = page.locator("#solver-compiling")
    queued.wait_for(timeout=15_000)
    assert "compiling the solver (first run only, about 45 s)" in queued.inner_text()
    assert "Waiting for a worker" in page.locator("#progress-title").inner_text()
    # a service without the field (or ready): no such note
    health["on"] = False
    page.reload()
    page.locator("#progress-title").wait_for()
    page.wait_for_timeout(1500)
    assert page.locator("#solver-compiling").count() == 0


def test_a_study_is_at_100_percent_only_when_every_job_has_finished(routed, server):
    page = routed
    st = _conditions_study(server)

    def one_running(s: dict) -> dict:
        n = s["n_jobs"]
        return {**s, "status": "running", "progress": 1.0,
                "counts": {"succeeded": n - 1, "running": 1}}

    switch = _route_json(page, f"**/api/v1/studies/{st['id']}", one_running)
    page.goto(f"/#/studies/{st['id']}")
    bar = page.get_by_role("progressbar", name="Study progress")
    bar.wait_for()
    assert bar.get_attribute("aria-valuenow") == "99"
    assert bar.inner_text() == "99 %"
    switch["on"] = False
    page.goto(f"/#/studies/{st['id']}?x=1")
    expect(page.get_by_role("progressbar", name="Study progress")).to_have_attribute(
        "aria-valuenow", "100", timeout=30_000)


def test_jobs_pager_counts_the_filtered_rows(page, server):
    _seat_job(server)
    _conditions_study(server)
    page.goto("/#/")
    page.locator("#jobs-table tbody tr[data-id]").first.wait_for()
    total = page.locator("#jobs-table tbody tr[data-id]").count()
    assert re.search(rf"1–{total} of \d+", page.locator("#jobs-count").inner_text())
    page.fill("#filter-text", "ui-conditions")
    shown = page.locator("#jobs-table tbody tr[data-id]:visible").count()
    assert 0 < shown < total
    assert page.locator("#jobs-count").inner_text().startswith(f"{shown} of {total} on this page")
    page.fill("#filter-text", "no-such-name")
    expect(page.locator("#jobs-count")).to_contain_text("0 of")
    assert "No job on this page matches" in page.locator("main").inner_text()


# -- figures as in the paper ----------------------------------------------------------------------


def test_sperling_against_speed_as_small_multiples(page, server, shot, wait_plot):
    st = _conditions_study(server)
    page.goto(f"/#/studies/{st['id']}")
    wait_plot(page, "#plot-sperling-speed")
    fig = page.eval_on_selector("#plot-sperling-speed .plot", """e => ({
        titles: e.layout.annotations.filter(a => a.text.includes('·')).map(a => a.text),
        axes: Object.keys(e.layout).filter(k => /^xaxis\\d*$/.test(k)).length,
        legend: e.data.filter(t => t.showlegend).map(t => t.name),
        perPanel: e.data.map(t => t.xaxis)})""")
    assert len(fig["titles"]) == 4 and fig["axes"] == 4  # two conditions × two directions
    assert any("random-straight" in t and "vertical" in t for t in fig["titles"])
    assert any("settlement" in t and "lateral" in t for t in fig["titles"])
    assert fig["legend"] == ["PR", "PFB", "PC", "PRB", "PLA", "PRA"]  # one entry per point
    assert len(set(fig["perPanel"])) == 4
    # the lateral direction only: two panels
    page.select_option("#sp-dir", "y")
    page.wait_for_function("() => document.querySelector('#plot-sperling-speed .plot')"
                           ".layout.annotations.filter(a => a.text.includes('·')).length === 2")
    page.select_option("#sp-dir", "both")
    wait_plot(page, "#plot-sperling-speed")
    shot(page, "32-study-small-multiples")
    page.get_by_role("tab", name="Peak vs speed").click()
    wait_plot(page, "#plot-peak-speed")
    assert page.eval_on_selector("#plot-peak-speed .plot",
                                 "e => e.data.some(t => t.name.startsWith('fit'))")


def test_flexible_against_rigid_is_a_chart_beside_the_table(page, server, shot, wait_plot):
    st = _table2_study(server)
    page.goto(f"/#/studies/{st['id']}?tab=flexrigid")
    wait_plot(page, "#plot-flex-rigid")
    rows = st["tables"]["flexible_vs_rigid"]
    pc = next(r for r in rows if r["point"] == "PC" and r["direction"] == "z"
              and r["quantity"] == "sperling")
    bars = page.eval_on_selector("#plot-flex-rigid .plot",
                                 "e => e.data.map(t => ({x: t.x, text: t.text, axis: t.xaxis}))")
    vertical = next(b for b in bars if b["axis"] == "x")
    label = vertical["text"][vertical["x"].index("PC")]
    assert label.endswith(" %")
    assert abs(float(label[:-2].replace("−", "-")) - 100 * pc["relative"]) < 0.06
    # beside the table (paper Table 2), the same numbers
    chart = page.locator("#plot-flex-rigid").bounding_box()
    table = page.locator("#panel-flexrigid table.data").bounding_box()
    assert abs(chart["y"] - table["y"]) < 150 and table["x"] > chart["x"] + chart["width"] - 5
    row = page.locator('#panel-flexrigid table.data tbody tr:has(abbr[data-point="PC"])')
    assert label.replace("−", "-").lstrip("+") in row.inner_text().replace("−", "-")
    shot(page, "33-study-flexible-vs-rigid")
    # the overlay compares against the rigid job
    page.locator("#flex-rigid-jobs a", has_text="overlay").first.click()
    page.wait_for_url(re.compile(r"#/compare\?"))
    page.locator("#cmp-ref").wait_for()
    rigid = pc["rigid_job"]
    assert page.locator("#cmp-ref").input_value() == rigid
    table = page.locator("table.data").last
    table.wait_for()
    caption = table.locator("caption").inner_text()
    assert "relative to the reference" in caption and "rigid" in caption


def test_compare_differences_are_relative_to_the_chosen_reference(page, server, wait_plot):
    st = _table2_study(server)
    row = st["tables"]["flexible_vs_rigid"][0]
    rigid, flexible = row["rigid_job"], row["flexible_job"]
    page.goto(f"/#/compare?jobs={flexible},{rigid}&channel=carbody.PC.acc.z")
    wait_plot(page, "#plot-compare-time")
    table = page.locator("table.data").last
    table.wait_for()
    # default: the first job
    assert page.locator("#cmp-ref").input_value() == flexible
    page.select_option("#cmp-ref", rigid)
    expect(table.locator("caption")).to_contain_text("rigid")
    assert f"ref={rigid}" in page.url
    rigid_row = table.locator("tbody tr", has=page.locator(f'a[href="#/jobs/{rigid}"]'))
    assert "reference" in rigid_row.inner_text()
    flex_row = table.locator("tbody tr", has=page.locator(f'a[href="#/jobs/{flexible}"]'))
    pc = next(r for r in st["tables"]["flexible_vs_rigid"] if r["point"] == "PC"
              and r["direction"] == "z" and r["quantity"] == "sperling")
    expected = f"{100 * pc['relative']:+.1f} %".replace("-", "−")
    assert expected in flex_row.inner_text()


# -- one force convention, running safety ---------------------------------------------------------


def test_forces_use_en14363_names_and_every_wheelset_is_shown(page, server, shot, wait_plot):
    job_id = _seat_job(server)
    summary = server.api(f"/jobs/{job_id}/summary")["summary"]
    page.goto(f"/#/jobs/{job_id}?tab=forces")
    matrix = page.locator("#safety-matrix")
    matrix.wait_for(timeout=60_000)
    heads = matrix.locator("thead th").all_inner_texts()
    assert any(h.startswith("Y/Q left") for h in heads)
    assert any(h.startswith("ΔQ/Q") for h in heads)
    assert any(h.startswith("ΣY") for h in heads)
    assert not any("Q/P" in h or "ΔP/P" in h for h in heads)
    help_text = page.locator("#safety-convention").inner_text()
    assert "Q vertical" in help_text and "GB 5599" in help_text and "Q/P is Y/Q" in help_text
    # every wheelset, on screen without scrolling, the governing value marked
    rows = matrix.locator("tbody tr")
    assert rows.count() == 4
    last = rows.nth(3).bounding_box()
    assert last["y"] + last["height"] <= 800, "wheelset 4 is below the fold"
    worst = max(summary["safety"]["indices"], key=lambda i: i["utilisation"])
    gov = matrix.locator("td.governing")
    assert gov.count() == 1 and "governing" in gov.inner_text()
    assert f"{100 * worst['utilisation']:.0f} %" in gov.inner_text()
    ws = worst["location"].split(".")[0]
    assert ws.replace("wheelset", "wheelset ") in matrix.locator("tr.governing-row").inner_text()
    # the summary card names the same one
    page.get_by_role("tab", name="Summary").click()
    cards = page.locator("#summary-cards").inner_text()
    assert f"at {ws.replace('wheelset', 'wheelset ')}" in cards
    page.get_by_role("tab", name="Forces & safety").click()
    wait_plot(page, "#plot-forces")
    names = page.eval_on_selector("#plot-forces .plot", "e => e.data.map(t => t.name)")
    assert all("vertical wheel force Q" in n for n in names)
    assert page.locator("#force-ws").input_value() == ws  # the governing wheelset first
    page.select_option("#force-dir", "y")
    page.wait_for_function("() => document.querySelector('#plot-forces .plot').data"
                           ".every(t => t.name.includes('lateral wheel force Y'))")
    shot(page, "34-job-forces-safety", full_page=False)


# -- forms and tables -----------------------------------------------------------------------------


def test_new_job_form_name_fix_button_and_job_details(page, server):
    page.console_log.allow(r"status of 422")  # the server's answer to the unstable step
    # the instant estimate of a flexible body not built yet (409) or of a busy service (503)
    page.console_log.allow(r"status of (409|503)")
    page.goto("/#/new?preset=paper-random-straight-80")
    page.locator("#f-speed_kmh").fill("60")
    expect(page.locator("#f-name")).to_have_value("paper-random-straight-60")
    page.fill("#f-duration_s", "1")
    page.fill("#f-distance_m", "")
    page.eval_on_selector('details[data-group="vehicle"]', "d => { d.open = true; }")
    page.select_option("#f-bodies-carbody-model", "flexible")
    expect(page.locator("#f-name")).to_have_value("paper-random-straight-60-flexible")
    page.select_option("#f-bodies-carbody-model", "rigid")
    expect(page.locator("#f-name")).to_have_value("paper-random-straight-60")
    # an unstable step: the fix button, gone once the form is submitted again
    page.eval_on_selector('details[data-group="solver"]', "d => { d.open = true; }")
    page.fill("#f-solver-dt", "0.001")
    page.click("#submit-job")
    page.locator("#use-dt").wait_for(timeout=60_000)
    suggested = re.search(r"= ([\d.e+-]+) s", page.locator("#use-dt").inner_text()).group(1)
    page.fill("#f-solver-dt", suggested)  # typed rather than clicked: Submit must clear the button
    # a name typed by the user stays
    page.fill("#f-name", "my-run")
    page.locator("#f-speed_kmh").fill("70")
    assert page.locator("#f-name").input_value() == "my-run"
    page.click("#submit-job")
    expect(page.locator("#use-dt")).to_have_count(0)
    page.wait_for_url(re.compile(r"#/jobs/[0-9a-f]+$"), timeout=60_000)
    job_id = page.url.rsplit("/", 1)[-1]
    assert server.api(f"/jobs/{job_id}")["preset"] == "paper-random-straight-80"
    page.locator("#job-details summary").click()
    details = page.locator("#job-details")
    expect(details).to_contain_text("Contact model")
    text = details.inner_text()
    assert "paper-random-straight-80" in text
    assert re.search(r"Car body\s+rigid", text) and re.search(r"Bogie frames\s+rigid", text)
    contact = server.api(f"/jobs/{job_id}/scenario")["contact"]
    expected = ("real profiles " + contact["wheel"]["builtin"]
                if contact["geometry"] == "profiles" else "conical tread")
    assert expected in text and "Kalker" in text
    assert "my-run" in page.locator("h1").inner_text()


def test_comfort_table_fits_1280_px_or_shows_a_scroll_cue(page, server):
    job_id = _seat_job(server)
    page.goto(f"/#/jobs/{job_id}")
    wrap = page.locator(".comfort-table")
    wrap.wait_for(timeout=60_000)
    fits = wrap.evaluate("w => w.scrollWidth <= w.clientWidth + 1")
    assert fits, "the comfort table scrolls sideways at 1280 px"
    assert page.locator(".scroll-box:has(.comfort-table) .scroll-cue").is_hidden()
    heads = wrap.locator("thead tr.group-head th").all_inner_texts()
    assert "Vertical (z)" in heads and "Lateral (y)" in heads
    page.set_viewport_size({"width": 900, "height": 800})
    cue = page.locator(".scroll-box:has(.comfort-table) .scroll-cue")
    expect(cue).to_be_visible()
    assert "scroll-x" in (wrap.get_attribute("class") or "")
    page.set_viewport_size({"width": 1280, "height": 800})


@pytest.mark.parametrize("preset", ["paper-metro", "paper-random-curve-60", "paper-settlement-60",
                                    "paper-corrugation-70"])
def test_every_form_field_has_its_unit_and_help(page, server, preset):
    page.goto(f"/#/new?preset={preset}")
    page.locator("#f-speed_kmh").wait_for()
    page.eval_on_selector_all("details[data-group]", "ds => ds.forEach(d => { d.open = true; })")
    fields = page.evaluate("""() => [...document.querySelectorAll('.schema-form .field')].map(f => {
        const input = f.querySelector('input, select, textarea');
        const help = f.querySelector('.help');
        return { id: input?.id || f.dataset.path, help: help ? help.innerText.trim() : '',
                 described: (input?.getAttribute('aria-describedby') || '')
                   .includes(help?.id || '#'),
                 numeric: !!f.querySelector('input[inputmode=decimal], input[inputmode=numeric]'),
                 unit: f.querySelector('.unit')?.innerText || '' }; })""")
    assert len(fields) > 50
    missing = [f["id"] for f in fields if len(f["help"]) < 8]
    assert not missing, f"fields without help: {missing}"
    undescribed = [f["id"] for f in fields if f["help"] and not f["described"]]
    assert not undescribed, f"help not attached (aria-describedby): {undescribed}"
    no_unit = [f["id"] for f in fields if f["numeric"] and not f["unit"]]
    assert not no_unit, f"numbers without unit: {no_unit}"
    speed = next(f for f in fields if f["id"] == "f-speed_kmh")
    assert "≤ 200 km/h" in speed["help"]


def test_fe_build_wait_shows_progress_and_estimate(page, server, coarse_build):
    page.goto(f"/#/flex?element_size_m={coarse_build}")
    # Read the note in the same instant it is seen: a coarse build may end (and the note
    # go) between two separate browser round trips.
    seen = page.wait_for_function(
        """() => {
            const note = document.querySelector('#fe-building');
            return note && {text: note.innerText,
                            bars: note.querySelectorAll('[role=progressbar]').length};
        }""",
        timeout=30_000,
    ).json_value()
    text = seen["text"]
    assert "first time only" in text and re.search(r"\d+(\.\d)? s so far", text)
    if "Waiting for a free worker" not in text:
        assert re.search(r"about (\d+ min )?[\d.]+ s in all", text)
        assert seen["bars"] == 1
    page.wait_for_selector("#plot-mesh .plot[data-state=ready]", timeout=180_000)


@pytest.fixture
def coarse_build(browser_name: str) -> float:
    """An element size (m) of a car body no other test builds (so this one sees the build)."""
    return {"chromium": 0.55, "firefox": 0.6}[browser_name]
