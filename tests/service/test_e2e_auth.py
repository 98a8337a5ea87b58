"""API keys against a live server: keys made by the CLI, 401s, ownership of jobs, per-key queue
limits, revocation without a restart, the SDK's key from the environment."""

from __future__ import annotations

import os
import stat
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from morphserve import Client, NoSuchJob, Unauthorized
from tests.live import REPO, LiveServer, wait_for_status

pytestmark = pytest.mark.e2e

SOURCE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
TARGET = [[1, 2, 3], [1, 3, 3], [0, 2, 3], [1, 2, 4]]  # 90° about z, then (1, 2, 3)
RIGID = {"inputs": {"source": SOURCE, "target": TARGET}}
PROBLEM = "application/problem+json"


def keys(*args: str, file: Path) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k != "MORPHSERVE_API_KEYS_FILE"}
    return subprocess.run([sys.executable, "-m", "service.cli", "keys", *args, "--file",
                           str(file)], capture_output=True, text=True, cwd=REPO, env=env,
                          timeout=60)


def add_key(name: str, file: Path) -> str:
    done = keys("add", name, file=file)
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


@pytest.fixture(scope="module")
def keyed(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[LiveServer, dict]]:
    root = tmp_path_factory.mktemp("auth")
    file = root / "keys"
    found = {"alice": add_key("alice", file), "bob": add_key("bob", file),
             "carol": add_key("carol", file), "file": file}
    srv = LiveServer(root / "data", env={"MORPHSERVE_API_KEYS_FILE": str(file),
                                         "MORPHSERVE_MAX_QUEUE_PER_KEY": "2"}).start()
    yield srv, found
    srv.stop()


def as_(srv: LiveServer, key: str | None) -> httpx.Client:
    return srv.client(headers={"Authorization": f"Bearer {key}"} if key else {})


def test_the_keys_file_holds_hashes_only_and_is_private(keyed) -> None:
    _, k = keyed
    text = k["file"].read_text()
    assert all(k[name] not in text for name in ("alice", "bob", "carol"))
    assert [line.split()[0] for line in text.splitlines()] == ["alice", "bob", "carol"]
    assert stat.S_IMODE(k["file"].stat().st_mode) == 0o600
    assert keys("list", file=k["file"]).stdout.split() == ["alice", "bob", "carol"]
    assert k["alice"] != k["bob"] and len(k["alice"]) > 40
    again = keys("add", "alice", file=k["file"])
    assert again.returncode == 1 and "already has a key named 'alice'" in again.stderr
    bad = keys("add", "no spaces", file=k["file"])
    assert bad.returncode == 2 and "letters, digits" in bad.stderr


def test_adding_and_revoking_keep_the_mode_of_a_keys_file_that_exists(tmp_path: Path) -> None:
    file = tmp_path / "keys"
    add_key("alice", file)
    assert stat.S_IMODE(file.stat().st_mode) == 0o600  # a new file: owner only
    file.chmod(0o644)  # made readable for a container's user, as the README says
    add_key("bob", file)
    assert stat.S_IMODE(file.stat().st_mode) == 0o644
    assert keys("revoke", "alice", file=file).returncode == 0
    assert stat.S_IMODE(file.stat().st_mode) == 0o644
    assert keys("list", file=file).stdout.split() == ["bob"]


@pytest.mark.parametrize("path", ["/", "/conformance", "/processes", "/jobs",
                                  "/processes/alignment.rigid"])
def test_every_route_but_health_and_static_pages_needs_a_key(keyed, path: str) -> None:
    srv, k = keyed
    for key, says in ((None, "needs an API key"), ("msk_wrong", "not valid")):
        with as_(srv, key) as c:
            r = c.get(path)
        assert r.status_code == 401, (path, r.text)
        assert r.headers["content-type"].startswith(PROBLEM)
        assert r.headers["www-authenticate"] == 'Bearer realm="morphserve"'
        body = r.json()
        assert body["type"].endswith("/unauthorized") and says in body["detail"]
        assert body["errors"][0]["input"] == "Authorization"
    with as_(srv, k["alice"]) as c:
        assert c.get(path).status_code == 200


def test_health_answers_without_a_key(keyed) -> None:
    srv, _ = keyed
    with as_(srv, None) as c:
        assert c.get("/healthz").status_code == 200
        assert c.get("/readyz").status_code == 200


@pytest.mark.parametrize("path", ["/openapi.json", "/ui", "/ui/app.js", "/docs"])
def test_the_static_pages_and_the_api_description_answer_without_a_key(keyed,
                                                                       path: str) -> None:
    """A browser loads the workbench and the API documentation with no way to send a key;
    they hold no one's data, and what they then ask the API for needs the key."""
    srv, _ = keyed
    with as_(srv, None) as c:
        assert c.get(path).status_code == 200, path


def test_posting_without_a_key_creates_no_job(keyed) -> None:
    srv, k = keyed
    with as_(srv, None) as c:
        r = c.post("/processes/alignment.rigid/execution", json=RIGID)
    assert r.status_code == 401
    with as_(srv, k["carol"]) as c:
        assert c.get("/jobs").json()["numberMatched"] == 0  # carol never submitted


def test_a_job_belongs_to_its_key(keyed) -> None:
    srv, k = keyed
    with as_(srv, k["alice"]) as alice, as_(srv, k["bob"]) as bob:
        r = alice.post("/processes/alignment.rigid/execution", json=RIGID,
                       headers={"Prefer": "respond-async"})
        assert r.status_code == 201
        job = r.json()["jobID"]
        assert wait_for_status(alice, job)["status"] == "successful"
        for method, path in (("GET", f"/jobs/{job}"), ("GET", f"/jobs/{job}/results"),
                             ("DELETE", f"/jobs/{job}")):
            r = bob.request(method, path)
            assert r.status_code == 404, (method, path, r.text)
            assert r.json()["type"].endswith("/no-such-job")  # as if it did not exist
        assert job not in [j["jobID"] for j in bob.get("/jobs", params={"limit": 1000})
                           .json()["jobs"]]
        assert job in [j["jobID"] for j in alice.get("/jobs", params={"limit": 1000})
                       .json()["jobs"]]
        assert alice.get(f"/jobs/{job}/results").json()["rmse"] < 1e-12  # still there
        assert alice.delete(f"/jobs/{job}").status_code == 200
        assert alice.get(f"/jobs/{job}").status_code == 404


def test_idempotency_keys_are_per_api_key(keyed) -> None:
    srv, k = keyed
    headers = {"Idempotency-Key": "shared-name", "Prefer": "wait=10"}
    with as_(srv, k["alice"]) as alice, as_(srv, k["bob"]) as bob:
        first = alice.post("/processes/alignment.rigid/execution", json=RIGID, headers=headers)
        other = {"inputs": {"source": TARGET, "target": SOURCE}}  # a different body
        second = bob.post("/processes/alignment.rigid/execution", json=other, headers=headers)
        assert first.status_code == second.status_code == 200, (first.text, second.text)
        a_job = first.headers["Location" if "Location" in first.headers else "Link"]
        b_job = second.headers["Location" if "Location" in second.headers else "Link"]
        assert a_job != b_job  # bob's request is neither a conflict nor alice's job
        again = alice.post("/processes/alignment.rigid/execution", json=RIGID,
                           headers=headers)
        assert again.headers["Link"] == first.headers["Link"]  # alice's replay finds hers


def test_the_queue_limit_is_per_key(keyed) -> None:
    srv, k = keyed
    sleep = {"inputs": {"seconds": 30, "steps": 300}}
    with as_(srv, k["bob"]) as bob, as_(srv, k["carol"]) as carol:
        url = "/processes/diagnostics.sleep/execution"
        jobs = [bob.post(url, json=sleep, headers={"Prefer": "respond-async"}).json()["jobID"]
                for _ in range(2)]
        try:
            r = bob.post(url, json=sleep, headers={"Prefer": "respond-async"})
            assert r.status_code == 429 and r.headers["retry-after"] == "5"
            assert r.json()["type"].endswith("/queue-full") and "per key is 2" in r.text
            r = carol.post("/processes/alignment.rigid/execution", json=RIGID)
            assert r.status_code == 200  # another key is not held up
        finally:
            for job in jobs:
                bob.delete(f"/jobs/{job}")
        r = bob.post("/processes/alignment.rigid/execution", json=RIGID)
        assert r.status_code == 200  # dismissed jobs free the key's places


def test_the_sdk_sends_the_key_from_the_environment(keyed, monkeypatch) -> None:
    srv, k = keyed
    monkeypatch.setenv("MORPHSERVE_API_KEY", k["carol"])
    with Client(srv.url) as client:
        job = client.execute("alignment.rigid", source=SOURCE, target=TARGET)
        job.wait()
        assert job.results()["rmse"] < 1e-12
        job_id = job.id
    with Client(srv.url, api_key=k["bob"]) as client, pytest.raises(NoSuchJob):
        client.job(job_id).status()
    monkeypatch.delenv("MORPHSERVE_API_KEY")
    with Client(srv.url) as client, pytest.raises(Unauthorized):
        client.processes()


def test_a_revoked_key_stops_working_without_a_restart(keyed) -> None:
    srv, k = keyed
    extra = add_key("dave", k["file"])
    with as_(srv, extra) as dave:
        assert dave.get("/jobs").status_code == 200  # the new line was picked up
        assert keys("revoke", "dave", file=k["file"]).returncode == 0
        assert dave.get("/jobs").status_code == 401
    with as_(srv, k["alice"]) as alice:
        assert alice.get("/jobs").status_code == 200


def test_a_malformed_keys_file_stops_the_service_before_it_listens(tmp_path: Path) -> None:
    file = tmp_path / "keys"
    file.write_text("alice sha256:not-hex\n")
    srv = LiveServer(tmp_path / "data", env={"MORPHSERVE_API_KEYS_FILE": str(file)})
    with pytest.raises(RuntimeError, match="server exited") as err:
        srv.start(timeout=60)
    assert "line 1: expected 'NAME sha256:HEX'" in str(err.value)
