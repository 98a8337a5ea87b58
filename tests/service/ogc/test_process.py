"""Port of the suite's ``Process`` class: ``GET /processes/{processId}``."""

from __future__ import annotations

import uuid

import pytest

from tests.service.ogc.standard import ECHO, OGC_EXCEPTION, json_of, validate

pytestmark = pytest.mark.e2e


def test_process_exception_no_such_process(http) -> None:  # noqa: ANN001
    """/req/core/process-exception-no-such-process: an unknown process id is answered 404
    with an exception (exception.yaml) of type
    ``http://www.opengis.net/def/exceptions/ogcapi-processes-1/1.0/no-such-process``."""
    r = http.get(f"/processes/invalid-process-{uuid.uuid4()}",
                 headers={"Accept": "application/json"})
    assert r.status_code == 404
    doc = json_of(r)
    validate("exception", doc)
    assert doc["type"] == OGC_EXCEPTION + "no-such-process"


def test_process(http) -> None:  # noqa: ANN001
    """/req/core/process (the process description operation): ``/processes/{processId}``
    answers 200 with the description of that process."""
    r = http.get(f"/processes/{ECHO}", headers={"Accept": "application/json"})
    assert r.status_code == 200
    doc = json_of(r)
    assert doc["id"] == ECHO and doc["inputs"] and doc["outputs"]


def test_process_success(http) -> None:  # noqa: ANN001
    """/req/core/process-success: the description is valid against process.yaml (the
    standard's, including its schema.yaml for every input and output schema), and links to
    itself and to its execution endpoint with absolute URLs."""
    doc = json_of(http.get(f"/processes/{ECHO}", headers={"Accept": "application/json"}))
    validate("process", doc)
    base = str(http.base_url).rstrip("/")
    hrefs = {link["rel"]: link["href"] for link in doc["links"]}
    assert hrefs["self"] == f"{base}/processes/{ECHO}"
    assert hrefs["http://www.opengis.net/def/rel/ogc/1.0/execute"] == \
        f"{base}/processes/{ECHO}/execution"
