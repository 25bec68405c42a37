"""ASGI middleware limiting the size of request bodies (413 beyond the limit), whether the
client announces the length or streams the body in chunks."""

from __future__ import annotations

import json
from typing import Any

from starlette.exceptions import HTTPException


class _TooLarge(HTTPException):
    """Raised while reading an oversized body; FastAPI passes HTTP errors through, so the
    client gets 413 (not 400) however the body is read."""

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
        body = json.dumps({"detail": message, "message": message}).encode()
        await send({"type": "http.response.start", "status": status,
                    "headers": [(b"content-type", b"application/json"),
                                (b"content-length", str(len(body)).encode())]})
        await send({"type": "http.response.body", "body": body})

    async def __call__(self, scope: dict, receive: Any, send: Any) -> None:
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
