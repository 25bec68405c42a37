"""Measured irregularities from a file, an upload or inline rows: one parser, one set of
checks, and sources that decide what may be read."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

from flexride.errors import ScenarioError
from flexride.scenario.excitation import MeasuredIrregularity
from flexride.track.excitation import build_profile
from flexride.track.measured import (
    MeasuredSources,
    load_measured,
    parse_measured_csv,
    table_from_rows,
)

CSV = b"distance_m,vertical,gauge\n0,0,0.001\n1,0.002,0\n2,0.001,-0.001\n3,0,0\n"
COLUMNS = ["distance_m", "vertical", "gauge"]
ROWS = [[0, 0, 0.001], [1, 0.002, 0], [2, 0.001, -0.001], [3, 0, 0]]


def _upload(tmp_path, data: bytes = CSV) -> str:
    digest = hashlib.sha256(data).hexdigest()
    (tmp_path / f"{digest}.csv").write_bytes(data)
    return digest


def test_rows_file_and_upload_give_the_same_table(tmp_path):
    path = tmp_path / "rec.csv"
    path.write_bytes(CSV)
    sources = MeasuredSources(upload_dir=tmp_path, allow_paths=True)
    tables = [load_measured(MeasuredIrregularity(path=str(path)), sources),
              load_measured(MeasuredIrregularity(upload=_upload(tmp_path)), sources),
              load_measured(MeasuredIrregularity(columns=COLUMNS, rows=ROWS), sources)]
    for t in tables[1:]:
        np.testing.assert_array_equal(t.distance, tables[0].distance)
        assert t.columns.keys() == tables[0].columns.keys() == {"vertical", "gauge"}
        for k in t.columns:
            np.testing.assert_array_equal(t.columns[k], tables[0].columns[k])


def test_inline_rows_build_the_interpolated_profile():
    exc = MeasuredIrregularity(columns=COLUMNS, rows=ROWS, scale=2.0)
    p = build_profile([exc], 4.0, ds=0.5)
    # z_left = z_right = 2·vertical, y_left = +gauge, y_right = −gauge (2 × g/2), zero outside
    s = np.arange(p.n) * 0.5
    zv = np.interp(s, [0, 1, 2, 3], [0, 0.002, 0.001, 0], right=0.0)
    g = np.interp(s, [0, 1, 2, 3], [0.001, 0, -0.001, 0], right=0.0)
    np.testing.assert_allclose(p.z_left, 2 * zv, atol=1e-15)
    np.testing.assert_allclose(p.z_right, 2 * zv, atol=1e-15)
    np.testing.assert_allclose(p.y_left, g, atol=1e-15)
    np.testing.assert_allclose(p.y_right, -g, atol=1e-15)


def test_service_sources_never_read_a_path(tmp_path):
    secret = tmp_path / "secret.csv"
    secret.write_text("distance_m,vertical\n0,0\n1,0\n")
    service = MeasuredSources(upload_dir=tmp_path, allow_paths=False)
    with pytest.raises(ScenarioError) as info:
        load_measured(MeasuredIrregularity(path=str(secret)), service)
    assert info.value.items[0].loc == ("path",)
    assert str(tmp_path) not in str(info.value)


def test_uploads_need_an_upload_store():
    with pytest.raises(ScenarioError, match="only available in the service"):
        load_measured(MeasuredIrregularity(upload="0" * 64))


def test_missing_upload_names_no_directory(tmp_path):
    with pytest.raises(ScenarioError) as info:
        load_measured(MeasuredIrregularity(upload="a" * 64), MeasuredSources(tmp_path, False))
    assert "no such file" in str(info.value) and str(tmp_path) not in str(info.value)
    assert info.value.items[0].loc == ("upload",)


@pytest.mark.parametrize(("data", "needle"), [
    (b"distance_m,vertical\n0,0\n1,\xff\n", "not UTF-8"),
    (b"\xef\xbb\xbfdistance_m,vertical\n0,0\n1,0.001\n", None),  # BOM is fine
    (b"distance_m,vertical\n0,0\n0.0005,0\n0.001,0\n", "below 0.001 m"),
    (b"distance_m,vertical\n0,0\n1,inf\n", "not a finite number"),
    (b"PATH=/usr/bin:/bin\nHOME=/root\nTOKEN=s3cr3t\n", "missing distance column"),
])
def test_csv_checks(data, needle):
    if needle is None:
        assert parse_measured_csv(data, "up").distance.size == 2
        return
    with pytest.raises(ScenarioError, match=needle) as info:
        parse_measured_csv(data, "up")
    assert "s3cr3t" not in str(info.value) and "/usr/bin" not in str(info.value)


@pytest.mark.parametrize(("rows", "needle"), [
    ([[0, 0], [1]], "row 1: expected 2 cells"),
    ([[0, 0], [0, 0]], "row 1, column 'distance_m': distance must be strictly increasing"),
    ([[0, 0]], "at least two data rows"),
])
def test_row_checks_name_the_row(rows, needle):
    with pytest.raises(ScenarioError, match=needle):
        table_from_rows(["distance_m", "vertical"], rows)


def test_errors_are_located_at_the_excitation_in_a_scenario(tmp_path):
    from flexride.scenario.presets import preset_dict
    from flexride.scenario.scenario import scenario_from_dict
    from flexride.solver.assemble import assemble

    data = preset_dict("paper-metro")
    data["excitation"] = [{"kind": "settlement"},
                          {"kind": "measured", "columns": ["distance_m", "vertical"],
                           "rows": [[0, 0], [0, 0]]}]
    with pytest.raises(ScenarioError) as info:
        assemble(scenario_from_dict(data))
    assert info.value.items[0].loc == ("excitation", 1, "rows")
