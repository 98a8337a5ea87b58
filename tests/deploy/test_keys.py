"""docker/compose.keys.yaml: the stack's API takes its keys from a keys file mounted as a
compose secret. Without a key (or with one not in the file) a request gets a 401 problem; with
a key from the file jobs run on the workers and belong to that key; the probes stay open; a
key revoked in the file is refused once the API is restarted. One stack start for all of it."""

from __future__ import annotations

import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import httpx
import numpy as np
import pytest

from tests.deploy.conftest import ROOT, Stack, podman, wait_ready
from tests.live import execute, wait_for_status

pytestmark = [pytest.mark.container, pytest.mark.e2e, pytest.mark.timeout(600)]

KEYS_OVERRIDE = ROOT / "docker" / "compose.keys.yaml"
README = ROOT / "README.md"
MORPHSERVE = str(Path(sys.executable).parent / "morphserve")


def keys_cli(keys_file: Path, *args: str) -> str:
    """``morphserve keys ... --file keys_file``, as the README shows; its standard output."""
    proc = subprocess.run([MORPHSERVE, "keys", *args, "--file", str(keys_file)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.strip()


def bearer(key: str) -> dict[str, str]:
    return {"Authorization": f"Bearer {key}"}


@pytest.fixture(scope="module")
def keys(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, str]]:
    keys_file = tmp_path_factory.mktemp("keys") / "keys.txt"
    made = {name: keys_cli(keys_file, "add", name) for name in ("alice", "bob")}
    keys_file.chmod(0o644)  # the README's step: readable by the containers' user 10001
    return keys_file, made


@pytest.fixture(scope="module")
def keys_stack(image: str, keys: tuple[Path, dict[str, str]],
               tmp_path_factory: pytest.TempPathFactory) -> Iterator[Stack]:
    stack = Stack(tmp_path_factory.mktemp("keys-stack"), image, name="-keys",
                  extra_files=(KEYS_OVERRIDE,), env={"MORPHSERVE_KEYS_FILE": str(keys[0])})
    with stack.running():  # wait_ready polls /readyz without a key: the probe is open
        yield stack


def assert_unauthorized(response: httpx.Response) -> None:
    assert response.status_code == 401, response.text
    assert response.headers["content-type"].startswith("application/problem+json")
    assert response.headers["www-authenticate"].lower().startswith("bearer")
    problem = response.json()
    assert problem["status"] == 401
    assert [e["input"] for e in problem["errors"]] == ["Authorization"]


RIGID = {"source": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
         "target": [[1, 2, 3], [1, 3, 3], [0, 2, 3], [1, 2, 4]]}


def test_keys_from_the_mounted_file(keys_stack: Stack, keys: tuple[Path, dict[str, str]]) -> None:
    keys_file, made = keys
    (api,) = keys_stack.containers("api")
    # the API reads the secret's path, not a copy baked anywhere
    env = podman("exec", api, "printenv", "MORPHSERVE_API_KEYS_FILE").stdout.strip()
    assert env == "/run/secrets/api-keys"
    mounted = podman("exec", api, "cat", env).stdout
    assert mounted == keys_file.read_text()

    with httpx.Client(base_url=keys_stack.url, timeout=60) as http:
        # open: the probes (orchestrators carry no key)
        assert http.get("/healthz").status_code == 200
        assert http.get("/readyz").json()["workers"] == 2
        # closed: no key, a malformed header, a key that is not in the file
        assert_unauthorized(http.get("/processes"))
        assert_unauthorized(execute(http, "alignment.rigid", RIGID))
        assert_unauthorized(http.get("/jobs", headers={"Authorization": made["alice"]}))
        assert_unauthorized(http.get("/jobs", headers=bearer(made["alice"] + "x")))

        # alice's key: the README's rigid job, answered (90° about z, then (1, 2, 3): by hand)
        http.headers.update(bearer(made["alice"]))
        response = execute(http, "alignment.rigid", RIGID)
        assert response.status_code == 200, response.text
        results = response.json()
        assert np.allclose(results["rotation"], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-9)
        assert np.allclose(results["translation"], [1, 2, 3], atol=1e-9)
        # and a job that runs on a worker, followed to its end
        response = execute(http, "diagnostics.sleep", {"seconds": 0.2, "steps": 2},
                           prefer="respond-async")
        assert response.status_code == 201, response.text
        job = response.json()["jobID"]
        assert wait_for_status(http, job, timeout=120)["status"] == "successful"
        assert http.get(f"/jobs/{job}/results").status_code == 200
        assert job in {j["jobID"] for j in http.get("/jobs").json()["jobs"]}

        # bob's key works too, but alice's job is not his
        bob = bearer(made["bob"])
        assert http.get("/processes", headers=bob).status_code == 200
        assert http.get(f"/jobs/{job}", headers=bob).status_code == 404
        assert job not in {j["jobID"] for j in http.get("/jobs", headers=bob).json()["jobs"]}

    # bob's key revoked on the host, as the README says: restart the API (the revoke keeps
    # the file's mode, so no second chmod)
    keys_cli(keys_file, "revoke", "bob")
    keys_stack.compose("restart", "api")
    wait_ready(keys_stack.url, workers=1)
    with httpx.Client(base_url=keys_stack.url, timeout=60) as http:
        assert_unauthorized(http.get("/processes", headers=bob))
        assert http.get(f"/jobs/{job}", headers=bearer(made["alice"])).json()["status"] == \
            "successful"


def test_the_readme_shows_the_keys_commands_this_test_runs() -> None:
    section = re.split(r"\n#{2,3} ", README.read_text().split("\n### Docker\n", 1)[1])[0]
    lines = [line.split("  #")[0].strip()
             for block in re.findall(r"```bash\n(.*?)```", section, flags=re.S)
             for line in block.splitlines()]
    assert "morphserve keys add alice --file docker/keys.txt" in lines
    assert "chmod 0644 docker/keys.txt" in lines
    assert ("podman-compose -f docker/compose.yaml -f docker/compose.keys.yaml up -d --no-build"
            in lines)
    assert "podman-compose -f docker/compose.yaml -f docker/compose.keys.yaml restart api" in lines
    # docker/keys.txt is the override's default, so the README's commands need no variable
    assert "${MORPHSERVE_KEYS_FILE:-./keys.txt}" in KEYS_OVERRIDE.read_text()
