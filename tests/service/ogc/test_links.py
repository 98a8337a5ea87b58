"""Absolute links behind a proxy, the links to the HTML pages, callbacks' links, and the SDK's
reading of the standard's exception types: what the ported suite needs besides its own
checks."""

from __future__ import annotations

import json
from types import SimpleNamespace
from typing import Any
from urllib.parse import parse_qsl, urlsplit

import httpx
import pytest
from starlette.requests import Request

from morphserve._exceptions import (
    NoSuchJob,
    NoSuchProcess,
    ResultNotReady,
    error_class,
    problem_from_response,
)
from service.app import _wire_callbacks
from service.jobs.status import Outcome
from service.jobs.store import JobRecord, JobRequest, Subscriber
from service.representation import html_alternate
from service.routes.common import base_url
from service.settings import Settings
from tests.live import wait_for_status
from tests.service.ogc.standard import (
    ECHO,
    ECHO_INPUTS,
    OGC_EXCEPTION,
    json_of,
    link_header,
    links_by_rel,
)


def _request(headers: dict[str, str], public_url: str | None = None,
             host: str = "127.0.0.1:8000", client: str = "127.0.0.1",
             allow: str = "127.0.0.1,::1") -> Request:
    settings = Settings(public_url=public_url, forwarded_allow_ips=allow)
    app = SimpleNamespace(state=SimpleNamespace(morphserve=SimpleNamespace(settings=settings)))
    raw = [(b"host", host.encode())] + [(k.lower().encode(), v.encode())
                                        for k, v in headers.items()]
    return Request({"type": "http", "method": "GET", "path": "/jobs", "headers": raw,
                    "scheme": "http", "server": ("127.0.0.1", 8000), "query_string": b"",
                    "client": (client, 50000), "app": app})


@pytest.mark.parametrize(("headers", "public", "expected"), [
    ({}, None, "http://127.0.0.1:8000"),
    ({"X-Forwarded-Proto": "https", "X-Forwarded-Host": "geo.example.org"}, None,
     "https://geo.example.org"),
    ({"X-Forwarded-Proto": "https", "X-Forwarded-Host": "geo.example.org, inner:8080",
      "X-Forwarded-Prefix": "/morphserve/"}, None, "https://geo.example.org/morphserve"),
    ({"X-Forwarded-Prefix": "/api"}, None, "http://127.0.0.1:8000/api"),
    # the configured public URL wins over anything the request says
    ({"X-Forwarded-Host": "evil.example"}, "https://geo.example.org/m/",
     "https://geo.example.org/m"),
    # values that are no URL's parts are ignored
    ({"X-Forwarded-Proto": "javascript"}, None, "http://127.0.0.1:8000"),
    ({"X-Forwarded-Host": "a.example/path"}, None, "http://127.0.0.1:8000"),
])
def test_base_url(headers: dict[str, str], public: str | None, expected: str) -> None:
    """The root URL that links start with: the setting, else the request's, as a proxy's
    X-Forwarded-Proto/Host/Prefix rewrite it (the first of a chain of proxies)."""
    assert base_url(_request(headers, public)) == expected


PROXIED = {"X-Forwarded-Proto": "https", "X-Forwarded-Host": "geo.example.org",
           "X-Forwarded-Prefix": "/m"}


@pytest.mark.parametrize(("client", "allow", "expected"), [
    ("127.0.0.1", "127.0.0.1,::1", "https://geo.example.org/m"),  # the default: a local proxy
    ("::1", "127.0.0.1,::1", "https://geo.example.org/m"),
    ("203.0.113.9", "127.0.0.1,::1", "http://127.0.0.1:8000"),  # anyone else: not believed
    ("10.1.2.3", "10.0.0.0/8", "https://geo.example.org/m"),  # the proxies' network
    ("10.1.2.3", "10.1.2.4", "http://127.0.0.1:8000"),
    ("203.0.113.9", "*", "https://geo.example.org/m"),
    ("testclient", "127.0.0.1", "http://127.0.0.1:8000"),  # a peer with no IP address
])
def test_forwarded_headers_count_only_from_the_allowed_proxies(
        client: str, allow: str, expected: str) -> None:
    """A client that is not one of ``forwarded_allow_ips`` cannot choose the host that links
    and Location headers name (uvicorn's rule, with its default)."""
    assert base_url(_request(PROXIED, client=client, allow=allow)) == expected


def test_forwarded_allow_ips_setting_is_checked() -> None:
    with pytest.raises(ValueError, match="forwarded_allow_ips.*proxy.example"):
        Settings(forwarded_allow_ips="127.0.0.1, proxy.example")


def test_public_url_setting_is_checked() -> None:
    with pytest.raises(ValueError, match="public_url"):
        Settings(public_url="geo.example.org/morphserve")


@pytest.mark.e2e
def test_links_behind_a_proxy(http) -> None:  # noqa: ANN001
    """Behind a proxy that forwards https://geo.example.org/morphserve, every link and the
    Location and Link headers name the proxy's URL."""
    proxy = {"X-Forwarded-Proto": "https", "X-Forwarded-Host": "geo.example.org",
             "X-Forwarded-Prefix": "/morphserve", "Content-Type": "application/json"}
    base = "https://geo.example.org/morphserve"
    landing = http.get("/", headers=proxy).json()
    assert {link["href"] for link in landing["links"]} >= {
        f"{base}/", f"{base}/processes", f"{base}/jobs", f"{base}/conformance"}
    for doc in (http.get("/processes?limit=2", headers=proxy).json(),
                http.get(f"/processes/{ECHO}", headers=proxy).json(),
                http.get("/jobs?limit=2", headers=proxy).json()):
        hrefs = [link["href"] for link in doc["links"]]
        assert hrefs and all(h.startswith(base + "/") for h in hrefs), hrefs
    r = http.post(f"/processes/{ECHO}/execution", content=json.dumps({"inputs": ECHO_INPUTS}),
                  headers={**proxy, "Prefer": "respond-async"})
    assert r.status_code == 201
    job = r.json()["jobID"]
    assert r.headers["location"] == f"{base}/jobs/{job}"
    assert link_header(r, "monitor") == [f"{base}/jobs/{job}"]
    assert all(link["href"].startswith(base + "/") for link in r.json()["links"])
    sync = http.post(f"/processes/{ECHO}/execution",
                     content=json.dumps({"inputs": ECHO_INPUTS}), headers=proxy)
    assert sync.status_code == 200
    (monitor,) = link_header(sync, "monitor")
    assert monitor.startswith(f"{base}/jobs/")


@pytest.mark.parametrize(("href", "expected"), [
    ("http://h/", "http://h/?f=html"),
    ("/jobs/j-1", "/jobs/j-1?f=html"),
    # the query kept, repeated parameters too; a given f replaced
    ("http://h/jobs?limit=2&offset=0&status=running&status=failed",
     "http://h/jobs?limit=2&offset=0&status=running&status=failed&f=html"),
    ("http://h/processes?f=json&limit=1", "http://h/processes?limit=1&f=html"),
])
def test_html_alternate(href: str, expected: str) -> None:
    link = html_alternate(href, "t")
    assert link == {"href": expected, "rel": "alternate", "type": "text/html", "title": "t"}


def _query(href: str) -> tuple[str, list[tuple[str, str]]]:
    parts = urlsplit(href)
    return parts.path, parse_qsl(parts.query)


@pytest.mark.e2e
def test_html_alternates(http) -> None:  # noqa: ANN001
    """/req/core/pl-links (and OGC API – Common): each JSON document that also has an HTML
    page (the landing page, the process list, a process description, the job list, a job's
    status) links to it: one ``alternate`` link, ``text/html``, its ``self`` link's absolute
    URL with ``f=html``, which answers the page whatever the Accept header; ``f=json``
    answers the JSON document."""
    r = http.post(f"/processes/{ECHO}/execution", content=json.dumps({"inputs": ECHO_INPUTS}),
                  headers={"Content-Type": "application/json", "Prefer": "respond-async"})
    assert r.status_code == 201
    job = r.json()["jobID"]
    base = str(http.base_url).rstrip("/")
    accept = {"Accept": "application/json"}
    for path in ("/", "/processes?limit=2&offset=1", f"/processes/{ECHO}",
                 "/jobs?limit=2", f"/jobs/{job}"):
        doc = json_of(http.get(path, headers=accept))
        (self_,) = links_by_rel(doc, "self")
        (alternate,) = links_by_rel(doc, "alternate")
        assert alternate["type"] == "text/html" and alternate["title"], path
        assert alternate["href"].startswith(base + "/"), alternate
        where, query = _query(self_["href"])
        assert _query(alternate["href"]) == (where, [*query, ("f", "html")]), path
        page = http.get(alternate["href"], headers=accept)
        assert page.status_code == 200, path
        assert page.headers["content-type"].split(";")[0] == "text/html", path
        sep = "&" if "?" in path else "?"
        assert json_of(http.get(path + sep + "f=json"))["links"] == doc["links"], path
    # the statuses of the job list link to their pages too
    listed = json_of(http.get("/jobs?limit=100", headers=accept))
    for info in listed["jobs"]:
        (alternate,) = links_by_rel(info, "alternate")
        assert alternate["href"] == f"{base}/jobs/{info['jobID']}?f=html"
    # a dismissed job that is removed has no page any more, and no link to one
    assert wait_for_status(http, job)["status"] == "successful"
    gone = http.delete(f"/jobs/{job}")
    assert gone.status_code == 200 and not links_by_rel(gone.json(), "alternate")
    assert http.get(f"/jobs/{job}?f=html").status_code == 404


class _Engine:
    def __init__(self) -> None:
        self.on_finish: list[Any] = []
        self.on_start: list[Any] = []


class _Notifier:
    def __init__(self) -> None:
        self.sent: list[tuple[str, Any]] = []

    def send(self, uri: str, document: Any) -> None:
        self.sent.append((uri, document))


class _Store:
    def __init__(self, job: JobRecord) -> None:
        self.job = job

    def get(self, job_id: str) -> JobRecord:
        return self.job


@pytest.mark.parametrize(("base", "expected"), [
    ("", "/jobs/j-1"), ("https://geo.example.org/m", "https://geo.example.org/m/jobs/j-1")])
def test_callback_links(base: str, expected: str) -> None:
    """A callback answers no request: its statusInfo's links start with the configured
    public URL, or are relative to the service's root when none is configured."""
    sub = Subscriber(success_uri=None, in_progress_uri="http://127.0.0.1:1/progress",
                     failed_uri="http://127.0.0.1:1/failed")
    job = JobRecord.accepted(process="alignment.rigid", request=JobRequest(subscriber=sub),
                             time_limit=60.0, idempotency_key=None, request_hash=None,
                             created=1_700_000_000.0)
    engine, notifier = _Engine(), _Notifier()
    _wire_callbacks(engine, _Store(job), notifier, base)  # type: ignore[arg-type]
    engine.on_start[0](job)
    engine.on_finish[0](job, Outcome.failed({"type": "x", "status": 500}))
    assert [uri for uri, _ in notifier.sent] == [sub.in_progress_uri, sub.failed_uri]
    for _, doc in notifier.sent:
        assert doc["links"][0]["href"] == expected.replace("j-1", job.id)
        assert None not in doc.values()


@pytest.mark.parametrize(("slug", "cls"), [
    ("no-such-process", NoSuchProcess), ("no-such-job", NoSuchJob),
    ("result-not-ready", ResultNotReady)])
def test_sdk_reads_both_forms_of_a_type(slug: str, cls: type) -> None:
    """The SDK maps the standard's exception type URIs and the service's own
    ``/problems/{slug}`` to the same class."""
    assert error_class(OGC_EXCEPTION + slug, 404) is cls
    assert error_class(f"/problems/{slug}", 404) is cls
    response = httpx.Response(404, json={"type": OGC_EXCEPTION + slug, "title": "t",
                                         "status": 404, "detail": "d"},
                              request=httpx.Request("GET", "http://127.0.0.1/jobs/x"))
    error = problem_from_response(response)
    assert type(error) is cls and error.type == OGC_EXCEPTION + slug


@pytest.mark.e2e
def test_sdk_follows_absolute_links(server) -> None:  # noqa: ANN001
    """The SDK, reading absolute Location headers and next links, still runs a job
    asynchronously and pages through the job list."""
    from morphserve import Client

    with Client(server.url) as client:
        jobs = [client.execute(ECHO, **ECHO_INPUTS) for _ in range(4)]  # Location: absolute
        for job in jobs:
            assert job.wait(timeout=60).status == "successful"
            assert job.results()["translation"].tolist() == pytest.approx([2.0, 3.0])
        listed = client.jobs(process=ECHO, limit=4)  # newest first: these four
        assert {j.job_id for j in listed} == {j.id for j in jobs}


_PAGES = {"/": "getLandingPage", "/processes": "getProcesses",
          "/processes/{processId}": "getProcessDescription", "/jobs": "getJobs",
          "/jobs/{jobId}": "getStatus"}


def test_openapi_documents_the_html_pages() -> None:
    """The API definition shows the HTML pages: each of the five operations takes the
    optional query parameter ``f`` (json or html) and may answer ``text/html``, its errors
    included; the other operations offer no page."""
    from service.openapi import document

    doc = document()
    for path, operation_id in _PAGES.items():
        op = doc["paths"][path]["get"]
        assert op["operationId"] == operation_id
        (f,) = [p for p in op["parameters"] if p["name"] == "f"]
        assert f["in"] == "query" and not f.get("required", False)
        (choice,) = [s for s in f["schema"]["anyOf"] if s.get("type") == "string"]
        assert choice["enum"] == ["json", "html"]
        for code, response in op["responses"].items():
            assert "text/html" in response["content"], (path, code)
    assert "text/html" not in doc["paths"]["/conformance"]["get"]["responses"]["200"].get(
        "content", {})
