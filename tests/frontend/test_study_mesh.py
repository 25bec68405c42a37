"""Browser tests of a study's mesh convergence (issue 33: the paper's element-size
pre-calculation, Fig. 4, as a study), in Chromium and Firefox (fixtures of
tests/frontend/conftest.py).

The study is the ``mesh-convergence`` preset (two conditions × six car-body element sizes,
12 flexible jobs) on a ``flexride serve`` of its own without a runner (``FLEXRIDE_RUNNER=none``:
the jobs are recorded, never run); the test writes each job's result into that server's store
as the runner would — a summary with the air spring's forces and run metadata with the car
body's elastic frequencies, known laws in the element size h — so the service's tables
(``tables.mesh_convergence``) have known values: the vertical dynamic rms 100 + 2000 h² N
(converged estimate 100 N, Richardson's; the 0.2 m mesh 80 % above it), the peak
300 + 6000 h² N, the first elastic frequency 5 + h Hz (order 1), the second 8 + 2 h² Hz (none
at 0.5 m), the third oscillating (converged estimate: the finest mesh's value), the vertical
Sperling index 1.8 + 0.2 h^0.3 (order 0.3, below 0.5: not reliable either); the random-straight
condition's forces are 1.5 times the smooth one's. On smooth track the lateral air-spring forces
are milli-newtons, below the resolution (1e-4 of the 91 kN static load): not judged, and the
vertical largest value is the static load alone, so the force "grows" in 2 of 3 judged rows
there and in all 6 on random track.
"""

from __future__ import annotations

import copy
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


def _forces(h: float, condition: str) -> dict[str, Any]:
    """The air spring's forces on the h mesh: vertical by the laws, lateral negligible on
    smooth track (the static load 91 kN is the largest vertical value there)."""
    k = SCALE[condition]
    rms, peak = k * (100.0 + 2000.0 * h**2), k * (300.0 + 6000.0 * h**2)
    if condition == "smooth-straight":
        lateral = {"mean": 0.0, "rms_dynamic": 1e-3 * (1 + h), "peak_dynamic": 3e-3 * (1 + h),
                   "max_abs": 3e-3 * (1 + h)}
        top = 9.1e4
    else:
        lateral = {"mean": 0.0, "rms_dynamic": k * (20.0 + 400.0 * h**2),
                   "peak_dynamic": k * (60.0 + 1200.0 * h**2),
                   "max_abs": k * (60.0 + 1200.0 * h**2)}
        top = 9e4 + peak
    return {"secondary.1L": {"z": {"mean": 9e4, "rms_dynamic": rms, "peak_dynamic": peak,
                                   "max_abs": top}, "y": lateral}}


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
                    h = j.axes[AXIS]
                    summary = copy.deepcopy(_summary(80.0))  # PC and PR share one dict
                    summary["points"]["PC"]["directions"]["z"]["sperling"]["value"] = (
                        1.8 + 0.2 * h**0.3)  # order 0.3: converged estimate not reliable
                    summary["suspension"] = _forces(h, j.axes["condition"])
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
    """The Plotly traces of a plot card by their ``meta`` (mesh, converged, band)."""
    data = page.eval_on_selector(f"{selector} .plot",
                                 "e => e.data.map(t => ({meta: t.meta, x: t.x, y: t.y}))")
    return {t["meta"]: t for t in data}


def _wait_trace(page: Any, selector: str, condition: str) -> None:
    """Wait until the plot's traces meet ``condition`` (JS of ``d``, the traces by meta)."""
    page.wait_for_function(f"""() => {{
        const e = document.querySelector('{selector} .plot');
        if (!e || !e.data) return false;
        const d = Object.fromEntries(e.data.map(t => [t.meta, t]));
        return {condition};
    }}""")


def _row(table: dict, key: str) -> dict:
    return next(r for r in table["rows"] if r["key"] == key)


def test_mesh_convergence_section_plots_and_tables(page, mesh_studies, shot, wait_plot):
    st = mesh_studies["mesh"]
    tables = st["tables"]["mesh_convergence"]
    # the groups as the axes' own values, in the jobs' axis order
    assert [list(t["group"].items()) for t in tables] == [
        [("condition", c), ("speed_kmh", 80.0), ("body_model", "flexible")]
        for c in ("smooth-straight", "random-straight")]
    smooth, rough = tables
    assert smooth["claim"]["negligible"] == [f"secondary.1L.y.{m}" for m in
                                             ("rms_dynamic", "peak_dynamic", "max_abs")]
    assert rough["claim"]["negligible"] == []
    _open(page, f"{mesh_studies['url']}/#/studies/{st['id']}")
    section = page.locator("#study-mesh")
    expect(section).to_be_visible()
    expect(section.get_by_role("heading", name="Mesh convergence")).to_be_visible()
    blocks = page.locator("#study-mesh .mesh-block")
    expect(blocks).to_have_count(2)
    heads = page.locator("#study-mesh .mesh-block > h3").all_inner_texts()
    assert "smooth-straight · 80 km/h · flexible body" in heads[0]
    assert "random-straight · 80 km/h · flexible body" in heads[1]
    # the claim's verdict, prominent in each block, and its two parts as badges
    verdicts = page.locator(".mesh-verdict-text").all_inner_texts()
    assert len(verdicts) == 2
    for text, t in zip(verdicts, tables, strict=True):
        assert text.startswith("Verdict:") and t["claim"]["text"][1:] in text
    assert "grows with the element size in 2 of 3 judged rows" in verdicts[0]
    assert "80.0 % for the forces" in verdicts[0]
    assert "3 rows below the resolution, not judged" in verdicts[0]
    assert "in 6 of 6 judged rows" in verdicts[1] and "below the resolution" not in verdicts[1]
    for i, (grows, adequate) in enumerate((("no", "no"), ("yes", "no"))):
        badges = page.locator(f"#mesh-table-{i} .mesh-verdict .mesh-claim")
        expect(badges).to_have_count(2)
        assert badges.all_inner_texts() == [f"force grows: {grows}",
                                            f"0.2 m adequate: {adequate}"]
        assert f"mesh-{grows}" in badges.nth(0).get_attribute("class")
        assert "mesh-no" in badges.nth(1).get_attribute("class")
        assert "at most 80 %" in badges.nth(1).get_attribute("title")
    assert "2 of 3 judged force rows" in page.locator(
        "#mesh-table-0 .mesh-claim-grows").get_attribute("title")
    # the plot: the air spring's vertical dynamic rms by default (the first force row judged
    # in both tables), six meshes, the converged estimate (Richardson's) 100 N / 150 N
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
        assert tr["converged"]["y"] == pytest.approx([100 * k, 100 * k], rel=1e-6)
        est = _row(tables[i], "secondary.1L.z.rms_dynamic")["estimate"]
        assert est["reliable"] and est["converged"] == pytest.approx(100 * k, rel=1e-6)
        half = est["band"] * est["converged"]  # ± band × |converged| around the converged
        assert min(tr["band"]["y"]) == pytest.approx(est["converged"] - half)
        assert max(tr["band"]["y"]) == pytest.approx(est["converged"] + half)
    names = page.eval_on_selector("#mesh-plot-0 .plot", "e => e.data.map(t => t.name)")
    assert "converged estimate: 100 N" in names
    layout_y = page.eval_on_selector("#mesh-plot-0 .plot", "e => e.layout.yaxis.title.text")
    assert layout_y == "air spring 1L z: rms of the dynamic part (N)"
    note = page.locator("#mesh-plot-0 .plot-note").inner_text()
    assert "Richardson's extrapolation" in note and "+80.0 % from the converged estimate" in note
    shot(page, "45-study-mesh-convergence")
    # another quantity: the second elastic frequency, without the 0.5 m mesh
    select.select_option("frequency.2")
    _wait_trace(page, "#mesh-plot-0", "d.mesh && d.mesh.x.length === 5")
    tr = _traces(page, "#mesh-plot-0")
    assert tr["mesh"]["x"] == SIZES[:5]
    assert tr["converged"]["y"] == pytest.approx([8.0, 8.0], rel=1e-6)
    assert page.eval_on_selector("#mesh-plot-0 .plot", "e => e.layout.yaxis.title.text") == (
        "carbody: elastic mode 2 (Hz)")
    assert len(_traces(page, "#mesh-plot-1")["mesh"]["x"]) == 5  # one choice for both
    # oscillatory: the converged estimate is the finest mesh's value, the band the spread
    select.select_option("frequency.3")
    _wait_trace(page, "#mesh-plot-0", "d.mesh && d.mesh.y[1] === 10.2")
    tr = _traces(page, "#mesh-plot-0")
    est = _row(smooth, "frequency.3")["estimate"]
    assert est["oscillatory"] and not est["reliable"]
    assert tr["converged"]["y"] == pytest.approx([10.0, 10.0])  # the 0.1 m mesh's value
    assert min(tr["band"]["y"]) == pytest.approx(10.0 - 0.2)  # spread 10.0..10.2
    assert max(tr["band"]["y"]) == pytest.approx(10.0 + 0.2)
    note = page.locator("#mesh-plot-0 .plot-note").inner_text()
    assert "finest mesh's value; the meshes oscillate" in note and "band = spread" in note
    # slower than order 0.5 (the vertical Sperling index, order 0.3): not reliable either
    select.select_option("PC.z.sperling")
    _wait_trace(page, "#mesh-plot-0", "d.mesh && d.mesh.y[0] > 1.85 && !!d.converged")
    est = _row(smooth, "PC.z.sperling")["estimate"]
    assert est["order"] == pytest.approx(0.3, abs=1e-6) and not est["reliable"]
    assert _traces(page, "#mesh-plot-0")["converged"]["y"][0] == pytest.approx(
        1.8 + 0.2 * 0.1**0.3)
    note = page.locator("#mesh-plot-0 .plot-note").inner_text()
    assert "finest mesh's value; the meshes converge slower than order 0.5" in note
    assert "band = spread" in note
    # a row below the resolution: markers only, the reason in the note; judged on random track
    select.select_option("secondary.1L.y.rms_dynamic")
    _wait_trace(page, "#mesh-plot-0", "d.mesh && d.mesh.y[0] < 1 && !d.converged && !d.band")
    _wait_trace(page, "#mesh-plot-1", "d.mesh && d.mesh.y[0] > 1 && !!d.converged && !!d.band")
    why = _row(smooth, "secondary.1L.y.rms_dynamic")["negligible"]
    assert "static air-spring load (91.0 kN)" in why
    assert f"not judged: {why}" in page.locator("#mesh-plot-0 .plot-note").inner_text()
    # the table of every row: values per size, order, converged, band, 0.2 m vs converged
    table = page.locator("#mesh-table-0 .mesh-table table")
    heads = table.locator("thead th").all_inner_texts()
    assert heads[:2] == ["Quantity", "Unit"]
    assert heads[2:8] == [f"{h:g} m" for h in SIZES]
    assert heads[8:] == ["Order", "Converged", "Band (%)", "0.2 m vs converged (%)"]
    assert "GCI where reliable" in table.locator("thead th").nth(10).get_attribute("title")
    rows = table.locator("tbody tr")
    expect(rows).to_have_count(len(smooth["rows"]))
    cells = rows.nth(0).locator("th, td").all_inner_texts()
    assert cells[0] == "air spring 1L z: rms of the dynamic part" and cells[1] == "N"
    assert cells[2:8] == ["120", "145", "180", "280", "420", "600"]
    assert cells[8:] == ["2.00", "100", "20.8", "+80.0 %"]
    second = table.locator("tbody tr", has_text="elastic mode 2").locator("td").all_inner_texts()
    assert second[6] == "–"  # no second frequency on the 0.5 m mesh
    third = table.locator("tbody tr", has_text="elastic mode 3")
    osc = third.locator(".mesh-osc")
    expect(osc).to_have_count(1)
    assert osc.inner_text().startswith("~") and "change sign" in osc.get_attribute("title")
    assert third.locator("td").all_inner_texts()[7:] == ["~1.45", "10", "2", "+1.0 %"]
    slow = table.locator("tbody tr", has_text="PC vertical Sperling index").locator(".mesh-slow")
    assert slow.inner_text() == "0.30?" and "below 0.5" in slow.get_attribute("title")
    # the rows below the resolution: greyed, the reason as title, no order/converged/band
    greyed = table.locator("tbody tr.mesh-negligible")
    expect(greyed).to_have_count(3)
    lateral = table.locator("tbody tr", has_text="1L y: rms of the dynamic part")
    assert "mesh-negligible" in lateral.get_attribute("class")
    nj = lateral.locator(".mesh-nj")
    assert nj.inner_text() == "(not judged)"
    assert why in lateral.locator("th span[title]").first.get_attribute("title")
    assert lateral.locator("td").all_inner_texts()[7:] == ["–", "–", "–", "–"]
    grey, ink = (page.eval_on_selector(sel, "e => getComputedStyle(e).color") for sel in (
        "#mesh-table-0 tr.mesh-negligible td", "#mesh-table-0 tbody tr:first-child td"))
    assert grey != ink
    expect(page.locator("#mesh-table-1 tbody tr.mesh-negligible")).to_have_count(0)


def test_default_quantity_skips_rows_below_the_resolution(page, mesh_studies):
    """The default quantity is the first force row judged in every table, else in any table,
    else the first force row (the module's rule, called in the page)."""
    _open(page, f"{mesh_studies['url']}/#/studies")
    picks = page.evaluate("""async () => {
        const m = await import('/components/meshconvergence.js');
        const r = (key, why, group = 'force') =>
          ({key, group, label: key, unit: 'N', negligible: why});
        const pick = (tables) => m.defaultMeshQuantity(tables, m.meshQuantities(tables));
        const S = 'small';
        return [
          pick([{rows: [r('a', S), r('b', null), r('f', null, 'frequency')]}]),
          pick([{rows: [r('a', null), r('b', null)]}, {rows: [r('a', S), r('b', null)]}]),
          pick([{rows: [r('a', null), r('b', S)]}, {rows: [r('a', S), r('b', S)]}]),
          pick([{rows: [r('a', S), r('f', null, 'frequency')]}]),
        ];
    }""")
    assert picks == ["b", "b", "a", "a"]


def test_a_study_without_element_sizes_has_no_mesh_section(page, mesh_studies, wait_plot):
    st = mesh_studies["plain"]
    assert st["tables"]["mesh_convergence"] == []
    _open(page, f"{mesh_studies['url']}/#/studies/{st['id']}")
    wait_plot(page, "#plot-sperling-speed")  # the study's tables are drawn
    assert page.locator("#study-mesh").count() == 0
    assert page.locator(".mesh-verdict").count() == 0
