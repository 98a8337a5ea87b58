"""``/ui``: the workbench, a single-page app in the browser (``service/static/ui/``).

The page is static files: HTML, CSS and JavaScript modules that run as they are (no build
step), and three.js vendored under ``service/static/vendor/three/`` (served at
``/ui/vendor/three/``, resolved by the page's import map). Everything the page shows comes
from the service's own JSON and binary endpoints (``/processes``, ``/jobs``,
``/jobs/{id}/results?f=glb``, ``/openapi.json``). These routes stay out of the OpenAPI
document: they are the browser's, not the API's.

``/ui/examples.json`` is the catalog's example inputs of every process, which the page
uses for a process whose OpenAPI execute operation carries no example. ``/ui/samples.json``
(a static file) lists the sample data sets the page offers and the processes each suits, such
as ``/ui/sample-digits.json`` (UCI handwritten digits, CC BY 4.0; see ``examples/digits/``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from fastapi import APIRouter, Request
from starlette.responses import FileResponse, RedirectResponse, Response

from service.catalog import processes
from service.errors import ServiceError
from service.jsonio import JSONResponse
from service.routes.common import state

router = APIRouter(include_in_schema=False)

STATIC = Path(__file__).resolve().parents[1] / "static"
UI = STATIC / "ui"
THREE = STATIC / "vendor" / "three"

#: The media types of the files served; any other suffix is not served.
MEDIA = {
    ".html": "text/html; charset=utf-8",
    ".js": "text/javascript; charset=utf-8",
    ".css": "text/css; charset=utf-8",
    ".svg": "image/svg+xml",
    ".png": "image/png",
    ".json": "application/json",
    ".txt": "text/plain; charset=utf-8",
}


def _file(root: Path, path: str, cache: str) -> FileResponse:
    """The file ``path`` under ``root``, or a 404 problem: nothing outside ``root`` (no
    ``..``, no absolute paths, no symlinks out) and only the suffixes of :data:`MEDIA`."""
    target = (root / path).resolve()
    media = MEDIA.get(target.suffix.lower())
    if media is None or not target.is_relative_to(root.resolve()) or not target.is_file():
        raise ServiceError("not-found", f"No such file of the workbench: {path!r}.")
    return FileResponse(target, media_type=media, headers={"Cache-Control": cache})


@router.api_route("/ui", methods=["GET", "HEAD"])
async def workbench() -> Response:
    return _file(UI, "index.html", "no-cache")


@router.api_route("/ui/", methods=["GET", "HEAD"])
async def workbench_slash() -> Response:
    return RedirectResponse("/ui", status_code=308)


@router.api_route("/ui/examples.json", methods=["GET", "HEAD"])
async def examples(request: Request) -> JSONResponse:
    """The catalog's example inputs, by process id."""
    st = state(request)
    out: dict[str, Any] = {p.id: dict(p.examples)
                           for p in processes(test_processes=st.settings.test_processes)}
    return JSONResponse(out, headers={"Cache-Control": "no-cache"})


@router.api_route("/ui/vendor/three/{path:path}", methods=["GET", "HEAD"])
async def three(path: str) -> Response:
    # pinned files that change only with the version in VERSION: a day in the cache
    return _file(THREE, path, "public, max-age=86400")


@router.api_route("/ui/{path:path}", methods=["GET", "HEAD"])
async def asset(path: str) -> Response:
    return _file(UI, path, "no-cache")
