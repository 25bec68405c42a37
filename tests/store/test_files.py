"""Result files: names, partial reads, description, copies, deletion."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.errors import ResultsFileError
from flexride.store import ResultFiles
from service.svc_testkit import synthetic_results

JOB = "0123456789abcdef0123456789abcdef"


@pytest.fixture
def files(tmp_path):
    f = ResultFiles(tmp_path / "results")
    synthetic_results(duration=6.0).write_hdf5(f.path(f.name_for(JOB)))
    return f


def test_read_selected_channels_and_time_range(files):
    data = files.read(f"{JOB}.h5", ["carbody.PR.acc.z"], t_start=1.0, t_end=2.0)
    assert list(data.channels) == ["carbody.PR.acc.z"] and data.sample_rate == 1000.0
    assert data.time[0] == 1.0 and data.time[-1] == 2.0 and data.time.size == 1001
    assert data.channels["carbody.PR.acc.z"].size == data.distance.size == 1001
    assert data.units["carbody.PR.acc.z"] == "m/s^2" and data.scenario["name"] == "synthetic"
    with pytest.raises(KeyError, match=r"carbody\.PR\.acc\.z"):
        files.read(f"{JOB}.h5", ["nope"])


def test_describe_copy_delete(files):
    d = files.describe(f"{JOB}.h5")
    assert d["n_samples"] == 6000 and "carbody.PC.acc.y" in d["channels"]
    other = "f" * 32
    name = files.copy(f"{JOB}.h5", other)
    a = files.read(name, ["carbody.PC.acc.y"]).channels["carbody.PC.acc.y"]
    np.testing.assert_array_equal(a, files.read(f"{JOB}.h5",
                                                ["carbody.PC.acc.y"]).channels["carbody.PC.acc.y"])
    assert files.delete(f"{JOB}.h5") and not files.exists(f"{JOB}.h5")
    assert files.exists(name)  # the copy is independent
    assert not files.delete(f"{JOB}.h5") and not files.delete(None)
    assert not files.exists("../x.h5")


def test_bad_files_and_names(files):
    with pytest.raises(ResultsFileError):
        files.name_for("../../etc")
    bad = files.path("e" * 32 + ".h5")
    bad.write_bytes(b"not hdf5")
    with pytest.raises(ResultsFileError):
        files.describe(bad.name)
    with pytest.raises(ResultsFileError, match="not found"):
        files.read("d" * 32 + ".h5", ["a"])
