"""``flexride contact conicity`` and ``flexride contact table`` (in-process, typer's runner).

Oracles: a cone's Δr table gives its conicity; the S1002/60E1 1:40 no-roll regression value of
the reference (3 mm → 0.174); the table's columns against the relations that define them
(Δr = r_left − r_right, σ = b0·roll/Δy); exit code 2 and one line for user errors.
"""

from __future__ import annotations

import csv
import io
import json

import pytest
from typer.testing import CliRunner

from contact.profile_data import mbench_file
from flexride.cli import app


def _invoke(*args: str) -> tuple[int, str, str]:
    r = CliRunner().invoke(app, ["contact", *args])
    return r.exit_code, r.stdout, " ".join(r.stderr.split())


def test_conicity_json_of_the_default_pair() -> None:
    code, out, err = _invoke("conicity", "--no-roll", "--json")
    assert code == 0, err
    rows = json.loads(out)
    assert [r["amplitude_mm"] for r in rows] == [1.0 + 0.5 * k for k in range(14)]
    got = {r["amplitude_mm"]: r["tan_gamma_e"] for r in rows}
    assert got[3.0] == pytest.approx(0.174, abs=0.002)
    code, out, _ = _invoke("conicity", "--no-roll", "--json", "--method", "harmonic",
                           "--amplitudes-mm", "3")
    assert code == 0 and json.loads(out)[0]["tan_gamma_e"] == pytest.approx(0.176, abs=0.002)


def test_conicity_of_a_delta_r_table(tmp_path) -> None:
    f = tmp_path / "cone.csv"
    rows = ["y_mm,delta_r_mm"] + [f"{y / 10:.1f},{2 * 0.07 * y / 10:.6f}"
                                  for y in range(-120, 121)]
    f.write_text("\n".join(rows) + "\n")
    code, out, err = _invoke("conicity", "--delta-r", str(f), "--json")
    assert code == 0, err
    assert all(r["tan_gamma_e"] == pytest.approx(0.07, rel=1e-6) for r in json.loads(out))
    code, out, _ = _invoke("conicity", "--delta-r", str(f))
    assert code == 0 and "0.0700" in out and "cone.csv" in out


def test_conicity_with_profile_files() -> None:
    code, out, err = _invoke("conicity", "--json", "--no-roll", "--wheel",
                             str(mbench_file("MBench_S1002_v3.prw")), "--rail",
                             str(mbench_file("MBench_UIC60_v3.prr")), "--inclination", "none",
                             "--amplitudes-mm", "3")
    assert code == 0, err
    assert json.loads(out)[0]["tan_gamma_e"] == pytest.approx(0.180, abs=0.002)


def test_table_csv_columns_are_consistent(tmp_path) -> None:
    out_file = tmp_path / "t.csv"
    code, out, err = _invoke("table", "--y-max-mm", "6", "--every-mm", "0.5", "--output",
                             str(out_file))
    assert code == 0, err
    assert "wrote 25 rows to t.csv" in out
    rows = list(csv.DictReader(io.StringIO(out_file.read_text())))
    assert len(rows) == 25 and rows[12]["dy_mm"] == "0.0"
    for r in rows:
        dr = float(r["r_left_mm"]) - float(r["r_right_mm"])
        assert float(r["dr_mm"]) == pytest.approx(dr, abs=2e-5)
        if r["roll_coefficient"] and float(r["dy_mm"]) != 0.0:
            sigma = 750.0 * float(r["roll_rad"]) / float(r["dy_mm"])
            assert float(r["roll_coefficient"]) == pytest.approx(sigma, rel=1e-3, abs=1e-6)
    # the jump of S1002 on 60E1 at 1:40 just off the centre (contact on the left wheel)
    s0 = float(rows[12]["wheel_left_mm"])
    s05 = float(rows[13]["wheel_left_mm"])
    assert s0 > 3.0 and s05 < -7.0


def test_table_json_and_terminal() -> None:
    code, out, err = _invoke("table", "--json", "--y-max-mm", "2", "--no-roll")
    assert code == 0, err
    data = json.loads(out)
    assert "dr_mm" in data["columns"] and len(data["rows"]) == 81
    assert all(r["roll_rad"] == 0.0 for r in data["rows"])
    code, out, err = _invoke("table", "--y-max-mm", "2")
    assert code == 0, err
    assert "Δr" in out and "S1002" in out


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (("conicity", "--wheel", "missing.prw"), "error: --wheel: missing.prw: no such file"),
        (("conicity", "--inclination", "steep"), "error: rail inclination must be '1:N'"),
        (("conicity", "--method", "linear"), "error: --method must be integration or harmonic"),
        (("conicity", "--amplitudes-mm", "0"), "error: --amplitudes-mm must be positive"),
        (("table", "--format", "xml"), "error: --format must be table, csv or json"),
        (("table", "--gauge-mm", "1200", "--flange-back-mm", "1360"),
         "error: flange-back distance"),
    ],
)
def test_errors_exit_2_with_one_line(args: tuple[str, ...], expected: str) -> None:
    code, _, err = _invoke(*args)
    assert code == 2 and err.startswith(expected), err
    assert "Traceback" not in err


def test_bad_files_exit_2_naming_file_and_line(tmp_path) -> None:
    f = tmp_path / "dr.csv"
    f.write_text("y_mm,delta_r_mm\n0,0\n-1,1\n2,2\n")
    code, _, err = _invoke("conicity", "--delta-r", str(f))
    assert code == 2 and err.startswith("error: dr.csv, line 3: y_mm must increase")
    w = tmp_path / "w.txt"
    w.write_text("0 0\n1 1\n")
    code, _, err = _invoke("table", "--wheel", str(w))
    assert code == 2 and err.startswith("error: w.txt: a wheel profile needs at least 10")
    assert str(tmp_path) not in err


def test_profile_text_export_reads_back_as_the_same_contact_geometry(tmp_path) -> None:
    """A built-in pair written as text (0.1 mm apart) and read back by the text reader gives
    the built-in pair's equivalent conicity (3 mm: within 0.1 %), and a converted MiniProf or
    SIMPACK file the one of the original."""
    files = {}
    for kind, name in (("wheel", "s1002"), ("rail", "60e1")):
        files[kind] = tmp_path / f"{name}.txt"
        code, out, err = _invoke("profile", kind, name, "-o", str(files[kind]),
                                 "--every-mm", "0.1")
        assert code == 0 and "points to" in out, err
        assert files[kind].read_text().startswith("# ")
    args = ("conicity", "--json", "--amplitudes-mm", "3")
    _, builtin, _ = _invoke(*args)
    _, text, _ = _invoke(*args, "--wheel", str(files["wheel"]), "--rail", str(files["rail"]))
    assert json.loads(text)[0]["tan_gamma_e"] == pytest.approx(
        json.loads(builtin)[0]["tan_gamma_e"], rel=1e-3)
    converted = tmp_path / "wheel-from-prw.txt"
    code, _, err = _invoke("profile", "wheel", str(mbench_file("MBench_S1002_v3.prw")), "-o",
                           str(converted), "--every-mm", "0.1")
    assert code == 0, err
    _, text, _ = _invoke(*args, "--wheel", str(converted))
    assert json.loads(text)[0]["tan_gamma_e"] == pytest.approx(
        json.loads(builtin)[0]["tan_gamma_e"], rel=5e-3)


def test_profile_export_errors_exit_2(tmp_path) -> None:
    code, _, err = _invoke("profile", "wheel", "nope", "-o", str(tmp_path / "x.txt"))
    assert code == 2 and err == "error: --wheel: nope: no such file (built-in: s1002)"
    code, _, err = _invoke("profile", "rail", "60e1", "-o", str(tmp_path / "x.txt"),
                           "--every-mm", "0")
    assert code == 2 and "--every-mm" in err
