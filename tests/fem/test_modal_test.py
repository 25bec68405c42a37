"""Measured modal data: the CSV reader's checks, the docs' example, sensors at model nodes."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from flexride.errors import FEModelError
from flexride.fem.modal_test import parse_modal_test, read_modal_test, sensor_nodes

DOCS = Path(__file__).resolve().parents[2] / "docs" / "fem.md"
GOOD = """# comment
x_m,y_m,z_m,direction,mode_5.0Hz,mode_6.5Hz:rhombic

0,0,1.1,z,1.0,0.1
0,0,3.8,y,0.2,-1.0
6.3,1.4,2.0,Y,-0.5,0.3
"""


def _docs_csv() -> str:
    (block,) = re.findall(r"```csv\n(.*?)```", DOCS.read_text(encoding="utf-8"), flags=re.S)
    return block


def test_a_good_file(tmp_path):
    path = tmp_path / "test.csv"
    path.write_text(GOOD, encoding="utf-8-sig")  # a byte-order mark, as spreadsheets write
    test = read_modal_test(path)
    assert test.source == "test.csv" and test.sensors.n_dofs == 3
    assert test.sensors.lines == (4, 5, 6)
    assert test.sensors.directions.tolist() == [2, 1, 1]
    assert np.allclose(test.sensors.positions[2], [6.3, 1.4, 2.0])
    (a, b) = test.targets
    assert (a.frequency_hz, a.mode_type, a.label) == (5.0, None, "mode_5.0Hz")
    assert (b.frequency_hz, b.mode_type) == (6.5, "rhombic")
    assert b.shape is not None and b.shape.tolist() == [0.1, -1.0, 0.3]


HEAD = "x_m,y_m,z_m,direction,mode_5Hz,mode_6Hz"
ROWS = ["0,0,1.1,z,1,0", "1,0,1.1,z,0,1"]


def _text(head: str = HEAD, rows: list[str] = ROWS) -> str:
    return "\n".join([head, *rows]) + "\n"


@pytest.mark.parametrize(("text", "message"), [
    ("# only a comment\n", "no header line"),
    (_text("x,y,z,direction,mode_5Hz"), r"line 1: the header must start with x_m,y_m,z_m"),
    (_text("x_m,y_m,z_m,direction"), "line 1: no mode columns"),
    (_text("x_m,y_m,z_m,direction,mode_5Hz,freq6"), r"line 1, column 6 'freq6': a mode column"),
    (_text("x_m,y_m,z_m,direction,mode_5Hz,mode_-6Hz"), r"column 6 'mode_-6Hz'"),
    (_text("x_m,y_m,z_m,direction,mode_5Hz,mode_6Hz:wobble"),
     r"column 'mode_6Hz:wobble': unknown mode type 'wobble'"),
    (_text(rows=["0,0,1.1,z,1,0", "1,abc,1.1,z,0,1"]), r"line 3, column 2 'y_m': 'abc' is not"),
    (_text(rows=["0,0,1.1,z,1,0", "1,0,1.1,z,0,nan"]), r"line 3, column 6 'mode_6Hz': 'nan'"),
    (_text(rows=["0,0,1.1,w,1,0", "1,0,1.1,z,0,1"]), r"line 2, column 4 'direction': direction"),
    (_text(rows=["0,0,1.1,z,1", "1,0,1.1,z,0,1"]), "line 2: 5 fields, the header has 6"),
    (_text(rows=["0,0,1.1,z,1,0", "0,0,1.1,z,0,1"]), "line 3: the same position and direction"),
    (_text(rows=["0,0,1.1,z,1,0", "1,0,1.1,z,0,0"]), r"column 'mode_6Hz': every value is zero"),
    (_text(rows=["0,0,1.1,z,1,0"]), "1 sensor rows for 2 modes"),
])
def test_format_errors_name_the_line_and_column(text, message):
    with pytest.raises(FEModelError, match=message) as err:
        parse_modal_test(text, source="t.csv")
    assert str(err.value).startswith("t.csv")


def test_unreadable_file(tmp_path):
    with pytest.raises(FEModelError, match="cannot read modal-test file"):
        read_modal_test(tmp_path / "missing.csv")
    bad = tmp_path / "latin1.csv"
    bad.write_bytes("x_m,y_m,z_m,direction,mode_5Hz\n0,0,0,z,\xe9\n".encode("latin-1"))
    with pytest.raises(FEModelError, match="cannot read modal-test file"):
        read_modal_test(bad)


def test_sensors_take_the_nearest_node_and_far_ones_are_refused():
    nodes = np.array([[0.0, 0.0, 1.1], [1.0, 0.0, 1.1], [0.0, 1.4, 2.0]])
    test = parse_modal_test(_text(rows=["0.1,0,1.1,x,1,0", "0,1.3,2.1,y,0,1"]))
    sn = sensor_nodes(nodes, test.sensors, max_distance=0.2)
    assert sn.nodes.tolist() == [0, 2] and sn.dofs.tolist() == [0, 13]
    assert sn.distances == pytest.approx([0.1, np.sqrt(0.02)])
    with pytest.raises(FEModelError, match=r"sensor on line 3 at \(0.0, 1.3, 2.1\) m is 0.14 m"):
        sensor_nodes(nodes, test.sensors, max_distance=0.1)


def test_the_docs_example_parses_and_pairs_with_the_default_body_by_mac(vehicle):
    from flexride.fem.calibration_eval import CalibrationSetup, Evaluations
    from flexride.fem.vehicle_models import carbody_params_for, carbody_target

    test = parse_modal_test(_docs_csv(), source="docs/fem.md")
    assert test.sensors.n_dofs == 15
    assert [(t.frequency_hz, t.mode_type) for t in test.targets] == [(5.32, None),
                                                                    (6.71, "rhombic")]
    setup = CalibrationSetup(
        base=carbody_params_for(vehicle), names=("floor_depth",),
        inertia=carbody_target(vehicle), element_size=0.6, n_modes=8,
        targets=tuple(test.targets), sensors=test.sensors, max_sensor_distance=0.6, min_mac=0.5)
    evaluate = Evaluations(setup)
    point = evaluate(np.log([setup.base.floor_depth]))
    assert [p.mode for p in point.pairs] == [0, 2]
    assert all(p.mac is not None and p.mac > 0.95 for p in point.pairs)
