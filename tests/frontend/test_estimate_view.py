"""Browser tests of the frequency-domain estimate in the dashboard against a real ``flexride
serve``, in Chromium and Firefox (fixtures of tests/frontend/conftest.py): the instant-estimate
panel of the new-job view (numbers for the default preset, asked again once after the speed is
typed, a refusal as a note and never a form error or a 4xx) and the sweep view ``#/estimate`` (a
curve with the requested number of values, refused values marked, redrawn without asking again;
the heatmap over the floor grid with the paper's points); no console errors (checked by the
``page`` fixture).
"""

from __future__ import annotations

import re
from typing import Any

PRESET = "paper-random-straight-80"


def _estimate_posts(page: Any) -> list[str]:
    """A list that collects the page's POST /api/v1/estimates requests from now on."""
    seen: list[str] = []
    page.on("request", lambda r: seen.append(r.url)
            if r.method == "POST" and r.url.endswith("/api/v1/estimates") else None)
    return seen


def _settled(page: Any, timeout: float = 90_000) -> str:
    """Wait until the panel has an answer (or a note); its state (``ready``, ``refused`` …)."""
    page.wait_for_function("() => ['ready', 'refused', 'error'].includes("
                           "document.querySelector('#estimate-panel')?.dataset.state)",
                           timeout=timeout)
    return page.get_attribute("#estimate-panel", "data-state")


def _cell(page: Any, point: str, column: int) -> str:
    return page.locator(f'#estimate-table tr[data-point="{point}"] td').nth(column).inner_text()


def test_instant_estimate_shows_the_default_preset_and_follows_the_speed(page, server, shot):
    page.goto(f"/#/new?preset={PRESET}")
    state = _settled(page)
    assert state == "ready", page.locator("#estimate-panel").inner_text()
    api = server.api("/estimates", {"preset": PRESET})["comfort"]
    rows = page.locator("#estimate-table tbody tr")
    assert rows.count() == len(api["points"]) == 6
    heads = page.locator("#estimate-table thead th").all_inner_texts()
    assert all(re.search(r"\((m/s²|–)\)$", t) for t in heads[1:]), heads  # a unit on every column
    pc = next(p for p in api["points"] if p["name"] == "PC")
    assert _cell(page, "PC", 4) == f"{pc['directions']['z']['sperling']:.2f}"
    assert _cell(page, "PC", 5) == f"{pc['directions']['y']['sperling']:.2f}"
    assert _cell(page, "PC", 6) == f"{pc['nmv']:.2f}"
    assert page.locator("#estimate-method").inner_text().startswith("Method: frequency domain")
    flags = page.locator("#estimate-flags").inner_text()
    assert (str(len(api["flags"])) in flags) if api["flags"] else flags.startswith("No flags")
    assert page.get_attribute("#estimate-panel", "data-speed") == "80"
    shot(page, "21-new-job-instant-estimate", full_page=False)
    # typing a new speed: one request after the typing stops (debounced), the table follows
    posts = _estimate_posts(page)
    before = _cell(page, "PC", 4)
    page.fill("#f-speed_kmh", "")
    page.type("#f-speed_kmh", "60", delay=60)
    page.wait_for_selector('#estimate-panel[data-speed="60"][data-state=ready]', timeout=30_000)
    assert len(posts) == 1  # not one per keystroke
    assert _cell(page, "PC", 4) != before
    assert "60 km/h" in page.locator("#estimate-status").inner_text()
    # never a form error
    assert page.locator("#f-speed_kmh").get_attribute("aria-invalid") is None
    # a value the form marks: the panel waits for it, without asking
    page.fill("#f-speed_kmh", "500")
    page.wait_for_selector("#estimate-panel[data-state=waiting]")
    assert "1 field marked" in page.locator("#estimate-note").inner_text()
    assert len(posts) == 1


def _estimate_statuses(page: Any) -> list[int]:
    """A list that collects the statuses of the page's POST /api/v1/estimates from now on."""
    seen: list[int] = []
    page.on("response", lambda r: seen.append(r.status)
            if r.request.method == "POST" and r.url.endswith("/api/v1/estimates") else None)
    return seen


def test_instant_estimate_refusal_is_a_note_not_a_form_error(page, server, shot):
    """The service says whether the estimate applies (``refusal: "answer"``: 200 with
    ``applicable: false``), so a refusal is no 4xx in the console (the ``page`` fixture)."""
    statuses = _estimate_statuses(page)
    page.goto("/#/new?preset=paper-random-curve-80")
    assert _settled(page) == "refused", page.locator("#estimate-panel").inner_text()
    note = page.locator("#estimate-note").inner_text()
    assert note.startswith("No linear estimate:") and "flange contact" in note
    assert page.locator("#estimate-table").count() == 0
    assert page.locator("[aria-invalid=true]").count() == 0
    assert all(t == "" for t in page.locator(".field-error.from-server").all_inner_texts())
    assert page.locator("#submit-message").inner_text() == ""
    shot(page, "22-new-job-estimate-refused", full_page=False)
    # a scenario without a random irregularity: the service's reason, at its excitation
    for name, words in (("paper-settlement-60", "settlement excitation"),
                        ("paper-metro", "no random irregularity")):
        page.select_option("#preset-select", name)
        page.get_by_role("button", name="Load preset").click()
        page.wait_for_function("w => document.querySelector('#estimate-note')?.textContent"
                               ".includes(w)", arg=words, timeout=60_000)
        note = page.locator("#estimate-note").inner_text()
        assert note.startswith("No linear estimate:"), note
    assert statuses and not any(400 <= s < 500 for s in statuses), statuses


def test_sweep_view_draws_the_requested_values(page, server, shot, wait_plot):
    page.goto("/#/")
    page.get_by_role("link", name="Estimate").click()
    page.wait_for_url(re.compile(r"#/estimate"))
    wait_plot(page, "#plot-estimate-sweep", timeout=90_000)  # a fresh server's first model
    assert page.locator('[data-nav="estimate"]').get_attribute("aria-current") == "page"
    page.fill("#est-parameter", "vehicle.primary.ky")
    page.fill("#est-from", "1000")
    page.fill("#est-to", "1000000")
    page.fill("#est-count", "7")
    posts = _estimate_posts(page)
    with page.expect_response(lambda r: r.url.endswith("/api/v1/estimates")
                              and r.request.method == "POST", timeout=120_000) as answered:
        page.click("#est-apply")
    answer = answered.value.json()
    page.wait_for_function("() => document.querySelector('#plot-estimate-sweep .plot')"
                           ".data?.[0]?.x?.length === 7", timeout=60_000)
    x, y, text = page.eval_on_selector("#plot-estimate-sweep .plot",
                                       "e => [e.data[0].x, e.data[0].y, e.data[0].text]")
    assert x[0] == 1000 and x[-1] == 1000000 and len(y) == 7
    assert all(re.match(r"(no flags|1 flag:|\d+ flags:)", t) for t in text), text
    # the values the service refused (1000 N/m of lateral primary stiffness hunts, and the
    # soft end near the stability limit) are gaps on the line, marked with ×, and counted
    refused_at = [r["value"] for r in answer["refused"]]
    assert 1000 in refused_at and len(refused_at) < 7
    assert [v is None for v in y] == [v in refused_at for v in x]
    refused = page.eval_on_selector("#plot-estimate-sweep .plot", "e => e.data[1].x")
    assert refused == refused_at
    assert f"{len(refused_at)} refused" in page.locator(
        "#plot-estimate-sweep .plot-note").inner_text()
    titles = page.eval_on_selector("#plot-estimate-sweep .plot",
                                   "e => [e.layout.xaxis.title.text, e.layout.yaxis.title.text]")
    assert titles[0] == "vehicle.primary.ky (N/m)" and titles[1].endswith("(–)"), titles
    shot(page, "23-estimate-sweep")
    # another index and point: drawn from the same answer
    n_posts = len(posts)
    page.select_option("#est-index", "rms")
    page.select_option("#est-point", "PR")
    page.wait_for_function("() => document.querySelector('#plot-estimate-sweep .plot')"
                           ".layout.yaxis.title.text.endsWith('(m/s²)')")
    assert "at PR" in page.eval_on_selector("#plot-estimate-sweep .plot", "e => e.data[0].name")
    page.wait_for_timeout(500)
    assert len(posts) == n_posts
    assert "count=7" in page.url and "point=PR" in page.url


def test_sweep_view_checks_the_values_and_shows_the_servers_message_at_its_field(page, server):
    page.console_log.allow(r"status of 422")  # the service refuses the unknown field
    page.goto("/#/estimate?count=5")
    page.wait_for_selector("#plot-estimate-sweep .plot[data-state=ready]", timeout=90_000)
    posts = _estimate_posts(page)
    page.fill("#est-count", "101")
    page.click("#est-apply")
    assert "1 to 100" in page.locator("#est-count-err").inner_text()
    assert page.locator("#est-count").get_attribute("aria-invalid") == "true"
    page.wait_for_timeout(600)
    assert posts == []
    # the service's 422 at its field: an unknown parameter, a value out of range of an override
    page.fill("#est-count", "5")
    page.fill("#est-parameter", "vehicle.secondary.nonsense")
    page.click("#est-apply")
    err = page.locator("#est-parameter-err")
    err.wait_for(state="visible")
    assert "not a field of the scenario" in err.inner_text()
    assert page.locator("#est-count-err").inner_text() == ""
    page.fill("#est-parameter", "vehicle.secondary.cz")
    page.fill("#est-overrides", "vehicle.secondary.kz: -5")
    page.click("#est-apply")
    page.locator("#est-overrides-err").wait_for(state="visible")
    assert "greater than or equal to 0" in page.locator("#est-overrides-err").inner_text()
    assert page.locator("#est-parameter-err").inner_text() == ""


def test_floor_map_is_a_heatmap_with_the_paper_points(page, server, shot, wait_plot):
    page.console_log.allow(r"status of 422")  # the service refuses a grid beyond its limit
    page.goto("/#/estimate?count=3")
    wait_plot(page, "#plot-floor-map", timeout=90_000)
    api = server.api("/estimates", {"preset": PRESET, "overrides": {}, "points": ["PC"],
                                    "floor_map": {"spacing_m": 1.0}})["floor_map"]
    data = page.eval_on_selector("#plot-floor-map .plot", "e => e.data.map(t => ({type: t.type,"
                                 " x: t.x, y: t.y, z: t.z, text: t.text}))")
    heat, marks = data
    assert heat["type"] == "heatmap" and heat["x"] == api["x_m"] and heat["y"] == api["y_m"]
    assert len(heat["x"]) == 19 and len(heat["y"]) == 3
    assert heat["z"] == api["indices"]["z"]["sperling"]
    assert marks["text"] == ["PFB", "PC", "PRB", "PLA", "PRA"]  # the paper's floor points
    assert [marks["x"][3], marks["y"][3]] == [-6.3, 0.95]  # PLA: rear bogie, left air spring
    axes = page.eval_on_selector("#plot-floor-map .plot", "e => [e.layout.xaxis.title.text,"
                                 " e.layout.yaxis.title.text]")
    assert axes[0].startswith("Position along the car body x (m") and "(m, left +)" in axes[1]
    shot(page, "24-estimate-floor-map")
    # another index from the same answer
    page.select_option("#floor-index", "awy")
    page.wait_for_function("() => document.querySelector('#plot-floor-map .plot-note')"
                           ".textContent.startsWith('ISO 2631 a_w lateral (y) (Wd)')")
    z = page.eval_on_selector("#plot-floor-map .plot", "e => e.data[0].z")
    assert z == api["indices"]["y"]["iso2631"]
    # a grid beyond the service's limit: its message at the spacing; a coarser one redraws
    page.fill("#floor-spacing", "")  # Firefox: fill alone may keep the number there
    page.fill("#floor-spacing", "0.3")
    page.press("#floor-spacing", "Enter")
    page.locator("#floor-spacing-err").wait_for(state="visible")
    assert "0.5 m fits" in page.locator("#floor-spacing-err").inner_text()
    assert page.get_attribute("#floor-spacing", "aria-invalid") == "true"
    page.fill("#floor-spacing", "")
    page.fill("#floor-spacing", "2")
    page.press("#floor-spacing", "Enter")
    # (the first map's bound: a new grid is computed like it, on a machine the suite loads)
    page.wait_for_function("() => document.querySelector('#plot-floor-map .plot')"
                           ".data?.[0]?.x?.length === 10", timeout=90_000)
    assert page.locator("#floor-spacing-err").inner_text() == ""
