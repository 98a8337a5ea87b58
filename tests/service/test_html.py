"""HTML pages for browsers (service.html): content negotiation, every page against a live
server, escaping, error pages, well-formed markup, and API keys.

The pages are renderings of the JSON documents; what they must show is read here from the
JSON API or from the catalog itself (service.catalog, the functions' signatures), never from
the pages' own code.
"""

from __future__ import annotations

import inspect
import json
import re
from collections.abc import Iterator
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest

from service.catalog import processes
from service.html import pages, wants_html
from service.html.middleware import quality
from tests.live import LiveServer, execute

BROWSER = "text/html,application/xhtml+xml,application/xml;q=0.9,image/avif,image/webp,*/*;q=0.8"
FIREFOX_OLD = "text/html,application/xhtml+xml,application/xml;q=0.9,*/*;q=0.8"
PAGES = ["/", "/processes", "/processes/registration.icp", "/jobs"]
XSS = "<script>alert(1)</script>"
XSS_PATH = "<svg onload=alert(1)>"  # no "/": it stays one path segment


# ------------------------------------------------------------------ negotiation (unit)

@pytest.mark.parametrize("accept, f, html", [
    (BROWSER, None, True),
    (FIREFOX_OLD, None, True),
    ("text/html", None, True),
    ("text/*", None, True),                          # text/html via text/*, json not at all
    ("*/*", None, False),                            # curl, httpx: JSON
    (None, None, False),                             # no header: JSON
    ("", None, False),
    ("application/json", None, False),
    ("application/json, text/html", None, False),    # a tie: JSON, the API's own format
    ("text/html;q=0.5, application/json", None, False),
    ("application/json;q=0.5, text/html", None, True),
    ("text/html;q=0, */*", None, False),             # html refused outright
    ("application/*;q=0.2, text/html;q=0.3", None, True),
    ("TEXT/HTML;Q=0.9, */*;q=0.8", None, True),      # case-insensitive
    ("text/html;level=1;q=0.9, application/json;q=0.8", None, True),  # params ignored
    ("text/html;q=abc, application/json;q=0.1", None, False),  # a malformed q drops its range
    ("application/json", "html", True),              # ?f= wins over Accept
    (BROWSER, "json", False),
])
def test_negotiation(accept, f, html):
    assert wants_html(accept, f) is html


def test_quality_takes_the_most_specific_range():
    """RFC 9110 §12.5.1's example: text/html;level=1 gets 1, text/html 0.7, text/plain 0.3,
    image/jpeg 0.5 (parameters other than q are ignored here, so the level=1 range and the
    plain text/html one are both 'text/html')."""
    accept = "text/*;q=0.3, text/html;q=0.7, */*;q=0.5"
    assert quality(accept, "text/html") == 0.7
    assert quality(accept, "text/plain") == 0.3
    assert quality(accept, "image/jpeg") == 0.5
    assert quality("application/json", "text/html") == 0.0
    assert quality(None, "text/html") == 1.0


# ------------------------------------------------------------------ a well-formedness check

VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source",
        "track", "wbr"}


class Page(HTMLParser):
    """Parses a page, checking that every element is closed in order, and keeps what the
    tests look at: links, text by element class, rows of tables by data attribute."""

    def __init__(self, text: str) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: list[str] = []
        self.errors: list[str] = []
        self.links: list[str] = []
        self.tags: list[tuple[str, dict[str, str]]] = []
        self.text: list[str] = []
        self.rows: dict[str, dict[str, str]] = {}  # data-input/output/job -> class -> text
        self._row: tuple[str, str] | None = None
        self._cell: list[str] = []
        self._cell_class: str | None = None
        self._capture: dict[str, list[str]] = {}
        self.captured: dict[str, str] = {}
        self.doctype = False
        self.feed(text)
        self.close()
        if self.stack:
            self.errors.append(f"unclosed at the end: {self.stack}")

    def handle_decl(self, decl: str) -> None:
        self.doctype = self.doctype or decl.lower() == "doctype html"

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = {k: v or "" for k, v in attrs}
        self.tags.append((tag, a))
        if tag == "a" and "href" in a:
            self.links.append(a["href"])
        if tag == "tr":
            for key in ("data-input", "data-output", "data-job"):
                if key in a:
                    self._row = (key, a[key])
                    self.rows[f"{key}={a[key]}"] = {}
        if tag == "td":
            self._cell, self._cell_class = [], a.get("class")
        for cls in a.get("class", "").split():
            if cls in ("reference", "detail", "message", "description"):
                self._capture.setdefault(cls, [])
        if tag not in VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.handle_starttag(tag, attrs)
        if tag not in VOID:
            self.stack.pop()

    def handle_endtag(self, tag: str) -> None:
        if tag in VOID:
            self.errors.append(f"end tag of the void element {tag}")
            return
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes {self.stack[-1:] or 'nothing'}")
            return
        self.stack.pop()
        if tag == "td" and self._row is not None and self._cell_class:
            key = f"{self._row[0]}={self._row[1]}"
            self.rows[key][self._cell_class] = "".join(self._cell).strip()
        if tag == "tr":
            self._row = None
        if tag in ("div", "p", "dd") and self._capture:
            for cls, chunks in list(self._capture.items()):
                self.captured.setdefault(cls, "".join(chunks).strip())
            self._capture.clear()

    def handle_data(self, data: str) -> None:
        self.text.append(data)
        self._cell.append(data)
        for chunks in self._capture.values():
            chunks.append(data)

    @property
    def all_text(self) -> str:
        return " ".join("".join(self.text).split())


def parse(text: str) -> Page:
    page = Page(text)
    assert page.doctype, "no <!DOCTYPE html>"
    assert not page.errors, page.errors
    assert "<script" not in text.lower()  # the pages run no script, ours or anyone's
    return page


def get_html(http: httpx.Client, path: str, **kw: Any) -> tuple[httpx.Response, Page]:
    r = http.get(path, headers={"Accept": BROWSER, **kw.pop("headers", {})}, **kw)
    assert r.headers["content-type"] == "text/html; charset=utf-8", (path, r.text[:300])
    assert "accept" in r.headers.get("vary", "").lower()
    return r, parse(r.text)


def nav_ok(page: Page) -> None:
    """Every page links to the workbench, the API docs and the JSON document it shows."""
    assert "/ui" in page.links and "/docs" in page.links
    assert any("f=json" in href for href in page.links)


# ------------------------------------------------------------------ live pages

@pytest.fixture(scope="module")
def jobs(server: LiveServer) -> dict[str, str]:
    """Two finished jobs of alignment.rigid, the newest last."""
    rng = np.random.default_rng(0)
    out = {}
    with server.client() as http:
        for name in ("first", "second"):
            src = rng.normal(size=(10, 3))
            r = execute(http, "alignment.rigid", {"source": src.tolist(),
                                                  "target": (src + 1).tolist()})
            assert r.status_code == 200, r.text
            out[name] = r.headers["content-location"].rstrip("/").split("/")[-2]
    return out


@pytest.mark.e2e
@pytest.mark.parametrize("path", PAGES)
def test_browsers_get_html_and_programs_json(http, path):
    r, page = get_html(http, path)
    assert r.status_code == 200
    nav_ok(page)
    assert "default-src 'none'" in r.headers["content-security-policy"]
    for accept in ("*/*", "application/json", None):
        headers = {"Accept": accept} if accept else {}
        j = http.get(path, headers=headers)
        assert j.status_code == 200
        assert j.headers["content-type"].startswith("application/json"), accept
        assert "accept" in j.headers["vary"].lower()
        j.json()
    forced = http.get(path, params={"f": "html"}, headers={"Accept": "application/json"})
    assert forced.headers["content-type"].startswith("text/html")
    back = http.get(path, params={"f": "json"}, headers={"Accept": BROWSER})
    assert back.headers["content-type"].startswith("application/json")
    assert back.json() == http.get(path).json()
    head = http.head(path, headers={"Accept": BROWSER})
    assert head.status_code == 200 and head.content == b""
    assert head.headers["content-type"] == "text/html; charset=utf-8"
    assert int(head.headers["content-length"]) == len(r.content)


@pytest.mark.e2e
def test_unknown_format_is_refused_naming_f(http):
    r = http.get("/processes", params={"f": "xml"})
    assert r.status_code == 422 and r.headers["content-type"] == "application/problem+json"
    assert r.json()["errors"][0]["input"] == "f"
    r, page = get_html(http, "/processes", params={"f": "xml"})
    assert r.status_code == 422 and "xml" in page.all_text


@pytest.mark.e2e
def test_landing_page(http):
    doc = http.get("/").json()
    r, page = get_html(http, "/")
    assert doc["title"] in page.all_text and doc["description"] in page.all_text
    for link in doc["links"]:
        assert link["href"] in page.links
    assert ("a", {"class": "button", "href": "/ui"}) in page.tags  # the prominent link


@pytest.mark.e2e
def test_process_list_groups_by_family_and_links_each(http):
    ids = [p["id"] for p in http.get("/processes").json()["processes"]]
    _, page = get_html(http, "/processes")
    for pid in ids:
        assert f"/processes/{pid}" in page.links and f"/ui?process={pid}" in page.links
    families = {pid.split(".")[0] for pid in ids}
    headings = {a["id"].removeprefix("family-") for t, a in page.tags
                if t == "h2" and a.get("id", "").startswith("family-")}
    assert headings == families


@pytest.mark.e2e
def test_process_list_search(http):
    listed = http.get("/processes").json()["processes"]

    def matches(p, words):
        text = " ".join([p["id"], p["title"], p["description"], " ".join(p["keywords"])])
        return all(w in text.lower() for w in words)

    for q in ("icp", "point cloud", "Laplacian mesh", "nothing-matches-this"):
        _, page = get_html(http, "/processes", params={"q": q, "f": "html"})
        shown = {h.removeprefix("/processes/") for h in page.links
                 if re.fullmatch(r"/processes/[a-z0-9_]+\.[a-z0-9_]+", h)}
        assert shown == {p["id"] for p in listed if matches(p, q.lower().split())}, q
    _, page = get_html(http, "/processes", params={"q": XSS})
    assert XSS in page.all_text  # shown as text; parse() refused any <script> element


def _defaults(process) -> dict[str, Any]:
    """The declared defaults of a process's service inputs, read from its function's
    signature (the one place they are declared); the display inputs have none."""
    sig = inspect.signature(process.function)
    return {name: sig.parameters[name].default for name in process.params.model_fields
            if name not in process.display
            and sig.parameters[name].default is not inspect.Parameter.empty}


@pytest.mark.e2e
def test_every_process_page_shows_its_declared_defaults(http):
    for process in processes():
        _, page = get_html(http, f"/processes/{process.id}")
        assert process.title in page.all_text
        assert f"/ui?process={process.id}" in page.links
        declared = _defaults(process)
        for name in process.params.model_fields:
            cells = page.rows[f"data-input={name}"]
            if name not in declared:
                assert cells["default"] == "—", (process.id, name, cells)
            elif declared[name] is None:
                assert cells["default"] in ("—", "null"), (process.id, name, cells)
            else:
                expected = json.loads(json.dumps(declared[name]))  # tuples as lists
                assert json.loads(cells["default"]) == expected, (process.id, name)
        for name in process.outputs:
            assert f"data-output={name}" in page.rows, (process.id, name)
        if process.reference:
            assert page.captured["reference"] == process.reference.replace("`", ""), process.id


@pytest.mark.e2e
def test_process_page_shows_choices_and_bounds(http):
    from typing import get_args, get_type_hints

    from service.catalog import lookup

    icp = lookup("registration.icp")
    _, page = get_html(http, "/processes/registration.icp")
    choices = get_args(get_type_hints(icp.function)["model"])
    allowed = page.rows["data-input=model"]["allowed"]
    assert [json.loads(c) for c in re.findall(r'"[^"]*"', allowed)] == list(choices)
    # max_iterations: >= 1 from the signature, <= 10000 from the service's limit
    assert page.rows["data-input=max_iterations"]["allowed"] == "≥ 1, ≤ 10000"
    assert page.rows["data-input=source"]["name"] == "source required"
    assert page.rows["data-input=model"]["name"] == "model"
    assert page.rows["data-input=source"]["type"] == "array of array of number"


@pytest.mark.e2e
def test_job_list_and_paging(http, jobs):
    listed = http.get("/jobs", params={"limit": 1}).json()
    r, page = get_html(http, "/jobs", params={"limit": 1})
    newest = listed["jobs"][0]
    row = page.rows[f"data-job={newest['jobID']}"]
    assert row["job"] == newest["jobID"] and row["process"] == newest["processID"]
    assert row["status"] == newest["status"] == "successful"
    assert row["progress"] == "100% 100%"  # the bar's fallback text, then the figure
    assert row["created"] == newest["created"] and row["finished"] == newest["finished"]
    assert f"/jobs/{newest['jobID']}" in page.links
    assert len([k for k in page.rows if k.startswith("data-job=")]) == 1
    nxt = next(link["href"] for link in listed["links"] if link["rel"] == "next")
    assert nxt in page.links
    second, page2 = get_html(http, nxt)
    assert second.status_code == 200
    assert f"/jobs/{http.get(nxt).json()['jobs'][0]['jobID']}" in page2.links
    # the route's own query parameters work alongside f=html
    r, page = get_html(http, "/jobs", params={"f": "html", "status": "successful",
                                              "processID": "alignment.rigid", "limit": 5})
    assert r.status_code == 200 and f"/jobs/{jobs['first']}" in page.links
    r, page = get_html(http, "/jobs", params={"status": "bogus"})
    assert r.status_code == 422 and "status" in page.all_text


@pytest.mark.e2e
def test_job_page(http, jobs):
    job = jobs["first"]
    info = http.get(f"/jobs/{job}").json()
    r, page = get_html(http, f"/jobs/{job}")
    assert r.status_code == 200
    assert info["status"] in page.all_text and info["processID"] in page.all_text
    assert info["created"] in page.all_text
    assert f"/ui?job={job}" in page.links
    results = f"/jobs/{job}/results"
    for href in (f"{results}?f=json", f"{results}?f=glb", f"{results}/transform?f=npy"):
        assert href in page.links
        assert http.get(href).status_code == 200, href
    assert f"{results}/rmse?f=npy" not in page.links  # a number, not an array


@pytest.mark.e2e
def test_error_pages_keep_the_status_and_escape(http):
    for path in ("/processes/no.such", "/jobs/nope", f"/processes/{XSS_PATH}",
                 f"/jobs/{XSS_PATH}"):
        problem = http.get(path).json()
        r, page = get_html(http, path)
        assert r.status_code == problem["status"] == 404, path
        assert page.captured["detail"] == problem["detail"]
    r = http.get(f"/jobs/{XSS_PATH}", headers={"Accept": BROWSER})
    assert XSS_PATH in http.get(f"/jobs/{XSS_PATH}").json()["detail"]  # the id is echoed
    assert "<svg" not in r.text and "&lt;svg onload=alert(1)&gt;" in r.text


def test_renderers_escape_what_the_documents_say():
    """A job's message, a process's texts and a problem's detail are text, not markup."""
    ctx = pages.Context(path="/jobs/x")
    job = {"jobID": "x", "processID": f"a.b{XSS}", "status": "failed", "message": XSS,
           "progress": 5, "created": XSS, "links": []}
    for html in (pages.job_page(job, {"title": XSS, "outputs": {XSS: {"schema": {}}}}, ctx),
                 pages.job_list_page({"jobs": [job], "links": [
                     {"rel": "next", "href": "javascript:alert(1)"}], "numberMatched": 1}, ctx),
                 pages.process_page({"id": f"x.{XSS}", "title": XSS, "description": f"`{XSS}`",
                                     "reference": XSS, "keywords": [XSS], "inputs": {XSS: {
                                         "title": XSS, "description": XSS, "schema": {
                                             "type": "string", "enum": [XSS],
                                             "default": XSS}}},
                                     "outputs": {XSS: {"description": XSS, "schema": {}}}},
                                    ctx),
                 pages.process_list_page({"processes": [{"id": f"x.{XSS}", "title": XSS,
                                                         "description": XSS}]}, ctx),
                 pages.landing_page({"title": XSS, "description": XSS, "links": [
                     {"href": "javascript:alert(1)", "title": XSS, "rel": XSS}]}, ctx),
                 pages.error_page(400, {"title": XSS, "detail": XSS, "errors": [
                     {"input": XSS, "message": XSS}]}, ctx)):
        page = parse(html)
        assert XSS in page.all_text
        assert "javascript:" not in " ".join(page.links)
    page = parse(pages.job_page(job, None, ctx))
    assert page.captured["message"] == XSS


def test_the_style_block_is_the_one_the_policy_allows():
    import base64
    import hashlib

    html = pages.landing_page({"title": "t", "links": []}, pages.Context(path="/"))
    style = re.search(r"<style>(.*?)</style>", html, re.S).group(1)
    digest = base64.b64encode(hashlib.sha256(style.encode()).digest()).decode()
    assert f"'sha256-{digest}'" in pages.CSP
    assert "url(" not in style and "@import" not in style  # loads nothing: works offline


# ------------------------------------------------------------------ API keys

@pytest.fixture(scope="module")
def keyed(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[LiveServer, str]]:
    from tests.service.test_e2e_auth import add_key

    root: Path = tmp_path_factory.mktemp("html-auth")
    key = add_key("alice", root / "keys")
    srv = LiveServer(root / "data", env={"MORPHSERVE_API_KEYS_FILE": str(root / "keys"),
                                         "MORPHSERVE_WORKERS": "1"}).start()
    yield srv, key
    srv.stop()


@pytest.mark.e2e
def test_without_a_key_browsers_get_a_401_page_not_the_content(keyed):
    from service.catalog import lookup

    srv, key = keyed
    rigid_title = lookup("alignment.rigid").title
    with srv.client() as anon, srv.client(headers={"Authorization": f"Bearer {key}"}) as me:
        for path in ("/", "/processes", "/processes/alignment.rigid", "/jobs"):
            for client, status in ((anon, 401), (me, 200)):
                r, page = get_html(client, path)
                assert r.status_code == status, (path, r.text[:200])
            r, page = get_html(anon, path)
            assert "www-authenticate" in r.headers
            assert "API key" in page.all_text
            assert me.get("/").json()["description"] not in page.all_text  # no content
            assert rigid_title not in page.all_text and "alignment.rigid" not in page.all_text
        with srv.client(headers={"Authorization": "Bearer wrong"}) as bad:
            r, page = get_html(bad, "/jobs")
            assert r.status_code == 401 and "not valid" in page.all_text


def test_templates_and_style_are_package_data():
    """The wheel carries every template and the style sheet: the package-data globs of
    pyproject.toml match them."""
    import tomllib

    root = Path(__file__).resolve().parents[2]
    globs = tomllib.loads((root / "pyproject.toml").read_text())["tool"]["setuptools"][
        "package-data"]["service"]
    service = root / "service"
    packaged = {f for g in globs for f in service.glob(g) if f.is_file()}
    html = service / "html"
    needed = {*html.glob("templates/*"), html / "style.css"}
    assert len(needed) == 8 and needed <= packaged, needed - packaged
