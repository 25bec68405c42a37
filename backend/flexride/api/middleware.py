"""ASGI middleware of the API.

* :class:`BodySizeLimit`: request bodies beyond the limit get 413, whether the client announces
  the length or streams the body in chunks;
* :class:`TrustedHosts`: requests whose ``Host`` header names another host get 400 (no DNS
  rebinding: a page on a foreign domain cannot reach the service through a browser);
* :class:`MethodNotAllowed`: a known path asked with a method it does not have gets 405 with
  the complete ``Allow`` header (Starlette names only the first route of the path, and the
  dashboard mounted at ``/`` would answer with its own);
* :class:`TokenGate`: a request to a route that needs the API token and does not carry it gets
  401 from its headers, before its body is read (and the connection is closed).

Time limits on receiving a request and the connections per client are the server's
(:mod:`flexride.api.server`): the application sees a request only once its headers are in.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Any

from starlette.exceptions import HTTPException
from starlette.routing import BaseRoute, Match, Router

if TYPE_CHECKING:  # checked against the installed FastAPI (≥ 0.130)
    from fastapi.routing import iter_route_contexts as _route_contexts
else:
    try:  # FastAPI ≥ 0.130 keeps included routers whole; this walks their effective routes
        from fastapi.routing import iter_route_contexts as _route_contexts
    except ImportError:  # pragma: no cover - older FastAPI copies every route into the app

        def _route_contexts(routes: Iterable[BaseRoute]) -> Iterable[BaseRoute]:
            return routes

TOKEN_REQUIRED = "a valid bearer token is required"
"""The message of a 401 (here and in :func:`flexride.api.deps.require_token`)."""


class _TooLarge(HTTPException):
    """Raised while reading an oversized body; FastAPI passes HTTP errors through, so the
    client gets 413 (not 400) however the body is read.
    """

    def __init__(self, limit: int):
        super().__init__(413, f"request body exceeds the limit of {limit} bytes")


class BodySizeLimit:
    """Refuse request bodies larger than ``max_bytes`` with 413 and a JSON error.

    Parameters
    ----------
    app : ASGI application
        The wrapped application.
    max_bytes : int
        Largest accepted body in bytes.
    """

    def __init__(self, app: Any, max_bytes: int):
        self.app = app
        self.max_bytes = int(max_bytes)

    async def _reply(self, send: Any, status: int, message: str) -> None:
        await reply_json(send, status, message)

    async def __call__(self, scope: dict, receive: Any, send: Any) -> None:
        """Pass the request on with its body counted; 413 beyond the limit."""
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        for key, value in scope.get("headers", ()):
            if key == b"content-length":
                try:
                    length = int(value)
                except ValueError:
                    await self._reply(send, 400, "invalid Content-Length header")
                    return
                if length > self.max_bytes:
                    await self._reply(send, 413, f"request body of {length} bytes exceeds the "
                                      f"limit of {self.max_bytes} bytes")
                    return
        received = 0
        started = False

        async def limited_receive() -> dict:
            nonlocal received
            message = await receive()
            if message["type"] == "http.request":
                received += len(message.get("body", b""))
                if received > self.max_bytes:
                    raise _TooLarge(self.max_bytes)
            return message

        async def tracking_send(message: dict) -> None:
            nonlocal started
            if message["type"] == "http.response.start":
                started = True
            await send(message)

        try:
            await self.app(scope, limited_receive, tracking_send)
        except _TooLarge:
            if not started:
                await self._reply(send, 413, f"request body exceeds the limit of "
                                  f"{self.max_bytes} bytes")


async def reply_json(send: Any, status: int, message: str,
                     headers: Iterable[tuple[bytes, bytes]] = ()) -> None:
    """Send a complete JSON error response ``{"detail": message, "message": message}``.

    Parameters
    ----------
    send : ASGI send callable
        Where the response goes.
    status : int
        HTTP status code.
    message : str
        The error text.
    headers : iterable of (bytes, bytes)
        Extra response headers.
    """
    body = json.dumps({"detail": message, "message": message}).encode()
    await send({"type": "http.response.start", "status": status,
                "headers": [(b"content-type", b"application/json"),
                            (b"content-length", str(len(body)).encode()), *headers]})
    await send({"type": "http.response.body", "body": body})


def host_name(value: str) -> str:
    """The host of a ``Host`` header or an allowed-host entry: lower case, without port,
    brackets (IPv6) or a trailing dot; ``""`` when it cannot be parsed.

    Examples
    --------
    >>> host_name("LocalHost:8000"), host_name("[::1]:8000"), host_name("example.org.")
    ('localhost', '::1', 'example.org')
    """
    value = value.strip().lower()
    if value.startswith("["):
        end = value.find("]")
        return value[1:end] if end > 0 else ""
    if value.count(":") == 1:
        value = value.split(":", 1)[0]
    return value.rstrip(".")


class TrustedHosts:
    """Answer only requests whose ``Host`` header names one of ``allowed`` (400 with a JSON
    error otherwise, also without a ``Host`` header).

    Parameters
    ----------
    app : ASGI application
        The wrapped application.
    allowed : iterable of str
        Host names, with or without port (ignored); ``*.example.org`` accepts its
        subdomains, ``*`` any host.
    """

    def __init__(self, app: Any, allowed: Iterable[str]):
        self.app = app
        names = {host_name(h) if not h.strip().startswith("*") else h.strip().lower()
                 for h in allowed}
        self.any = "*" in names
        self.suffixes = tuple(n[1:] for n in names if n.startswith("*."))
        self.names = frozenset(n for n in names if n and not n.startswith("*"))

    def allows(self, header: str) -> bool:
        """Whether a request with ``Host: header`` is answered."""
        if self.any:
            return True
        name = host_name(header)
        return bool(name) and (name in self.names or name.endswith(self.suffixes))

    async def __call__(self, scope: dict, receive: Any, send: Any) -> None:
        """Refuse a request whose Host header is not allowed, else pass on."""
        if scope["type"] == "http" and not self.any:
            header = next((v.decode("latin-1") for k, v in scope.get("headers", ())
                           if k == b"host"), "")
            if not self.allows(header):
                shown = header[:100] if header else "(none)"
                await reply_json(send, 400, f"invalid Host header {shown!r}: this service "
                                 "answers only its own host names (FLEXRIDE_ALLOWED_HOSTS)")
                return
        await self.app(scope, receive, send)


class MethodNotAllowed:
    """405 with ``Allow`` listing every method of the path, for a path that some route has
    but not with the request's method.

    The path is the first route template (in routing order) that matches the request's path,
    so ``Allow`` names the methods the OpenAPI document gives that path: ``PUT
    /jobs/validate`` names ``POST`` only. ``GET /jobs/validate`` reaches the route of
    ``/jobs/{job_id}``, which refuses ``validate`` as an id (422): such an answer (404 or 422)
    of a route whose template comes after the fixed path's is replaced by 405 too.

    Parameters
    ----------
    app : ASGI application
        The wrapped application.
    router : starlette.routing.Router
        The application's router; its routes are read at each request (mounts are left to
        themselves: static files answer 405 with ``Allow: GET, HEAD``).
    """

    def __init__(self, app: Any, router: Router):
        self.app = app
        self.router = router

    def allowed_methods(self, scope: dict) -> set[str] | None:
        """The methods of the first route template that matches the path, or None when a
        route of that template takes the request as it is (or no route has the path).
        """
        allowed: set[str] = set()
        template = None
        for route in _route_contexts(self.router.routes):
            methods = getattr(route, "methods", None)
            if not methods:
                continue  # mounts, websocket routes
            match, _ = route.matches(scope)
            if match is Match.FULL:  # an earlier (fixed) template owns the path, if any
                return allowed if template not in (None, route.path_format) else None
            if match is Match.PARTIAL and template in (None, route.path_format):
                template = route.path_format
                allowed |= methods
        return allowed or None

    async def __call__(self, scope: dict, receive: Any, send: Any) -> None:
        """Answer 405 with ``Allow`` where the routes say so, else pass on."""
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        # the routes are matched only for answers that may be wrong (404, 405, and 422 of a
        # path parameter), not for every request: the app answers first, and such an answer
        # is replaced
        replaced = False

        async def guarded(message: dict) -> None:
            nonlocal replaced
            if message["type"] == "http.response.start" and message["status"] in (404, 405,
                                                                                 422):
                allowed = self.allowed_methods(scope)
                if allowed is not None:
                    replaced = True
                    await reply_json(send, 405, "Method Not Allowed",
                                     [(b"allow", ", ".join(sorted(allowed)).encode())])
                    return
            if not replaced:
                await send(message)

        await self.app(scope, receive, guarded)


class TokenGate:
    """401 (``WWW-Authenticate: Bearer``, ``Connection: close``) for a request to a route that
    needs the API token when it does not carry it, answered before the app reads the body:
    FastAPI reads a body before it runs the route's dependencies, so without this a client
    without the token could hold a connection for as long as it takes to send its body.

    Parameters
    ----------
    app : ASGI application
        The wrapped application.
    router : starlette.routing.Router
        The application's router; the routes that need the token are found in it at the
        first request.
    needs_token : callable(route) -> bool
        Whether a route needs the token (:func:`flexride.api.deps.needs_token`).
    authorized : callable(authorization header or None) -> bool
        Whether a request with that ``Authorization`` header may pass.
    """

    SAFE_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})

    def __init__(self, app: Any, router: Router, needs_token: Callable[[Any], bool],
                 authorized: Callable[[str | None], bool]):
        self.app = app
        self.router = router
        self.needs_token = needs_token
        self.authorized = authorized
        self._protected: list[Any] | None = None

    def protected(self, scope: dict) -> bool:
        """Whether the request goes to a route that needs the token."""
        if self._protected is None:
            self._protected = [r for r in _route_contexts(self.router.routes)
                               if self.needs_token(r)]
        return any(r.matches(scope)[0] is Match.FULL for r in self._protected)

    async def __call__(self, scope: dict, receive: Any, send: Any) -> None:
        """Refuse an unauthorised request to a protected route, else pass on."""
        if scope["type"] == "http" and scope["method"] not in self.SAFE_METHODS:
            header = next((v.decode("latin-1") for k, v in scope.get("headers", ())
                           if k == b"authorization"), None)
            if not self.authorized(header) and self.protected(scope):
                await reply_json(send, 401, TOKEN_REQUIRED,
                                 [(b"www-authenticate", b"Bearer"), (b"connection", b"close")])
                return
        await self.app(scope, receive, send)
