"""The vocabulary of mode types shared by the classifier and typed calibration targets."""

from __future__ import annotations

import pytest

from flexride.errors import FEModelError
from flexride.fem.mode_types import (
    MODE_TYPES,
    ModeType,
    match_rank,
    name_types,
    parse_mode_type,
)


@pytest.mark.parametrize("name", list(MODE_TYPES))
def test_every_type_parses_to_itself(name):
    assert str(parse_mode_type(name)) == name
    assert parse_mode_type(f"  {name.upper()} ") == ModeType(name)


def test_orders_and_forgiving_spelling():
    assert parse_mode_type("first vertical bending") == ModeType("vertical bending", 1)
    assert parse_mode_type("5th lateral bending") == ModeType("lateral bending", 5)
    assert parse_mode_type("second  torsion") == ModeType("torsion", 2)
    assert str(parse_mode_type("first torsion")) == "torsion"  # the classifier's spelling
    assert parse_mode_type("Roof-Floor breathing").base == "roof–floor breathing"


@pytest.mark.parametrize("text", ["wobble", "first rhombic", "0th vertical bending",
                                  "vertical", "bending", ""])
def test_unknown_types_list_the_allowed_names(text):
    with pytest.raises(FEModelError) as err:
        parse_mode_type(text)
    for name in MODE_TYPES:
        assert f"'{name}'" in str(err.value)


def test_classifier_names_split_into_types():
    assert name_types("floor local + first vertical bending") == (
        ModeType("floor local"), ModeType("vertical bending", 1))
    assert name_types("torsion") == (ModeType("torsion", 1),)
    assert name_types("unclassified") == ()


def test_a_type_without_order_matches_any_order():
    any_torsion, first = parse_mode_type("torsion"), parse_mode_type("first torsion")
    assert match_rank(any_torsion, "second torsion") == 0
    assert match_rank(first, "second torsion") is None
    assert match_rank(first, "torsion") == 0


def test_match_rank_tells_dominant_from_secondary_part():
    bending = parse_mode_type("first vertical bending")
    assert match_rank(bending, "first vertical bending") == 0
    assert match_rank(bending, "roof–floor breathing + first vertical bending") == 1
    assert match_rank(bending, "second vertical bending") is None
    assert match_rank(parse_mode_type("rhombic"), "roof local") is None
