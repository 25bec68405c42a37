"""The scenario's contact-geometry choice: schema, profile sources and defaults."""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from flexride.contact.scenario_table import load_profile, placement_for
from flexride.errors import ScenarioError
from flexride.scenario.contact import Contact, ProfileSource
from flexride.track.measured import MeasuredSources


def test_defaults_and_shear_modulus_from_e_and_nu():
    c = Contact()
    assert c.geometry == "conical" and c.shear_modulus_for(2.1e11) == 8.0e10
    p = Contact(geometry="profiles", poisson=0.3)
    assert p.shear_modulus_for(2.6e11) == pytest.approx(1.0e11)
    assert Contact(geometry="profiles", shear_modulus=7e10).shear_modulus_for(2.1e11) == 7e10


def test_profile_source_exactly_one_way_and_known_builtins():
    with pytest.raises(ValidationError):
        ProfileSource()
    with pytest.raises(ValidationError):
        ProfileSource(builtin="s1002", path="x.prw")
    with pytest.raises(ValidationError):
        Contact(geometry="profiles", wheel={"builtin": "lm"})
    with pytest.raises(ValidationError):
        Contact(geometry="profiles", rail={"upload": "not-a-hash"})


def test_paths_are_refused_where_not_allowed_and_missing_uploads_are_located(tmp_path):
    service = MeasuredSources(upload_dir=tmp_path, allow_paths=False)
    with pytest.raises(ScenarioError) as err:
        load_profile(ProfileSource(path="/etc/wheel.prw"), "wheel", service)
    assert err.value.items[0].loc == ("path",)
    with pytest.raises(ScenarioError) as err:
        load_profile(ProfileSource(upload="a" * 64), "rail", service)
    assert err.value.items[0].loc == ("upload",)


def test_uploaded_profile_is_read_from_the_upload_directory(tmp_path):
    from flexride.contact.profiles import s1002

    prof = s1002()
    rows = "\n".join(f"{y * 1e3:.6f} {z * 1e3:.6f}" for y, z in zip(prof.y, prof.z, strict=True))
    (tmp_path / ("b" * 64 + ".txt")).write_text(rows)
    got = load_profile(ProfileSource(upload="b" * 64), "wheel",
                       MeasuredSources(upload_dir=tmp_path, allow_paths=False))
    assert got.y.size == prof.y.size


def test_flange_back_defaults_to_the_vehicle_rolling_circles():
    pl = placement_for(Contact(geometry="profiles"), r0=0.42, b0=0.7465)
    assert pl.taping_line == pytest.approx(0.7465) and pl.flange_back == pytest.approx(1.353)
    pl = placement_for(Contact(geometry="profiles", flange_back_distance=1.36), 0.42, 0.7465)
    assert pl.taping_line == pytest.approx(0.75)
