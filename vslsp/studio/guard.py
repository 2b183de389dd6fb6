"""Who may talk to the studio (docs/studio.md, "Threat model"): an ASGI middleware in front of every
HTTP request and websocket, the pages', the API's and NiceGUI's own.

A local web app is reachable by every web page its user opens: a page of any origin can send it
requests (``fetch(..., {mode: "no-cors"})``, a form, a websocket), and a DNS name rebound to
127.0.0.1 makes the studio that page's own origin. So every request must pass, in this order:

1. **Host**: the ``Host`` header names the studio as it was bound (its address, ``localhost``, a
   loopback address, or a name given with ``--allow-host``) and its port. A rebound DNS name is not
   among them (HTTP 403).
2. **Origin**: a request that carries ``Origin`` comes from the studio's own origin (the same
   allowed host and port); ``null`` and any other origin are refused (403), and so is a request a
   browser marks ``Sec-Fetch-Site: cross-site`` or ``same-site`` (another port of the same host is
   the same *site*, not the same origin).
3. **The secret**: a per-session token, required even on loopback: ``?token=`` in the address the
   studio prints and opens (it sets the cookie and is then dropped from the address by a redirect),
   the cookie ``vslsp_studio_PORT`` (HttpOnly, SameSite=Strict), ``Authorization: Bearer T`` or the
   header ``X-Vslsp-Token: T``. A request that changes state (any method but GET and HEAD, and a
   websocket) needs more than the cookie, which the browser adds to forged requests too: the API's
   (``/api/...``) must carry the token in a header (a page of another origin cannot add one without a
   CORS preflight, which the studio never grants), NiceGUI's own (its socket.io channel, its
   uploads) must come with the studio's own ``Origin``.
4. **Bodies**: the API takes ``application/json`` only (``multipart/form-data`` for ``/api/upload``;
   a POST without a body, such as a cancel, may name no type), 415 otherwise; every body is counted
   while it is read and cut at its limit (413), so a huge or endless post never sits in memory.
"""

from __future__ import annotations

import hmac
import ipaddress
import json
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import parse_qsl, urlencode, urlsplit

from vslsp.errors import InputError

#: Host names that always name this machine's loopback.
LOOPBACK_NAMES = frozenset({"localhost", "127.0.0.1", "::1"})
#: Methods that only read.
SAFE_METHODS = frozenset({"GET", "HEAD"})
#: The largest body of an API request other than an upload (three texts of 2 MiB characters, UTF-8).
API_BODY_BYTES = 6 * 1024 * 1024 + 64 * 1024
#: The largest upload request (an image of 32 MiB and the multipart framing).
UPLOAD_BODY_BYTES = 32 * 1024 * 1024 + 64 * 1024
#: The largest body of any other request (NiceGUI's socket.io messages and uploads).
OTHER_BODY_BYTES = 34 * 1024 * 1024


def is_loopback(host: str) -> bool:
    """Whether ``host`` (a name or an address, IPv6 with or without brackets) is this machine's loopback."""
    host = host.strip("[]").lower()
    if host in LOOPBACK_NAMES:
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def _is_address(host: str) -> bool:
    try:
        ipaddress.ip_address(host)
    except ValueError:
        return False
    return True


@dataclass(frozen=True)
class Access:
    """What the guard lets in.

    ``token``: the session's secret. ``bound``: the address the studio listens on (``0.0.0.0`` or
    ``::``: every address of the machine). ``port``: its port (None: any, for a server in a test
    process). ``hosts``: further host names the ``Host`` header may give (``--allow-host``, a proxy's
    name; lower case)."""

    token: str
    bound: str = "127.0.0.1"
    port: int | None = None
    hosts: frozenset[str] = field(default_factory=frozenset)

    @property
    def cookie(self) -> str:
        """The cookie's name: one per port, since cookies are kept per host and not per port."""
        return f"vslsp_studio_{self.port or 'test'}"

    def allows_host(self, host: str) -> bool:
        """Whether a ``Host`` (or ``Origin``) host name names this studio."""
        name = host.strip("[]").lower()
        if name in self.hosts or name == self.bound.strip("[]").lower():
            return True
        if is_loopback(name):
            return True
        # Bound to every address: any address of the machine may be used, but never a DNS name that is not
        # listed (DNS rebinding always arrives with a name, never with an address).
        return self.bound in ("0.0.0.0", "::") and _is_address(name)


def split_host(value: str) -> tuple[str, int | None] | None:
    """``host[:port]`` (IPv6 in brackets) as (host, port), or None when it is not one."""
    value = value.strip()
    if not value or any(c in value for c in "/@?#\\ "):
        return None
    try:
        parts = urlsplit(f"http://{value}")
        port = parts.port
    except ValueError:
        return None
    if parts.hostname is None:
        return None
    return parts.hostname, port


def _refusal(status: int, message: str, headers: Iterable[tuple[bytes, bytes]] = ()) -> dict[str, Any]:
    return {"status": status, "body": json.dumps({"error": message, "exit_code": 2}).encode(), "headers": list(headers)}


class Guard:
    """The ASGI middleware of the module's rules (wrap the whole app: it must see NiceGUI's routes too)."""

    def __init__(self, app: Any, access: Access) -> None:
        self.app, self.access = app, access

    async def __call__(self, scope: dict, receive: Any, send: Any) -> None:
        if scope["type"] not in ("http", "websocket"):
            return await self.app(scope, receive, send)
        headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope.get("headers", [])}
        refused = self.refusal(scope, headers)
        if refused is not None:
            if scope["type"] == "websocket":
                return await send({"type": "websocket.close", "code": 1008})
            return await _answer(send, refused)
        if scope["type"] == "websocket":
            return await self.app(scope, receive, send)
        query = dict(parse_qsl(scope.get("query_string", b"").decode("latin-1")))
        if "token" in query and scope["method"] == "GET" and "text/html" in headers.get("accept", ""):
            # A page opened with the token: set the cookie and drop the token from the address (so that it is in
            # no history, bookmark or Referer).
            rest = urlencode({k: v for k, v in query.items() if k != "token"})
            location = scope.get("root_path", "") + scope["path"] + (f"?{rest}" if rest else "")
            return await _answer(
                send, {"status": 303, "body": b"", "headers": [(b"location", location.encode()), self.set_cookie()]}
            )
        limit = self.body_limit(scope["path"])
        declared = headers.get("content-length")
        if declared is not None and (not declared.isdigit() or int(declared) > limit):
            return await _answer(send, _refusal(413, f"the request is over {limit // (1024 * 1024)} MiB"))
        counted = _Counted(receive, limit)
        if "token" in query:
            return await self.app(scope, counted, self._with_cookie(send))
        return await self.app(scope, counted, send)

    def refusal(self, scope: dict, headers: dict[str, str]) -> dict[str, Any] | None:
        """Why the request is refused (status and JSON body), or None when it may go on."""
        access = self.access
        host = split_host(headers.get("host", ""))
        if host is None or not access.allows_host(host[0]) or (access.port and host[1] not in (None, access.port)):
            return _refusal(403, "the studio does not answer to this Host name; open the address it printed")
        origin = headers.get("origin")
        if origin is not None and not self.own_origin(origin):
            return _refusal(403, f"requests from {origin[:100]} are refused; open the studio's own address")
        if headers.get("sec-fetch-site") in ("cross-site", "same-site"):
            return _refusal(403, "requests from other sites are refused; open the studio's own address")
        changing = scope["type"] == "websocket" or scope["method"] not in SAFE_METHODS
        in_header = _header_token(headers)
        in_query = dict(parse_qsl(scope.get("query_string", b"").decode("latin-1"))).get("token")
        in_cookie = _cookie(headers.get("cookie", ""), access.cookie)
        path = scope["path"]
        if path.startswith("/api/") and changing:
            if not _same(in_header, access.token):
                return _refusal(
                    401, "this request needs the studio's token in a header (Authorization: Bearer T or X-Vslsp-Token)"
                )
            kind = headers.get("content-type", "").split(";")[0].strip().lower()
            wanted = "multipart/form-data" if path == "/api/upload" else "application/json"
            bodiless = headers.get("content-length", "0") == "0" and "transfer-encoding" not in headers
            if kind != wanted and not (bodiless and not kind):  # a bodiless POST (cancel) needs no type
                return _refusal(415, f"send the body as {wanted}, not {kind or 'no content type'}")
            return None
        if not any(_same(given, access.token) for given in (in_header, in_query, in_cookie)):
            return _refusal(401, "this studio needs its token: open the address it printed (?token=...)")
        if changing and in_header is None and origin is None:
            # NiceGUI's own channel and uploads carry only the cookie: a browser sends Origin with them, and the
            # origin was checked above; without Origin (or a header token) nothing says the studio's page sent it.
            return _refusal(403, "send the studio's token in a header, or open the studio's own page")
        return None

    def own_origin(self, origin: str) -> bool:
        """Whether ``Origin`` is the studio's own (http, an allowed host, its port)."""
        if origin == "null" or not origin.startswith(("http://", "https://")):
            return False
        found = split_host(origin.split("://", 1)[1])
        if found is None:
            return False
        host, port = found
        port = port if port is not None else (443 if origin.startswith("https://") else 80)
        return self.access.allows_host(host) and (self.access.port is None or port == self.access.port)

    def body_limit(self, path: str) -> int:
        if path == "/api/upload":
            return UPLOAD_BODY_BYTES
        return API_BODY_BYTES if path.startswith("/api/") else OTHER_BODY_BYTES

    def set_cookie(self) -> tuple[bytes, bytes]:
        value = f"{self.access.cookie}={self.access.token}; Path=/; HttpOnly; SameSite=Strict"
        return b"set-cookie", value.encode()

    def _with_cookie(self, send: Any) -> Any:
        async def sending(message: dict) -> None:
            if message["type"] == "http.response.start":
                message = {**message, "headers": [*message.get("headers", []), self.set_cookie()]}
            await send(message)

        return sending


class TooLarge(InputError):
    """A request body over its limit (HTTP 413), found while it is read."""


class _Counted:
    """An ASGI ``receive`` that counts the body's bytes and stops at ``limit``."""

    def __init__(self, receive: Any, limit: int) -> None:
        self.receive, self.limit, self.seen = receive, limit, 0

    async def __call__(self) -> dict:
        message = await self.receive()
        if message["type"] == "http.request":
            self.seen += len(message.get("body", b""))
            if self.seen > self.limit:
                raise TooLarge(f"the request is over {self.limit // (1024 * 1024)} MiB")
        return message


def _header_token(headers: dict[str, str]) -> str | None:
    """The token of ``X-Vslsp-Token`` or ``Authorization: Bearer T`` (a bare ``Authorization: T`` is none)."""
    if "x-vslsp-token" in headers:
        return headers["x-vslsp-token"]
    scheme, _, value = headers.get("authorization", "").partition(" ")
    return value.strip() if scheme.lower() == "bearer" and value.strip() else None


def _cookie(header: str, name: str) -> str | None:
    for part in header.split(";"):
        key, _, value = part.strip().partition("=")
        if key == name:
            return value
    return None


def _same(given: str | None, token: str) -> bool:
    return given is not None and hmac.compare_digest(given.encode(), token.encode())


async def _answer(send: Any, answer: dict[str, Any]) -> None:
    body = answer["body"]
    headers = [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]
    await send({"type": "http.response.start", "status": answer["status"], "headers": headers + answer["headers"]})
    await send({"type": "http.response.body", "body": body})
