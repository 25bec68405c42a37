"""Read caching of finished jobs' results (not timed): answers kept in memory are exact, keyed
by every parameter, never outlive their job or file, stay within their bounds; the job list
and the check of a cached answer read only small columns."""

from __future__ import annotations

import os
import re
import threading
import time

import h5py
import numpy as np
import pytest
from sqlalchemy import event

from flexride.api.services.result_cache import (
    forget_job,
    replace_response_cache,
    response_cache,
)
from flexride.store import ResultFiles
from flexride.store.lru import ByteLRU
from service.svc_testkit import insert_finished_job, services, synthetic_results

API = "/api/v1"
PR_Z, PC_Y = "carbody.PR.acc.z", "carbody.PC.acc.y"


@pytest.fixture
def finished(sqlite_client):
    svc = services(sqlite_client)
    job_id = insert_finished_job(svc.store, svc.files, synthetic_results(duration=4.0))
    return sqlite_client, svc, job_id


def _series(client, job_id, **params):
    params = {"channels": [PR_Z], "max_points": 200, **params}
    r = client.get(f"{API}/jobs/{job_id}/series", params=params)
    assert r.status_code == 200, r.text
    return r.json()


def _keys_of(svc, job_id):
    return [k for k in response_cache(svc).lru.keys() if k[0] == job_id]


def test_deleted_job_is_not_answered_from_the_cache(client):
    svc = services(client)
    job_id = insert_finished_job(svc.store, svc.files, synthetic_results(duration=4.0))
    for path in ("summary", "channels", f"series?channels={PR_Z}"):
        assert client.get(f"{API}/jobs/{job_id}/{path}").status_code == 200
        assert client.get(f"{API}/jobs/{job_id}/{path}").status_code == 200  # from the cache
    assert len(_keys_of(svc, job_id)) == 3
    assert client.delete(f"{API}/jobs/{job_id}").status_code == 204
    for path in ("summary", "channels", f"series?channels={PR_Z}"):
        assert client.get(f"{API}/jobs/{job_id}/{path}").status_code == 404
    # its entries go at the next sweep (any process may have deleted the file), or at once
    response_cache(svc).sweep(force=True)
    assert _keys_of(svc, job_id) == []
    assert not [k for k in svc.files.cache.keys() if k[1] == f"{job_id}.h5"]


def test_forget_job_drops_answers_and_file_contents(finished):
    client, svc, job_id = finished
    _series(client, job_id)
    assert _keys_of(svc, job_id) and svc.files.cache.keys()
    assert forget_job(svc, job_id) >= 2
    assert _keys_of(svc, job_id) == [] and svc.files.cache.keys() == []
    assert _series(client, job_id)["n_samples"] == 4000  # read again


def test_a_replaced_result_file_is_read_again(finished):
    client, svc, job_id = finished
    before = _series(client, job_id, method="none", max_points=5000)["channels"][0]["values"]
    path = svc.files.path(f"{job_id}.h5")
    other = synthetic_results(duration=4.0, seed=7)
    other.channels[PR_Z] = other.channels[PR_Z] + 1.0
    tmp = path.with_name("replacement.h5")
    other.write_hdf5(tmp)
    os.replace(tmp, path)
    after = _series(client, job_id, method="none", max_points=5000)["channels"][0]["values"]
    np.testing.assert_allclose(after, other.channels[PR_Z])
    assert not np.allclose(after, before)


def test_each_parameter_set_has_its_own_answer(finished):
    client, _, job_id = finished
    a = _series(client, job_id, max_points=100)
    b = _series(client, job_id, max_points=300)
    assert len(a["channels"][0]["time"]) <= 100 < len(b["channels"][0]["time"]) <= 300
    ab = _series(client, job_id, channels=[PR_Z, PC_Y])
    ba = _series(client, job_id, channels=[PC_Y, PR_Z])
    assert [c["name"] for c in ab["channels"]] == [PR_Z, PC_Y]
    assert [c["name"] for c in ba["channels"]] == [PC_Y, PR_Z]
    w = _series(client, job_id, t_start=1.0, t_end=2.0, method="none", max_points=2000)
    assert w["channels"][0]["time"][0] == 1.0 and w["channels"][0]["time"][-1] == 2.0
    assert "distance" in _series(client, job_id, distance=True)["channels"][0]
    assert "distance" not in _series(client, job_id)["channels"][0]
    lttb = _series(client, job_id, method="lttb")["channels"][0]["values"]
    assert lttb != _series(client, job_id, method="minmax")["channels"][0]["values"]
    psd = client.get(f"{API}/jobs/{job_id}/psd", params={"channels": [PR_Z], "fmax": 10})
    amp = client.get(f"{API}/jobs/{job_id}/spectrum", params={"channels": [PR_Z], "fmax": 10})
    assert psd.json()["kind"] != amp.json()["kind"]


def test_cached_answers_equal_fresh_ones_and_errors_are_not_kept(finished):
    client, svc, job_id = finished
    paths = ["summary", "channels", f"series?channels={PR_Z}&max_points=500",
             f"spectrum?channels={PR_Z}&fmax=20", f"sperling?channels={PR_Z}",
             f"correlation?reference=carbody.PRB.acc.z&channels={PR_Z}",
             f"spectrogram?channel={PR_Z}&fmax=10"]
    cached = [client.get(f"{API}/jobs/{job_id}/{p}").json() for p in paths]
    assert cached == [client.get(f"{API}/jobs/{job_id}/{p}").json() for p in paths]
    replace_response_cache(svc, max_bytes=0)  # nothing kept: computed on every request
    assert cached == [client.get(f"{API}/jobs/{job_id}/{p}").json() for p in paths]
    assert response_cache(svc).lru.keys() == []
    for _ in range(2):
        r = client.get(f"{API}/jobs/{job_id}/series", params={"channels": ["carbody.XX.acc.z"]})
        assert r.status_code == 422
    assert client.get(f"{API}/jobs/{'0' * 32}/summary").status_code == 404


def test_gzip_as_the_middleware_answers(finished):
    client, _, job_id = finished
    url = f"{API}/jobs/{job_id}/series"
    big = {"channels": [PR_Z, PC_Y], "max_points": 2000}
    for _ in range(2):  # filled, then from the cache
        gz = client.get(url, params=big, headers={"Accept-Encoding": "gzip"})
        plain = client.get(url, params=big, headers={"Accept-Encoding": "identity"})
        assert gz.headers["content-encoding"] == "gzip"
        assert "accept-encoding" in gz.headers["vary"].lower()
        assert "content-encoding" not in plain.headers
        assert int(plain.headers["content-length"]) == len(plain.content)
        assert gz.json() == plain.json()
    small = client.get(url, params={"channels": [PR_Z], "max_points": 10},
                       headers={"Accept-Encoding": "gzip"})
    assert len(small.content) < 4096 and "content-encoding" not in small.headers


def test_answer_cache_is_bounded(finished):
    client, svc, job_id = finished
    cache = replace_response_cache(svc, max_bytes=120_000, max_entries=100)
    first = _series(client, job_id, max_points=400)
    for n in range(410, 600, 10):
        _series(client, job_id, max_points=n)
    stats = cache.lru.stats()
    assert stats.bytes <= 120_000 and stats.evictions > 0
    assert not [k for k in cache.lru.keys() if k[4][1] == 400]  # the oldest went first
    assert _series(client, job_id, max_points=400) == first
    few = replace_response_cache(svc, max_bytes=10**8, max_entries=3)
    for n in (100, 200, 300, 400):
        _series(client, job_id, max_points=n)
    assert few.lru.stats().entries == 3


def _file(tmp_path, duration=2.0):
    files_dir = tmp_path / "results"
    res = synthetic_results(duration=duration)
    name = "0123456789abcdef0123456789abcdef.h5"
    ResultFiles(files_dir).path(name)
    res.write_hdf5(files_dir / name)
    return files_dir, name, res


def test_file_contents_cache_is_bounded_and_read_only(tmp_path):
    root, name, res = _file(tmp_path)  # 2000 samples: 16 kB per channel
    files = ResultFiles(root, cache_bytes=100_000)
    chans = sorted(res.channels)[:8]
    for c in chans:
        data = files.read(name, [c])
        np.testing.assert_array_equal(data.channels[c], res.channels[c])
        assert not data.channels[c].flags.writeable and not data.time.flags.writeable
        with pytest.raises(ValueError, match="read-only"):
            data.channels[c][0] = 1.0
    stats = files.cache_stats()
    assert 0 < stats.bytes <= 100_000 and stats.evictions > 0
    # a dataset larger than a quarter of the bound is read alone, never kept
    small = ResultFiles(root, cache_bytes=40_000)
    data = small.read(name, [PR_Z], t_start=0.5, t_end=0.6)
    np.testing.assert_array_equal(data.channels[PR_Z], res.channels[PR_Z][500:601])
    assert not [k for k in small.cache.keys() if k[0] == "dataset"]


def test_file_contents_are_not_read_again(tmp_path, monkeypatch):
    root, name, _ = _file(tmp_path)
    files = ResultFiles(root)
    opened = []
    real = h5py.File

    def counting(*a, **kw):
        opened.append(a[0])
        return real(*a, **kw)

    monkeypatch.setattr(h5py, "File", counting)
    for _ in range(3):
        files.read(name, [PR_Z, PC_Y], t_start=0.2)
        files.describe(name)
    assert len(opened) == 5  # once each: the facts, two channels, distance, describe()
    d = files.describe(name)
    d["channels"].clear()  # callers get their own copy
    assert files.describe(name)["channels"]


def test_lru_bounds_and_single_flight():
    lru = ByteLRU(max_bytes=100, max_entries=10, max_entry_fraction=0.5)
    for i in range(5):
        assert lru.put(i, i, 30)
    assert lru.keys() == [2, 3, 4] and lru.stats().bytes == 90
    assert lru.get(2) == 2 and lru.put(5, 5, 30)  # 2 was used: 3 goes
    assert lru.keys() == [4, 2, 5]
    assert not lru.put("huge", 0, 51)  # more than half the bound: not kept
    assert lru.keys() == [4, 2, 5] and lru.stats().evictions == 3
    calls = []

    def make():
        calls.append(1)
        time.sleep(0.05)
        return "value", 10

    threads = [threading.Thread(target=lambda: lru.get_or_make("k", make)) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(calls) == 1 and lru.get("k") == "value"


def _statements(engine):
    seen: list[str] = []

    def record(_conn, _cursor, statement, *_args):
        if "flexride_jobs" in statement:
            seen.append(statement)

    event.listen(engine, "before_cursor_execute", record)
    return seen, lambda: event.remove(engine, "before_cursor_execute", record)


def test_list_and_cached_results_read_only_small_columns(client):
    svc = services(client)
    job_id = insert_finished_job(svc.store, svc.files, synthetic_results(duration=4.0))
    assert client.get(f"{API}/jobs/{job_id}/summary").status_code == 200
    seen, stop = _statements(svc.store.engine)
    try:
        page = client.get(f"{API}/jobs").json()
        assert page["total"] == 1 and page["items"][0]["id"] == job_id
        listing = list(seen)
        seen.clear()
        assert client.get(f"{API}/jobs/{job_id}/summary").status_code == 200
        check = list(seen)
    finally:
        stop()
    big = re.compile(r"flexride_jobs\.(scenario|summary)\b")
    assert len(listing) == 2 and not any(big.search(s) for s in listing), listing
    # a cached answer of a job whose file was seen: no query at all (its file is checked)
    assert check == []


def test_first_answer_of_a_job_checks_its_record(client):
    svc = services(client)
    job_id = insert_finished_job(svc.store, svc.files, synthetic_results(duration=4.0))
    seen, stop = _statements(svc.store.engine)
    try:
        assert client.get(f"{API}/jobs/{job_id}/summary").status_code == 200
    finally:
        stop()
    assert re.search(r"SELECT flexride_jobs\.result_file\s+FROM", seen[0]), seen


def test_a_vanished_file_sends_the_request_to_the_database(finished):
    client, svc, job_id = finished
    assert client.get(f"{API}/jobs/{job_id}/summary").status_code == 200
    path = svc.files.path(svc.store.get_job(job_id).result_file)
    aside = path.with_name(".deleting-" + path.name)
    os.replace(path, aside)  # as a deletion in another process does before it deletes
    r = client.get(f"{API}/jobs/{job_id}/summary")
    assert r.status_code == 404 and "not found" in r.json()["detail"]
    os.replace(aside, path)  # the deletion failed and put it back
    assert client.get(f"{API}/jobs/{job_id}/summary").status_code == 200
