"""The workbench's files as the service serves them (no browser needed): the page, its
modules and the vendored three.js, with their media types; nothing outside them."""

from __future__ import annotations

import json
import re
from typing import Any

import pytest

from service.routes.ui import THREE

pytestmark = pytest.mark.e2e


def test_the_page_and_every_module_it_imports_are_served(http: Any) -> None:
    page = http.get("/ui")
    assert page.status_code == 200
    assert page.headers["content-type"].startswith("text/html")
    html = page.text
    imports = json.loads(re.search(r'<script type="importmap">(.*?)</script>', html,
                                   re.S).group(1))["imports"]
    assert set(imports) == {"three", "three/addons/"}
    modules = [imports["three"], imports["three/addons/"] + "controls/OrbitControls.js",
               imports["three/addons/"] + "loaders/GLTFLoader.js",
               *re.findall(r'<script type="module" src="([^"]+)"', html),
               *re.findall(r'<link rel="stylesheet" href="([^"]+)"', html)]
    seen = set()
    while modules:  # the modules, and the relative imports of each, transitively
        path = modules.pop()
        if path in seen:
            continue
        seen.add(path)
        r = http.get(path)
        assert r.status_code == 200, path
        if path.endswith(".js"):
            assert r.headers["content-type"].startswith("text/javascript"), path
            base = path.rsplit("/", 1)[0]
            for rel in re.findall(r"""from\s+['"](\.{1,2}/[^'"]+)['"]""", r.text):
                parts = (base + "/" + rel).split("/")
                out: list[str] = []
                for p in parts:
                    if p == "..":
                        out.pop()
                    elif p != ".":
                        out.append(p)
                modules.append("/".join(out))
    assert any(p.endswith("three.core.js") for p in seen)  # three.module.js's own import
    assert http.get("/ui/", follow_redirects=False).headers["location"] == "/ui"


def test_the_vendored_three_is_the_pinned_version() -> None:
    pinned = re.search(r"three (\d+)\.(\d+)\.(\d+)", (THREE / "VERSION").read_text())
    assert pinned is not None
    core = (THREE / "build" / "three.core.js").read_text()
    assert re.search(r"REVISION = '(\d+)'", core).group(1) == pinned.group(2)
    assert "MIT License" in (THREE / "LICENSE").read_text()


@pytest.mark.parametrize("path", [
    "/ui/vendor/three/..%2F..%2F..%2Fapp.py",
    "/ui/..%2Froutes%2Fui.py",
    "/ui/vendor/three/LICENSE",  # no served suffix
    "/ui/nothing.js",
    "/ui/vendor/three/build",
])
def test_nothing_else_is_served(http: Any, path: str) -> None:
    r = http.get(path)
    assert r.status_code == 404
    assert r.headers["content-type"] == "application/problem+json"


def test_the_examples_are_the_catalogs(http: Any) -> None:
    examples = http.get("/ui/examples.json").json()
    ids = [p["id"] for p in http.get("/processes").json()["processes"]]
    assert list(examples) == ids
    # every required input of every process has an example (what "Fill the example" fills)
    for pid in ids:
        inputs = http.get(f"/processes/{pid}").json()["inputs"]
        required = {n for n, i in inputs.items() if i["minOccurs"] > 0}
        assert required <= set(examples[pid]), pid


def test_the_workbench_is_not_part_of_the_api(http: Any) -> None:
    assert not [p for p in http.get("/openapi.json").json()["paths"] if p.startswith("/ui")]
