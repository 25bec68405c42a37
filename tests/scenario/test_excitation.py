"""Excitation schemas: defaults, bounds, cross-field checks and the discriminated union."""

from __future__ import annotations

import typing

import pytest
from pydantic import TypeAdapter, ValidationError

from flexride.scenario.excitation import (
    Corrugation,
    Excitation,
    MeasuredIrregularity,
    RandomIrregularity,
    Settlement,
)

ALL_MODELS = (RandomIrregularity, Corrugation, Settlement, MeasuredIrregularity)


def test_defaults_match_the_paper_case():
    r = RandomIrregularity()
    assert r.kind == "random"
    assert r.spectrum == "german-high"
    assert r.components == ["vertical", "alignment", "cross_level", "gauge"]
    assert (r.wavelength_min_m, r.wavelength_max_m, r.seed, r.scale) == (1.0, 120.0, 1, 1.0)
    c = Corrugation()
    assert (c.wavelength_m, c.depth_m, c.start_m, c.length_m, c.rails) == (
        0.5,
        0.001,
        0.0,
        None,
        "both",
    )
    s = Settlement()
    assert (s.wavelength_m, s.depth_m, s.position_m, s.rails) == (20.0, 0.1, 50.0, "both")
    m = MeasuredIrregularity(path="track.csv")
    assert (m.distance_column, m.scale) == ("distance_m", 1.0)


def test_default_lists_are_not_shared():
    a = RandomIrregularity()
    a.components.remove("gauge")
    assert RandomIrregularity().components == ["vertical", "alignment", "cross_level", "gauge"]


@pytest.mark.parametrize(
    ("model", "field", "value"),
    [
        (RandomIrregularity, "wavelength_min_m", 0.05),
        (RandomIrregularity, "wavelength_min_m", 60.0),
        (RandomIrregularity, "wavelength_max_m", 1500.0),
        (RandomIrregularity, "seed", -1),
        (RandomIrregularity, "scale", -0.1),
        (RandomIrregularity, "scale", 10.5),
        (RandomIrregularity, "spectrum", "american-class-6"),
        (RandomIrregularity, "components", []),
        (RandomIrregularity, "components", ["vertical", "twist"]),
        (Corrugation, "wavelength_m", 0.005),
        (Corrugation, "wavelength_m", 6.0),
        (Corrugation, "depth_m", -0.001),
        (Corrugation, "depth_m", 0.02),
        (Corrugation, "start_m", -1.0),
        (Corrugation, "length_m", 0.0),
        (Corrugation, "rails", "middle"),
        (Settlement, "wavelength_m", 0.5),
        (Settlement, "wavelength_m", 600.0),
        (Settlement, "depth_m", -0.01),
        (Settlement, "depth_m", 0.6),
        (Settlement, "position_m", -5.0),
        (MeasuredIrregularity, "scale", 11.0),
        (MeasuredIrregularity, "path", ""),
    ],
)
def test_out_of_bounds_values_are_rejected_naming_the_field(model, field, value):
    kwargs = {"path": "x.csv"} if model is MeasuredIrregularity and field != "path" else {}
    with pytest.raises(ValidationError) as info:
        model(**kwargs, **{field: value})
    locs = [err["loc"] for err in info.value.errors()]
    assert any(loc and loc[0] == field for loc in locs), locs


def test_wavelength_band_must_be_ordered():
    with pytest.raises(ValidationError) as info:
        RandomIrregularity(wavelength_min_m=30.0, wavelength_max_m=20.0)
    msg = str(info.value)
    assert "wavelength_max_m" in msg and "wavelength_min_m" in msg
    with pytest.raises(ValidationError):
        RandomIrregularity(wavelength_min_m=20.0, wavelength_max_m=20.0)
    RandomIrregularity(wavelength_min_m=0.5, wavelength_max_m=300.0)  # fine


def test_assignment_is_validated():
    r = RandomIrregularity()
    with pytest.raises(ValidationError):
        r.wavelength_max_m = 0.5


def test_components_must_be_unique():
    with pytest.raises(ValidationError) as info:
        RandomIrregularity(components=["vertical", "gauge", "vertical"])
    assert "vertical" in str(info.value)
    assert RandomIrregularity(components=["gauge"]).components == ["gauge"]


def test_unknown_keys_are_rejected():
    with pytest.raises(ValidationError) as info:
        Settlement(depth=0.1)
    assert "depth" in str(info.value)


@pytest.mark.parametrize("kwargs", [
    {},
    {"path": "a.csv", "upload": "0" * 64},
    {"path": "a.csv", "columns": ["distance_m", "vertical"], "rows": [[0, 0], [1, 0]]},
    {"rows": [[0, 0], [1, 0]]},
    {"upload": "0" * 64, "columns": ["distance_m", "vertical"]},
])
def test_measured_needs_exactly_one_source(kwargs):
    with pytest.raises(ValidationError, match=r"exactly one way|need 'columns'"):
        MeasuredIrregularity(**kwargs)


@pytest.mark.parametrize("upload", ["../../etc/passwd", "A" * 64, "0" * 63, "/tmp/x.csv"])
def test_measured_upload_must_be_a_content_hash(upload):
    with pytest.raises(ValidationError) as info:
        MeasuredIrregularity(upload=upload)
    assert info.value.errors()[0]["loc"] == ("upload",)


@pytest.mark.parametrize(
    ("data", "cls"),
    [
        ({"kind": "random", "seed": 7, "components": ["vertical"]}, RandomIrregularity),
        ({"kind": "corrugation", "wavelength_m": 0.3, "rails": "left"}, Corrugation),
        ({"kind": "settlement", "depth_m": 0.05}, Settlement),
        ({"kind": "measured", "path": "rec.csv", "distance_column": "s"}, MeasuredIrregularity),
    ],
)
def test_union_parses_each_kind_from_dicts(data, cls):
    adapter = TypeAdapter(Excitation)
    exc = adapter.validate_python(data)
    assert type(exc) is cls
    for key, value in data.items():
        assert getattr(exc, key) == value
    # JSON round trip keeps the kind
    again = adapter.validate_json(adapter.dump_json(exc))
    assert again == exc


def test_union_list_and_bad_kind():
    adapter = TypeAdapter(list[Excitation])
    excs = adapter.validate_python(
        [{"kind": "random"}, {"kind": "settlement"}, {"kind": "corrugation"}]
    )
    assert [type(e) for e in excs] == [RandomIrregularity, Settlement, Corrugation]
    with pytest.raises(ValidationError) as info:
        adapter.validate_python([{"kind": "earthquake"}])
    assert "kind" in str(info.value) or "earthquake" in str(info.value)
    with pytest.raises(ValidationError) as info:
        adapter.validate_python([{"kind": "settlement", "depth_m": 1.0}])
    assert "depth_m" in str(info.value)


def _is_numeric(annotation) -> bool:
    args = typing.get_args(annotation) or (annotation,)
    return any(a in (int, float) for a in args)


@pytest.mark.parametrize("model", ALL_MODELS)
def test_numeric_fields_document_a_unit_and_have_bounds(model):
    for name, info in model.model_fields.items():
        if not _is_numeric(info.annotation):
            continue
        desc = info.description or ""
        assert desc.rstrip().endswith(")") and "(" in desc, (model.__name__, name, desc)
        if name != "seed":
            bounds = [m for m in info.metadata if type(m).__name__ in ("Ge", "Gt", "Le", "Lt")]
            assert bounds, (model.__name__, name)
