"""HDF5 results file: round trip, attributes, atomic write."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from flexride.errors import ResultsFileError
from flexride.results import Results


def _results():
    t = np.arange(100) / 1000.0
    return Results(time=t, distance=t * 20, channels={"carbody.PC.acc.z": np.sin(t)},
                   units={"carbody.PC.acc.z": "m/s^2"}, scenario={"name": "x"},
                   meta={"output_rate": 1000.0})


def test_round_trip(tmp_path):
    r = _results()
    p = r.write_hdf5(tmp_path / "sub" / "r.h5")
    back = Results.read_hdf5(p)
    assert np.array_equal(back.channels["carbody.PC.acc.z"], r.channels["carbody.PC.acc.z"])
    assert back.units["carbody.PC.acc.z"] == "m/s^2"
    assert back.scenario == {"name": "x"} and back.sample_rate == 1000.0
    with h5py.File(p) as f:
        assert f["time"].attrs["unit"] == "s"


def test_failed_write_leaves_nothing(tmp_path, monkeypatch):
    r = _results()
    r.channels["bad"] = object()  # not storable
    with pytest.raises(TypeError):
        r.write_hdf5(tmp_path / "r.h5")
    assert list(tmp_path.iterdir()) == []


def test_not_a_results_file(tmp_path):
    p = tmp_path / "x.h5"
    with h5py.File(p, "w") as f:
        f["a"] = 1
    with pytest.raises(ResultsFileError, match="not a flexride results file"):
        Results.read_hdf5(p)
    with pytest.raises(ResultsFileError, match="not found"):
        Results.read_hdf5(tmp_path / "missing.h5")
