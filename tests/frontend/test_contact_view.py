"""Browser tests of the contact-geometry view (``#/contact``) against a real ``flexride serve``,
in Chromium and Firefox (fixtures of tests/frontend/conftest.py, as test_dashboard.py): the
view loads from the navigation with its three plots, the Δy slider moves the drawn wheel and
its contact point (to where the API puts them), a refused parameter is shown at its field, no
console errors (checked by the ``page`` fixture).
"""

from __future__ import annotations

import re
from typing import Any

import pytest

from contact.profile_data import mbench_file

PLOTS = ("#plot-contact-section", "#plot-contact-dr", "#plot-contact-conicity")


def _drawn_contact(page: Any) -> list[float]:
    """(y, z) of the contact point drawn on the cross-section (mm)."""
    return page.eval_on_selector("#plot-contact-section .plot",
                                 "e => [e.data[2].x[0], e.data[2].y[0]]")


def _drawn_wheel_start(page: Any) -> list[float]:
    return page.eval_on_selector("#plot-contact-section .plot",
                                 "e => [e.data[1].x[0], e.data[1].y[0]]")


def test_contact_view_loads_and_the_slider_moves_the_contact(page, server, shot, wait_plot):
    page.goto("/#/")
    page.get_by_role("link", name="Contact geometry").click()
    page.wait_for_url(re.compile(r"#/contact$"))
    for sel in PLOTS:
        wait_plot(page, sel)
    assert page.locator('[data-nav="contact"]').get_attribute("aria-current") == "page"
    api = server.api("/contact/geometry")
    n = len(api["rows"])
    i0 = n // 2
    slider = page.locator("#contact-dy")
    assert slider.get_attribute("max") == str(n - 1) and slider.input_value() == str(i0)
    assert "Δy = 0 mm" in page.locator("#contact-dy-value").inner_text()
    at0 = api["contacts"][i0]
    y0, z0 = _drawn_contact(page)
    assert (y0, z0) == (at0["left_y_mm"], at0["left_z_mm"])
    wheel0 = _drawn_wheel_start(page)
    # the conicity and Δr plots carry the API's numbers, with units on the axes
    cone = page.eval_on_selector("#plot-contact-conicity .plot", "e => e.data[0].y")
    assert cone == [c["tan_gamma_e"] for c in api["conicity"]]
    titles = page.eval_on_selector_all(
        ".plot", "els => els.flatMap(e => [e.layout.xaxis.title.text, e.layout.yaxis.title.text])")
    assert all(re.search(r"\((mm|–)\)$", t) for t in titles), titles
    overflow = page.evaluate("() => document.documentElement.scrollWidth - window.innerWidth")
    assert overflow <= 0, f"horizontal overflow of {overflow} px"
    shot(page, "20-contact-geometry")
    # to the flange: the slider's far end moves the wheel and its contact point
    slider.focus()
    page.keyboard.press("End")
    expect_dy = api["rows"][-1]["dy_mm"]
    page.wait_for_function("() => document.querySelector('#contact-dy-value').textContent"
                           f".includes('{expect_dy:g} mm')")
    page.wait_for_function(f"() => document.querySelector('#plot-contact-section .plot')"
                           f".data[2].x[0] !== {y0}")
    at = api["contacts"][-1]
    assert _drawn_contact(page) == [at["left_y_mm"], at["left_z_mm"]]
    assert _drawn_wheel_start(page)[0] > wheel0[0] + expect_dy - 0.5
    marker = page.eval_on_selector("#plot-contact-dr .plot",
                                   "e => [e.data[2].x[0], e.data[2].y[0]]")
    assert marker == [api["rows"][-1]["dy_mm"], api["rows"][-1]["dr_mm"]]
    page.keyboard.press("ArrowLeft")
    page.wait_for_function(f"() => document.querySelector('#plot-contact-section .plot')"
                           f".data[2].x[0] === {api['contacts'][-2]['left_y_mm']}")
    page.wait_for_function("() => location.hash.includes('dy=')")
    shot(page, "20b-contact-geometry-flange")


def test_contact_view_shows_a_refused_parameter_at_its_field(page, server):
    page.console_log.allow(r"status of 422")  # the service's answer to the bad parameters
    page.goto("/#/contact?roll=false")
    page.wait_for_selector("#plot-contact-section .plot[data-state=ready]")
    page.fill("#contact-y_max_mm", "30")
    page.click("#contact-apply")
    err = page.locator("#contact-y_max_mm-err")
    err.wait_for(state="visible")
    assert "less than or equal to 20" in err.inner_text()
    assert page.locator("#contact-y_max_mm").get_attribute("aria-invalid") == "true"
    assert "refused" in page.locator("#contact-form-msg").inner_text()
    # a flange-back distance beyond the gauge is refused by the service at that field
    page.fill("#contact-y_max_mm", "12")
    page.fill("#contact-flange_back_mm", "1500")
    page.click("#contact-apply")
    fb = page.locator("#contact-flange_back_mm-err")
    fb.wait_for(state="visible")
    assert "smaller than the gauge" in fb.inner_text()
    assert page.locator("#contact-y_max_mm-err").inner_text() == ""
    page.fill("#contact-flange_back_mm", "1360")
    page.click("#contact-apply")
    fb.wait_for(state="hidden")
    assert page.locator("#contact-flange_back_mm").get_attribute("aria-invalid") is None


def test_an_uploaded_wheel_file_is_used_by_its_id(page, server, wait_plot):
    """CONTACT's S1002 file (the Manchester benchmark's, equal to EN 13715 within 1e-5 mm)
    uploaded from the wheel field: the field takes the stored id and the view recomputes with
    it, so the equivalent conicity equals the built-in S1002's (an independent copy of the same
    profile: a wrong orientation, unit or mirroring of the upload would change it)."""
    page.goto("/#/contact")
    wait_plot(page, "#plot-contact-conicity")
    builtin = page.eval_on_selector("#plot-contact-conicity .plot", "e => e.data[0].y")
    note0 = page.locator("#plot-contact-section .plot-note").inner_text()
    page.set_input_files("#contact-wheel-file", str(mbench_file("MBench_S1002_v3.prw")))
    page.wait_for_function(
        "() => /^[0-9a-f]{64}$/.test(document.querySelector('#contact-wheel').value)")
    assert "MBench_S1002_v3.prw: wheel profile, prw format" in page.locator(
        "#contact-wheel-help").inner_text()
    page.wait_for_function(  # the drawing is the answer for the uploaded wheel
        "note => document.querySelector('#plot-contact-section .plot-note')?.textContent !== note"
        " && location.hash.includes('wheel=')", arg=note0, timeout=30_000)
    wait_plot(page, "#plot-contact-conicity")
    uploaded = page.eval_on_selector("#plot-contact-conicity .plot", "e => e.data[0].y")
    assert len(uploaded) == len(builtin)
    assert uploaded == pytest.approx(builtin, rel=2e-3, abs=1e-4)


def test_a_refused_profile_file_is_shown_at_its_field(page, server, tmp_path):
    page.console_log.allow(r"status of 422")  # the service's answer to the bad file
    page.goto("/#/contact")
    page.wait_for_selector("#plot-contact-section .plot[data-state=ready]")
    bad = tmp_path / "worn.txt"
    bad.write_text("0 0\n1 0.1\nnan 0.2\n3 0.3\n")
    page.set_input_files("#contact-rail-file", str(bad))
    err = page.locator("#contact-rail-err")
    err.wait_for(state="visible")
    assert "line 3" in err.inner_text()
    assert page.locator("#contact-rail").get_attribute("aria-invalid") == "true"
    assert page.locator("#contact-rail").input_value() == "60e1"  # the field keeps its profile
    # a wheel file given as a rail is refused by its kind, at the same field
    page.set_input_files("#contact-rail-file", str(mbench_file("MBench_S1002_v3.prw")))
    page.wait_for_function("() => document.querySelector('#contact-rail-err').textContent"
                           ".includes('wheel')")
