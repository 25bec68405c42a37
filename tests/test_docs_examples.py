"""Every example in the README and docs/*.md runs: the scenario file, the CLI lines (existing
commands and presets) and the curl lines of the service (against the real app)."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import yaml

from flexride.scenario.scenario import scenario_from_dict
from flexride.solver.simulate import simulate

README = Path(__file__).resolve().parents[1] / "README.md"


def _blocks(lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.S)


def test_readme_yaml_scenario_runs():
    (block,) = _blocks("yaml")
    data = yaml.safe_load(block)
    sc = scenario_from_dict(data, source="README")
    assert sc.vehicle.carbody.mass == 38000.0
    assert sc.vehicle.carbody.iyy == 1410960.0  # the rest comes from the preset
    short = sc.model_copy(update={"distance_m": 15.0})
    res = simulate(short)
    assert "carbody.SEAT12.acc.z" in res.channels
    seat = next(p for p in res.recorded_points if p["name"] == "SEAT12")
    assert (seat["body"], seat["x"], seat["y"], seat["z"]) == ("carbody", 3.0, 0.8, 1.6)


DOCS = [*sorted((README.parent / "docs").glob("*.md")), README]


def _doc_blocks(path: Path, lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.*?)```", path.read_text(encoding="utf-8"), flags=re.S)


def test_cli_examples_in_readme_and_docs_name_existing_commands_and_presets():
    from flexride.cli import app
    from flexride.cli.fe import fe_app
    from flexride.scenario.presets import PRESETS

    commands = {c.name or c.callback.__name__ for c in app.registered_commands}
    groups = {g.name for g in app.registered_groups}
    fe_commands = {c.name or c.callback.__name__ for c in fe_app.registered_commands}
    seen = 0
    for path in DOCS:
        for block in _doc_blocks(path, "bash"):
            for line in block.splitlines():
                line = line.split("#")[0].strip()
                if not line.startswith("flexride "):
                    continue
                seen += 1
                words = line.split()
                assert words[1] in commands | groups, (path.name, line)
                if words[1] == "fe":
                    assert words[2] in fe_commands, (path.name, line)
                m = re.search(r"--preset (\S+)", line)
                if m:
                    assert m.group(1) in PRESETS, (path.name, line)
    assert seen >= 8


# -- the curl examples of the service -------------------------------------------------------------

_BASE = ("$API", "http://127.0.0.1:8000/api/v1")


def _shell_commands(block: str):
    """The commands of a bash block as word lists (continuation lines and quoted text spanning
    lines joined, comments dropped)."""
    import shlex

    buf = ""
    for line in block.splitlines():
        buf += line + "\n"
        if buf.rstrip().endswith("\\"):
            continue
        try:
            words = shlex.split(buf.replace("\\\n", " "), comments=True)
        except ValueError:  # an open quote: the command goes on
            continue
        buf = ""
        if words:
            yield words


def _curl(words: list[str], files: Path) -> tuple[str, str, str | bytes | None]:
    """(method, URL, body) of a curl command line (``--data-binary @name`` from ``files``)."""
    method, url, body = "GET", None, None
    it = iter(words[1:])
    for w in it:
        if w == "-X":
            method = next(it)
        elif w in ("-d", "-H"):
            value = next(it)
            body = value if w == "-d" else body
        elif w == "--data-binary":
            body = (files / next(it).lstrip("@")).read_bytes()
        elif any(w.startswith(b) for b in _BASE):
            url = w
    assert url is not None, words
    if body is not None and method == "GET":
        method = "POST"
    return method, url, body


def _run_in(directory: Path, args: list[str]) -> None:
    """Run a ``flexride`` command in-process with ``directory`` as the working directory."""
    from typer.testing import CliRunner

    from flexride.cli import app

    cwd = os.getcwd()
    os.chdir(directory)
    try:
        r = CliRunner().invoke(app, args)
    finally:
        os.chdir(cwd)
    assert r.exit_code == 0, (args, r.output)


def test_curl_examples_in_the_docs_run_against_the_api(tmp_path):
    """Every curl line of README.md and docs/*.md, in order, against the real app (SQLite, jobs
    recorded but not run, FE exports from a stand-in build): each answers 2xx. ``$JOB`` is a
    finished job (results, flexible car body) for reads and the last submitted job for changes;
    ``$STUDY`` the last submitted study."""
    from fastapi.testclient import TestClient

    from flexride.api import create_app
    from flexride.scenario.presets import load_preset
    from service.svc_testkit import (
        insert_finished_job,
        make_settings,
        synthetic_results,
        use_fe_builds,
    )

    app = create_app(make_settings(tmp_path / "data", preflight=False))
    use_fe_builds(app, wait_s=5.0)
    svc = app.state.services
    res = synthetic_results()
    res.scenario = load_preset("paper-metro", {"bodies.carbody.model": "flexible"}).model_dump(
        mode="json")
    finished = insert_finished_job(svc.store, svc.files, res)
    ids: dict[str, str | None] = {"job": None, "study": None, "upload": None, "profile": None}
    ran = 0
    with TestClient(app, raise_server_exceptions=False) as client:
        for path in DOCS:
            for block in _doc_blocks(path, "bash"):
                for words in _shell_commands(block):
                    if words[:1] == ["printf"] and words[-2] == ">":  # a file for --data-binary
                        text = words[1].encode().decode("unicode_escape")
                        (tmp_path / words[-1]).write_text(text)
                    if words[:3] == ["flexride", "contact", "profile"]:  # a file to upload
                        _run_in(tmp_path, words[1:])
                    if words[0].endswith("=$(curl"):  # VAR=$(curl … | python3 -c …)
                        words = ["curl", *words[1:]]
                    if words[0] != "curl":
                        continue
                    method, url, body = _curl(words, tmp_path)
                    if isinstance(body, str):
                        body = body.replace('"UPLOAD"', json.dumps(ids["upload"]))
                        body = body.replace('"RAIL"', json.dumps(ids["profile"]))
                    for base in _BASE:
                        url = url.replace(base, "/api/v1")
                    job = finished if method == "GET" else ids["job"]
                    url = url.replace("$JOB", str(job)).replace("JOB_ID", str(job))
                    url = url.replace("$STUDY", str(ids["study"]))
                    r = client.request(method, url, content=body,
                                       headers={"Content-Type": "application/json"})
                    assert r.status_code in (200, 201, 202, 204), (path.name, words, r.text)
                    if method == "POST" and url.endswith(("/jobs", "/studies")):
                        ids["job" if url.endswith("/jobs") else "study"] = r.json()["id"]
                    if method == "POST" and url.endswith("/irregularities"):
                        ids["upload"] = r.json()["id"]
                    if method == "POST" and "/profiles?" in url:
                        ids["profile"] = r.json()["id"]
                    ran += 1
        # the error example of docs/service.md is what the API answers
        (example,) = _doc_blocks(README.parent / "docs" / "service.md", "json")
        r = client.post("/api/v1/jobs", json={"preset": "paper-metro",
                                              "overrides": {"speed_kmh": 500}})
        item = json.loads(example)["detail"][0]
        assert r.status_code == 422 and r.json()["detail"][0] == item
    assert ran >= 35
