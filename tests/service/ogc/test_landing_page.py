"""Port of the suite's ``LandingPage`` and ``GeneralHttp`` classes: ``/`` and HTTP."""

from __future__ import annotations

import pytest

from tests.service.ogc.standard import REL, json_of, validate

pytestmark = pytest.mark.e2e


def test_landing_page_retrieval(http) -> None:  # noqa: ANN001
    """Abstract Test 1, /conf/core/landingpage-op (requirement /req/core/landingpage-op):
    the landing page is answered at ``/`` with 200, as JSON."""
    r = http.get("/", headers={"Accept": "application/json"})
    assert r.status_code == 200
    json_of(r)


def test_landing_page_validation(http) -> None:  # noqa: ANN001
    """Abstract Test 2, /conf/core/landingpage-success (/req/core/landingpage-success): the
    landing page is valid against landingPage.yaml and links to the API definition
    (``service-desc`` and/or ``service-doc``), to the conformance declaration and to the
    processes, with the standard's link relations; every link works."""
    r = http.get("/", headers={"Accept": "application/json"})
    doc = json_of(r)
    validate("landing_page", doc)
    rels = {link["rel"]: link["href"] for link in doc["links"]}
    assert "service-desc" in rels or "service-doc" in rels
    for rel in (REL + "conformance", REL + "processes", REL + "job-list"):
        assert rel in rels, rel
    for href in rels.values():
        assert href.startswith(str(http.base_url).rstrip("/") + "/"), href  # absolute
        assert http.get(href).status_code == 200, href


def test_http(http) -> None:  # noqa: ANN001
    """A.2.1.1 HTTP, Abstract Test 1 (/req/core/http): the service speaks HTTP 1.1."""
    r = http.get("/")
    assert r.status_code == 200 and r.http_version == "HTTP/1.1"
