"""What the tests of ``tests/service/ogc/`` share: the standard's schemas, link reading, and
the process they run.

The tests port the OGC executable test suite of OGC API – Processes – Part 1 (1.0),
``ets-ogcapi-processes10``: one test function per ``@Test`` of the suite, named after it.
They validate the service's documents with ``jsonschema_rs`` against our own JSON Schemas of
what the standard requires of each document (:mod:`tests.service.ogc.schemas`, which names
the requirement and the standard's schema behind each, and says where the standard's schema
is broken as written and what it means there), and against the standard's schema files
themselves, vendored with their licence in ``standard_schemas/`` (:mod:`tests.service.ogc.vendored`).

The suite runs its jobs on an "echo" process with a plain string input. The service has none;
its tests run ``alignment.rigid`` on a hand-computed case instead: three points moved by a
known translation, whose fit is the identity rotation and that translation, with zero error.
"""

from __future__ import annotations

import json
from typing import Any

import httpx

from tests.service.ogc import schemas

__all__ = ["validate", "errors", "link_header", "links_by_rel", "ECHO",
           "ECHO_INPUTS", "SHIFT", "OGC_EXCEPTION", "REL", "json_of"]

OGC_EXCEPTION = "http://www.opengis.net/def/exceptions/ogcapi-processes-1/1.0/"
REL = "http://www.opengis.net/def/rel/ogc/1.0/"

#: The process the job tests run (the suite's "echo process"), and its hand-computed case.
ECHO = "alignment.rigid"
SHIFT = [2.0, 3.0]
_SOURCE = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
ECHO_INPUTS: dict[str, Any] = {
    "source": _SOURCE,
    "target": [[x + SHIFT[0], y + SHIFT[1]] for x, y in _SOURCE],
}


def errors(name: str, document: Any) -> list[str]:
    """What makes ``document`` invalid as the standard's document ``name`` (a key of
    :data:`tests.service.ogc.schemas.DEFINITIONS`, ``"status_info"``); empty when valid."""
    return schemas.errors(name, document)


def validate(name: str, document: Any) -> None:
    found = errors(name, document)
    assert not found, f"invalid as {name}:\n" + "\n".join(found[:20])


def json_of(response: httpx.Response) -> Any:
    """The body of a JSON answer, checking its media type as the standard names it."""
    media = response.headers["content-type"].split(";")[0].strip()
    assert media in ("application/json", "application/problem+json"), media
    return json.loads(response.content)


def link_header(response: httpx.Response, rel: str) -> list[str]:
    """The targets of the ``Link`` header's links of relation ``rel``, parsed as RFC 8288
    says (a quoted ``rel="monitor"`` and a bare ``rel=monitor`` are the same)."""
    return [link["url"] for link in response.links.values()
            if rel in link.get("rel", "").split()]


def links_by_rel(document: dict[str, Any], rel: str) -> list[dict[str, Any]]:
    return [link for link in document.get("links", []) if link.get("rel") == rel]
