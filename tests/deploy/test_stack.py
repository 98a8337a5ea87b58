"""The image and docker/compose.yaml, really built and run (podman, podman-compose).

What a user of the Docker section of the README relies on: the README's curl answers through
the stack; a job of each family runs on the stack's workers; a worker killed mid-job costs no
job; an API restarted with jobs accepted finishes them; ``down`` keeps the data volume, so a
second ``up`` still lists the old jobs; the image runs as a non-root user and its healthcheck
passes. Every port is on 127.0.0.1, and nothing reaches outside the machine.
"""

from __future__ import annotations

import hashlib
import json
import re
import statistics
import subprocess
import time
from collections.abc import Iterator
from typing import Any

import httpx
import numpy as np
import pytest

from service import catalog
from tests.deploy.conftest import FIGURES, PROXY_NETWORKS, ROOT, Stack, podman, wait_ready
from tests.live import LiveServer, example, execute, free_port, wait_for_status

pytestmark = [pytest.mark.container, pytest.mark.e2e, pytest.mark.timeout(600)]

README = ROOT / "README.md"
UID = "10001"


def readme_curl() -> str:
    """The README's first curl: alignment.rigid on four points, answered in the response."""
    block = re.findall(r"```sh\n(.*?)```", README.read_text(), flags=re.S)[1]
    assert "alignment.rigid" in block and "Prefer: wait=10" in block
    return block


def run_readme_curl(url: str) -> dict[str, Any]:
    script = readme_curl().replace("localhost:8000", url.removeprefix("http://"))
    out = subprocess.run(["bash", "-euo", "pipefail", "-c", script], capture_output=True,
                         text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    results: dict[str, Any] = json.loads(out.stdout)
    return results


def check_rigid_results(results: dict[str, Any]) -> None:
    # target = R source + (1, 2, 3), R the 90° turn about z: x -> y, y -> -x (by hand)
    rotation = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1]], dtype=float)
    assert np.allclose(results["rotation"], rotation, atol=1e-9)
    assert np.allclose(results["translation"], [1, 2, 3], atol=1e-9)
    assert results["rmse"] < 1e-9


def sleep_job(http: httpx.Client, seconds: float, steps: int = 20) -> str:
    response = execute(http, "diagnostics.sleep", {"seconds": seconds, "steps": steps},
                       prefer="respond-async")
    assert response.status_code == 201, response.text
    job_id: str = response.json()["jobID"]
    return job_id


# --------------------------------------------------------------------------------------------
# the image on its own: `podman run`, as the README shows
# --------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def lone_container(image: str) -> Iterator[tuple[str, str]]:
    name = f"morphserve-pytest-run-{free_port()}"
    port = free_port()
    start = time.monotonic()
    podman("run", "-d", "--rm", "--name", name, "-p", f"127.0.0.1:{port}:8000", image)
    try:
        url = f"http://127.0.0.1:{port}"
        deadline = time.monotonic() + 120
        while True:
            try:
                if httpx.get(url + "/healthz", timeout=2).status_code == 200:
                    break
            except httpx.HTTPError:
                pass
            assert time.monotonic() < deadline, podman("logs", name, check=False).stdout
            time.sleep(0.1)
        FIGURES["podman run to /healthz 200 (s)"] = round(time.monotonic() - start, 1)
        yield name, url
    finally:
        podman("rm", "-f", "-v", "-t", "0", name, check=False)  # -v: its anonymous /data


#: the digest of every module of the image's packages, as the image's Python finds them
DIGESTS = """
import hashlib, json, pathlib, service
site = pathlib.Path(service.__file__).parents[1]
print(json.dumps({p.relative_to(site).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
                  for pkg in ("algorithms", "service", "morphserve") for p in (site / pkg).rglob("*.py")}))
"""


def test_the_image_holds_the_working_trees_code(image: str) -> None:
    """The image is the working tree's: every module of its three packages is the tree's, and
    none is missing or extra. (A build that takes an old layer for the new wheel's install
    would run every test below on old code.)"""
    inside = json.loads(podman("run", "--rm", "--entrypoint", "python", image, "-c",
                               DIGESTS).stdout)
    tree = {p.relative_to(ROOT).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for pkg in ("algorithms", "service", "morphserve") for p in (ROOT / pkg).rglob("*.py")}
    assert sorted(set(inside) ^ set(tree)) == [], "modules only in the image or only in the tree"
    stale = sorted(path for path in tree if inside[path] != tree[path])
    assert not stale, f"the image holds other versions of {len(stale)} modules: {stale[:10]}"


#: morphserve's licence text as the image's installed distribution carries it
OWN_LICENCE = """
import importlib.metadata as m
d = m.distribution("morphserve")
print("".join(f.read_text() for f in d.files or ()
               if f.name == "LICENSE" and ".dist-info/" in f.as_posix()), end="")
"""


def test_the_image_carries_morphserves_own_licence(image: str) -> None:
    """The MIT licence of morphserve itself ships in the image (in the wheel's metadata),
    beside the licence texts of what it bundles."""
    inside = podman("run", "--rm", "--entrypoint", "python", image, "-c", OWN_LICENCE).stdout
    assert inside == (ROOT / "LICENSE").read_text()


#: the names of every distribution installed in the image
DISTRIBUTIONS = """
import importlib.metadata as m
print("\\n".join(d.metadata["Name"] for d in m.distributions()))
"""
#: what the base image (python:3.11-slim) installs beside Python itself: MIT, both
BASE_IMAGE = {"pip", "setuptools", "wheel"}


def test_the_default_image_holds_the_default_install_and_nothing_else(image: str) -> None:
    """The default image target is the default install: exactly the distributions that
    ``tests/test_licences.py`` walks from morphserve's requirements and judges permissive
    (no cvxopt, no cholespy: CHOLMOD comes only with ``EXTRAS=cholmod``), plus morphserve
    and the base image's installers."""
    from packaging.utils import canonicalize_name

    from tests.test_licences import default_install

    inside = {canonicalize_name(n) for n in podman("run", "--rm", "--entrypoint", "python", image,
                                           "-c", DISTRIBUTIONS).stdout.split()}
    walked = {canonicalize_name(d.name) for d in default_install()}
    assert not {"cvxopt", "cholespy"} & inside
    assert inside - BASE_IMAGE == walked | {"morphserve"}, (
        f"only in the image: {sorted(inside - BASE_IMAGE - walked - {'morphserve'})}; "
        f"only in the walk: {sorted(walked - inside)}")


def test_image_runs_as_a_non_root_user(image: str, lone_container: tuple[str, str]) -> None:
    assert podman("image", "inspect", "--format", "{{.Config.User}}", image).stdout.strip() == (
        f"{UID}:{UID}")
    name, _ = lone_container
    # every process of the container, the server included
    uids = podman("top", name, "huser").stdout.split()[1:]
    assert uids and set(uids) == {UID}, uids
    owner = podman("exec", name, "stat", "-c", "%u", "/data").stdout.strip()
    assert owner == UID, "the data dir (and so a fresh volume) must belong to the service's user"


def test_image_healthcheck_passes(image: str, lone_container: tuple[str, str]) -> None:
    check = json.loads(podman("image", "inspect", "--format", "{{json .Config.Healthcheck}}",
                              image).stdout)
    assert check and "/healthz" in " ".join(check["Test"]), f"no HEALTHCHECK in the image: {check}"
    name, _ = lone_container
    # no systemd here to run it on its timer: run it as the timer would
    assert podman("healthcheck", "run", name, check=False).returncode == 0
    status = podman("inspect", "--format", "{{.State.Health.Status}}", name).stdout.strip()
    assert status == "healthy"


def test_readme_curl_answers_from_the_lone_container(lone_container: tuple[str, str]) -> None:
    check_rigid_results(run_readme_curl(lone_container[1]))


# --------------------------------------------------------------------------------------------
# the compose stack
# --------------------------------------------------------------------------------------------
def test_stack_runs_as_non_root_with_healthy_api(stack: Stack) -> None:
    for service in ("api", "scheduler", "worker"):
        names = stack.containers(service)
        assert len(names) == (2 if service == "worker" else 1), (service, names)
        for name in names:
            uids = set(podman("top", name, "huser").stdout.split()[1:])
            assert uids == {UID}, f"{name} runs processes as {uids}"
    (api,) = stack.containers("api")
    assert podman("healthcheck", "run", api, check=False).returncode == 0
    (scheduler,) = stack.containers("scheduler")
    assert podman("healthcheck", "run", scheduler, check=False).returncode == 0


def test_readme_curl_through_the_stack(stack: Stack) -> None:
    check_rigid_results(run_readme_curl(stack.url))


def test_browser_pages_are_served_from_the_image(stack: Stack) -> None:
    """The pages and their assets are package data: a wheel without them would 404 here."""
    with httpx.Client(base_url=stack.url, timeout=30) as http:
        for page in ("/ui", "/docs"):
            response = http.get(page)
            assert response.status_code == 200, (page, response.status_code)
            assert response.headers["content-type"].startswith("text/html")
            assets = re.findall(r'(?:src|href)="(/[^"]+\.(?:js|css))"', response.text)
            assert assets, f"{page} references no script or style sheet"
            for asset in assets:
                assert http.get(asset).status_code == 200, f"{page}: {asset} not served"


def family_examples() -> list[str]:
    """One process of each family, the first the catalog lists."""
    first: dict[str, str] = {}
    for process in catalog.processes():
        first.setdefault(process.id.split(".")[0], process.id)
    return sorted(first.values())


@pytest.fixture(scope="module")
def embedded(tmp_path_factory: pytest.TempPathFactory) -> Iterator[LiveServer]:
    """The embedded default (`make serve`): the peer of the stack."""
    server = LiveServer(tmp_path_factory.mktemp("embedded") / "data").start()
    try:
        yield server
    finally:
        server.stop()


def test_an_sdk_job_of_each_family_through_the_stack(stack: Stack, embedded: LiveServer) -> None:
    """Each family's example, sent by the SDK, runs on the stack and gives what the embedded
    server gives (same code, but the image's own builds of numpy, scipy and the rest)."""
    from morphserve import Client

    ids = family_examples()
    assert len(ids) == len({p.id.split(".")[0] for p in catalog.processes()}) >= 10
    with embedded.client() as http, Client(stack.url) as remote, Client(embedded.url) as local:
        for process_id in ids:
            inputs = example(http, process_id)
            # results() raises JobFailed unless the job was successful
            there = remote.execute(process_id, wait=60, **inputs).results()
            here = local.execute(process_id, wait=60, **inputs).results()
            assert set(there) == set(here), process_id
            for key, value in here.items():
                if isinstance(value, np.ndarray) and value.dtype.kind in "fc":
                    assert np.allclose(there[key], value, atol=1e-6), (process_id, key)


def test_readme_job_latency_stack_vs_embedded(stack: Stack, embedded: LiveServer) -> None:
    """A figure for the closing note (the median of 15 README jobs each way), not a check of
    time: what is asserted is that every one of them gave the right answer."""
    for name, url in (("stack", stack.url), ("embedded", embedded.url)):
        times = []
        for _ in range(15):
            start = time.monotonic()
            check_rigid_results(run_readme_curl(url))
            times.append(time.monotonic() - start)
        FIGURES[f"README curl, median ms ({name})"] = round(statistics.median(times) * 1000, 1)
    # a job that must go through the Dask scheduler (not the fast path)
    for name, url in (("stack", stack.url), ("embedded", embedded.url)):
        times = []
        with httpx.Client(base_url=url, timeout=60) as http:
            for _ in range(15):
                start = time.monotonic()
                response = execute(http, "diagnostics.sleep", {"seconds": 0, "steps": 1})
                assert response.status_code == 200, response.text
                times.append(time.monotonic() - start)
        FIGURES[f"diagnostics.sleep(0) on a worker, median ms ({name})"] = round(
            statistics.median(times) * 1000, 1)


#: what a proxy in front of the published port sends
FORWARDED = {"X-Forwarded-Proto": "https", "X-Forwarded-Host": "proxy.example",
             "X-Forwarded-Prefix": "/morphserve"}


def landing_links(url: str) -> list[str]:
    """The hrefs of the landing page, fetched from ``url`` as a proxy would."""
    response = httpx.get(url + "/", params={"f": "json"}, headers=FORWARDED, timeout=30)
    assert response.status_code == 200, response.text
    links = [link["href"] for link in response.json()["links"]]
    assert links
    return links


def test_a_proxy_is_believed_only_when_the_stack_is_told_so(
        stack: Stack, lone_container: tuple[str, str]) -> None:
    """A client of the published port reaches the API from the network's gateway, never from
    127.0.0.1: with the default MORPHSERVE_FORWARDED_ALLOW_IPS (the lone container) its
    X-Forwarded-* headers are ignored; compose.yaml passes the setting from the environment
    of `up` (the stack was started with PROXY_NETWORKS), and then they are believed."""
    name, url = lone_container
    assert all(href.startswith(url + "/") for href in landing_links(url))
    believed = landing_links(stack.url)
    assert all(href.startswith("https://proxy.example/morphserve/") for href in believed), believed
    (api,) = stack.containers("api")
    assert podman("exec", api, "printenv", "MORPHSERVE_FORWARDED_ALLOW_IPS").stdout.strip() == (
        PROXY_NETWORKS)
    # MORPHSERVE_PUBLIC_URL, not set for `up`, is left unset, not set empty (which the
    # service would refuse at start-up)
    assert podman("exec", api, "printenv", "MORPHSERVE_PUBLIC_URL", check=False).returncode == 1


def test_killing_a_worker_mid_job_loses_no_job(stack: Stack) -> None:
    """Two jobs on two one-thread workers: one runs on each. SIGKILL one worker container;
    the scheduler gives its job to the other worker and both end successful."""
    wait_ready(stack.url, workers=2)
    with httpx.Client(base_url=stack.url, timeout=30) as http:
        jobs = [sleep_job(http, 6) for _ in range(2)]
        deadline = time.monotonic() + 60
        while not all(http.get(f"/jobs/{j}").json()["progress"] > 0 for j in jobs):
            assert time.monotonic() < deadline, [http.get(f"/jobs/{j}").json() for j in jobs]
            time.sleep(0.1)
        victim = stack.containers("worker")[0]
        podman("kill", "--signal", "KILL", victim)
        for job_id in jobs:
            info = wait_for_status(http, job_id, timeout=120)
            assert info["status"] == "successful", info
    stack.compose("up", "-d", "--no-build")  # the killed worker back, for the next tests


def test_restarting_the_api_finishes_the_accepted_jobs(stack: Stack) -> None:
    (api,) = stack.containers("api")
    with httpx.Client(base_url=stack.url, timeout=30) as http:
        jobs = [sleep_job(http, 2, steps=4) for _ in range(4)]
        statuses = {http.get(f"/jobs/{j}").json()["status"] for j in jobs}
        assert statuses & {"accepted", "running"}, "the jobs ended before the restart"
        podman("restart", "-t", "2", api)
        wait_ready(stack.url, workers=1)
        for job_id in jobs:
            info = wait_for_status(http, job_id, timeout=120)
            assert info["status"] == "successful", info


def test_down_keeps_the_data_volume_and_up_lists_the_old_jobs(stack: Stack) -> None:
    with httpx.Client(base_url=stack.url, timeout=30) as http:
        job_id = sleep_job(http, 0.1, steps=1)
        assert wait_for_status(http, job_id)["status"] == "successful"
        before = {j["jobID"] for j in http.get("/jobs", params={"limit": 1000}).json()["jobs"]}
    assert job_id in before
    stack.down()
    assert podman("volume", "exists", stack.volume, check=False).returncode == 0, (
        "`down` removed the data volume")
    assert not stack.containers("api")
    stack.up()
    with httpx.Client(base_url=stack.url, timeout=30) as http:
        after = {j["jobID"] for j in http.get("/jobs", params={"limit": 1000}).json()["jobs"]}
        assert before <= after, before - after
        assert http.get(f"/jobs/{job_id}/results").status_code == 200


def test_the_readme_shows_the_commands_these_tests_run() -> None:
    from tests.deploy.conftest import BUILD, IMAGE

    section = re.split(r"\n#{2,3} ", README.read_text().split("\n### Docker\n", 1)[1])[0]
    lines = [line.split("  #")[0].strip()
             for block in re.findall(r"```bash\n(.*?)```", section, flags=re.S)
             for line in block.splitlines()]
    # the build, with the tests' tag in place of the README's
    assert "podman " + " ".join(BUILD).replace(IMAGE, "morphserve:local") in lines
    # what Stack.up and Stack.down run (the tests add their project name and override file)
    assert "MORPHSERVE_PORT=18000 podman-compose -f docker/compose.yaml up -d --no-build" in lines
    assert "podman-compose -f docker/compose.yaml down" in lines
    # what lone_container runs, and the same for Docker
    assert "podman run --rm -p 127.0.0.1:18000:8000 morphserve:local" in lines
    assert "docker build -f docker/Dockerfile -t morphserve:local ." in lines
    assert "docker compose -f docker/compose.yaml up -d" in lines
