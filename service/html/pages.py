"""The HTML pages, rendered from the JSON documents of the routes by Jinja2 templates.

Jinja2 escapes every value it inserts (``autoescape``), so a process's description, a job's
message or an input's name reach the page as text, never as markup; the few pieces built
here as markup (:func:`prose`) escape their text first. Styles are inline (one ``<style>``
block allowed by its hash in the Content-Security-Policy, :data:`CSP`): the pages load
nothing else, run no script and work offline.
"""

from __future__ import annotations

import base64
import hashlib
import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from urllib.parse import quote, urlencode, urlsplit

from jinja2 import Environment, FileSystemLoader, select_autoescape
from markupsafe import Markup, escape

__all__ = ["Context", "landing_page", "process_list_page", "process_page", "job_list_page",
           "job_page", "error_page", "CSP", "schema_type", "schema_bounds", "schema_choices",
           "prose", "ui_href"]

_HERE = Path(__file__).resolve().parent
CSS = (_HERE / "style.css").read_text(encoding="utf-8")
_CSS_HASH = base64.b64encode(hashlib.sha256(CSS.encode("utf-8")).digest()).decode()
#: What the pages may load: their own inline style block, nothing else (no script at all).
CSP = (f"default-src 'none'; style-src 'sha256-{_CSS_HASH}'; img-src 'self' data:; "
       "form-action 'self'; base-uri 'none'; frame-ancestors 'none'")

_env = Environment(loader=FileSystemLoader(_HERE / "templates"),
                   autoescape=select_autoescape(["html"], default=True),
                   trim_blocks=True, lstrip_blocks=True)

#: Job states in which the page refreshes itself (seconds) until the job ends.
_REFRESH = {"accepted": 2, "running": 2}


@dataclass(frozen=True)
class Context:
    """Where a page is: its path, its query (without ``f``), the service's root path."""

    path: str
    query: list[tuple[str, str]] = field(default_factory=list)
    root: str = ""

    @property
    def json_href(self) -> str:
        """This page's JSON document."""
        return self.root + self.path + "?" + urlencode([*self.query, ("f", "json")])

    def arg(self, name: str) -> str:
        values = [v for k, v in self.query if k == name]
        return values[-1] if values else ""


def ui_href(root: str, kind: str, ident: str) -> str:
    """The workbench opened on a process or a job: ``/ui?process=<id>``, ``/ui?job=<id>``."""
    return f"{root}/ui?{kind}={quote(ident, safe='._-')}"


def safe_href(href: Any) -> str:
    """A link's target if it is a path or an http(s) URL, else ``#`` (no ``javascript:``)."""
    if not isinstance(href, str):
        return "#"
    scheme = urlsplit(href).scheme.lower()
    return href if scheme in ("", "http", "https") else "#"


_CODE = re.compile(r"`([^`]+)`")


def prose(text: Any) -> Markup:
    """Plain text as HTML: escaped, with `backquoted` spans as code and blank lines as
    paragraph breaks."""
    if text is None:
        return Markup("")
    paragraphs = [p.strip() for p in re.split(r"\n\s*\n", str(text)) if p.strip()]
    html = []
    for p in paragraphs:
        escaped = str(escape(p))
        html.append("<p>" + _CODE.sub(r"<code>\1</code>", escaped) + "</p>")
    return Markup("\n".join(html))


def _branches(schema: Any) -> list[dict[str, Any]]:
    """A schema and the alternatives of its unions (anyOf, oneOf, allOf), depth first."""
    if not isinstance(schema, dict):
        return []
    out = [schema]
    for key in ("anyOf", "oneOf", "allOf"):
        for alt in schema.get(key, []) or []:
            out += _branches(alt)
    return out


def schema_type(schema: Any) -> str:
    """A short reading of a JSON Schema's type: ``integer``, ``string``, ``array of
    number``, ``string or array of array of number``, ``object (vertices, faces)``."""
    if not isinstance(schema, dict):
        return ""
    if "$ref" in schema:
        return str(schema["$ref"]).rsplit("/", 1)[-1]
    alts = schema.get("anyOf") or schema.get("oneOf")
    if alts:
        names = []
        for alt in alts:
            name = schema_type(alt)
            if name and name not in names:
                names.append(name)
        text = " or ".join(names)
    else:
        kind = schema.get("type")
        if isinstance(kind, list):
            text = " or ".join(str(k) for k in kind)
        elif kind == "array":
            items = schema.get("items")
            text = "array of " + schema_type(items) if isinstance(items, dict) and \
                schema_type(items) else "array"
        elif kind == "object" and isinstance(schema.get("properties"), dict):
            text = "object (" + ", ".join(schema["properties"]) + ")"
        elif kind is None and "enum" in schema:
            text = "one of the choices"
        else:
            text = str(kind or "any")
    if schema.get("nullable"):
        text += " or null"
    return text


def _number(x: Any) -> str:
    return json.dumps(x)


def schema_bounds(schema: Any) -> list[str]:
    """The numeric bounds of a schema and its alternatives, as ``≥ 1``, ``< 1``: JSON
    Schema 2020-12 (numeric exclusive bounds) and OpenAPI 3.0 (boolean flags) alike."""
    out: list[str] = []
    for s in _branches(schema):
        ex_min, ex_max = s.get("exclusiveMinimum"), s.get("exclusiveMaximum")
        if "minimum" in s:
            out.append(("> " if ex_min is True else "≥ ") + _number(s["minimum"]))
        if isinstance(ex_min, (int, float)) and not isinstance(ex_min, bool):
            out.append("> " + _number(ex_min))
        if "maximum" in s:
            out.append(("< " if ex_max is True else "≤ ") + _number(s["maximum"]))
        if isinstance(ex_max, (int, float)) and not isinstance(ex_max, bool):
            out.append("< " + _number(ex_max))
    return list(dict.fromkeys(out))


def schema_choices(schema: Any) -> list[str]:
    """The allowed values (``enum``, ``const``) of a schema and its alternatives, as JSON."""
    out: list[str] = []
    for s in _branches(schema):
        for value in s.get("enum", []) or []:
            out.append(json.dumps(value))
        if "const" in s:
            out.append(json.dumps(s["const"]))
    return list(dict.fromkeys(out))


def _default(schema: Any) -> str | None:
    """The schema's default as JSON text, None when it declares none."""
    if isinstance(schema, dict) and "default" in schema:
        return json.dumps(schema["default"])
    return None


_env.filters["prose"] = prose
_env.filters["href"] = safe_href
_env.globals.update(schema_type=schema_type, schema_bounds=schema_bounds,
                    schema_choices=schema_choices, default_of=_default, ui_href=ui_href)


def _render(template: str, ctx: Context, title: str, **values: Any) -> str:
    return _env.get_template(template).render(ctx=ctx, root=ctx.root, title=title,
                                              css=Markup(CSS), **values)


def _family(process_id: str) -> str:
    return process_id.split(".", 1)[0] if "." in process_id else "other"


def landing_page(doc: dict[str, Any], ctx: Context) -> str:
    links = [link for link in doc.get("links", []) if isinstance(link, dict)]
    return _render("landing.html", ctx, str(doc.get("title", "morphserve")), doc=doc,
                   links=links)


def process_list_page(doc: dict[str, Any], ctx: Context) -> str:
    """The processes grouped by family (in catalog order), filtered by the words of ``q``
    (each must appear in the id, title, description or keywords)."""
    q = ctx.arg("q").strip()
    words = q.lower().split()
    groups: dict[str, list[dict[str, Any]]] = {}
    total = 0
    for p in doc.get("processes", []):
        if not isinstance(p, dict):
            continue
        total += 1
        text = " ".join([str(p.get("id", "")), str(p.get("title", "")),
                         str(p.get("description", "")),
                         " ".join(map(str, p.get("keywords", []) or []))]).lower()
        if all(w in text for w in words):
            groups.setdefault(_family(str(p.get("id", ""))), []).append(p)
    shown = sum(len(g) for g in groups.values())
    return _render("processes.html", ctx, "Processes", groups=groups, q=q, shown=shown,
                   total=total)


def process_page(doc: dict[str, Any], ctx: Context) -> str:
    inputs = doc.get("inputs", {}) if isinstance(doc.get("inputs"), dict) else {}
    outputs = doc.get("outputs", {}) if isinstance(doc.get("outputs"), dict) else {}
    return _render("process.html", ctx, str(doc.get("title") or doc.get("id", "Process")),
                   p=doc, inputs=inputs, outputs=outputs, family=_family(str(doc.get("id"))))


def job_list_page(doc: dict[str, Any], ctx: Context) -> str:
    jobs = [j for j in doc.get("jobs", []) if isinstance(j, dict)]
    links = {link.get("rel"): link.get("href") for link in doc.get("links", [])
             if isinstance(link, dict)}
    offset = ctx.arg("offset")
    first = int(offset) + 1 if offset.isdigit() else 1
    return _render("jobs.html", ctx, "Jobs", jobs=jobs, matched=doc.get("numberMatched"),
                   next=links.get("next"), prev=links.get("prev"), first=first)


def job_page(doc: dict[str, Any], process: dict[str, Any] | None, ctx: Context) -> str:
    """A job's status; when it succeeded, its results as JSON, GLB (when the process shows
    its results as geometry) and NPY (each array output)."""
    from service.catalog import lookup

    job_id = str(doc.get("jobID", ""))
    pid = str(doc.get("processID", ""))
    entry = lookup(pid, test_processes=True)
    outputs = (process or {}).get("outputs", {}) if isinstance(process, dict) else {}
    arrays = [name for name, o in outputs.items()
              if isinstance(o, dict) and isinstance(o.get("schema"), dict)
              and o["schema"].get("type") == "array"]
    results = f"{ctx.root}/jobs/{quote(job_id, safe='')}/results"
    return _render("job.html", ctx, f"Job {job_id}", job=doc, results=results,
                   geometry=entry is not None and entry.geometry is not None,
                   outputs=list(outputs), arrays=arrays,
                   refresh=_REFRESH.get(str(doc.get("status"))),
                   process_title=(process or {}).get("title") if process else None)


def error_page(status: int, problem: dict[str, Any], ctx: Context) -> str:
    errors = [e for e in problem.get("errors", []) or [] if isinstance(e, dict)]
    title = str(problem.get("title") or "Error")
    return _render("error.html", ctx, f"{status} {title}", status=status, problem=problem,
                   errors=errors, heading=title)
