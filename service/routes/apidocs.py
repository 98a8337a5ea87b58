"""``/docs``: the API documentation, Swagger UI served by the service itself.

Swagger UI is vendored under ``service/static/swagger/`` (the ``swagger-ui-dist`` npm
package, pinned; see its README there), so the page works with no network: it loads its
script, style sheet and icon from ``/docs/assets/`` and the API definition from
``/openapi.json``. Swagger UI's online validator badge is switched off (it would fetch an
image from validator.swagger.io). ReDoc is not offered: Swagger UI alone runs the examples
("Try it out"), and one vendored viewer is enough. These routes stay out of the OpenAPI
document: they are the browser's, not the API's.
"""

from __future__ import annotations

import html
import json
from pathlib import Path

from fastapi import APIRouter
from starlette.responses import FileResponse, HTMLResponse, RedirectResponse, Response

from service.errors import ServiceError

__all__ = ["router", "ASSETS", "SWAGGER"]

router = APIRouter(include_in_schema=False)

SWAGGER = Path(__file__).resolve().parents[1] / "static" / "swagger"

#: The files of Swagger UI the page uses, with their media types; nothing else is served.
ASSETS = {
    "swagger-ui-bundle.js": "text/javascript; charset=utf-8",
    "swagger-ui.css": "text/css; charset=utf-8",
    "favicon-32x32.png": "image/png",
    "favicon-16x16.png": "image/png",
}

_CONFIG = {
    "url": "/openapi.json",
    "dom_id": "#swagger-ui",
    "deepLinking": True,
    "docExpansion": "none",
    "tryItOutEnabled": False,
    "displayOperationId": False,
    "defaultModelsExpandDepth": 0,
    "validatorUrl": None,
    "filter": True,
}
"""Swagger UI's options: operations folded (one per process makes a long page), a search box
(by tag: the family), no online validator."""


def _page(title: str) -> str:
    config = json.dumps(_CONFIG, indent=2)
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{html.escape(title)}</title>
<link rel="stylesheet" href="/docs/assets/swagger-ui.css">
<link rel="icon" type="image/png" sizes="32x32" href="/docs/assets/favicon-32x32.png">
<link rel="icon" type="image/png" sizes="16x16" href="/docs/assets/favicon-16x16.png">
</head>
<body>
<div id="swagger-ui"></div>
<script src="/docs/assets/swagger-ui-bundle.js"></script>
<script>
const config = {config};
config.presets = [SwaggerUIBundle.presets.apis];
window.ui = SwaggerUIBundle(config);
</script>
</body>
</html>
"""


_PAGE = _page("morphserve: API documentation")


@router.get("/docs")
async def docs_page() -> HTMLResponse:
    return HTMLResponse(_PAGE, headers={"Cache-Control": "no-cache"})


@router.get("/docs/")
async def docs_slash() -> Response:
    return RedirectResponse("/docs", status_code=308)


@router.get("/docs/assets/{name}")
async def asset(name: str) -> Response:
    # pinned files that change only with the version in VERSION: a day in the cache
    media = ASSETS.get(name)
    if media is None:
        raise ServiceError("not-found", f"No such file of the API documentation: {name!r}.")
    return FileResponse(SWAGGER / name, media_type=media,
                        headers={"Cache-Control": "public, max-age=86400"})
