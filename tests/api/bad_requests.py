"""Families of bad requests, hand-made: what an attacker or a careless client sends. Shared by
the in-process run on SQLite and PostgreSQL (tests/api/test_bad_input.py) and the live
service that holds secrets (tests/api/test_no_secret_leaks.py).

Each request is ``(method, path below /api/v1, httpx keyword arguments)``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

Request = tuple[str, str, dict[str, Any]]

SERVER_PATHS = ["/proc/self/environ", "/proc/self/cmdline", "/etc/passwd",
                "../../../../etc/passwd", "/dev/zero", "~/.bash_history", "flexride.db",
                "results/x.h5"]
"""Server files a request may try to reach."""

BAD_IDS = ["%00", "%00" + "0" * 31, "0" * 31 + "%00", "%1b%5b31m", "%0a" + "0" * 32,
           "0" * 32 + "%0d%0aX-Injected:%201", "..%2F..%2Fetc%2Fpasswd", "x" * 300, "0" * 31,
           "0" * 33, "g" * 32, "%E2%80%AE" + "0" * 29, "%F0%9F%98%80", "%20" + "0" * 32,
           "-1", "1e400", "null", "%7B%7D", "0" * 8 + "_" + "0" * 23]
"""Path segments that are not job or study ids (percent-encoded as sent)."""

NUL = "\x00"


def id_spellings(job_id: str) -> list[str]:
    """Spellings of the same UUID a client may send (``job_id`` in the stored form)."""
    dashed = f"{job_id[:8]}-{job_id[8:12]}-{job_id[12:16]}-{job_id[16:20]}-{job_id[20:]}"
    return [job_id, job_id.upper(), dashed, dashed.upper(), f"%7B{dashed}%7D",
            f"urn:uuid:{dashed}"]


def id_routes(spec: dict[str, Any]) -> list[tuple[str, str, str]]:
    """``(method, path template, id parameter)`` of every operation of the OpenAPI document
    that takes a job or study id in its path (other parameters filled in)."""
    out = []
    for path, ops in spec["paths"].items():
        for name in ("job_id", "study_id"):
            if "{" + name + "}" in path:
                filled = path.removeprefix("/api/v1").replace("{kind}", "carbody")
                out += [(m.upper(), filled, name) for m in ops]
    return out


def nul_bodies() -> list[tuple[str, dict[str, Any], list[str | int]]]:
    """``(path, JSON body, where the NUL is)`` of request bodies with a NUL character in a
    text, a key, a list item."""
    job = {"preset": "paper-metro", "overrides": {"duration_s": 0.5, "distance_m": None}}
    base = {"preset": "paper-metro"}
    return [
        ("/jobs", {**job, "name": f"a{NUL}b"}, ["body", "name"]),
        ("/jobs", {"scenario": {"preset": "paper-metro", "name": f"x{NUL}"}},
         ["body", "scenario", "name"]),
        ("/jobs", {"scenario": {"preset": "paper-metro", "description": NUL}},
         ["body", "scenario", "description"]),
        ("/jobs", {**job, "overrides": {f"name{NUL}": 1}}, ["body", "overrides", f"name{NUL}"]),
        ("/jobs", {"preset": f"paper-metro{NUL}"}, ["body", "preset"]),
        ("/jobs/validate", {**job, "overrides": {"output.points": [{"name": NUL}]}},
         ["body", "overrides", "output.points", 0, "name"]),
        ("/studies", {"name": "s", "description": f"d{NUL}", "base": base,
                      "speeds_kmh": [60]}, ["body", "description"]),
        ("/studies", {"name": "s", "base": base, "conditions": [f"random{NUL}"]},
         ["body", "conditions", 0]),
        ("/estimates", {"preset": "paper-metro", "points": [f"PC{NUL}"]},
         ["body", "points", 0]),
    ]


def query_families() -> list[Request]:
    """Query strings with control characters, wrong types and out-of-range values."""
    reqs: list[Request] = []
    for value in ("%00", "%1b%5b31m", "%0a", "x" * 5000, "-1", "1e400", "nan", "%F0%9F%98%80"):
        reqs += [("GET", f"/jobs?study_id={value}", {}), ("GET", f"/jobs?status={value}", {}),
                 ("GET", f"/jobs?kind={value}", {}), ("GET", f"/jobs?limit={value}", {}),
                 ("GET", f"/studies?offset={value}", {}),
                 ("GET", f"/presets/{value}", {}), ("GET", f"/study-presets/{value}", {}),
                 ("GET", f"/fe/carbody?preset={value}", {}),
                 ("GET", f"/contact/geometry?wheel={value}", {}),
                 ("GET", f"/irregularities/{value}", {}), ("GET", f"/profiles/{value}", {})]
    return reqs


def hostile_requests(secret: str) -> list[Request]:
    """Requests that try to reach server files or provoke error texts (``secret`` is put
    where an answer might echo it)."""
    reqs: list[Request] = []
    environ = Path("/proc/self/environ").read_bytes()
    for p in SERVER_PATHS:
        measured = {"kind": "measured", "path": p}
        for ep in ("/jobs/validate", "/jobs"):
            reqs.append(("POST", ep, {"json": {"preset": "paper-metro",
                                                "overrides": {"excitation": [measured]}}}))
            reqs.append(("POST", ep, {"json": {"scenario": {"preset": "paper-metro",
                                                             "excitation": [measured]}}}))
        reqs.append(("POST", "/jobs", {"json": {"preset": p}}))
        reqs.append(("POST", "/jobs/validate", {"json": {"preset": "paper-metro",
                                                         "overrides": {p: 1}}}))
        reqs.append(("GET", f"/jobs/{p}", {}))
        reqs.append(("GET", f"/fe/carbody?preset={p}", {}))
        reqs.append(("GET", f"/irregularities/{p}", {}))
        reqs.append(("GET", f"/presets/{p}", {}))
        reqs.append(("POST", f"/irregularities?distance_column={p}", {"content": environ}))
        reqs.append(("GET", f"/profiles/{p}", {}))
        reqs.append(("POST", "/jobs/validate", {"json": {"preset": "paper-metro", "overrides": {
            "contact": {"geometry": "profiles", "wheel": {"path": p}}}}}))
    reqs.append(("POST", "/irregularities", {"content": f"TOKEN={secret}\n".encode()}))
    for fmt in ("txt", "prw", "ban"):
        reqs.append(("POST", f"/profiles?format={fmt}&kind=rail", {"content": environ}))
        reqs.append(("POST", f"/profiles?format={fmt}&kind=wheel",
                     {"content": f"0 {secret}\n1 2\n".encode()}))
    return reqs


def malformed_bodies() -> list[Request]:
    """Bodies that are not what the endpoint reads: broken JSON, wrong types, NaN, deep
    nesting, bytes that are not UTF-8."""
    raw = {"headers": {"content-type": "application/json"}}
    reqs: list[Request] = []
    for ep in ("/jobs", "/jobs/validate", "/studies", "/estimates"):
        for content in (b"{not json", b'{"preset": "paper-metro", "overrides": {"x": NaN}}',
                        b"[" * 5000 + b"]" * 5000, b'"just a string"', b"\xff\xfe\x00",
                        b'{"preset": 1}', b'{"scenario": []}', b"{}", b""):
            reqs.append(("POST", ep, {"content": content, **raw}))
    return reqs
