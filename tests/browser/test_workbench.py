"""The workbench (/ui) in a real browser, against a live server.

For one process of every family: open the workbench, fill the example, run it, wait for
success, see the result drawn on the canvas and the quality table agree with the JSON API.
Also: a registration's moved source lies over its target (and the unmoved source does
not), a PLY uploaded through the file input, a long job cancelled, the jobs list, the index
of a point under the pointer.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from service.catalog import FAMILIES
from tests.live import LiveServer

pytestmark = pytest.mark.e2e

#: One process of each family, run on its example.
ONE_OF_EACH = {
    "alignment": "alignment.rigid",
    "assignment": "assignment.nearest",
    "classification": "classification.lda",
    "layout": "layout.laplacian",
    "clustering": "clustering.spectral",
    "deformation": "deformation.arap",
    "embedding": "embedding.tsne",
    "interpolation": "interpolation.arap",
    "parameterization": "parameterization.tutte",
    "registration": "registration.icp",
}

#: The viewer's clear colour, #20242c, as the canvas holds it.
BACKGROUND = (0x20, 0x24, 0x2C)

# Counts the canvas's pixels unlike the background and their bounding box, after two
# animation frames (so that what was changed has been drawn).
_CANVAS_STATS = """
const [bg, done] = [arguments[0], arguments[arguments.length - 1]];
requestAnimationFrame(() => requestAnimationFrame(() => {
  const c = document.querySelector('#view canvas');
  const t = document.createElement('canvas');
  t.width = c.width; t.height = c.height;
  const g = t.getContext('2d');
  g.drawImage(c, 0, 0);
  const d = g.getImageData(0, 0, c.width, c.height).data;
  let n = 0, x0 = c.width, y0 = c.height, x1 = -1, y1 = -1;
  for (let y = 0; y < c.height; y++) for (let x = 0; x < c.width; x++) {
    const i = 4 * (y * c.width + x);
    if (Math.abs(d[i] - bg[0]) + Math.abs(d[i + 1] - bg[1]) + Math.abs(d[i + 2] - bg[2]) > 24) {
      n++; if (x < x0) x0 = x; if (x > x1) x1 = x; if (y < y0) y0 = y; if (y > y1) y1 = y;
    }
  }
  done({n, box: [x0, y0, x1, y1], width: c.width, height: c.height,
        corner: [d[0], d[1], d[2]]});
}));
"""

_TABLE = """
return [...document.querySelectorAll('#quality tbody tr[data-name]')].map(
  (tr) => [tr.dataset.name, tr.querySelector('td').dataset.value, tr.querySelector('td').textContent]);
"""


def wait_until(browser: Any, script: str, timeout: float = 60.0) -> Any:
    from selenium.webdriver.support.ui import WebDriverWait

    return WebDriverWait(browser, timeout, poll_frequency=0.05).until(
        lambda d: d.execute_script(script))


def open_workbench(browser: Any, server: LiveServer, process: str) -> None:
    browser.get(f"{server.url}/ui?process={process}")
    state = wait_until(browser, "return document.body.dataset.ready")
    assert state == "true", browser.find_element("id", "problem").text
    wait_until(browser, f"return window.workbench.state.process?.id === {json.dumps(process)}")


def run_example(browser: Any, timeout: float = 90.0) -> str:
    """Fills the example, runs it, waits for the job's result to be shown; its id."""
    wait_until(browser, "return !document.querySelector('#example').disabled")
    browser.find_element("id", "example").click()
    return run(browser, timeout)


def run(browser: Any, timeout: float = 90.0) -> str:
    browser.execute_script("delete document.body.dataset.shown")
    browser.find_element("id", "run").click()
    job = wait_until(browser, "const l = document.querySelector('#job-line'); "
                     "return ['successful', 'failed', 'dismissed'].includes(l.dataset.status) "
                     "&& l.dataset.job", timeout)
    status = browser.find_element("id", "job-line").get_attribute("data-status")
    assert status == "successful", (status, browser.find_element("id", "problem").text)
    wait_until(browser, f"return document.body.dataset.shown === {json.dumps(job)}", timeout)
    return str(job)


def canvas(browser: Any) -> dict[str, Any]:
    stats: dict[str, Any] = browser.execute_async_script(_CANVAS_STATS, list(BACKGROUND))
    return stats


def set_layer(browser: Any, name: str, visible: bool) -> None:
    box = browser.find_element("css selector", f'#layers input[data-layer="{name}"]')
    if box.is_selected() != visible:
        box.click()


def layers(browser: Any) -> list[str]:
    return list(browser.execute_script(
        "return [...document.querySelectorAll('#layers input')].map((b) => b.dataset.layer)"))


def scalar_figures(doc: Any, prefix: str = "") -> dict[str, Any]:
    """The scalar members of a results document, nested objects' by dotted name."""
    out: dict[str, Any] = {}
    for key, value in doc.items():
        name = f"{prefix}.{key}" if prefix else key
        if value is None or isinstance(value, (bool, int, float, str)):
            out[name] = value
        elif isinstance(value, dict):
            out.update(scalar_figures(value, name))
    return out


def browser_errors(browser: Any) -> list[str]:
    """The page's console errors, but for the 406 of a result without geometry (asked for
    as GLB, which the viewer then draws from the inputs)."""
    return [e["message"] for e in browser.get_log("browser") if e["level"] == "SEVERE"
            and not ("f=glb" in e["message"] and "406" in e["message"])]


def test_one_process_of_every_family_is_covered() -> None:
    assert set(ONE_OF_EACH) == set(FAMILIES)
    assert all(p.split(".")[0] == f for f, p in ONE_OF_EACH.items())


@pytest.mark.parametrize("family", sorted(ONE_OF_EACH))
def test_run_the_example(browser: Any, server: LiveServer, http: Any, shot: Any,
                         family: str) -> None:
    process = ONE_OF_EACH[family]
    open_workbench(browser, server, process)
    job = run_example(browser)
    stats = canvas(browser)
    shot()
    assert tuple(stats["corner"]) == BACKGROUND  # what counts as background is right
    # something drawn, and not the whole canvas (a fitted view leaves a margin)
    assert 30 <= stats["n"] < 0.9 * stats["width"] * stats["height"], stats

    # what ran is the example of the process's OpenAPI execute operation (else the catalog's),
    # inputs equal to their default left out
    sent = browser.execute_script("return window.workbench.state.sent.get(arguments[0])", job)
    content = http.get("/openapi.json").json()["paths"].get(
        f"/processes/{process}/execution", {}).get("post", {}).get("requestBody", {}).get(
        "content", {}).get("application/json", {})
    example = (next(iter(content["examples"].values()))["value"]["inputs"]
               if content.get("examples") else http.get("/ui/examples.json").json()[process])
    inputs = http.get(f"/processes/{process}").json()["inputs"]
    assert set(sent) <= set(example)
    for name, value in example.items():
        if name in sent:
            assert sent[name] == value, name
        else:
            assert value == inputs[name]["schema"].get("default"), name

    api = http.get(f"/jobs/{job}/results").json()
    figures = scalar_figures(api)
    table = browser.execute_script(_TABLE)
    assert [row[0] for row in table] == list(figures)
    assert figures, f"{process}'s results hold no scalar"
    for name, value, text in table:
        assert json.loads(value) == figures[name], name
        expected = figures[name]
        if isinstance(expected, bool):
            assert text == str(expected).lower()
        elif isinstance(expected, (int, float)):
            assert math.isclose(float(text), expected, rel_tol=1e-5, abs_tol=1e-300), name
        elif expected is None:
            assert text == "—"
        else:
            assert text == expected
    links = {a.get_attribute("href").removeprefix(server.url) for a in
             browser.find_elements("css selector", "#downloads a")}
    assert f"/jobs/{job}/results" in links
    for link in links:  # every download answers
        assert http.get(link).status_code == 200, link
    assert browser_errors(browser) == []


def _overlap(a: list[int], b: list[int]) -> float:
    """Intersection over union of two pixel boxes [x0, y0, x1, y1]."""
    ix = max(0, min(a[2], b[2]) - max(a[0], b[0]) + 1)
    iy = max(0, min(a[3], b[3]) - max(a[1], b[1]) + 1)
    area = lambda r: (r[2] - r[0] + 1) * (r[3] - r[1] + 1)  # noqa: E731
    return ix * iy / (area(a) + area(b) - ix * iy)


def test_registration_moved_source_lies_over_the_target(browser: Any, server: LiveServer,
                                                        shot: Any) -> None:
    open_workbench(browser, server, "registration.icp")
    run_example(browser)
    names = layers(browser)
    assert {"source (moved)", "target"} <= set(names), names
    unmoved = "source" if "source" in names else "source (as given)"
    assert unmoved in names

    def only(name: str) -> dict[str, Any]:
        for other in names:
            set_layer(browser, other, other == name)
        return canvas(browser)

    moved, target, source = only("source (moved)"), only("target"), only(unmoved)
    shot("unmoved-source")
    for stats in (moved, target, source):
        assert stats["n"] > 0
    # the example's source is the target turned and shifted: moved back onto it, its box
    # is the target's; the unmoved source's is not
    assert _overlap(moved["box"], target["box"]) > 0.9
    assert _overlap(source["box"], target["box"]) < 0.9 * _overlap(moved["box"], target["box"])
    set_layer(browser, "source (moved)", True)
    set_layer(browser, "target", True)
    set_layer(browser, unmoved, False)
    shot("overlay")


def _grid_ply(path: Path, n: int = 10) -> tuple[int, int]:
    """A flat n x n grid of vertices, triangulated, written as PLY by trimesh; its vertex
    and face counts."""
    import trimesh

    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    vertices = np.column_stack([x.ravel(), y.ravel(), 0.1 * np.sin(3 * x.ravel())])
    faces = []
    for i in range(n - 1):
        for j in range(n - 1):
            a, b, c, d = i * n + j, i * n + j + 1, (i + 1) * n + j, (i + 1) * n + j + 1
            faces += [[a, b, d], [a, d, c]]
    trimesh.Trimesh(vertices, np.array(faces), process=False).export(path)
    return n * n, len(faces)


def test_upload_a_ply(browser: Any, server: LiveServer, http: Any, shot: Any,
                      tmp_path: Path) -> None:
    path = tmp_path / "grid.ply"
    n_vertices, n_faces = _grid_ply(path)
    open_workbench(browser, server, "parameterization.tutte")
    browser.find_element("id", "in-mesh-file").send_keys(str(path))
    assert "grid.ply" in browser.find_element("css selector",
                                              '[data-input="mesh"] .file-name').text
    job = run(browser)
    shot()
    result = http.get(f"/jobs/{job}/results").json()
    assert len(result["uv"]) == n_vertices  # the uploaded mesh, not the example
    assert len(result["mesh"]["faces"]) == n_faces
    assert result["flipped_faces"] == 0  # Tutte on a convex boundary: none (Floater)
    assert canvas(browser)["n"] > 1000  # a textured surface, not a few dots
    assert "UV layout" in layers(browser)
    assert browser_errors(browser) == []


def test_cancel_a_long_job(browser: Any, server: LiveServer, http: Any, shot: Any) -> None:
    open_workbench(browser, server, "diagnostics.sleep")
    browser.execute_script("document.querySelector('details.more')?.setAttribute('open', '')")
    seconds = browser.find_element("id", "in-seconds")
    seconds.clear()
    seconds.send_keys("120")
    steps = browser.find_element("id", "in-steps")
    steps.clear()
    steps.send_keys("1200")
    browser.find_element("id", "run").click()
    # live progress: the bar moves while the job runs
    wait_until(browser, "return document.querySelector('#job-line').dataset.status === 'running'"
               " && document.querySelector('#progress').value >= 1", 60)
    job = browser.find_element("id", "job-line").get_attribute("data-job")
    assert http.get(f"/jobs/{job}").json()["status"] == "running"
    shot("running")
    cancel = browser.find_element("id", "cancel")
    assert cancel.is_enabled()
    cancel.click()
    wait_until(browser, "return document.querySelector('#job-line').dataset.status "
               "=== 'dismissed'", 30)
    assert http.get(f"/jobs/{job}").json()["status"] == "dismissed"
    assert not browser.find_element("id", "cancel").is_enabled()
    assert browser.find_element("id", "run").is_enabled()


def test_jobs_list_opens_a_job(browser: Any, server: LiveServer, http: Any) -> None:
    open_workbench(browser, server, "alignment.rigid")
    job = run_example(browser)
    browser.find_element("id", "tab-jobs").click()
    row = f'#jobs tr[data-job="{job}"]'
    wait_until(browser, f"return document.querySelector({json.dumps(row)})", 10)
    assert "successful" in browser.find_element("css selector", row).text
    browser.execute_script("document.body.dataset.shown = ''")
    browser.find_element("css selector", f"{row} button").click()
    wait_until(browser, f"return document.body.dataset.shown === {json.dumps(job)}", 30)
    assert browser.find_element("id", "pane-run").is_displayed()


def test_hover_shows_the_point_index(browser: Any, server: LiveServer, http: Any) -> None:
    from selenium.webdriver.common.action_chains import ActionChains

    open_workbench(browser, server, "embedding.pca")
    job = run_example(browser)
    embedding = np.asarray(http.get(f"/jobs/{job}/results/embedding").json(), dtype=float)
    # point 5's place on the screen, projected by the viewer's own camera
    xy = browser.execute_script("""
      const v = window.workbench.viewer, p = arguments[0];
      const pts = []; v.root.traverse((o) => { if (o.isPoints) pts.push(o); });
      const a = pts[0].geometry.attributes.position;
      const w = pts[0].localToWorld(new (v.camera.position.constructor)(a.getX(5), a.getY(5), a.getZ(5)));
      w.project(v.camera);
      const r = v.renderer.domElement.getBoundingClientRect();
      return [(w.x + 1) / 2 * r.width, (1 - w.y) / 2 * r.height, r.width, r.height,
              a.getX(5), a.getY(5)];
    """, 5)
    assert xy[4] == pytest.approx(embedding[5, 0], rel=1e-5)  # float32 in the GLB
    assert xy[5] == pytest.approx(embedding[5, 1] if embedding.shape[1] > 1 else 0, rel=1e-5, abs=1e-6)
    view = browser.find_element("css selector", "#view canvas")
    ActionChains(browser).move_to_element_with_offset(
        view, int(xy[0] - xy[2] / 2), int(xy[1] - xy[3] / 2)).perform()
    text = wait_until(browser, "const h = document.querySelector('#hover'); "
                      "return !h.hidden && h.textContent", 10)
    assert re.search(r"#5\b", text), text


def test_interpolation_time_slider_moves_the_shape(browser: Any, server: LiveServer,
                                                   shot: Any) -> None:
    open_workbench(browser, server, "interpolation.arap")
    run_example(browser)
    assert browser.find_element("id", "timeline").is_displayed()

    def at(position: int) -> dict[str, Any]:
        browser.execute_script("const s = document.querySelector('#time'); s.value = "
                               "String(arguments[0]); s.dispatchEvent(new Event('input'));",
                               position)
        return canvas(browser)

    start, end = at(0), at(1000)
    shot("end-of-animation")
    # the example's source and target differ: the last frame is not the first
    assert start["box"] != end["box"] or start["n"] != end["n"]
    assert at(0) == start  # and the slider comes back to the first frame exactly
    browser.find_element("id", "play").click()
    assert browser.find_element("id", "play").text == "Pause"
    wait_until(browser, "return Number(document.querySelector('#time').value) > 0", 10)
    browser.find_element("id", "play").click()


def test_up_axis_turns_the_view(browser: Any, server: LiveServer, shot: Any) -> None:
    from selenium.webdriver.support.ui import Select

    open_workbench(browser, server, "registration.icp")
    run_example(browser)
    y_up = canvas(browser)
    Select(browser.find_element("id", "up-axis")).select_by_value("z")
    z_up = canvas(browser)
    shot("z-up")
    assert z_up["n"] > 0 and z_up["box"] != y_up["box"]
    Select(browser.find_element("id", "up-axis")).select_by_value("y")
    assert canvas(browser) == y_up


def _scan_ply(path: Path, points: np.ndarray) -> None:
    """A point cloud (no faces) written as PLY by trimesh, as a scanner's export is."""
    import trimesh

    trimesh.PointCloud(points).export(path)


_DROP = """
const [selector, name, b64, done] = arguments;
const bytes = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
const data = new DataTransfer();
data.items.add(new File([bytes], name, {type: 'application/octet-stream'}));
const zone = document.querySelector(selector);
for (const type of ['dragenter', 'dragover', 'drop']) {
  zone.dispatchEvent(new DragEvent(type, {dataTransfer: data, bubbles: true, cancelable: true}));
}
done(true);
"""


def test_register_two_scans_dropped_and_picked(browser: Any, server: LiveServer, http: Any,
                                               shot: Any, tmp_path: Path) -> None:
    """The acceptance's "register two scans without writing code": the source scan dropped
    on its input (drag and drop), the target chosen with the file picker, both PLY point
    clouds sent as multipart; the fit is the known motion and the moved source lies over the
    target on the canvas."""
    import base64

    # a scanned patch of a curved surface, sampled at random, and its copy moved a little
    # (as two scans of one surface from nearby poses): ICP's basin of convergence
    x, y = np.random.default_rng(7).uniform(-1, 1, size=(2, 800))
    source = np.column_stack([x, y, 0.3 * np.sin(3 * x) * np.cos(2 * y) + 0.2 * x ** 2])
    angle = np.radians(3.0)
    rotation = np.array([[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0],
                         [0, 0, 1]])
    shift = np.array([0.05, -0.03, 0.02])
    target = source @ rotation.T + shift
    _scan_ply(tmp_path / "scan-a.ply", source)
    _scan_ply(tmp_path / "scan-b.ply", target)

    open_workbench(browser, server, "registration.icp")
    browser.execute_async_script(_DROP, '[data-input="source"] .drop', "scan-a.ply",
                                 base64.b64encode((tmp_path / "scan-a.ply").read_bytes()).decode())
    browser.find_element("id", "in-target-file").send_keys(str(tmp_path / "scan-b.ply"))
    for name, file in (("source", "scan-a.ply"), ("target", "scan-b.ply")):
        assert file in browser.find_element(
            "css selector", f'[data-input="{name}"] .file-name').text, name
    job = run(browser)
    shot()
    result = http.get(f"/jobs/{job}/results").json()
    transform = np.asarray(result["transform"], dtype=float)
    np.testing.assert_allclose(transform[:3, :3], rotation, atol=1e-6)
    np.testing.assert_allclose(transform[:3, 3], shift, atol=1e-6)
    assert result["rmse"] < 1e-6
    names = layers(browser)
    assert {"source (moved)", "target"} <= set(names), names
    boxes = {}
    for name in ("source (moved)", "target"):
        for other in names:
            set_layer(browser, other, other == name)
        boxes[name] = canvas(browser)
        assert boxes[name]["n"] > 0, name
    assert _overlap(boxes["source (moved)"]["box"], boxes["target"]["box"]) > 0.95
    assert browser_errors(browser) == []


def test_search_processes_by_name_and_family(browser: Any, server: LiveServer,
                                             http: Any) -> None:
    """The process picker: words typed in the search box keep the processes whose id, title
    or keywords hold them all; a family keeps that family's; choosing one loads its form."""
    from selenium.webdriver.support.ui import Select

    catalog = http.get("/processes", params={"limit": 1000}).json()["processes"]
    listed = "return [...document.querySelectorAll('#process option')].map((o) => o.value)"
    browser.get(f"{server.url}/ui")
    wait_until(browser, "return document.body.dataset.ready")
    assert sorted(browser.execute_script(listed)) == sorted(p["id"] for p in catalog)

    search = browser.find_element("id", "search")
    search.send_keys("icp")
    found = browser.execute_script(listed)
    assert "registration.icp" in found
    assert all("icp" in (p["id"] + " " + p["title"] + " " + " ".join(p.get("keywords", [])))
               .lower() for p in catalog if p["id"] in found), found
    assert len(found) < len(catalog)

    search.clear()
    search.send_keys(" ")  # an input event with an empty query: everything again
    Select(browser.find_element("id", "family")).select_by_value("embedding")
    found = browser.execute_script(listed)
    assert found and sorted(found) == sorted(p["id"] for p in catalog
                                             if p["id"].startswith("embedding."))
    Select(browser.find_element("id", "process")).select_by_value("embedding.tsne")
    wait_until(browser, "return window.workbench.state.process?.id === 'embedding.tsne'", 10)
    assert browser.find_element("css selector", '[data-input="points"]').is_displayed()


_FIELDS = """
return [...document.querySelectorAll('#form [data-input]')].map((box) => {
  const c = box.querySelector('#in-' + CSS.escape(box.dataset.input));
  return {name: box.dataset.input, kind: box.dataset.kind, tag: c && c.tagName,
          type: c && c.type, min: c && c.getAttribute('min'), max: c && c.getAttribute('max'),
          value: c && (c.type === 'checkbox' ? c.checked : c.value),
          options: c && c.tagName === 'SELECT' ? [...c.options].map((o) => o.value) : null};
});
"""


@pytest.mark.parametrize("process", ["registration.icp", "embedding.tsne",
                                     "parameterization.tutte", "clustering.spectral"])
def test_the_form_follows_the_schema(browser: Any, server: LiveServer, http: Any,
                                     process: str) -> None:
    """The form of a process is its description's input schemas: a choice is a select of
    exactly its values, a number field carries the schema's bounds, and every field starts
    at the input's default."""
    open_workbench(browser, server, process)
    inputs = http.get(f"/processes/{process}").json()["inputs"]
    fields = {f["name"]: f for f in browser.execute_script(_FIELDS)}
    assert set(fields) == set(inputs)
    seen = set()
    for name, field in fields.items():
        schema = inputs[name]["schema"]
        default = schema.get("default")
        if "enum" in schema:
            seen.add("enum")
            assert field["tag"] == "SELECT", name
            values = [json.loads(v) for v in field["options"] if v != ""]
            assert values == schema["enum"], name
            if default is not None:
                assert json.loads(field["value"]) == default, name
        elif schema.get("type") in ("number", "integer"):
            seen.add("number")
            assert (field["tag"], field["type"]) == ("INPUT", "number"), name
            for bound, attr in (("minimum", "min"), ("maximum", "max")):
                if bound in schema:
                    seen.add(bound)
                    assert float(field[attr]) == schema[bound], (name, bound)
                else:
                    assert field[attr] is None, (name, bound)
            if default is not None:
                assert float(field["value"]) == default, name
        elif schema.get("type") == "boolean":
            assert field["value"] is bool(default), name
    assert seen & {"enum", "number"}, f"{process} has no choice nor number to check"
    if process == "registration.icp":  # bounded numbers (max_iterations >= 1, ...) and choices
        assert {"enum", "number", "minimum"} <= seen, seen
