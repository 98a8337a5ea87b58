"""The workbench with large results: page load, first frame and orbit frame times.

Runs two jobs on a live server (started here on loopback unless --url names one): a Tutte
parameterization of a 200k-vertex grid mesh (its GLB: the textured mesh and its UV layout)
and a PCA of 1M points (a 1M-point cloud). Then, in headless Chromium (Debian's chromium and
chromedriver, as the browser tests use), it opens ``/ui?job=ID`` for each and prints one
table: the page's load event, the first frame that shows the result (submitted, and drawn:
read back; both from the start of navigation), the time from the GLB's arrival to that
frame's submission, the GLB's size, and the mean
time of a frame while orbiting (--frames frames, each turned 6 degrees and waited for by
reading a pixel back). WebGL runs on SwiftShader, the CPU: a GPU is much faster. Nothing is
asserted; the machine is shared and noisy.

    python bench/workbench.py [--url http://127.0.0.1:8000] [--grid 448] [--points 1000000]
                              [--frames 10]
"""

from __future__ import annotations

import argparse
import base64
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import orjson

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT)]
from tests.live import LiveServer  # noqa: E402


def typed(a: np.ndarray) -> dict[str, Any]:
    a = np.ascontiguousarray(a)
    return {"dtype": a.dtype.str, "shape": list(a.shape),
            "data": base64.b64encode(a.tobytes()).decode()}


def grid_mesh(n: int) -> tuple[np.ndarray, np.ndarray]:
    """An n x n grid over the unit square, gently curved, two triangles per cell."""
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    v = np.column_stack([x.ravel(), y.ravel(), 0.2 * np.sin(4 * x.ravel()) * np.cos(3 * y.ravel())])
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    b, c, d = a + 1, a + n, a + n + 1
    f = np.concatenate([np.column_stack([a, b, d]), np.column_stack([a, d, c])]).astype(np.int32)
    return v, f


def run_job(http: httpx.Client, process: str, inputs: dict[str, Any]) -> str:
    r = http.post(f"/processes/{process}/execution", content=orjson.dumps({"inputs": inputs}),
                  headers={"Content-Type": "application/json", "Prefer": "respond-async"})
    r.raise_for_status()
    job = r.json()["jobID"]
    while True:
        info = http.get(f"/jobs/{job}").json()
        if info["status"] in ("successful", "failed", "dismissed"):
            if info["status"] != "successful":
                raise SystemExit(f"{process}: job {job} {info['status']}: {info.get('message')}")
            return str(job)
        time.sleep(0.2)


_ORBIT = """
const FRAMES = arguments[0], v = window.workbench.viewer, gl = v.renderer.getContext();
const c = v.controls.target, p = v.camera.position.clone().sub(c);
const px = new Uint8Array(4);
const t0 = performance.now();
for (let k = 0; k < FRAMES; k++) {
  p.applyAxisAngle(v.camera.up, Math.PI / 30);
  v.camera.position.copy(c).add(p);
  v.camera.lookAt(c);
  v.renderer.render(v.scene, v.camera);
  gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);  // waits for the frame
}
return (performance.now() - t0) / FRAMES;
"""


def measure(driver: Any, url: str, job: str, frames: int) -> dict[str, float]:
    from selenium.webdriver.support.ui import WebDriverWait

    driver.get(f"{url}/ui?job={job}")
    WebDriverWait(driver, 300, poll_frequency=0.05).until(
        lambda d: d.execute_script("return window.workbench?.viewer?.firstFrameAt"))
    # the frame is drawn once a pixel of it can be read back
    drawn = driver.execute_script("const gl = window.workbench.viewer.renderer.getContext(); "
                                  "gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, "
                                  "new Uint8Array(4)); return performance.now();")
    timing = driver.execute_script("""
      const n = performance.getEntriesByType('navigation')[0];
      const glb = performance.getEntriesByType('resource').find((r) => r.name.includes('f=glb'));
      return {load: n.loadEventEnd, first: window.workbench.viewer.firstFrameAt,
              fromGlb: window.workbench.viewer.firstFrameMs,
              bytes: glb ? glb.encodedBodySize || glb.transferSize : 0};""")
    driver.set_script_timeout(600)
    timing["drawn"] = drawn
    timing["orbit"] = driver.execute_script(_ORBIT, frames)
    return timing


def browser() -> Any:
    os.environ["SE_OFFLINE"] = "true"
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = os.environ.get("MORPHSERVE_CHROMIUM", "/usr/bin/chromium")
    for arg in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage",
                "--window-size=1400,900", "--use-angle=swiftshader",
                "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"):
        options.add_argument(arg)
    service = Service(executable_path=os.environ.get("MORPHSERVE_CHROMEDRIVER",
                                                     "/usr/bin/chromedriver"))
    return webdriver.Chrome(service=service, options=options)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--url", help="a running service (default: start one here)")
    ap.add_argument("--grid", type=int, default=448, help="grid side: 448 -> 200,704 vertices")
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument("--frames", type=int, default=10, help="frames of the orbit timed")
    args = ap.parse_args()
    server = None
    url = args.url
    if url is None:
        tmp = Path(tempfile.mkdtemp(prefix="bench-workbench-"))
        server = LiveServer(tmp / "data",
                            {"MORPHSERVE_MAX_REQUEST_BYTES": str(512 * 2**20)}).start()
        url = server.url
    try:
        with httpx.Client(base_url=url, timeout=600) as http:
            v, f = grid_mesh(args.grid)
            cases = [(f"parameterization.tutte, {len(v):,} vertices",
                      run_job(http, "parameterization.tutte",
                              {"mesh": {"vertices": typed(v), "faces": typed(f)}}))]
            pts = np.random.default_rng(0).normal(size=(args.points, 3)) * [3, 2, 1]
            cases.append((f"embedding.pca, {args.points:,} points",
                          run_job(http, "embedding.pca",
                                  {"points": typed(pts), "n_components": 3})))
        driver = browser()
        try:
            rows = [(name, measure(driver, url, job, args.frames)) for name, job in cases]
        finally:
            driver.quit()
    finally:
        if server is not None:
            server.stop()
    print(f"{'result':<42} {'GLB MB':>7} {'load ms':>8} {'1st frame ms':>13} "
          f"{'drawn by ms':>12} {'GLB->frame ms':>14} {'orbit ms/frame':>15}")
    for name, t in rows:
        print(f"{name:<42} {t['bytes'] / 2**20:>7.1f} {t['load']:>8.0f} {t['first']:>13.0f} "
              f"{t['drawn']:>12.0f} {t['fromGlb']:>14.0f} {t['orbit']:>15.1f}")


if __name__ == "__main__":
    main()
