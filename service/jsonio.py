"""JSON in and out, with orjson.

Point arrays make request and response bodies large: orjson parses 2 × 1,000 × 3 numbers in
~0.9 ms where the standard library takes ~3.3 ms, and writes numpy arrays without a detour
through Python lists. Standard JSON has no NaN or Infinity; a body that uses them (as Python's
``json.dumps`` does) is read again leniently so that validation can name the input and row
holding the bad number instead of answering "malformed body".

Nesting is bounded: orjson refuses documents nested deeper than :data:`MAX_DEPTH` levels of
arrays and objects, and the lenient second reading (the standard library's parser, which
recurses) is tried only on a document whose depth, counted without recursion by
:func:`deeper_than`, is within :data:`LENIENT_DEPTH`. A document nested deeper is a ``ValueError``
that says so, never a ``RecursionError``.

Dataclasses among the outputs (a deformed :class:`algorithms.core.mesh.Mesh`, handles) are
written by orjson natively as objects of their fields, ``{"vertices": [...], "faces":
[...]}``, arrays included (C-contiguous ones directly, others through ``_default``).
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import orjson
from starlette.responses import Response

__all__ = ["loads", "dumps", "deeper_than", "JSONResponse", "MAX_DEPTH"]

#: Most levels of nested arrays and objects in a document: orjson's own limit.
MAX_DEPTH = 1024

#: Bytes scanned at a time by :func:`deeper_than` (its temporary arrays are ~8× this).
_CHUNK = 1 << 20

#: The bytes :func:`deeper_than` looks at: quotes, brackets and braces.
_SPECIAL = np.zeros(256, dtype=bool)
_SPECIAL[list(b'"[]{}')] = True

#: Most levels of nesting in a document that orjson refuses for another reason than depth
#: (NaN, Infinity, 1e999): the standard library's parser, which reads those, recurses once
#: per level (Python allows ~1000 frames in all).
LENIENT_DEPTH = 512


def loads(raw: bytes | bytearray) -> Any:
    """Parse a request body; raises ``ValueError`` with the position of the error, also for
    a document nested deeper than :data:`MAX_DEPTH` levels."""
    try:
        return orjson.loads(raw)
    except orjson.JSONDecodeError as exc:
        if "depth" in exc.msg or "recursion" in exc.msg:
            raise ValueError(_too_deep(exc.pos)) from None
    # NaN, Infinity, 1e999, integers beyond 64 bits; a real syntax error raises again
    if deeper_than(raw, LENIENT_DEPTH):  # the standard library's parser recurses
        raise ValueError(_too_deep(None))
    try:
        return json.loads(raw)
    except RecursionError:  # not reached: the depth was counted above
        raise ValueError(_too_deep(None)) from None


def _too_deep(pos: int | None) -> str:
    if pos is None:
        return (f"it holds a number that is not a double (NaN, Infinity, 1e999) or a "
                f"syntax error, and is nested deeper than {LENIENT_DEPTH} levels of arrays "
                "and objects, the most for such a document")
    return f"it is nested deeper than {MAX_DEPTH} levels of arrays and objects (at " \
        f"character {pos})"


def deeper_than(raw: bytes | bytearray | memoryview, limit: int) -> bool:
    """Whether the JSON text ``raw`` nests arrays and objects deeper than ``limit`` levels.

    Counted without recursion and without parsing, a chunk at a time with numpy: brackets
    and braces outside strings open and close levels; a quote opens or closes a string
    unless an odd run of backslashes precedes it. For text that is not JSON the count may be
    anything, which is harmless: such text then fails to parse."""
    a = np.frombuffer(raw, dtype=np.uint8)
    depth = 0  # levels open at the start of the chunk
    quotes = 0  # parity of the unescaped quotes before it (1: inside a string)
    run = 0  # backslashes that end the text before it
    for start in range(0, len(a), _CHUNK):
        chunk = a[start:start + _CHUNK]
        backslash = chunk == 0x5C
        if run or backslash.any():  # escapes: every byte counts
            pos = np.arange(len(chunk), dtype=np.int64)
            # the last byte at or before each position that is no backslash (-1 - run:
            # the backslashes that ended the chunk before)
            last = np.maximum.accumulate(np.where(backslash, -1 - run, pos))
            before = np.concatenate(([-1 - run], last[:-1]))  # ... strictly before it
            c = chunk
            quote = (c == 0x22) & ((pos - 1 - before) % 2 == 0)
            run = len(chunk) - 1 - int(last[-1])
        else:  # only quotes and brackets count: look at those alone (~20x faster)
            c = chunk[np.flatnonzero(_SPECIAL[chunk])]
            quote = c == 0x22
        if not len(c):
            continue
        inside = (np.cumsum(quote, dtype=np.int64) + quotes) % 2 == 1
        step = ((c == 0x5B) | (c == 0x7B)).astype(np.int64) - ((c == 0x5D) | (c == 0x7D))
        step[inside] = 0
        levels = np.cumsum(step) + depth
        if int(levels.max()) > limit:
            return True
        depth = int(levels[-1])
        quotes = (quotes + int(np.count_nonzero(quote))) % 2
    return False


def _default(obj: Any) -> Any:
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    raise TypeError(f"cannot encode {type(obj).__name__} as JSON")


def dumps(obj: Any) -> bytes:
    return orjson.dumps(obj, default=_default, option=orjson.OPT_SERIALIZE_NUMPY)


class JSONResponse(Response):
    """A JSON response rendered by orjson (numpy arrays and scalars included)."""

    media_type = "application/json"

    def render(self, content: Any) -> bytes:
        return dumps(content)
