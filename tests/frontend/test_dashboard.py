"""Browser tests of the dashboard (frontend/) against a real ``flexride serve`` with the embedded
runner, in the system's headless Chromium and Firefox (every test in both): submit a short job
from the form and open its results (every plot has data), run a small study and see its
Sperling-against-speed chart, the server's message at an invalid field, compare, the
flexible-body view, the jobs list, empty and error states, keyboard use; no console errors
anywhere (checked by the ``page`` fixture).

The tests of a browser run in file order and share the jobs they create (``state``, one per
browser); each creates what it needs when run alone. Screenshots:
tests/frontend/artifacts/<browser>/.
"""

from __future__ import annotations

import json
import math
import re
from typing import Any

import pytest

try:
    from playwright.sync_api import expect
except ImportError:  # the browser fixture skips these tests (or fails them in CI)
    expect = None

STATES: dict[str, dict[str, Any]] = {}
RUN_S = 5.5  # simulated time: the spectral Sperling index needs at least 5 s


@pytest.fixture
def state(browser_name: str) -> dict[str, Any]:
    """What the earlier tests in this browser created (job, study, the study's jobs)."""
    return STATES.setdefault(browser_name, {})


def goto(page: Any, route: str) -> None:
    page.goto(f"/#{route}")


def open_group(page: Any, group: str) -> None:
    page.eval_on_selector(f'details[data-group="{group}"]', "d => { d.open = true; }")


def finished_job(server: Any, **overrides: Any) -> str:
    """A finished job submitted through the API (for tests run on their own)."""
    ov = {"duration_s": RUN_S, "distance_m": None, **overrides}
    job = server.api("/jobs", {"preset": "paper-random-straight-80", "overrides": ov})
    assert server.wait_job(job["id"])["status"] == "succeeded"
    return job["id"]


# -- first view, empty state ----------------------------------------------------------------------


def test_first_view_is_fast_and_shows_the_empty_state(page, server, shot):
    page.goto("about:blank")  # start the renderer (a browser that is already open)
    times = []
    goto(page, "/")
    for _ in range(2):  # the first visit, then a reload (the machine may be busy once)
        page.wait_for_selector("#jobs-table tbody tr[data-id], .notice-empty", state="visible")
        # time from navigation start until the jobs view is on screen
        times.append(page.evaluate("() => performance.now()"))
        if times[-1] < 1500:
            break
        page.reload()
    assert min(times) < 1500, f"first view took {times} ms"
    assert page.locator("h1").inner_text() == "Jobs and studies"
    if not page.locator("#jobs-table tbody tr").count():
        assert "No jobs here yet" in page.locator(".notice-empty").first.inner_text()
    expect(page.locator("#service-status")).to_contain_text("Service ok")
    shot(page, "01-jobs-empty")


# -- new job: validation ------------------------------------------------------------------------


def test_invalid_field_is_marked_before_and_by_the_server(page, server, shot):
    page.console_log.allow(r"status of 422")  # the server's answer to the invalid scenario
    # the instant estimate while every estimate slot is busy (a note in its panel, by design)
    page.console_log.allow(r"status of 503")
    goto(page, "/new?preset=paper-random-straight-80")
    speed = page.locator("#f-speed_kmh")
    speed.fill("500")
    err = page.locator("#f-speed_kmh-err")
    assert "less than or equal to 200" in err.inner_text()
    assert speed.get_attribute("aria-invalid") == "true"
    assert "1 problem" in page.locator('details[data-group="run"] .group-errors').inner_text()
    # the form refuses to submit and names the problem
    page.click("#submit-job")
    assert "problem" in page.locator("#submit-message").inner_text()
    assert page.url.endswith("/#/new?preset=paper-random-straight-80")
    speed.fill("80")
    assert err.inner_text() == ""
    # a value inside the schema's range that only the server rejects: an unstable time step
    open_group(page, "solver")
    page.fill("#f-solver-dt", "0.001")
    page.click("#submit-job")
    dt_err = page.locator("#f-solver-dt-err")
    dt_err.wait_for(state="visible")
    assert "stability limit" in dt_err.inner_text()
    assert "from-server" in (dt_err.get_attribute("class") or "")
    assert page.locator("#f-solver-dt").get_attribute("aria-invalid") == "true"
    assert "rejected" in page.locator("#submit-message").inner_text()
    shot(page, "02-new-job-server-error", full_page=False)
    # the suggested step (the server's dt_suggested) is one click away, and the button goes
    fix = page.get_by_role("button", name=re.compile(r"Use solver\.dt"))
    suggested = float(re.search(r"= ([\d.e+-]+) s", fix.inner_text()).group(1))
    assert suggested < 1.25e-4
    fix.click()
    assert float(page.locator("#f-solver-dt").input_value()) == suggested
    assert page.locator("#use-dt").count() == 0


def _unit_of(page, field_id):
    """The unit shown beside a form field (None when there is none)."""
    unit = page.locator(f".field:has(#{field_id}) .input-row .unit")
    return unit.inner_text() if unit.count() else None


def test_form_shows_the_units_of_the_schema(page, server):
    """Units come from the schema's ``unit`` (not from parsing descriptions): the slips the
    description parser made are gone."""
    schema = server.api("/schemas/scenario")
    goto(page, "/new?preset=paper-metro")
    page.locator("#f-speed_kmh").wait_for()
    for group in ("vehicle", "track", "output"):
        open_group(page, group)
    expected = {
        "f-bodies-carbody-damping_ratio": "-",       # was "rayleigh"
        "f-track-rail_centre_half_distance": "m",    # was "2b"
        "f-track-fastener-k_roll": "N·m/rad",        # was missing
        "f-track-fastener-c_roll": "N·m·s/rad",      # was missing
        "f-output-rate_hz": "Hz",                    # was missing
        "f-output-floor_grid_spacing_m": "m",        # was missing
    }
    for field_id, unit in expected.items():
        assert _unit_of(page, field_id) == ("–" if unit == "-" else unit), field_id
    assert schema["$defs"]["Fastener"]["properties"]["k_roll"]["unit"] == "N·m/rad"
    legends = page.locator("fieldset.obj > legend").all_inner_texts()
    assert any("Car body" in t for t in legends) and any("bogie frames" in t for t in legends)


def test_yaml_editor_reads_a_preset_based_file(page, server):
    goto(page, "/new")
    # the form is built from the schema: click the tab once it is (timed out once in a full
    # run in Firefox, the editor not shown)
    page.locator("#f-speed_kmh").wait_for()
    page.get_by_role("tab", name="YAML / JSON").click()
    page.locator("#scenario-text").wait_for(state="visible")
    page.fill(
        "#scenario-text",
        "preset: paper-random-straight-60\nduration_s: 2\ndistance_m: null\n"
        "excitation:\n  - kind: settlement\n    depth_m: 0.05\n",
    )
    page.get_by_role("button", name="Apply to form").click()
    expect(page.locator("#f-speed_kmh")).to_have_value("60")
    assert page.locator("#f-duration_s").input_value() == "2"
    open_group(page, "excitation")
    assert page.locator("#f-excitation-0-kind").input_value() == "settlement"
    assert page.locator("#f-excitation-0-depth_m").input_value() == "0.05"


# -- new job: submit, follow, results -----------------------------------------------------------


def test_submit_job_from_form_and_see_every_result(
    page, state, server, shot, wait_plot, download
):
    goto(page, "/new?preset=paper-random-straight-80")
    page.fill("#f-name", "ui-job")
    page.fill("#f-duration_s", str(RUN_S))
    page.fill("#f-distance_m", "")
    open_group(page, "output")
    page.fill("#f-output-floor_grid_spacing_m", "2")  # for the comfort map
    page.click("#submit-job")
    page.wait_for_url(re.compile(r"#/jobs/[0-9a-f]+$"))
    job_id = page.url.rsplit("/", 1)[-1]
    state["job"] = job_id
    # live progress while it runs, then the results (first job: numba compiles the kernels)
    page.wait_for_selector("#summary-cards", timeout=150_000)
    assert "succeeded" in page.locator("h1").inner_text()
    cards = page.locator("#summary-cards").inner_text()
    assert "Sperling vertical (PC)" in cards and "spectral form" in cards
    assert re.search(r"(excellent|good|qualified|fails)", cards)
    assert page.locator("table.data tbody tr").count() >= 6
    shot(page, "03-job-summary")

    page.get_by_role("tab", name="Time histories").click()
    n_full = wait_plot(page, "#plot-time")
    shot(page, "04-job-time")
    # zoom: the server decimates the visible range again
    with page.expect_response(lambda r: "/series" in r.url and "t_start" in r.url) as resp:
        page.eval_on_selector(
            "#plot-time .plot", "e => Plotly.relayout(e, {'xaxis.range': [1, 1.5]})"
        )
    assert resp.value.ok
    page.wait_for_function(
        "() => { const d = document.querySelector('#plot-time .plot').data; "
        "return d && d[0].x[0] >= 0.99 && d[0].x[d[0].x.length - 1] <= 1.51; }"
    )
    assert 0 < wait_plot(page, "#plot-time") <= n_full
    # CSV of the plotted data and PNG export
    time_plot = page.locator("#plot-time")
    name, csv = download(page, time_plot.get_by_role("button", name="CSV", exact=True).click)
    assert name.endswith(".csv")
    text = csv.decode()
    assert text.startswith("series,time (s),value,unit") and text.count("\n") > 100
    name, png = download(page, time_plot.get_by_role("button", name="PNG", exact=True).click)
    assert name.endswith(".png")
    assert png.startswith(b"\x89PNG\r\n\x1a\n")

    page.get_by_role("tab", name="Spectra").click()
    wait_plot(page, "#plot-spectrum")
    wait_plot(page, "#plot-psd")
    assert "Hz" in page.locator("#plot-spectrum .plot-note").inner_text()
    n_ann = page.eval_on_selector(
        "#plot-spectrum .plot", "e => (e.layout.annotations || []).length"
    )
    assert n_ann > 0, "dominant peaks are labelled"
    name, svg = download(
        page, page.locator("#plot-psd").get_by_role("button", name="SVG", exact=True).click
    )
    assert name.endswith(".svg")
    assert b"<svg" in svg[:200]
    shot(page, "05-job-spectra")

    page.get_by_role("tab", name="Spectrogram").click()
    wait_plot(page, "#plot-spectrogram")
    shot(page, "06-job-spectrogram")

    page.get_by_role("tab", name="Sperling").click()
    wait_plot(page, "#plot-sperling")

    page.get_by_role("tab", name="Correlation").click()
    wait_plot(page, "#plot-correlation")
    note = page.locator("#plot-correlation .plot-note").inner_text()
    assert re.search(r"Maximum [-\d.]+ at τ = [-\d.e]+ s", note)
    shapes = page.eval_on_selector("#plot-correlation .plot", "e => e.layout.shapes.length")
    assert shapes == 1, "the lag of the maximum is marked"
    shot(page, "07-job-correlation")

    page.get_by_role("tab", name="Forces & safety").click()
    wait_plot(page, "#plot-forces")
    assert "Force (kN)" in page.eval_on_selector(
        "#plot-forces .plot", "e => e.layout.yaxis.title.text"
    )
    assert page.locator("#safety-matrix tbody tr").count() == 4  # every wheelset
    assert "passed" in page.locator("#safety-result").inner_text()
    shot(page, "08-job-forces")

    # the HDF5 download
    href = page.get_by_role("link", name="Download HDF5").get_attribute("href")
    r = page.request.get(href)
    assert r.ok and r.body()[:8] == b"\x89HDF\r\n\x1a\n"


def test_failed_job_shows_its_reason(page, server, shot):
    job = server.api(
        "/jobs",
        {
            "preset": "paper-random-straight-80",
            "overrides": {
                "duration_s": 1.0,
                "distance_m": None,
                "solver.runaway_displacement_m": 1e-6,
            },
        },
    )
    goto(page, f"/jobs/{job['id']}")
    page.wait_for_selector("#job-error", timeout=60_000)
    assert "diverged" in page.locator("#job-error").inner_text()
    assert "failed" in page.locator("h1").inner_text()
    shot(page, "09-job-failed", full_page=False)


# -- jobs list ------------------------------------------------------------------------------------


def test_jobs_list_filters_and_follows_progress(page, state, server, shot):
    job_id = state.get("job") or finished_job(server)
    goto(page, "/")
    row = page.locator(f'#jobs-table tr[data-id="{job_id}"]')
    row.wait_for()
    assert "succeeded" in row.inner_text()
    assert row.locator('[role="progressbar"]').get_attribute("aria-valuenow") == "100"
    page.select_option("#filter-status", "failed")
    page.wait_for_function(
        "() => [...document.querySelectorAll('#jobs-table tbody tr')]"
        ".every(r => r.innerText.includes('failed'))"
    )
    assert row.count() == 0
    page.select_option("#filter-status", "")
    row.wait_for()
    page.fill("#filter-text", "no-such-job-name")
    assert not row.is_visible()
    page.fill("#filter-text", "")
    # a new job appears and its progress is followed without reloading
    job = server.api(
        "/jobs",
        {
            "preset": "paper-random-straight-70",
            "overrides": {"duration_s": 2.0, "distance_m": None},
        },
    )
    new_row = page.locator(f'#jobs-table tr[data-id="{job["id"]}"]')
    new_row.wait_for(timeout=15_000)
    new_row.locator(".badge.st-succeeded").wait_for(timeout=60_000)
    shot(page, "10-jobs-list")
    # delete asks once more, then removes the row
    new_row.get_by_role("button", name="Delete").click()
    new_row.get_by_role("button", name="Confirm delete").click()
    new_row.wait_for(state="detached")


# -- study ----------------------------------------------------------------------------------------


def test_study_presets_fill_the_form_and_count_jobs(page, server):
    goto(page, "/studies/new")
    page.get_by_role("button", name="Fill the form with paper-table3", exact=True).click()
    assert page.locator("#study-count").inner_text() == "16"
    page.get_by_role("button", name="Fill the form with paper-table2", exact=True).click()
    assert page.locator("#study-count").inner_text() == "2"
    page.get_by_role("button", name="Add parameter").click()
    page.fill("#param-path-0", "vehicle.secondary.kz")
    page.fill("#param-values-0", "300000, 400000, 500000")
    assert page.locator("#study-count").inner_text() == "6"
    assert "(N/m)" in page.locator("#study-params").inner_text()
    page.fill("#study-speeds", "80, 300")
    page.click("#submit-study")
    assert "outside the allowed range" in page.locator("#study-speeds-err").inner_text()


def test_small_study_shows_sperling_against_speed(page, state, server, shot, wait_plot):
    goto(page, "/studies/new")
    page.fill("#study-name", "ui-study")
    page.select_option("#study-base", "paper-random-straight-80")
    page.fill("#study-speeds", "60, 80")
    page.fill("#study-duration", str(RUN_S))
    assert page.locator("#study-count").inner_text() == "2"
    shot(page, "11-new-study", full_page=False)
    page.click("#submit-study")
    page.wait_for_url(re.compile(r"#/studies/[0-9a-f]+$"))
    state["study"] = page.url.rsplit("/", 1)[-1]
    page.locator(".page-head .badge.st-succeeded").wait_for(timeout=120_000)
    n = wait_plot(page, "#plot-sperling-speed")
    assert n >= 2 * 6, "two speeds at six points"
    xs = page.eval_on_selector("#plot-sperling-speed .plot", "e => e.data[0].x")
    assert sorted(xs) == [60, 80]
    shot(page, "12-study-sperling")
    page.get_by_role("tab", name="Peak vs speed").click()
    wait_plot(page, "#plot-peak-speed")
    assert "R²" in page.locator("#panel-peak").inner_text()
    page.get_by_role("tab", name="Flexible vs rigid").click()
    assert "no rigid-against-flexible axis" in page.locator("#panel-flexrigid").inner_text()
    page.get_by_role("tab", name="Jobs and indices").click()
    rows = page.locator("#panel-jobs table.data tbody tr")
    assert rows.count() == 2
    state["study_jobs"] = [
        h.split("/")[-1]
        for h in rows.locator("a").evaluate_all("as => as.map(a => a.getAttribute('href'))")
    ]
    shot(page, "13-study-jobs")
    # keyboard: Enter on a row opens its job
    rows.first.focus()
    page.keyboard.press("Enter")
    page.wait_for_url(re.compile(r"#/jobs/[0-9a-f]+$"))


# -- compare --------------------------------------------------------------------------------------


def test_compare_overlays_jobs_in_time_and_frequency(page, state, server, shot, wait_plot):
    jobs = state.get("study_jobs") or [
        finished_job(server, speed_kmh=60),
        finished_job(server, speed_kmh=80),
    ]
    goto(page, f"/compare?jobs={','.join(jobs[:2])}&channel=carbody.PC.acc.z")
    wait_plot(page, "#plot-compare-time")
    assert page.eval_on_selector("#plot-compare-time .plot", "e => e.data.length") == 2
    wait_plot(page, "#plot-compare-spectrum")
    wait_plot(page, "#plot-compare-psd")
    page.select_option("#cmp-channel", "carbody.PR.acc.y")
    page.wait_for_function(
        "() => document.querySelector('#plot-compare-time .plot').data"
        ".every(t => t.name && true) && location.hash.includes('PR.acc.y')"
    )
    table = page.locator("table.data").last
    table.wait_for()
    assert "Sperling" in table.inner_text() and table.locator("tbody tr").count() == 2
    shot(page, "14-compare")


# -- flexible body --------------------------------------------------------------------------------


def _tube_mesh() -> dict:
    """A small box-section tube with two mode shapes, in the export_mesh shape."""
    xs = [-9 + 3 * i for i in range(7)]
    ring = [
        (-1.4, 1.1),
        (0, 1.1),
        (1.4, 1.1),
        (1.4, 2.4),
        (1.4, 3.7),
        (0, 3.7),
        (-1.4, 3.7),
        (-1.4, 2.4),
    ]
    nodes = [[x, y, z] for x in xs for (y, z) in ring]
    m = len(ring)
    quads = [
        [i * m + j, (i + 1) * m + j, (i + 1) * m + (j + 1) % m, i * m + (j + 1) % m]
        for i in range(len(xs) - 1)
        for j in range(m)
    ]
    bend = [[0.0, 0.0, round(math.sin(math.pi * (x + 9) / 18), 4)] for x, _, _ in nodes]
    twist = [
        [0.0, round(-(z - 2.4) * x / 9 / 1.3, 4), round(y * x / 9 / 1.4, 4)] for x, y, z in nodes
    ]
    return {
        "units": {"length": "m", "frequency": "Hz"},
        "nodes": nodes,
        "quads": quads,
        "beams": [],
        "modes": [
            {
                "index": 1,
                "frequency_hz": 9.8,
                "classification": "first vertical bending",
                "scale_m": 0.01,
                "displacements": bend,
            },
            {
                "index": 2,
                "frequency_hz": 12.1,
                "classification": "torsion",
                "scale_m": 0.01,
                "displacements": twist,
            },
        ],
    }


#: Element size (m) of a coarse car body per browser (0.5 m: 868 nodes, 0.45 m: 1198 nodes), built
#: in a few seconds, long enough to see the view's "building" state (the server answers 202
#: after waiting 3 s for a build). Each browser gets its own: the server serves a model that the
#: other browser's tests built at once, without that state.
COARSE = {"chromium": 0.5, "firefox": 0.45}


@pytest.fixture
def coarse(browser_name: str) -> float:
    """The element size (m) of the coarse car body this browser's tests build."""
    return COARSE[browser_name]


def test_flexible_body_view_builds_and_draws_the_car_body(page, server, shot, wait_plot, coarse):
    goto(page, f"/flex?element_size_m={coarse}")
    # the server builds the model (202): the view says so and asks again
    building = page.locator("#fe-building")
    building.wait_for(timeout=30_000)
    assert "Building the FE model" in page.locator("main").inner_text()
    assert "first time only" in page.locator("main").inner_text()
    n = wait_plot(page, "#plot-mesh", timeout=180_000)
    # drawn with WebGL (where a browser has none, Plotly shows its "not supported" box instead)
    assert page.locator("#plot-mesh .no-webgl").count() == 0, "no WebGL in this browser"
    assert page.locator("#plot-mesh .gl-container canvas").count() >= 1
    exported = server.api(f"/fe/carbody?element_size_m={coarse}")
    assert n >= len(exported["nodes"]) > 100
    modes = page.locator(".mode-list button")
    assert modes.count() == len(exported["modes"]) == 12
    f1 = exported["modes"][0]["frequency_hz"]
    assert f"{f1:.3g}" in modes.first.inner_text() and "Hz" in modes.first.inner_text()
    info = page.locator("#fe-model-info").inner_text()
    assert "modal reduction" in info and f"element size {coarse} m" in info
    # each mode with its expected discretisation error, from the build's coarser companion
    disc = exported["model"]["discretisation"]
    assert f"against a {disc['companion_element_size_m']:g} m companion mesh" in info
    g1 = disc["modes"][0]["gci"]
    assert f"±{100 * g1:.1f} %" in modes.first.inner_text()
    assert page.locator("#fe-element-size").input_value() == str(coarse)
    assert not building.is_visible()
    modes.nth(1).click()
    assert "Mode 2:" in page.locator("#plot-mesh .plot-note").inner_text()
    shot(page, "15-flexible-body")


def test_flexible_body_pairs_its_modes_with_calibration_targets(page, server, shot, wait_plot,
                                                                coarse):
    """Targets in the address are paired once the model is drawn, as GET /fe/carbody/pairing
    pairs them (the table row by row; an unpaired target's reason beside it); a type that
    does not exist is refused at the field with the allowed names."""
    from urllib.parse import quote

    page.console_log.allow(r"status of 422")  # the service refuses the unknown type
    targets = "5.0,6.2,9:rhombic,20:third lateral bending"
    goto(page, f"/flex?element_size_m={coarse}&targets={quote(targets)}")
    wait_plot(page, "#plot-mesh", timeout=180_000)
    rows = page.locator("#fe-pairing table tbody tr")
    rows.first.wait_for(timeout=30_000)
    answer = server.api(f"/fe/carbody/pairing?element_size_m={coarse}&max_modes=12"
                        f"&targets={quote(targets)}")
    assert rows.count() == len(answer["pairs"]) == 4
    for k, pair in enumerate(answer["pairs"]):
        cells = rows.nth(k).locator("th, td").all_inner_texts()
        assert cells[2] == ("none" if pair["mode"] is None else str(pair["mode"]))
        if pair["model_hz"] is not None:
            assert f"{pair['model_hz']:.4g}" in cells[3]
    missing = answer["pairs"][3]
    assert missing["mode"] is None  # no lateral bending of third order among 12 modes
    assert missing["message"] in page.locator("#fe-pairing").inner_text()
    page.locator("#fe-pairing").scroll_into_view_if_needed()
    shot(page, "15b-flexible-body-pairing", full_page=False)
    page.fill("#fe-targets", "5:twisting")
    page.click("#fe-pair")
    page.locator("#fe-targets-err").wait_for(state="visible")
    assert "torsion" in page.locator("#fe-targets-err").inner_text()
    assert page.get_attribute("#fe-targets", "aria-invalid") == "true"
    assert "twisting" in page.url  # the targets are kept in the address


def test_flexible_body_builds_the_car_body_calibrated_to_the_targets(page, server, wait_plot,
                                                                    coarse):
    """"Build calibrated" asks for the car body calibrated to the targets typed in (GET
    /fe/carbody?calibration_targets=…, a job on the server): the view says to what it was
    calibrated and how well, and pairs the calibrated model's modes; the address keeps it; an
    unknown type is refused at the targets' field."""
    from urllib.parse import quote

    page.console_log.allow(r"status of 422")  # the service refuses the unknown type
    targets = "6.5:rhombic,5.59"
    goto(page, f"/flex?element_size_m={coarse}&targets={quote(targets)}")
    wait_plot(page, "#plot-mesh", timeout=180_000)
    page.locator("#fe-pairing table tbody tr").first.wait_for(timeout=30_000)
    assert "default car body" in page.locator("#fe-calibration").inner_text()
    page.click("#fe-calibrate")
    done = page.locator("#fe-calibration", has_text="Calibrated car body")
    done.wait_for(timeout=240_000)
    query = (f"element_size_m={coarse}&max_modes=12&calibration_targets={quote(targets)}")
    model = server.api(f"/fe/carbody?{query}")["model"]
    cal = model["calibration"]
    text = done.inner_text()
    assert f"to {cal['targets']}" in text and f"{cal['n_evaluations']} of at most 30" in text
    for pair in cal["pairs"]:
        assert f"mode {pair['mode']} {pair['model_hz']:.4g} Hz" in text
    assert "calibrated car body model" in page.locator("#fe-model-info").inner_text()
    assert "calibrate=" in page.url
    # the pairing card shows the calibrated model's pairing
    answer = server.api(f"/fe/carbody/pairing?{query}&targets={quote(targets)}")
    assert answer["model"]["key"] == model["key"]
    rows = page.locator("#fe-pairing table tbody tr")
    page.wait_for_function(
        "([sel, want]) => [...document.querySelectorAll(sel)].map((r) => r.cells[3]?.innerText)"
        ".join('|') === want",
        arg=["#fe-pairing table tbody tr",
             "|".join(f"{p['model_hz']:.4g}" for p in answer["pairs"])], timeout=30_000)
    assert rows.count() == len(answer["pairs"]) == 2
    page.fill("#fe-targets", "5:twisting")
    page.click("#fe-calibrate")
    page.locator("#fe-targets-err").wait_for(state="visible")
    assert "twisting" in page.locator("#fe-targets-err").inner_text()
    assert page.get_attribute("#fe-targets", "aria-invalid") == "true"


def test_flexible_body_of_a_job_is_that_jobs_model(page, server, wait_plot):
    job = server.api("/jobs", {"preset": "paper-random-straight-80", "reuse": False, "overrides": {
        "duration_s": 0.5, "distance_m": None, "bodies.carbody.model": "flexible",
        "bodies.carbody.element_size_m": 0.5, "bodies.carbody.cutoff_hz": 30.0}})
    goto(page, f"/flex?job={job['id']}")
    wait_plot(page, "#plot-mesh", timeout=180_000)
    info = page.locator("#fe-model-info").inner_text()
    assert f"of job {job['id'][:8]}" in info and "cut-off 30 Hz" in info
    # the job's own parameters, not editable here
    assert page.locator("#fe-cutoff").input_value() == "30"
    assert page.locator("#fe-cutoff").is_disabled()
    assert server.wait_job(job["id"], timeout=240)["status"] == "succeeded"


def test_flexible_body_mesh_file_and_comfort_map(
    page, state, server, shot, wait_plot, tmp_path, coarse
):
    job_id = state.get("job") or finished_job(server, **{"output.floor_grid_spacing_m": 2.0})
    mesh = tmp_path / "tube.json"
    mesh.write_text(json.dumps(_tube_mesh()))
    goto(page, f"/flex?job={job_id}&element_size_m={coarse}")
    wait_plot(page, "#plot-mesh", timeout=180_000)  # the service's model first
    assert "models the car body as rigid" in page.locator("#fe-model-info").inner_text()
    # a mesh file replaces it
    page.set_input_files("#mesh-file", str(mesh))
    page.get_by_text("tube.json:").wait_for()
    assert wait_plot(page, "#plot-mesh") >= len(_tube_mesh()["nodes"])
    modes = page.locator(".mode-list button")
    assert modes.count() == 2 and "9.8 Hz" in modes.first.inner_text()
    modes.nth(1).click()
    assert modes.nth(1).get_attribute("aria-pressed") == "true"
    assert "12.1 Hz" in page.locator("#plot-mesh .plot-note").inner_text()
    z0 = page.eval_on_selector("#plot-mesh .plot", "e => e.data[0].z.slice()")
    page.check("#mode-animate")
    page.wait_for_timeout(400)
    z1 = page.eval_on_selector("#plot-mesh .plot", "e => e.data[0].z.slice()")
    page.uncheck("#mode-animate")
    assert z0 != z1, "the animation moves the mesh"
    # the comfort map: floor-grid points where the channel list places them
    n = wait_plot(page, "#plot-comfort-map")
    assert n >= 20, "a 2 m floor grid has 20 points"
    heat = page.eval_on_selector("#plot-comfort-map .plot", "e => [e.data[0].x, e.data[0].y]")
    assert heat == [[-9 + 2 * i for i in range(10)], [-1.2, 1.2]]
    marks = page.eval_on_selector("#plot-comfort-map .plot",
                                  "e => e.data[1].x.map((x, i) => [x, e.data[1].y[i]])")
    assert [6.3, 0] in marks and [-6.3, 0.95] in marks  # PFB and PLA
    assert "largest at F" in page.locator("#plot-comfort-map .plot-note").inner_text()
    shot(page, "15b-flexible-body-file-and-comfort-map")


# -- errors, keyboard -----------------------------------------------------------------------------


def test_server_down_shows_a_banner_and_recovers(page, server, shot):
    page.console_log.allow(r"net::ERR_FAILED|Failed to load resource")
    goto(page, "/")
    page.wait_for_selector("#jobs-table, .notice-empty")
    page.route("**/api/v1/**", lambda route: route.abort())
    page.evaluate("() => { location.hash = '#/studies/new'; }")
    banner = page.locator("#banner")
    banner.wait_for(state="visible")
    assert "cannot be reached" in banner.inner_text()
    assert "flexride serve" in page.locator("main").inner_text()
    shot(page, "16-server-down", full_page=False)
    page.unroute("**/api/v1/**")
    page.get_by_role("button", name="Retry now").click()
    banner.wait_for(state="hidden")
    page.wait_for_selector("#study-count")


def test_keyboard_navigation(page, server):
    goto(page, "/")
    page.wait_for_selector("#jobs-table, .notice-empty")
    page.keyboard.press("Tab")
    assert page.evaluate("() => document.activeElement.className") == "skip-link"
    page.keyboard.press("Tab")
    page.keyboard.press("Tab")
    assert page.evaluate("() => document.activeElement.textContent") == "Jobs & studies"
    page.keyboard.press("Tab")
    page.keyboard.press("Enter")
    page.wait_for_url(re.compile(r"#/new$"))
    page.wait_for_selector("#f-speed_kmh")
    # focus moves to the page heading; the scenario tabs work with the arrow keys
    assert page.evaluate("() => document.activeElement.tagName") == "H1"
    page.get_by_role("tab", name="Form").focus()
    page.keyboard.press("ArrowRight")
    assert page.evaluate("() => document.activeElement.id") == "tab-text"
    assert page.locator("#scenario-text").is_visible()
    # every form control has a label
    unlabeled = page.evaluate("""() => [...document.querySelectorAll('input, select, textarea')]
        .filter(e => e.type !== 'hidden' && !e.labels?.length && !e.getAttribute('aria-label'))
        .map(e => e.id || e.outerHTML.slice(0, 60))""")
    assert unlabeled == []


def test_views_fit_a_laptop_screen(page, server, coarse):
    page.set_viewport_size({"width": 1280, "height": 800})
    # (a coarse car body on /flex: the one the flexible-body tests built)
    for route in ["/", "/new", "/studies/new", "/compare", f"/flex?element_size_m={coarse}"]:
        goto(page, route)
        page.wait_for_selector("h1")
        page.wait_for_timeout(150)
        overflow = page.evaluate("() => document.documentElement.scrollWidth - window.innerWidth")
        assert overflow <= 0, f"{route}: horizontal overflow of {overflow} px"
