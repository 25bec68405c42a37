"""Calibration targets and their command-line spelling."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.errors import FEModelError
from flexride.fem.targets import ModeTarget, as_targets, parse_targets


def test_typed_and_untyped_targets_in_any_order():
    t = parse_targets("8.84:first vertical bending, 5.03:torsion;6.11:Rhombic,7.40")
    assert [x.frequency_hz for x in t] == [8.84, 5.03, 6.11, 7.40]
    assert [x.mode_type for x in t] == ["first vertical bending", "torsion", "rhombic", None]


def test_type_stored_in_the_classifiers_spelling():
    assert ModeTarget(5.0, "roof-floor  breathing").mode_type == "roof–floor breathing"
    assert ModeTarget(5.0, "first torsion").mode_type == "torsion"


@pytest.mark.parametrize(("text", "message"), [
    ("", "no targets"),
    (" , ", "no targets"),
    ("5.03,abc", r"target 2 'abc': 'abc' is not a frequency"),
    ("5.03:", "a mode type must follow"),
    ("-5:torsion", "positive"),
    ("nan", "positive"),
    ("5.03:wobble", r"target 1 '5.03:wobble': unknown mode type 'wobble': use one of"),
])
def test_bad_targets_are_named(text, message):
    with pytest.raises(FEModelError, match=message):
        parse_targets(text)


def test_shapes_are_checked_and_frozen():
    t = ModeTarget(6.0, shape=[1.0, -2.0, 0.5])
    assert t.shape is not None and not t.shape.flags.writeable
    with pytest.raises(FEModelError, match="not all zero"):
        ModeTarget(6.0, shape=np.zeros(3))
    with pytest.raises(FEModelError, match="finite"):
        ModeTarget(6.0, shape=[1.0, np.inf])


def test_bare_frequencies_become_untyped_targets():
    t = as_targets([5.0, ModeTarget(6.0, "rhombic")])
    assert [(x.frequency_hz, x.mode_type) for x in t] == [(5.0, None), (6.0, "rhombic")]
    with pytest.raises(FEModelError, match="no targets"):
        as_targets([])
