"""Port of the suite's ``Conformance`` class: ``/conformance``."""

from __future__ import annotations

import pytest

from tests.service.ogc.standard import json_of, validate

pytestmark = pytest.mark.e2e

CONF = "http://www.opengis.net/spec/ogcapi-processes-1/1.0/conf/"


def test_validate_conformance_operation_and_response(http) -> None:  # noqa: ANN001
    """/conf/core/conformance-success (/req/core/conformance-success): ``/conformance``
    answers 200 with a document valid against confClasses.yaml whose ``conformsTo`` is a
    list of strings naming the Core class. (The suite runs this once per conformance path
    the API definition declares; ours declares one, ``/conformance``.)"""
    r = http.get("/conformance", headers={"Accept": "application/json"})
    assert r.status_code == 200
    doc = json_of(r)
    validate("conformance", doc)
    assert all(isinstance(c, str) for c in doc["conformsTo"])
    assert CONF + "core" in doc["conformsTo"]
    # every class the service claims is one the standard defines
    known = {CONF + c for c in ("core", "ogc-process-description", "json", "html", "oas30",
                                "job-list", "callback", "dismiss")}
    assert set(doc["conformsTo"]) <= known, set(doc["conformsTo"]) - known
