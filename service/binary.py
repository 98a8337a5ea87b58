"""Typed binary arrays inside JSON: ``{"dtype": "float64", "shape": [n, 3], "data": BASE64}``.

Any input, or any array inside an input (``mesh.vertices``, ``mesh.faces``,
``handles.positions``), may be sent this way instead of as nested JSON lists: the bytes are
the array in C order, little-endian unless the dtype says otherwise (``">f8"``), base64
encoded. Decoding 1M points this way takes milliseconds where JSON lists take over 100 ms,
the values arrive bit-exact, and an empty array keeps its shape. Integer, unsigned and
floating dtypes of up to 8 bytes are accepted; validation of the values (NaN, ranges,
shapes for the method) is the same as for lists.

A large body's long base64 strings never become Python strings: :func:`lift_base64` cuts
them out of the raw body before the JSON is parsed (orjson spent ~70 ms making the two 32 MB
strings of two 1M-point inputs), and :func:`decode_arrays` decodes them from the body where
they lie. Base64 is decoded by pybase64 (SIMD; 32 MB in ~2 ms, where binascii took ~64 ms).
"""

from __future__ import annotations

import binascii
import dataclasses
import math
import re
import secrets
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pybase64

from algorithms.core.errors import InvalidInputError

__all__ = ["BINARY_KEYS", "MAX_DEPTH", "Lifted", "decode_arrays", "encode_arrays",
           "is_binary_array", "lift_base64", "owned", "too_deep"]

#: The members of a typed binary array object, exactly.
BINARY_KEYS = frozenset({"dtype", "shape", "data"})

#: Most dimensions a binary array may declare.
MAX_NDIM = 4

#: Most levels of objects inside one input that the walks over an input look into by default
#: (and the default of the service's setting ``max_input_depth``, which it passes):
#: ``mesh.vertices`` is one level, a qualified value ``{"value": {"vertices": ...}}`` two.
#: The walks recurse once per level.
MAX_DEPTH = 32


#: Shortest base64 string that :func:`lift_base64` cuts out of a body.
LIFT_CHARS = 4096

#: A member named data whose value is a string, up to the string's opening quote (a regular
#: expression finds it 3x faster than bytes.find in a body of digits: it looks for quotes
#: first).
_DATA_STRING = re.compile(rb'"data"[ \t\n\r]*:[ \t\n\r]*"')


@dataclass
class Lifted:
    """The long base64 strings of a JSON body, cut out of it before it was parsed.

    In the parsed document each stands as the string ``prefix + str(i)``; ``spans[i]`` is
    the ``(offset, length)`` of its text in ``body``. ``decoded`` lists what
    :func:`decode_arrays` made of them: ``(bytearray, offset, length)``, the decoded bytes and
    the text they came from (the job store may keep the text instead of the bytes)."""

    body: memoryview
    spans: list[tuple[int, int]]
    nonce: str = field(default_factory=lambda: secrets.token_hex(8))
    decoded: list[tuple[bytearray, int, int]] = field(default_factory=list)

    @property
    def prefix(self) -> str:
        # a NUL (escaped in the JSON text) and a nonce: no base64, nor any string a client
        # could send on purpose, begins with it
        return f"\0base64:{self.nonce}:"

    @property
    def complete(self) -> bool:
        """Every string cut out was decoded as the data of a typed binary array: nothing
        else of the document holds one of the stand-in strings."""
        return len(self.decoded) == len(self.spans)

    def span(self, data: Any) -> tuple[int, int] | None:
        """The ``(offset, length)`` of the text that the stand-in ``data`` replaced (None if
        it is none)."""
        if not isinstance(data, str) or not data.startswith(self.prefix):
            return None
        return self.spans[int(data[len(self.prefix):])]

    def text(self, data: Any) -> memoryview | None:
        """The base64 text that the stand-in ``data`` replaced (None if it is none)."""
        span = self.span(data)
        return None if span is None else self.body[span[0]:span[0] + span[1]]


def lift_base64(raw: bytes | bytearray, min_chars: int = LIFT_CHARS
                ) -> tuple[bytes | bytearray, Lifted | None]:
    """``raw`` (a JSON text) with every string of at least ``min_chars`` that is the value
    of a member named ``data`` and holds no escapes replaced by a short stand-in, and what
    was cut out; ``(raw, None)`` when there is nothing to cut.

    Why this is safe without tokenizing: in valid JSON the quote after ``data`` is not
    escaped, so it closes a string, which the colon makes a member's name (``"data"``, or a
    longer one ending so, such as ``"x\"data"``); the next quote opens its value, a string
    that ends at the first unescaped quote, which is the next quote of all when the string
    holds no backslash. So exactly the contents of one string are replaced, and the
    document is otherwise the same. The caller must still check: that the body was valid
    JSON is known only if the rest parses and every cut-out string decodes as base64 (a
    raw control character, say, is no base64), and a stand-in that :func:`decode_arrays`
    did not consume (a long string that was not the data of a typed binary array) shows in
    :attr:`Lifted.complete`; otherwise the caller parses ``raw`` as it is."""
    find = raw.find
    pieces: list[bytes | bytearray] = []
    spans: list[tuple[int, int]] = []
    lifted = Lifted(memoryview(raw), spans)
    done = pos = 0
    while (member := _DATA_STRING.search(raw, pos)) is not None:
        start = member.end()
        end = find(b'"', start)
        if end < 0:
            break
        pos = end + 1
        if end - start < min_chars or find(b"\\", start, end) >= 0:
            continue
        pieces += (raw[done:start], f"\\u0000base64:{lifted.nonce}:{len(spans)}".encode())
        spans.append((start, end - start))
        done = end
    if not spans:
        return raw, None
    pieces.append(raw[done:])
    return b"".join(pieces), lifted


def is_binary_array(value: Any) -> bool:
    return isinstance(value, dict) and value.keys() == BINARY_KEYS


def decode_arrays(value: Any, name: str, lifted: Lifted | None = None, *,
                  max_depth: int = MAX_DEPTH) -> Any:
    """``value`` with every typed binary array object in it (at any depth of objects, up to
    ``max_depth`` levels) replaced by its numpy array; errors name the input path, such as
    ``mesh.vertices``. ``lifted``: the base64 strings cut out of the body the value was
    parsed from."""
    if is_binary_array(value):
        return _decode(value, name, lifted)
    if isinstance(value, dict):
        if max_depth <= 0:
            raise too_deep(name)
        return {k: decode_arrays(v, f"{name}.{k}", lifted, max_depth=max_depth - 1)
                for k, v in value.items()}
    return value


def too_deep(name: str) -> InvalidInputError:
    """The error for objects nested deeper than the limit inside an input; ``name`` is the
    path to the object at the limit."""
    head = name.split(".", 1)[0]
    return InvalidInputError(
        f"Expected `{head}` to hold objects nested only a few levels deep, got more levels "
        f"than the limit, at `{_shortened(name)}`.", field=head)


def _shortened(path: str, keep: int = 200) -> str:
    return path if len(path) <= keep else f"{path[:keep // 2]}...{path[-keep // 2:]}"


def _decode(obj: dict[str, Any], name: str, lifted: Lifted | None = None) -> np.ndarray:
    what = f"`{name}` as a typed binary array"
    try:
        dtype = np.dtype(obj["dtype"]) if isinstance(obj["dtype"], str) else None
    except TypeError:
        dtype = None
    if dtype is None or dtype.kind not in "iuf" or dtype.itemsize > 8:
        raise InvalidInputError(
            f"Expected {what} to have a dtype of integers or floats of up to 8 bytes "
            f"(such as 'float64', 'float32', 'int64', '<f8'), got {obj['dtype']!r}.",
            field=name)
    shape = obj["shape"]
    if not isinstance(shape, list) or not 1 <= len(shape) <= MAX_NDIM or not all(
            isinstance(s, int) and not isinstance(s, bool) and s >= 0 for s in shape):
        raise InvalidInputError(
            f"Expected {what} to have a shape of 1 to {MAX_NDIM} non-negative integers, got "
            f"{shape!r}.", field=name)
    data = obj["data"]
    span = lifted.span(data) if lifted is not None else None
    if lifted is not None and span is not None:
        data = lifted.body[span[0]:span[0] + span[1]]
    elif not isinstance(data, str):
        raise InvalidInputError(f"Expected {what} to carry its bytes as a base64 string, got "
                                f"{type(data).__name__}.", field=name)
    expected = math.prod(shape) * dtype.itemsize
    if len(data) > 4 * (expected // 3 + 1) + 4:  # refuse before decoding a mismatch
        raise InvalidInputError(
            f"Expected {what} of shape {tuple(shape)} and dtype {dtype.str} to hold "
            f"{expected} bytes, got a longer base64 string ({len(data)} characters).",
            field=name)
    try:  # strict: only the alphabet and correct padding
        raw = pybase64.b64decode_as_bytearray(data, validate=True)
    except (binascii.Error, ValueError):
        raise InvalidInputError(f"Expected {what} to carry valid base64 in `data`.",
                                field=name) from None
    if len(raw) != expected:
        raise InvalidInputError(
            f"Expected {what} of shape {tuple(shape)} and dtype {dtype.str} to hold "
            f"{expected} bytes, got {len(raw)}.", field=name)
    if lifted is not None and span is not None:
        lifted.decoded.append((raw, *span))
    arr = np.frombuffer(raw, dtype=dtype).reshape(shape)  # writable: the bytes are its own
    return arr if dtype.isnative else arr.astype(dtype.newbyteorder("="))


def owned(kwargs: dict[str, Any]) -> dict[str, Any]:
    """``kwargs`` with every array that is a read-only or misaligned view (of a request
    body, of an unpickled task) replaced by a writable, aligned copy (:func:`owned_value`):
    what a method, which may work in place on its input and whose BLAS calls may take other
    paths for misaligned operands, must get."""
    return {k: owned_value(v) for k, v in kwargs.items()}


def owned_value(value: Any) -> Any:
    """``value`` with its read-only or misaligned arrays replaced by writable, aligned
    copies, in meshes and other dataclasses, tuples, lists and dicts too; arrays that are
    writable and aligned, and everything else, are kept as they are."""
    if isinstance(value, np.ndarray):
        return value if value.flags.writeable and value.flags.aligned else value.copy()
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        changes = {f.name: owned_value(getattr(value, f.name))
                   for f in dataclasses.fields(value)
                   if isinstance(getattr(value, f.name), np.ndarray)}
        return dataclasses.replace(value, **changes) if changes else value
    if isinstance(value, tuple):
        return tuple(owned_value(v) for v in value)
    if isinstance(value, list):
        return [owned_value(v) for v in value]
    if isinstance(value, dict):
        return {k: owned_value(v) for k, v in value.items()}
    return value


def encode_arrays(value: Any) -> Any:
    """``value`` with its integer and float arrays (nested in dicts, lists and result
    dataclasses too) as typed binary arrays, little-endian: what :func:`decode_arrays`
    reads. Results sent this way are bit-exact, fast to decode, and an empty array keeps
    its shape; boolean arrays stay lists."""
    if isinstance(value, np.ndarray):
        if not 1 <= value.ndim <= MAX_NDIM or value.dtype.kind not in "biuf":
            return value
        if value.dtype.kind == "b":
            return value.tolist()
        a = np.ascontiguousarray(value, dtype=value.dtype.newbyteorder("<"))
        return {"dtype": a.dtype.str, "shape": list(a.shape),
                "data": pybase64.b64encode_as_string(a.data)}
    if isinstance(value, dict):
        return {k: encode_arrays(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [encode_arrays(v) for v in value]
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: encode_arrays(getattr(value, f.name))
                for f in dataclasses.fields(value)}
    return value
