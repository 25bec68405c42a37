"""Browser tests of a study's mesh convergence (issue 33: the paper's element-size
pre-calculation, Fig. 4, as a study), in Chromium and Firefox (fixtures of
tests/frontend/conftest.py).

The study is the ``mesh-convergence`` preset (two conditions × six car-body element sizes,
12 flexible jobs) on a ``flexride serve`` of its own without a runner (``FLEXRIDE_RUNNER=none``:
the jobs are recorded, never run); the test writes each job's result into that server's store
as the runner would — a summary with the air spring's forces and run metadata with the car
body's elastic frequencies, known laws in the element size h — so the service's tables
(``tables.mesh_convergence``) have known values: the vertical dynamic rms 100 + 2000 h² N
(extrapolated 100 N, the 0.2 m mesh 80 % above it), the peak 300 + 6000 h² N, the first
elastic frequency 5 + h Hz (order 1), the second 8 + 2 h² Hz (none at 0.5 m), the third
oscillating; the random-straight condition's forces are 1.5 times the smooth one's.
"""

from __future__ import annotations

import json
import shutil
import urllib.request
from typing import Any

import pytest
from sqlalchemy import update

from flexride.store import Job, JobStore

try:
    from playwright.sync_api import expect
except ImportError:  # the browser fixture skips these tests (or fails them in CI)
    expect = None

AXIS = "bodies.carbody.element_size_m"
QUICK = {"duration_s": 1.0, "distance_m": None}
SIZES = [0.1, 0.15, 0.2, 0.3, 0.4, 0.5]
THIRD = {0.1: 10.0, 0.15: 10.2, 0.2: 10.1, 0.3: 10.3, 0.4: 10.4, 0.5: 10.5}  # oscillatory
SCALE = {"smooth-straight": 1.0, "random-straight": 1.5}


def _summary(speed: float) -> dict[str, Any]:
    """Comfort indices of two points (the same on every mesh)."""
    dirs = {d: {"peaks": {"max_abs": 0.01 * speed, "rms": 0.001 * speed},
                "sperling": {"value": 1.0 + 0.01 * speed},
                "iso2631": {"Wb" if d == "z" else "Wd": {"a_w": 0.002 * speed}}}
            for d in ("z", "y")}
    return {"points": {"PC": {"directions": dirs}, "PR": {"directions": dirs}}}


class _Api:
    def __init__(self, url: str) -> None:
        self.url = url

    def __call__(self, path: str, body: dict | None = None) -> Any:
        data = json.dumps(body).encode() if body is not None else None
        req = urllib.request.Request(f"{self.url}/api/v1{path}", data=data,
                                     headers={"Content-Type": "application/json"} if data else {})
        with urllib.request.urlopen(req, timeout=60) as r:
            return json.loads(r.read().decode())


@pytest.fixture(scope="module")
def mesh_studies(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """A server without a runner and its two studies with finished (written) jobs: the
    mesh-convergence preset and a study without an element-size axis."""
    from live_server import start_server  # tools/, on the path through conftest.py

    data = tmp_path_factory.mktemp("flexride-mesh")
    live = start_server(data, cache_dir=data / "cache", log=data / "serve.log",
                        env={"FLEXRIDE_RUNNER": "none"})
    try:
        api = _Api(live.url)
        mesh = api("/studies", {"preset": "mesh-convergence", "overrides": QUICK})
        plain = api("/studies", {"name": "ui-no-mesh", "base": {"preset": "paper-metro"},
                                 "conditions": ["random-straight"], "speeds_kmh": [60, 80],
                                 "overrides": QUICK})
        assert mesh["n_jobs"] == 12 and plain["n_jobs"] == 2
        store = JobStore.from_url(f"sqlite:///{data / 'flexride.db'}", create=False)
        try:
            with store.writing() as s, s.begin():
                for j in store.study_jobs(mesh["id"]):
                    h, k = j.axes[AXIS], SCALE[j.axes["condition"]]
                    summary = _summary(80.0)
                    summary["suspension"] = {"secondary.1L": {"z": {
                        "mean": 9e4, "rms_dynamic": k * (100.0 + 2000.0 * h**2),
                        "peak_dynamic": k * (300.0 + 6000.0 * h**2), "max_abs": 9.1e4}}}
                    freqs = [5.0 + h, 8.0 + 2.0 * h**2, THIRD[h]] if h < 0.5 else [5.0 + h]
                    meta = {"flexible_bodies": {"carbody": {"element_size_m": h,
                                                            "elastic_frequencies_hz": freqs}}}
                    s.execute(update(Job).where(Job.id == j.id).values(
                        status="succeeded", progress=1.0, summary=summary, run_meta=meta))
                for j in store.study_jobs(plain["id"]):
                    s.execute(update(Job).where(Job.id == j.id).values(
                        status="succeeded", progress=1.0, summary=_summary(j.speed_kmh)))
        finally:
            store.engine.dispose()
        yield {"url": live.url, "mesh": api(f"/studies/{mesh['id']}"),
               "plain": api(f"/studies/{plain['id']}")}
    finally:
        live.stop()
        shutil.rmtree(data, ignore_errors=True)


def _open(page: Any, url: str) -> None:
    """Open a study page. Its jobs' results were written without a result file, so the view's
    request for the points of a finished job (``/jobs/{id}/channels``) is answered 409 "no
    results" by design (the points card keeps the paper's list): that line is no page error."""
    def allow(response: Any) -> None:
        if response.status == 409 and "/channels" in response.url:
            page.console_log.allow(r"status of 409")
    page.on("response", allow)
    page.goto(url)


def _traces(page: Any, selector: str) -> dict[str, dict]:
    """The Plotly traces of a plot card by their ``meta`` (mesh, extrapolated, gci)."""
    data = page.eval_on_selector(f"{selector} .plot",
                                 "e => e.data.map(t => ({meta: t.meta, x: t.x, y: t.y}))")
    return {t["meta"]: t for t in data}


def test_mesh_convergence_section_plots_and_tables(page, mesh_studies, shot, wait_plot):
    st = mesh_studies["mesh"]
    tables = st["tables"]["mesh_convergence"]
    assert [t["group"]["condition"] for t in tables] == ["smooth-straight", "random-straight"]
    _open(page, f"{mesh_studies['url']}/#/studies/{st['id']}")
    section = page.locator("#study-mesh")
    expect(section).to_be_visible()
    expect(section.get_by_role("heading", name="Mesh convergence")).to_be_visible()
    blocks = page.locator("#study-mesh .mesh-block")
    expect(blocks).to_have_count(2)
    heads = page.locator("#study-mesh .mesh-block > h3").all_inner_texts()
    assert "smooth-straight" in heads[0] and "80 km/h" in heads[0] and "flexible body" in heads[0]
    assert "random-straight" in heads[1]
    # the claim's verdict, prominent in each block
    verdicts = page.locator(".mesh-verdict").all_inner_texts()
    assert len(verdicts) == 2
    for text, t in zip(verdicts, tables, strict=True):
        assert text.startswith("Verdict:") and t["claim"]["text"][1:] in text
    assert "grows with element size in 2 of 2 rows" in verdicts[0]
    assert "80.0 % for the forces" in verdicts[0]
    # the plot: the air spring's vertical dynamic rms by default, six meshes, extrapolated 100 N
    select = page.locator("#mesh-quantity")
    assert "Quantity against element size" in page.locator("label[for=mesh-quantity]").inner_text()
    assert select.input_value() == "secondary.1L.z.rms_dynamic"
    assert page.locator("#mesh-quantity optgroup").first.get_attribute("label") == (
        "Air-spring forces")
    wait_plot(page, "#mesh-plot-0")
    wait_plot(page, "#mesh-plot-1")
    for i, k in enumerate((1.0, 1.5)):
        tr = _traces(page, f"#mesh-plot-{i}")
        assert tr["mesh"]["x"] == SIZES
        assert tr["mesh"]["y"] == pytest.approx([k * (100 + 2000 * h**2) for h in SIZES])
        assert tr["extrapolated"]["y"] == pytest.approx([100 * k, 100 * k], rel=1e-6)
        est = next(r for r in tables[i]["rows"]
                   if r["key"] == "secondary.1L.z.rms_dynamic")["estimate"]
        half = est["gci_fine"] * 120 * k  # ± GCI × the finest (0.1 m) value
        assert min(tr["gci"]["y"]) == pytest.approx(120 * k - half)
        assert max(tr["gci"]["y"]) == pytest.approx(120 * k + half)
    layout_y = page.eval_on_selector("#mesh-plot-0 .plot", "e => e.layout.yaxis.title.text")
    assert layout_y == "air spring 1L z: rms of the dynamic part (N)"
    assert "+80.0 %" in page.locator("#mesh-plot-0 .plot-note").inner_text()
    shot(page, "45-study-mesh-convergence")
    # another quantity: the second elastic frequency, without the 0.5 m mesh
    select.select_option("frequency.2")
    page.wait_for_function("""() => {
        const d = document.querySelector('#mesh-plot-0 .plot').data || [];
        const m = d.find(t => t.meta === 'mesh');
        return m && m.x.length === 5;
    }""")
    tr = _traces(page, "#mesh-plot-0")
    assert tr["mesh"]["x"] == SIZES[:5]
    assert tr["extrapolated"]["y"] == pytest.approx([8.0, 8.0], rel=1e-6)
    assert page.eval_on_selector("#mesh-plot-0 .plot", "e => e.layout.yaxis.title.text") == (
        "carbody: elastic mode 2 (Hz)")
    assert len(_traces(page, "#mesh-plot-1")["mesh"]["x"]) == 5  # one choice for both
    # the table of every row: values per size, order, extrapolated, GCI, 0.2 m vs extrapolated
    table = page.locator("#mesh-table-0 .mesh-table table")
    heads = table.locator("thead th").all_inner_texts()
    assert heads[:2] == ["Quantity", "Unit"]
    assert heads[2:8] == [f"{h:g} m" for h in SIZES]
    assert heads[8:] == ["Order", "Extrapolated", "GCI (%)", "0.2 m vs extrapolated (%)"]
    rows = table.locator("tbody tr")
    expect(rows).to_have_count(len(tables[0]["rows"]))
    cells = rows.nth(0).locator("th, td").all_inner_texts()
    assert cells[0] == "air spring 1L z: rms of the dynamic part" and cells[1] == "N"
    assert cells[2:8] == ["120", "145", "180", "280", "420", "600"]
    assert cells[8] == "2.00" and cells[9] == "100" and cells[11] == "+80.0 %"
    second = table.locator("tbody tr", has_text="elastic mode 2").locator("td").all_inner_texts()
    assert second[6] == "–"  # no second frequency on the 0.5 m mesh
    third = table.locator("tbody tr", has_text="elastic mode 3")
    osc = third.locator(".mesh-osc")
    expect(osc).to_have_count(1)
    assert osc.inner_text().startswith("~") and "change sign" in osc.get_attribute("title")


def test_a_study_without_element_sizes_has_no_mesh_section(page, mesh_studies, wait_plot):
    st = mesh_studies["plain"]
    assert st["tables"]["mesh_convergence"] == []
    _open(page, f"{mesh_studies['url']}/#/studies/{st['id']}")
    wait_plot(page, "#plot-sperling-speed")  # the study's tables are drawn
    assert page.locator("#study-mesh").count() == 0
    assert page.locator(".mesh-verdict").count() == 0
