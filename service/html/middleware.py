"""The ASGI middleware that answers browsers with HTML renderings of the JSON documents."""

from __future__ import annotations

import json
import math
import re
from typing import Any
from urllib.parse import parse_qsl, urlencode

from starlette.types import ASGIApp, Message, Receive, Scope, Send

from service.html import pages

__all__ = ["HtmlMiddleware", "wants_html", "quality"]

#: The paths that have an HTML page: /, /processes, /processes/{id}, /jobs, /jobs/{id}.
PAGE = re.compile(r"^/(?:(?P<kind>processes|jobs)(?:/(?P<id>[^/]+))?)?$")

HTML, JSON = "text/html", "application/json"
_FORMATS = ("json", "html")


def _ranges(accept: str) -> list[tuple[str, float]]:
    """The media ranges of an Accept header with their q-values (RFC 9110 §12.5.1);
    parameters other than ``q`` are ignored, as is a range with a malformed ``q``."""
    out = []
    for item in accept.split(","):
        media, *params = item.split(";")
        media = media.strip().lower()
        if not media:
            continue
        q = 1.0
        for param in params:
            key, _, value = param.partition("=")
            if key.strip().lower() == "q":
                try:
                    q = float(value.strip())
                except ValueError:
                    q = math.nan
        if math.isfinite(q) and 0 <= q <= 1:
            out.append((media, q))
    return out


def quality(accept: str | None, media_type: str) -> float:
    """The q-value an Accept header gives ``media_type``: that of the most specific range
    that matches it (``type/subtype`` over ``type/*`` over ``*/*``), 0 if none does; no
    header accepts everything (q = 1)."""
    if accept is None or not accept.strip():
        return 1.0
    kind = media_type.split("/", 1)[0]
    best: tuple[int, float] | None = None
    for media, q in _ranges(accept):
        if media == media_type:
            specific = 3
        elif media == f"{kind}/*":
            specific = 2
        elif media in ("*/*", "*"):
            specific = 1
        else:
            continue
        if best is None or specific > best[0] or (specific == best[0] and q > best[1]):
            best = (specific, q)
    return best[1] if best is not None else 0.0


def wants_html(accept: str | None, f: str | None = None) -> bool:
    """Whether to answer HTML: ``f`` ("html" or "json") decides when given; else the Accept
    header must rank ``text/html`` strictly above ``application/json`` (a browser's
    ``text/html,...,*/*;q=0.8`` does; ``*/*``, no header, or a tie gives JSON)."""
    if f is not None:
        return f == "html"
    if accept is None or not accept.strip():
        return False
    html = quality(accept, HTML)
    return html > 0 and html > quality(accept, JSON)


def _header(scope: Scope, name: bytes) -> str | None:
    values = [v.decode("latin-1") for k, v in scope["headers"] if k == name]
    return ", ".join(values) if values else None


def _with_vary(headers: list[tuple[bytes, bytes]]) -> list[tuple[bytes, bytes]]:
    """``headers`` with ``Accept`` in their ``Vary``."""
    out, seen = [], False
    for key, value in headers:
        if key.lower() == b"vary":
            seen = True
            names = {v.strip().lower() for v in value.split(b",")}
            if b"accept" not in names and b"*" not in names:
                value = value + b", Accept"
        out.append((key, value))
    if not seen:
        out.append((b"vary", b"Accept"))
    return out


class _Captured:
    """What the application answered a sub-request: status, headers, body."""

    def __init__(self) -> None:
        self.status = 500
        self.headers: list[tuple[bytes, bytes]] = []
        self.chunks: list[bytes] = []

    async def send(self, message: Message) -> None:
        if message["type"] == "http.response.start":
            self.status = message["status"]
            self.headers = list(message.get("headers", []))
        elif message["type"] == "http.response.body":
            self.chunks.append(message.get("body", b""))

    def header(self, name: str) -> str:
        for key, value in self.headers:
            if key.decode("latin-1").lower() == name:
                return value.decode("latin-1")
        return ""

    def json(self) -> Any:
        ctype = self.header("content-type").split(";")[0].strip().lower()
        if ctype != JSON and not ctype.endswith("+json"):
            return None
        try:
            return json.loads(b"".join(self.chunks))
        except ValueError:
            return None


class HtmlMiddleware:
    """Pure ASGI middleware: HTML pages for browsers, rendered from the JSON documents.

    Install it outside the authentication middleware, so that a 401 is rendered too and
    the sub-requests it makes pass through authentication with the client's headers.
    """

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        match = PAGE.match(scope.get("path", "")) if scope["type"] == "http" else None
        if match is None or scope["method"] not in ("GET", "HEAD"):
            await self.app(scope, receive, send)
            return
        query = parse_qsl(scope.get("query_string", b"").decode("latin-1"),
                          keep_blank_values=True)
        formats = [v for k, v in query if k == "f"]
        f = formats[-1].strip().lower() if formats else None
        accept = _header(scope, b"accept")
        if f is not None and f not in _FORMATS:
            await self._bad_format(scope, receive, send, formats[-1], wants_html(accept))
            return
        if not wants_html(accept, f):
            async def send_vary(message: Message) -> None:
                if message["type"] == "http.response.start":
                    message = {**message, "headers": _with_vary(list(message["headers"]))}
                await send(message)

            await self.app(scope, receive, send_vary)
            return
        rest = [(k, v) for k, v in query if k != "f"]
        answer = await self._get(scope, scope["path"], urlencode(rest))
        doc = answer.json()
        ctx = pages.Context(path=scope["path"], query=rest, root=scope.get("root_path", ""))
        if answer.status >= 400 and isinstance(doc, dict):
            body = pages.error_page(answer.status, doc, ctx)
            keep = {"www-authenticate", "retry-after", "allow"}
            extra = [(k, v) for k, v in answer.headers if k.decode("latin-1").lower() in keep]
            await self._send_html(scope, send, answer.status, body, extra)
            return
        if answer.status != 200 or doc is None:  # nothing we render: as the application said
            await send({"type": "http.response.start", "status": answer.status,
                        "headers": _with_vary(answer.headers)})
            await send({"type": "http.response.body",
                        "body": b"" if scope["method"] == "HEAD" else b"".join(answer.chunks)})
            return
        kind, item = match["kind"], match["id"]
        if kind is None:
            body = pages.landing_page(doc, ctx)
        elif kind == "processes" and item is None:
            body = pages.process_list_page(doc, ctx)
        elif kind == "processes":
            body = pages.process_page(doc, ctx)
        elif item is None:
            body = pages.job_list_page(doc, ctx)
        else:
            process = None
            if isinstance(doc, dict) and isinstance(doc.get("processID"), str):
                described = await self._get(scope, f"/processes/{doc['processID']}", "")
                process = described.json() if described.status == 200 else None
            body = pages.job_page(doc, process, ctx)
        await self._send_html(scope, send, 200, body, [])

    async def _get(self, scope: Scope, path: str, query: str) -> _Captured:
        """GET ``path`` from the application as JSON, with the client's other headers."""
        headers = [(k, v) for k, v in scope["headers"] if k not in (b"accept", b"content-length",
                                                                    b"content-type")]
        sub = {**scope, "method": "GET", "path": path,
               "raw_path": (scope.get("root_path", "") + path).encode(),
               "query_string": query.encode("latin-1"),
               "headers": [*headers, (b"accept", JSON.encode())]}
        sent = False

        async def receive() -> Message:
            nonlocal sent
            if not sent:
                sent = True
                return {"type": "http.request", "body": b"", "more_body": False}
            return {"type": "http.disconnect"}

        answer = _Captured()
        await self.app(sub, receive, answer.send)
        return answer

    async def _send_html(self, scope: Scope, send: Send, status: int, body: str,
                         extra: list[tuple[bytes, bytes]]) -> None:
        data = body.encode("utf-8")
        headers = [(b"content-type", b"text/html; charset=utf-8"),
                   (b"content-length", str(len(data)).encode()),
                   (b"content-security-policy", pages.CSP.encode()),
                   (b"x-content-type-options", b"nosniff"),
                   (b"vary", b"Accept"), *extra]
        await send({"type": "http.response.start", "status": status, "headers": headers})
        await send({"type": "http.response.body",
                    "body": b"" if scope["method"] == "HEAD" else data})

    async def _bad_format(self, scope: Scope, receive: Receive, send: Send, value: str,
                          html: bool) -> None:
        """422 for ``?f=`` other than json or html, as the service's other inputs get."""
        from service.errors import problem_response
        from service.problems import problem_body

        message = f"Expected 'json' or 'html', got {value!r}."
        problem = problem_body("invalid-input", f"f: {message}", instance=scope["path"],
                               errors=[{"input": "f", "message": message}])
        if html:
            ctx = pages.Context(path=scope["path"], query=[], root=scope.get("root_path", ""))
            await self._send_html(scope, send, 422, pages.error_page(422, problem, ctx), [])
            return
        await problem_response(problem, {"Vary": "Accept"})(scope, receive, send)
