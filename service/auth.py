"""API keys: who may use the service, and whose jobs are whose.

The keys file (``MORPHSERVE_API_KEYS_FILE``) never holds a key, only its SHA-256: one line
per key, ``NAME sha256:HEX``, where NAME (letters, digits, ``_.-``) names the key's owner.
Blank lines and ``#`` comments are ignored. ``morphserve keys add NAME`` makes a key,
prints it once and appends its line. The file is read again when it changes, so keys can
be added or revoked without a restart.

When the file is set, every route but ``/healthz`` and ``/readyz`` needs
``Authorization: Bearer KEY`` (401 otherwise), and a job belongs to the key that created
it: other keys get 404 for it and do not see it in ``/jobs``. Without the file the service
is open and every job belongs to "" (the server then binds to 127.0.0.1 by default).
"""

from __future__ import annotations

import hashlib
import hmac
import logging
import re
import secrets
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from starlette.types import ASGIApp, Receive, Scope, Send

__all__ = ["KeyRing", "KeyFileError", "AuthMiddleware", "hash_key", "new_key", "key_line",
           "owner_of", "OPEN_PATHS", "is_open"]

log = logging.getLogger("morphserve")

#: Routes that answer without a key: the probes (orchestrators carry no credentials) and the
#: API's own description, which holds no one's data.
OPEN_PATHS = frozenset({"/healthz", "/readyz", "/openapi.json"})

#: Static pages and their assets (the workbench, the API documentation): a browser loads them
#: with no way to send a key; the workbench then sends the key its user types to the API.
OPEN_TREES = ("/ui", "/docs")


def is_open(path: str) -> bool:
    """Whether ``path`` answers without a key: an open path, or one of the static trees
    (``/ui``, ``/ui/app.js``; not ``/uix``)."""
    return path in OPEN_PATHS or any(path == t or path.startswith(t + "/") for t in OPEN_TREES)

_NAME = re.compile(r"[A-Za-z0-9_.-]{1,64}")
_LINE = re.compile(r"(?P<name>\S+)\s+sha256:(?P<hex>[0-9a-fA-F]{64})")
_SCOPE_KEY = "morphserve.owner"


class KeyFileError(ValueError):
    """The keys file cannot be read or has a malformed line."""


def hash_key(key: str) -> str:
    """The hex SHA-256 of a key, as the keys file stores it."""
    return hashlib.sha256(key.encode()).hexdigest()


def new_key() -> str:
    """A new random key: 256 bits, URL-safe."""
    return "msk_" + secrets.token_urlsafe(32)


def key_line(name: str, key: str) -> str:
    """The keys-file line for ``key`` owned by ``name``."""
    if not _NAME.fullmatch(name):
        raise KeyFileError(f"A key name is 1-64 letters, digits, '_', '.' or '-'; got {name!r}.")
    return f"{name} sha256:{hash_key(key)}"


def parse_keys(text: str, source: str = "keys file") -> dict[str, str]:
    """``{sha256 hex: name}`` from the text of a keys file."""
    keys: dict[str, str] = {}
    for number, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        m = _LINE.fullmatch(line)
        if m is None or not _NAME.fullmatch(m["name"]):
            raise KeyFileError(f"{source}, line {number}: expected 'NAME sha256:HEX' (NAME of "
                               "letters, digits, '_', '.', '-'; 64 hex digits).")
        keys[m["hex"].lower()] = m["name"]
    return keys


@dataclass
class _Snapshot:
    stamp: tuple[int, int] | None
    keys: dict[str, str]


class KeyRing:
    """The keys of one keys file, re-read whenever the file changes."""

    def __init__(self, path: Path) -> None:
        self.path = Path(path)
        self._lock = threading.Lock()
        self._snap = _Snapshot(None, {})
        self._load(strict=True)

    def _stamp(self) -> tuple[int, int]:
        st = self.path.stat()
        return st.st_mtime_ns, st.st_size

    def _load(self, *, strict: bool) -> None:
        try:
            stamp = self._stamp()
            if stamp == self._snap.stamp:
                return
            keys = parse_keys(self.path.read_text(encoding="utf-8"), str(self.path))
        except (OSError, KeyFileError) as exc:
            if strict:
                raise KeyFileError(f"Cannot use the API keys file: {exc}") from exc
            # A half-written or vanished file: keep the keys we had, say so once per change.
            log.warning("API keys file unreadable, keeping the previous keys: %s", exc)
            return
        with self._lock:
            self._snap = _Snapshot(stamp, keys)

    def owner(self, key: str) -> str | None:
        """The name owning ``key``, or None when it is not a valid key."""
        self._load(strict=False)
        digest = hash_key(key)
        for known, name in self._snap.keys.items():  # constant time in the key's content
            if hmac.compare_digest(known, digest):
                return name
        return None

    def __len__(self) -> int:
        return len(self._snap.keys)


def owner_of(scope_or_request: Any) -> str:
    """The owner a request was authenticated as ("" on an open service)."""
    scope = getattr(scope_or_request, "scope", scope_or_request)
    owner: str = scope.get(_SCOPE_KEY, "")
    return owner


class AuthMiddleware:
    """Pure ASGI middleware: checks the bearer key and records its owner in the scope."""

    def __init__(self, app: ASGIApp, keyring: KeyRing | None) -> None:
        self.app = app
        self.keyring = keyring

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http" or self.keyring is None or is_open(scope["path"]):
            await self.app(scope, receive, send)
            return
        token = None
        for name, value in scope["headers"]:
            if name == b"authorization":
                scheme, _, rest = value.decode("latin-1").partition(" ")
                if scheme.lower() == "bearer" and rest.strip():
                    token = rest.strip()
                break
        owner = self.keyring.owner(token) if token else None
        if owner is None:
            await _unauthorized(scope, receive, send, missing=token is None)
            return
        scope[_SCOPE_KEY] = owner
        await self.app(scope, receive, send)


async def _unauthorized(scope: Scope, receive: Receive, send: Send, *, missing: bool) -> None:
    from service.errors import problem_response
    from service.problems import problem_body

    detail = ("This service needs an API key: send the header 'Authorization: Bearer KEY' "
              "(the SDK and CLI read MORPHSERVE_API_KEY)." if missing else
              "The API key is not valid for this service.")
    body = problem_body("unauthorized", detail, instance=scope["path"],
                        errors=[{"input": "Authorization", "message": detail}])
    response = problem_response(body, {"WWW-Authenticate": 'Bearer realm="morphserve"'})
    await response(scope, receive, send)
