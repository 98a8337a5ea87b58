"""Port of the suite's ``ProcessList`` class: ``GET /processes`` and its ``limit``."""

from __future__ import annotations

from urllib.parse import parse_qs, urlsplit

import pytest

from service.catalog import processes
from tests.service.ogc.standard import json_of, validate

pytestmark = pytest.mark.e2e

#: Every process the test server offers (it runs with the diagnostic processes on).
OFFERED = [p.id for p in processes(test_processes=True)]


def _operation(http, path: str, method: str = "get") -> dict:  # noqa: ANN001
    return http.get("/openapi.json").json()["paths"][path][method]


def test_pl_limit_definition(http) -> None:  # noqa: ANN001
    """Abstract Test 9, /conf/core/pl-limit-definition (/req/core/pl-limit-definition): the
    operation takes an optional integer query parameter ``limit``, minimum 1, maximum
    10000, and the request ``?limit=10`` is valid against the API definition.

    The requirement's fragment shows ``default: 10``; this service's default is the whole
    catalog (up to 1000), because OWSLib and the service's SDK read the first page only, and
    the standard lets the server choose its default."""
    (limit,) = [p for p in _operation(http, "/processes")["parameters"]
                if p["name"] == "limit"]
    assert limit["in"] == "query" and not limit.get("required", False)
    schema = limit["schema"]
    assert schema["type"] == "integer"
    assert schema["minimum"] == 1 and schema["maximum"] == 10_000
    assert schema["minimum"] <= 10 <= schema["maximum"]
    assert http.get("/processes?limit=10").status_code == 200
    r = http.get("/processes?limit=0")
    assert r.status_code == 422 and r.json()["errors"][0]["input"] == "limit"


@pytest.mark.parametrize("limit", [1, 2, 5])
def test_pl_limit_response(http, limit: int) -> None:  # noqa: ANN001
    """Abstract Test 12, /conf/core/pl-limit-response (/req/core/pl-limit-response): the
    response holds no more process summaries than ``limit``; walking the ``next`` links
    visits every process once, in order."""
    r = http.get(f"/processes?limit={limit}", headers={"Accept": "application/json"})
    doc = json_of(r)
    assert len(doc["processes"]) == limit
    seen = [p["id"] for p in doc["processes"]]
    while True:
        nxt = [link["href"] for link in doc["links"] if link["rel"] == "next"]
        if not nxt:
            break
        doc = http.get(nxt[0]).json()
        assert 1 <= len(doc["processes"]) <= limit
        seen += [p["id"] for p in doc["processes"]]
    assert seen == OFFERED


def test_pl_links(http) -> None:  # noqa: ANN001
    """Abstract Test 11, /conf/core/pl-links (/req/core/pl-links): the response links to
    itself (``self``) with an absolute URL that answers the same page, and to the same page
    in every other media type the service offers (``alternate``: the HTML page, the same
    query with ``f=html``); pages have ``next`` and ``prev`` links. (The suite only checks
    that ``links`` is an array.)"""
    base = str(http.base_url).rstrip("/")
    doc = json_of(http.get("/processes?limit=1&offset=1"))
    rels = {link["rel"]: link["href"] for link in doc["links"]}
    assert len(rels) == len(doc["links"])  # one link of each relation
    assert set(rels) == {"self", "alternate", "next", "prev"}
    for href in rels.values():
        assert href.startswith(base + "/processes?"), href
    query = parse_qs(urlsplit(rels["self"]).query)
    assert query == {"limit": ["1"], "offset": ["1"]}
    assert parse_qs(urlsplit(rels["alternate"]).query) == {**query, "f": ["html"]}
    assert parse_qs(urlsplit(rels["next"]).query)["offset"] == ["2"]
    assert parse_qs(urlsplit(rels["prev"]).query)["offset"] == ["0"]
    assert http.get(rels["self"]).json()["processes"] == doc["processes"]
    (alternate,) = [link for link in doc["links"] if link["rel"] == "alternate"]
    assert alternate["type"] == "text/html" and alternate["title"]
    page = http.get(rels["alternate"])
    assert page.status_code == 200
    assert page.headers["content-type"].split(";")[0] == "text/html"
    # the same page: the one process of this JSON page, not the next one
    assert f"/processes/{OFFERED[1]}\"" in page.text
    assert f"/processes/{OFFERED[2]}\"" not in page.text
    last = json_of(http.get(f"/processes?limit=1&offset={len(OFFERED) - 1}"))
    assert "next" not in {link["rel"] for link in last["links"]}
    first = json_of(http.get("/processes?limit=1"))
    assert "prev" not in {link["rel"] for link in first["links"]}


def test_process_list(http) -> None:  # noqa: ANN001
    """Abstract Test 8, /conf/core/process-list (/req/core/process-list): ``/processes``
    lists the processes: at least one, and exactly those the catalog offers."""
    doc = json_of(http.get("/processes", headers={"Accept": "application/json"}))
    assert [p["id"] for p in doc["processes"]] == OFFERED and OFFERED


def test_process_list_success(http) -> None:  # noqa: ANN001
    """Abstract Test 10, /conf/core/process-list-success (/req/core/process-list-success):
    the process list is valid against processList.yaml, and each summary's links are
    absolute and lead to its description, its description's HTML page and its execution
    endpoint."""
    r = http.get("/processes", headers={"Accept": "application/json"})
    assert r.status_code == 200
    doc = json_of(r)
    validate("process_list", doc)
    base = str(http.base_url).rstrip("/")
    for summary in doc["processes"]:
        hrefs = {link["rel"]: link["href"] for link in summary["links"]}
        assert hrefs["self"] == f"{base}/processes/{summary['id']}"
        assert hrefs["alternate"] == f"{base}/processes/{summary['id']}?f=html"
        assert hrefs["http://www.opengis.net/def/rel/ogc/1.0/execute"] == \
            f"{base}/processes/{summary['id']}/execution"
