"""Two small ASGI middlewares: the API token and the request size limit."""
from __future__ import annotations

import json
import secrets

from starlette.exceptions import HTTPException

OPEN_PATHS = ("/health",)


async def _reply(send, status: int, detail: str, headers: list[tuple[bytes, bytes]] | None = None) -> None:
    body = json.dumps({"detail": detail}).encode()
    await send({"type": "http.response.start", "status": status,
                "headers": [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]
                + (headers or [])})
    await send({"type": "http.response.body", "body": body})


class TokenAuth:
    """Every route but /health needs ``Authorization: Bearer <token>`` (401 otherwise)."""

    def __init__(self, app, token: str):
        self.app = app
        self.token = token.encode()

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http" or scope.get("path") in OPEN_PATHS:
            return await self.app(scope, receive, send)
        given = b""
        for key, value in scope.get("headers", ()):
            if key == b"authorization":
                scheme, _, rest = value.partition(b" ")
                if scheme.lower() == b"bearer":
                    given = rest.strip()
                break
        if not given or not secrets.compare_digest(given, self.token):
            return await _reply(send, 401, "this service needs an API token: send 'Authorization: Bearer <token>'",
                                [(b"www-authenticate", b"Bearer")])
        return await self.app(scope, receive, send)


class BodyLimit:
    """Refuse request bodies larger than ``limit`` bytes with 413, by the Content-Length
    header when there is one and by counting the bytes otherwise (chunked uploads)."""

    def __init__(self, app, limit: int):
        self.app = app
        self.limit = int(limit)

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        for key, value in scope.get("headers", ()):
            if key == b"content-length":
                try:
                    n = int(value)
                except ValueError:
                    return await _reply(send, 400, "bad Content-Length header")
                if n > self.limit:
                    return await _reply(send, 413, self.message(n))
        received = 0

        async def counted():
            nonlocal received
            message = await receive()
            if message["type"] == "http.request":
                received += len(message.get("body", b""))
                if received > self.limit:
                    raise HTTPException(413, self.message(received))
            return message

        return await self.app(scope, counted, send)

    def message(self, n: int) -> str:
        return (f"the request body ({'at least ' if n else ''}{n} bytes) is larger than this service takes "
                f"({self.limit} bytes; RFESIM_MAX_REQUEST_BYTES)")
