"""Browser tests of the frequency-domain estimate drawn over a finished job's Welch PSD (the
"Overlay frequency-domain estimate" check box of the job view's spectra tab), in Chromium and
Firefox against a real ``flexride serve`` (fixtures of tests/frontend/conftest.py).

The overlay's numbers are the service's: the estimate of the job's own scenario with
``spectra`` (tests/api/test_estimates_api.py checks them against the library), times the
quasi-static split's gain when the Welch PSD removes that part. That the estimate and a Welch
PSD of the time-domain response agree is tested at the library level
(tests/frequency/test_against_time_domain.py). No console errors (checked by the ``page``
fixture): a refused estimate is a note.
"""

from __future__ import annotations

from typing import Any

RUN_S = 2.0  # a short run: the overlay does not need a long record


def _finished_job(server: Any, preset: str) -> str:
    job = server.api("/jobs", {"preset": preset,
                               "overrides": {"duration_s": RUN_S, "distance_m": None}})
    assert server.wait_job(job["id"])["status"] == "succeeded"
    return job["id"]


def _open_spectra(page: Any, job_id: str, wait_plot: Any) -> None:
    page.goto(f"/#/jobs/{job_id}?tab=spectra")
    wait_plot(page, "#plot-psd", timeout=60_000)


def _traces(page: Any) -> list[dict[str, Any]]:
    return page.eval_on_selector(
        "#plot-psd .plot",
        "e => e.data.map(t => ({name: t.name, n: t.x.length, x: t.x, y: t.y}))")


def test_the_estimate_is_overlaid_on_the_welch_psd(page, server, shot, wait_plot):
    job_id = _finished_job(server, "paper-random-straight-80")
    _open_spectra(page, job_id, wait_plot)
    welch = _traces(page)
    assert [t["name"] for t in welch] == ["car body PC acc z", "car body PR acc z"]
    page.check("#psd-overlay")
    page.wait_for_function("() => document.querySelector('#plot-psd .plot').data.length === 4",
                           timeout=90_000)
    traces = _traces(page)
    est = traces[2:]
    assert [t["name"] for t in est] == [f"{w['name']} – frequency-domain estimate"
                                        for w in welch]
    # the same units and axes: the service's PSD of the job's scenario times the split's gain
    scenario = server.api(f"/jobs/{job_id}/scenario")
    ans = server.api("/estimates", {"scenario": scenario, "points": ["PC", "PR"],
                                    "spectra": True})["response"]
    f, gain = ans["frequencies_hz"], ans["dynamic_part_gain"]
    psd = ans["psd"]["carbody.PC.acc.z"]
    i = next(k for k, v in enumerate(f) if v > 1.0)
    j = est[0]["x"].index(f[i])
    assert est[0]["y"][j] == psd[i] * gain[i]
    assert max(est[0]["x"]) <= 30.0  # the plot's "Up to" frequency
    assert page.eval_on_selector("#plot-psd .plot", "e => e.layout.yaxis.title.text") == \
        "PSD ((m/s²)²/Hz)"
    note = page.locator("#psd-overlay-note").inner_text()
    assert note.startswith("Dotted: the expected PSD") and "Method: frequency domain" in note
    shot(page, "30-job-psd-overlay")
    # with the raw record the estimate is drawn without the split's gain
    page.locator("label", has_text="Remove the quasi-static part").locator("input").uncheck()
    page.wait_for_function(
        "v => { const d = document.querySelector('#plot-psd .plot').data;"
        " return d.length === 4 && d[2].y[d[2].x.indexOf(v[0])] === v[1]; }",
        arg=[f[i], psd[i]], timeout=30_000)
    # off again: the Welch PSDs alone
    page.uncheck("#psd-overlay")
    page.wait_for_function("() => document.querySelector('#plot-psd .plot').data.length === 2")
    assert page.locator("#psd-overlay-note").inner_text() == ""


def test_a_refused_estimate_is_a_note_beside_the_chart(page, server, wait_plot):
    job_id = _finished_job(server, "paper-settlement-60")
    _open_spectra(page, job_id, wait_plot)
    page.check("#psd-overlay")
    page.wait_for_selector("#psd-overlay-note[data-state=refused]", timeout=60_000)
    note = page.locator("#psd-overlay-note").inner_text()
    assert note.startswith("No frequency-domain estimate:") and "settlement" in note, note
    assert "POST /api/v1/jobs" in note  # what to do
    wait_plot(page, "#plot-psd")
    assert len(_traces(page)) == 2  # the Welch PSDs stay
