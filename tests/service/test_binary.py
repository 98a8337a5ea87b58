"""Long base64 strings cut out of a JSON body before it is parsed (service.binary.lift_base64):
the document is the one the body says, whatever its spacing, escapes and member names, and a
body that is not valid JSON, or not valid base64, is never read as one that is."""

from __future__ import annotations

import base64
import json
from typing import Any

import numpy as np
import orjson
import pytest

from algorithms.core.errors import InvalidInputError
from service.binary import Lifted, decode_arrays, lift_base64

MIN = 16  # cut out strings from 16 characters: small documents exercise every path


def _b64(rng: np.random.Generator) -> dict[str, Any]:
    dtype = rng.choice(["<f8", "<f4", "<i4", "<i8", "<u2"])
    a = (rng.normal(size=(int(rng.integers(0, 12)), 3)) * 100).astype(dtype)
    return {"dtype": a.dtype.str, "shape": list(a.shape),
            "data": base64.b64encode(a.tobytes()).decode()}


def _text(rng: np.random.Generator) -> str:
    """A string that tempts the cutter: base64-like, or holding the text it looks for."""
    kind = int(rng.integers(0, 4))
    if kind == 0:
        return base64.b64encode(rng.bytes(int(rng.integers(0, 60)))).decode()
    if kind == 1:
        return '"data":"' + "A" * int(rng.integers(0, 40)) + '"'
    if kind == 2:
        return "x/y+z=" * int(rng.integers(1, 8))
    return "é\n\t" + "Q" * int(rng.integers(10, 30))


def _value(rng: np.random.Generator, depth: int = 0) -> Any:
    kind = int(rng.integers(0, 7 if depth < 3 else 3))
    if kind == 0:
        return _text(rng)
    if kind == 1:
        return float(rng.normal())
    if kind == 2:
        return _b64(rng)
    if kind == 3:
        return [_value(rng, depth + 1) for _ in range(int(rng.integers(0, 4)))]
    if kind == 4:  # a long string as the data of an object that is no typed binary array
        return {"data": base64.b64encode(rng.bytes(40)).decode(), "note": _text(rng)}
    keys = ["data", 'x"data', "metadata", "source", "\\data", "da\"ta"]
    return {str(rng.choice(keys)) + (str(i) if i else ""): _value(rng, depth + 1)
            for i in range(int(rng.integers(0, 4)))}


def _dumps(doc: Any, rng: np.random.Generator) -> bytes:
    style = int(rng.integers(0, 4))
    if style == 0:
        text = json.dumps(doc, separators=(",", ":"))
    elif style == 1:
        text = json.dumps(doc, indent=2)
    elif style == 2:
        text = json.dumps(doc, separators=(" ,\n", " :\t "))
    else:  # escapes (PHP writes \/ for every slash), non-ASCII as \u escapes
        text = json.dumps(doc).replace("/", "\\/")
    return text.encode()


def _restore(value: Any, lifted: Lifted, found: list[int]) -> Any:
    """The parsed skeleton with every stand-in replaced by the text it stands for."""
    if isinstance(value, dict):
        return {k: _restore(v, lifted, found) for k, v in value.items()}
    if isinstance(value, list):
        return [_restore(v, lifted, found) for v in value]
    text = lifted.text(value)
    if text is None:
        return value
    found.append(1)
    return bytes(text).decode("ascii")


@pytest.mark.parametrize("seed", range(300))
def test_the_skeleton_is_the_document_with_strings_stood_in_for(seed: int) -> None:
    rng = np.random.default_rng(seed)
    doc = {"inputs": {f"in{i}": _value(rng) for i in range(int(rng.integers(1, 5)))}}
    raw = _dumps(doc, rng)
    skeleton, lifted = lift_base64(bytearray(raw), MIN)
    if lifted is None:
        assert skeleton == raw
        return
    assert len(skeleton) < len(raw) + 40 * len(lifted.spans)
    found: list[int] = []
    assert _restore(orjson.loads(skeleton), lifted, found) == orjson.loads(raw) == doc
    assert len(found) == len(lifted.spans)  # every string cut out stands somewhere, once


def _inputs(doc: Any, lifted: Lifted | None) -> dict[str, Any]:
    return {k: decode_arrays(v, k, lifted) for k, v in doc["inputs"].items()}


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, np.ndarray):
        return isinstance(b, np.ndarray) and a.dtype == b.dtype and a.shape == b.shape and \
            a.tobytes() == b.tobytes()
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(
            _same(a[k], b[k]) for k in a)
    return a == b


def _arrays(rng: np.random.Generator) -> dict[str, Any]:
    return {"inputs": {"source": _b64(rng), "mesh": {"vertices": _b64(rng), "faces": _b64(rng)},
                       "k": 3}}


@pytest.mark.parametrize("seed", range(40))
def test_arrays_decoded_from_the_body_are_those_of_the_document(seed: int) -> None:
    rng = np.random.default_rng(seed)
    doc = _arrays(rng)
    raw = bytearray(_dumps(doc, rng))
    skeleton, lifted = lift_base64(raw, MIN)
    want = _inputs(orjson.loads(raw), None)
    if lifted is None:  # every array short (or escaped)
        return
    got = _inputs(orjson.loads(skeleton), lifted)
    assert lifted.complete and _same(got, want)
    for data, offset, length in lifted.decoded:  # each names the text it came from
        assert base64.b64decode(bytes(raw[offset:offset + length])) == data


def test_a_long_string_that_is_no_array_data_leaves_the_cut_incomplete() -> None:
    text = base64.b64encode(bytes(range(256)) * 4).decode()
    raw = json.dumps({"inputs": {"source": {"data": text, "shape": [1]}}}).encode()
    skeleton, lifted = lift_base64(raw, MIN)
    assert lifted is not None and len(lifted.spans) == 1
    _inputs(orjson.loads(skeleton), lifted)
    assert not lifted.complete  # the caller parses the body itself then


def test_escaped_strings_stay_in_the_body() -> None:
    a = np.arange(300.0)
    text = base64.b64encode(a.tobytes()).decode()
    doc = {"inputs": {"source": {"dtype": "<f8", "shape": [300], "data": text}}}
    raw = json.dumps(doc).replace("/", "\\/").encode()
    assert "/" in text
    skeleton, lifted = lift_base64(raw, MIN)
    assert lifted is None and skeleton is raw
    np.testing.assert_array_equal(_inputs(orjson.loads(raw), None)["source"], a)


_CORRUPT = [b"\n", b'"', b"\\", b"!", b"\x00", "é".encode(), b"\xff", b"=", b"}", b" "]


@pytest.mark.parametrize("seed", range(200))
def test_a_corrupted_body_is_never_read_as_another_document(seed: int) -> None:
    """One byte of a body replaced (a control character, a quote, a stray escape, invalid
    UTF-8, padding): whenever the cut-out path reads arrays from it, the body itself is
    valid JSON holding exactly those arrays."""
    rng = np.random.default_rng(seed)
    raw = bytearray(_dumps(_arrays(rng), rng))
    _, clean = lift_base64(bytes(raw), MIN)
    at = int(rng.integers(0, len(raw)))
    if clean is not None and seed % 2:  # at the edges or inside of a string to be cut out
        offset, length = clean.spans[int(rng.integers(0, len(clean.spans)))]
        at = int(rng.choice([offset - 1, offset, offset + length // 2, offset + length - 1,
                             offset + length]))
    raw[at:at + 1] = _CORRUPT[int(rng.integers(0, len(_CORRUPT)))]
    skeleton, lifted = lift_base64(raw, MIN)
    if lifted is None:
        return
    try:
        got = _inputs(orjson.loads(skeleton), lifted)
    except (orjson.JSONDecodeError, InvalidInputError):
        return  # the service parses the body itself then, and reports what it says
    if not lifted.complete:
        return
    assert _same(got, _inputs(orjson.loads(raw), None))


def test_invalid_base64_in_a_cut_out_string_names_the_input() -> None:
    text = base64.b64encode(np.zeros(600).tobytes()).decode()
    raw = json.dumps({"inputs": {"source": {"dtype": "<f8", "shape": [600],
                                            "data": text[:100] + "*" + text[101:]}}}).encode()
    skeleton, lifted = lift_base64(raw, MIN)
    assert lifted is not None
    with pytest.raises(InvalidInputError, match="valid base64") as info:
        _inputs(orjson.loads(skeleton), lifted)
    assert info.value.field == "source"
