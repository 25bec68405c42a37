"""The HTTP server's limits on a connection: how long a client may take to send a request,
and how many connections one client address may hold at once.

uvicorn reads a request's headers and body without a time limit (its keep-alive timeout only
covers the pause *between* requests), so a client that sends the headers of a POST announcing
1000 bytes and then 10 of them, or half a request line, holds a connection and a task for as
long as it likes. :func:`protocol_class` makes a subclass of uvicorn's httptools protocol
(``uvicorn[standard]``, what ``flexride serve`` runs) that adds:

* a deadline for the request line and headers (``header_timeout_s``, from the connection or
  from the first byte of a later request on it): **408** and the connection closed (a new
  connection that sent nothing is closed without an answer);
* a limit on the pause between two parts of a body (``body_idle_timeout_s``) and on the
  whole body (``body_timeout_s``): **408** if the application has not answered yet, and the
  connection closed either way;
* at most ``max_connections_per_client`` open connections per client address: a request on a
  further one is answered **429** with ``Retry-After`` and the connection closed.

The total number of connections is uvicorn's own ``limit_concurrency`` (503 beyond). A request
to a route that needs the API token is refused before its body is read
(:class:`flexride.api.middleware.TokenGate`).
"""

from __future__ import annotations

import asyncio
import json
from collections import Counter
from dataclasses import dataclass
from http import HTTPStatus
from typing import Any, ClassVar

from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol

from flexride.api.middleware import reply_json


@dataclass(frozen=True)
class ConnectionLimits:
    """What one connection may take (s) and how many one client address may hold."""

    header_timeout_s: float
    body_idle_timeout_s: float
    body_timeout_s: float
    max_connections_per_client: int

    @classmethod
    def from_settings(cls, settings: Any) -> ConnectionLimits:
        """The limits of :class:`flexride.settings.Settings`."""
        return cls(settings.header_timeout_s, settings.body_idle_timeout_s,
                   settings.body_timeout_s, settings.max_connections_per_client)


class LimitedHttpToolsProtocol(HttpToolsProtocol):
    """uvicorn's httptools protocol with :class:`ConnectionLimits` (see the module)."""

    limits: ClassVar[ConnectionLimits]
    open_per_client: ClassVar[Counter[str]]

    def __init__(self, *args: Any, **kwargs: Any):
        super().__init__(*args, **kwargs)
        self._client_key: str | None = None
        self._too_many = False
        self._in_request = False
        self._head_timer: asyncio.TimerHandle | None = None
        self._body_timer: asyncio.TimerHandle | None = None
        self._body_started = 0.0
        self._body_seen = 0.0

    # -- connections per client ---------------------------------------------------------------

    def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
        """Count the connection for its client address (or mark it one too many) and start
        the header deadline.
        """
        super().connection_made(transport)
        key = self.client[0] if self.client else ""
        if self.open_per_client[key] >= self.limits.max_connections_per_client:
            self._too_many = True
        else:
            self.open_per_client[key] += 1
            self._client_key = key
        self._arm_head()

    def connection_lost(self, exc: Exception | None) -> None:
        """Stop the timers and uncount the connection."""
        self._disarm()
        self._uncount()
        super().connection_lost(exc)

    def handle_websocket_upgrade(self) -> None:
        """The connection goes to uvicorn's WebSocket protocol (the API has no WebSocket
        route: it is refused there): nothing of it is this protocol's any more.
        """
        self._disarm()
        self._uncount()
        super().handle_websocket_upgrade()

    def _uncount(self) -> None:
        if self._client_key is not None:
            self.open_per_client[self._client_key] -= 1
            if self.open_per_client[self._client_key] <= 0:
                del self.open_per_client[self._client_key]
            self._client_key = None

    # -- parser callbacks ---------------------------------------------------------------------

    def on_message_begin(self) -> None:
        """A request starts: its headers have :attr:`ConnectionLimits.header_timeout_s` (counted
        from the connection for the first request).
        """
        super().on_message_begin()
        self._in_request = True
        if self._head_timer is None:
            self._arm_head()

    def on_headers_complete(self) -> None:
        """Headers in: stop their deadline, start the body's (or answer 429 on a connection
        beyond the client's limit).
        """
        self._cancel_head()
        if self._too_many:
            app, self.app = self.app, self._too_many_connections
            try:
                super().on_headers_complete()
            finally:
                self.app = app
        else:
            super().on_headers_complete()
        now = self.loop.time()
        self._body_started = self._body_seen = now
        self._body_timer = self.loop.call_at(now + self.limits.body_idle_timeout_s,
                                             self._body_timeout)

    def on_body(self, body: bytes) -> None:
        """Part of the body: progress (the pause limit starts again)."""
        self._body_seen = self.loop.time()
        super().on_body(body)

    def on_message_complete(self) -> None:
        """The whole request is in: no deadline until the next one begins."""
        self._in_request = False
        self._cancel_body()
        super().on_message_complete()

    # -- deadlines ----------------------------------------------------------------------------

    def _arm_head(self) -> None:
        self._head_timer = self.loop.call_later(self.limits.header_timeout_s, self._head_timeout)

    def _cancel_head(self) -> None:
        if self._head_timer is not None:
            self._head_timer.cancel()
            self._head_timer = None

    def _cancel_body(self) -> None:
        if self._body_timer is not None:
            self._body_timer.cancel()
            self._body_timer = None

    def _disarm(self) -> None:
        self._cancel_head()
        self._cancel_body()

    def _head_timeout(self) -> None:
        self._head_timer = None
        if self.transport.is_closing():
            return
        if self._in_request:
            self._refuse(408, f"the request's headers did not arrive within "
                         f"{self.limits.header_timeout_s:g} s")
        else:  # a connection that never sent a request
            self.transport.close()

    def _body_timeout(self) -> None:
        self._body_timer = None
        now, limits = self.loop.time(), self.limits
        end = min(self._body_seen + limits.body_idle_timeout_s,
                  self._body_started + limits.body_timeout_s)
        if now < end:  # progress since the timer was set: wait for the rest
            self._body_timer = self.loop.call_at(end, self._body_timeout)
            return
        if self.transport.is_closing():
            return
        if now >= self._body_started + limits.body_timeout_s:
            why = f"the request's body did not arrive within {limits.body_timeout_s:g} s"
        else:
            why = f"no part of the request's body arrived for {limits.body_idle_timeout_s:g} s"
        self._refuse(408, why)

    def _refuse(self, status: int, message: str) -> None:
        """Answer ``status`` (unless the application already answered) and close; the
        application's request, if any, sees the client gone.
        """
        cycle = self.cycle
        if cycle is None or not cycle.response_started:
            body = json.dumps({"detail": message, "message": message}).encode()
            self.transport.write(b"".join([
                f"HTTP/1.1 {status} {HTTPStatus(status).phrase}\r\n".encode(),
                b"content-type: application/json\r\n",
                f"content-length: {len(body)}\r\n".encode(),
                b"connection: close\r\n\r\n", body]))
        if cycle is not None and not cycle.response_complete:
            cycle.disconnected = True  # nothing more from the application goes out
            cycle.message_event.set()  # a read of the body returns "disconnected"
        self.transport.close()

    async def _too_many_connections(self, scope: Any, receive: Any, send: Any) -> None:
        n = self.limits.max_connections_per_client
        await reply_json(send, 429, f"too many connections from this address: at most {n} at "
                         "once (FLEXRIDE_MAX_CONNECTIONS_PER_CLIENT)",
                         [(b"retry-after", b"1"), (b"connection", b"close")])


def protocol_class(limits: ConnectionLimits) -> type[LimitedHttpToolsProtocol]:
    """A :class:`LimitedHttpToolsProtocol` with ``limits`` and its own count of connections
    per client (give it to uvicorn as ``http=``).
    """
    return type("FlexrideHttpProtocol", (LimitedHttpToolsProtocol,),
                {"limits": limits, "open_per_client": Counter()})
