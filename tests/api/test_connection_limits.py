"""Slow and greedy clients against a real ``flexride serve`` (uvicorn with the limits of
flexride.api.server), over raw sockets: a request whose headers or body do not arrive in time
gets 408 and its connection is closed; a request without the token is refused from its headers,
before its body; a client address beyond its connections gets 429; the log holds no raw
control character. The servers run with short limits; the test waits for their answers
(a socket timeout only ends a test that would otherwise hang).
"""

from __future__ import annotations

import socket
import sys
import time
from collections.abc import Iterator

import pytest

from service.svc_testkit import REPO, TEST_TOKEN, wait_for

sys.path.insert(0, str(REPO / "tools"))
from live_server import LiveServer, start_server

SAFETY_S = 60.0
"""A socket read that takes longer fails the test (it would mean no limit at all)."""
PER_CLIENT = 3


def _serve(tmp_path_factory, name: str, **limits: str) -> Iterator[LiveServer]:
    data = tmp_path_factory.mktemp(name)
    env = {"FLEXRIDE_API_TOKEN": TEST_TOKEN, "FLEXRIDE_RUNNER": "none",
           "FLEXRIDE_LOG_LEVEL": "info", **limits}
    server = start_server(data / "data", cache_dir=data / "cache", log=data / "serve.log",
                          env=env)
    try:
        yield server
    finally:
        server.stop()


@pytest.fixture(scope="module")
def tight(tmp_path_factory):
    """A server that gives 2 s for headers, 2 s between parts of a body, 4 s for a body."""
    yield from _serve(tmp_path_factory, "tight", FLEXRIDE_HEADER_TIMEOUT_S="2",
                      FLEXRIDE_BODY_IDLE_TIMEOUT_S="2", FLEXRIDE_BODY_TIMEOUT_S="4")


@pytest.fixture(scope="module")
def few(tmp_path_factory):
    """A server that lets a client address hold 3 connections (and waits long for them)."""
    yield from _serve(tmp_path_factory, "few", FLEXRIDE_HEADER_TIMEOUT_S="300",
                      FLEXRIDE_MAX_CONNECTIONS_PER_CLIENT=str(PER_CLIENT))


def _connect(server: LiveServer) -> socket.socket:
    port = int(server.url.rsplit(":", 1)[1])
    s = socket.create_connection(("127.0.0.1", port), timeout=SAFETY_S)
    return s


def _answer(s: socket.socket) -> tuple[int | None, bytes]:
    """Status and raw bytes of what the server sends until it closes the connection."""
    out = b""
    while True:
        try:
            chunk = s.recv(65536)
        except ConnectionResetError:
            break
        if not chunk:
            break
        out += chunk
    s.close()
    status = int(out.split(b" ", 2)[1]) if out.startswith(b"HTTP/1.1 ") else None
    return status, out


def _post_head(length: int, token: bool = True) -> bytes:
    auth = f"Authorization: Bearer {TEST_TOKEN}\r\n" if token else ""
    return (f"POST /api/v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\n{auth}"
            f"Content-Type: application/json\r\nContent-Length: {length}\r\n\r\n").encode()


def test_a_body_that_stops_coming_is_408(tight):
    s = _connect(tight)
    s.sendall(_post_head(1000) + b'{"preset":')  # 10 of 1000 bytes, then nothing
    status, raw = _answer(s)
    assert status == 408 and b"no part of the request's body arrived for 2 s" in raw, raw
    assert b"connection: close" in raw.lower()


def test_a_body_sent_a_byte_at_a_time_is_408_after_the_body_limit(tight):
    s = _connect(tight)
    s.sendall(_post_head(1000))
    try:
        for _ in range(1000):  # one byte per 0.5 s: progress, but 500 s for the body
            s.sendall(b" ")
            time.sleep(0.5)  # the slow client itself, not a wait for the server
    except OSError:
        pass  # the server closed the connection
    status, raw = _answer(s)
    assert status == 408 and b"body did not arrive within 4 s" in raw, raw


def test_headers_that_stop_coming_are_408_and_a_silent_connection_is_closed(tight):
    s = _connect(tight)
    s.sendall(b"GET /api/v1/health HTTP/1.1\r\nHost: 127.")
    status, raw = _answer(s)
    assert status == 408 and b"headers did not arrive within 2 s" in raw, raw
    assert _answer(_connect(tight)) == (None, b"")  # connected, sent nothing: closed


def test_without_the_token_the_answer_comes_before_the_body(tight):
    s = _connect(tight)
    s.sendall(_post_head(1000, token=False) + b'{"preset":')
    status, raw = _answer(s)  # 401 at once: a server reading the body first would say 408
    assert status == 401 and b"www-authenticate: bearer" in raw.lower(), raw
    s = _connect(tight)  # with the token, a whole request is answered as before
    csv = b"distance_m,vertical\n0,0\n1,0.001\n2,0\n"
    s.sendall(f"POST /api/v1/irregularities HTTP/1.1\r\nHost: 127.0.0.1\r\n"
              f"Authorization: Bearer {TEST_TOKEN}\r\nConnection: close\r\n"
              f"Content-Length: {len(csv)}\r\n\r\n".encode() + csv)
    assert _answer(s)[0] == 201


def test_a_client_beyond_its_connections_gets_429(few):
    held = [_connect(few) for _ in range(PER_CLIENT)]
    try:
        for h in held:
            h.sendall(b"GET /api/v1/health HTTP/1.1\r\n")  # headers never finished

        def one_more() -> tuple[int | None, bytes]:
            s = _connect(few)
            s.sendall(b"GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                      b"Connection: close\r\n\r\n")
            return _answer(s)

        status, raw = one_more()
        assert status == 429 and b"at most 3 at once" in raw and b"retry-after: 1" in raw, raw
    finally:
        for h in held:
            h.close()
    # the held connections are gone: a new one is served again
    wait_for(lambda: one_more()[0] == 200, 30.0, 0.1, "a connection to be served again")


def test_control_characters_in_requests_never_reach_the_log_raw(tight):
    for target in (b"/api/v1/jobs/%00%1b%5b31m%0d%0aFAKE", b"/api/v1/presets/%07%08%7f%c2%9b",
                   b"/api/v1/jobs?study_id=%00&status=%1b"):
        s = _connect(tight)
        s.sendall(b"GET " + target + b" HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n")
        assert _answer(s)[0] in (404, 422)
    s = _connect(tight)  # a raw control byte in the request line: the parser refuses it
    s.sendall(b"GET /api/v1/jobs/\x1b[31m HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
    assert _answer(s)[0] == 400
    log = tight.log.read_bytes() if tight.log else b""
    assert b"/api/v1/jobs/%00" in log  # the access log has the requests, encoded
    raw = sorted({c for c in log if c < 0x20 and c not in b"\t\n\r"} | (
        {0x7F} & set(log)))
    assert not raw, raw
