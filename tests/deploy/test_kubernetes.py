"""deploy/kubernetes: valid manifests for the current Kubernetes API, consistent with the image,
the CLI and one another (no cluster needed: kubernetes-validate carries the API's schemas)."""

from __future__ import annotations

import shlex
from pathlib import Path
from typing import Any

import kubernetes_validate
import pytest
import yaml

from tests.service.test_docker import dockerfile_instructions, final_stage, parse_size

ROOT = Path(__file__).resolve().parents[2]
MANIFESTS = sorted((ROOT / "deploy" / "kubernetes").glob("*.yaml"))
KUBERNETES = kubernetes_validate.latest_version()


def documents() -> list[tuple[str, dict[str, Any]]]:
    docs = []
    for path in MANIFESTS:
        for doc in yaml.safe_load_all(path.read_text()):
            if doc is not None:
                docs.append((path.name, doc))
    return docs


def resource(kind: str, name: str) -> dict[str, Any]:
    found = [d for _, d in documents() if d["kind"] == kind and d["metadata"]["name"] == name]
    assert len(found) == 1, f"expected one {kind} {name}, found {len(found)}"
    return found[0]


def container(deployment: str) -> dict[str, Any]:
    (only,) = resource("Deployment", deployment)["spec"]["template"]["spec"]["containers"]
    result: dict[str, Any] = only
    return result


def pod_spec(deployment: str) -> dict[str, Any]:
    spec: dict[str, Any] = resource("Deployment", deployment)["spec"]["template"]["spec"]
    return spec


def test_the_layout_is_there() -> None:
    kinds = sorted((d["kind"], d["metadata"]["name"]) for _, d in documents())
    assert kinds == [
        ("Deployment", "morphserve-api"), ("Deployment", "morphserve-scheduler"),
        ("Deployment", "morphserve-worker"), ("NetworkPolicy", "morphserve-scheduler"),
        ("PersistentVolumeClaim", "morphserve-data"), ("Secret", "morphserve-dask-tls"),
        ("Secret", "morphserve-keys"),
        ("Service", "morphserve-api"), ("Service", "morphserve-scheduler"),
    ]


@pytest.mark.parametrize(("name", "doc"), documents(),
                         ids=[f"{n}:{d['kind']}" for n, d in documents()])
def test_manifest_is_valid_for_current_kubernetes(name: str, doc: dict[str, Any]) -> None:
    """Strict: an unknown or misspelt field is an error too, not silently dropped."""
    try:
        kubernetes_validate.validate(doc, KUBERNETES, strict=True)
    except kubernetes_validate.ValidationError as exc:
        pytest.fail(f"{name}: {doc['kind']} invalid for Kubernetes {KUBERNETES}: {exc.message}")


def test_a_broken_manifest_is_refused() -> None:
    """The validator is not vacuous: a Deployment with a string for replicas fails."""
    broken = yaml.safe_load(yaml.safe_dump(resource("Deployment", "morphserve-worker")))
    broken["spec"]["replicas"] = "two"
    with pytest.raises(kubernetes_validate.ValidationError):
        kubernetes_validate.validate(broken, KUBERNETES, strict=True)


def test_selectors_match_their_pods_and_services() -> None:
    for _, doc in documents():
        if doc["kind"] == "Deployment":
            labels = doc["spec"]["template"]["metadata"]["labels"]
            assert doc["spec"]["selector"]["matchLabels"].items() <= labels.items()
    for service in ("morphserve-api", "morphserve-scheduler"):
        selector = resource("Service", service)["spec"]["selector"]
        labels = resource("Deployment", service)["spec"]["template"]["metadata"]["labels"]
        assert selector.items() <= labels.items(), service


def test_commands_are_accepted_by_the_cli_and_reach_the_scheduler_service() -> None:
    import click
    from distributed.cli.dask_scheduler import main as dask_scheduler

    from service.cli import build_parser

    port = resource("Service", "morphserve-scheduler")["spec"]["ports"][0]["port"]
    address = f"tls://morphserve-scheduler:{port}"
    for deployment in ("morphserve-api", "morphserve-worker"):
        argv = container(deployment)["command"]
        assert argv[0] == "morphserve"
        try:
            args = build_parser().parse_args(argv[1:])
        except SystemExit as exc:
            pytest.fail(f"{deployment}: `{shlex.join(argv)}` rejected (exit {exc.code})")
        assert args.scheduler == address, deployment
    argv = container("morphserve-scheduler")["command"]
    assert argv[:2] == ["dask", "scheduler"]
    try:
        dask_scheduler.make_context("dask scheduler", argv[2:])
    except click.ClickException as exc:
        pytest.fail(f"`{shlex.join(argv)}` rejected by the dask CLI: {exc.format_message()}")
    assert argv[argv.index("--port") + 1] == str(port)
    assert argv[argv.index("--protocol") + 1] == "tls"


def test_every_dask_link_is_mutual_tls_from_the_secret() -> None:
    """The scheduler, the workers and the API each need the CA and a certificate with its key
    for every role they play, all from the mounted TLS Secret, with encryption required."""
    for deployment in ("morphserve-api", "morphserve-scheduler", "morphserve-worker"):
        box = container(deployment)
        env = {e["name"]: e.get("value") for e in box["env"]}
        assert env["DASK_DISTRIBUTED__COMM__REQUIRE_ENCRYPTION"] == "true", deployment
        tls = {k: v for k, v in env.items() if k.startswith("DASK_DISTRIBUTED__COMM__TLS__")}
        for role in ("SCHEDULER", "WORKER", "CLIENT"):
            assert {f"DASK_DISTRIBUTED__COMM__TLS__{role}__CERT",
                    f"DASK_DISTRIBUTED__COMM__TLS__{role}__KEY"} <= set(tls), (deployment, role)
        assert "DASK_DISTRIBUTED__COMM__TLS__CA_FILE" in tls
        volumes = {v["name"]: v for v in pod_spec(deployment)["volumes"]}
        (directory,) = {str(Path(v).parent) for v in tls.values()}
        (mount,) = [m for m in box["volumeMounts"] if m["mountPath"] == directory]
        assert mount["readOnly"] is True
        secret = resource("Secret", volumes[mount["name"]]["secret"]["secretName"])
        assert {Path(v).name for v in tls.values()} <= set(secret["stringData"]), deployment
        # group-readable by the pod's fsGroup, which is the image's user
        assert pod_spec(deployment)["securityContext"]["fsGroup"] == 10001


def test_pods_run_as_the_images_user() -> None:
    users = [args for kw, args in final_stage(dockerfile_instructions()) if kw == "USER"]
    uid, _, gid = users[-1].partition(":")
    for deployment in ("morphserve-api", "morphserve-scheduler", "morphserve-worker"):
        context = pod_spec(deployment)["securityContext"]
        assert context["runAsNonRoot"] is True
        assert (str(context["runAsUser"]), str(context["runAsGroup"])) == (uid, gid)
        assert container(deployment)["securityContext"]["allowPrivilegeEscalation"] is False


def test_api_and_workers_share_the_data_volume_read_write_many() -> None:
    claim = resource("PersistentVolumeClaim", "morphserve-data")
    assert claim["spec"]["accessModes"] == ["ReadWriteMany"]
    for deployment in ("morphserve-api", "morphserve-worker"):
        volumes = {v["name"]: v for v in pod_spec(deployment)["volumes"]}
        mounts = {m["mountPath"]: m["name"] for m in container(deployment)["volumeMounts"]}
        assert volumes[mounts["/data"]]["persistentVolumeClaim"]["claimName"] == "morphserve-data"
        env = {e["name"]: e.get("value") for e in container(deployment)["env"]}
        assert env["MORPHSERVE_DATA_DIR"] == "/data", deployment


def test_one_api_replica_replaced_not_rolled() -> None:
    """One SQLite writer: never two API pods at once, even during an update."""
    spec = resource("Deployment", "morphserve-api")["spec"]
    assert spec["replicas"] == 1 and spec["strategy"]["type"] == "Recreate"


def test_api_probes_are_healthz_and_readyz_on_the_served_port() -> None:
    api = container("morphserve-api")
    argv = api["command"]
    served = int(argv[argv.index("--port") + 1])
    ports = {p["name"]: p["containerPort"] for p in api["ports"]}
    paths = {}
    for probe in ("startupProbe", "livenessProbe", "readinessProbe"):
        get = api[probe]["httpGet"]
        assert ports[get["port"]] == served, probe
        paths[probe] = get["path"]
    assert paths == {"startupProbe": "/healthz", "livenessProbe": "/healthz",
                     "readinessProbe": "/readyz"}


def test_api_keys_come_from_the_mounted_secret() -> None:
    api = container("morphserve-api")
    env = {e["name"]: e.get("value") for e in api["env"]}
    keys_file = Path(env["MORPHSERVE_API_KEYS_FILE"])
    mounts = {m["mountPath"]: m for m in api["volumeMounts"]}
    mount = mounts[str(keys_file.parent)]
    assert mount["readOnly"] is True
    volume = next(v for v in pod_spec("morphserve-api")["volumes"] if v["name"] == mount["name"])
    secret = resource("Secret", volume["secret"]["secretName"])
    assert keys_file.name in secret["stringData"]
    # readable by the pod's user: the Secret's files are 0644 unless defaultMode says otherwise
    # (group-readable is enough, the pod's fsGroup being the image's user's group)
    mode = volume["secret"].get("defaultMode", 0o644)
    assert mode & 0o004 or (mode & 0o040 and pod_spec("morphserve-api")["securityContext"]
                                            ["fsGroup"] == 10001), oct(mode)
    # mounted as a directory, not a subPath: the kubelet then updates the file when the Secret
    # changes, and the service re-reads it (keys added or revoked without a restart)
    assert "subPath" not in mount


def test_worker_memory_limit_sits_below_the_containers() -> None:
    worker = container("morphserve-worker")
    argv = worker["command"]
    dask_limit = parse_size(argv[argv.index("--memory-limit") + 1])
    nworkers = int(argv[argv.index("--nworkers") + 1])
    container_limit = parse_size(worker["resources"]["limits"]["memory"].replace("Gi", "g"))
    assert nworkers * dask_limit < container_limit


def test_only_api_and_workers_may_reach_the_scheduler() -> None:
    policy = resource("NetworkPolicy", "morphserve-scheduler")["spec"]
    scheduler = resource("Deployment", "morphserve-scheduler")["spec"]["template"]["metadata"]
    assert policy["podSelector"]["matchLabels"].items() <= scheduler["labels"].items()
    (rule,) = policy["ingress"]
    (peer,) = rule["from"]
    (expression,) = peer["podSelector"]["matchExpressions"]
    allowed = set(expression["values"])
    assert allowed == {"api", "worker"}
    for deployment in ("morphserve-api", "morphserve-worker"):
        labels = resource("Deployment", deployment)["spec"]["template"]["metadata"]["labels"]
        assert labels[expression["key"]] in allowed
    assert scheduler["labels"][expression["key"]] not in allowed


def test_no_manifest_exposes_a_port_outside_the_cluster() -> None:
    for _, doc in documents():
        if doc["kind"] == "Service":
            assert doc["spec"].get("type", "ClusterIP") == "ClusterIP", doc["metadata"]["name"]


def test_api_carries_the_proxy_setting_with_a_value_the_service_accepts() -> None:
    """Behind an ingress the API is reached from the ingress controller's pods: the manifest
    carries MORPHSERVE_FORWARDED_ALLOW_IPS, the knob to set to their network (as compose.yaml
    passes it through), with a value the service's settings accept."""
    from service.settings import Settings

    env = {e["name"]: e.get("value") for e in container("morphserve-api")["env"]}
    value = env["MORPHSERVE_FORWARDED_ALLOW_IPS"]
    assert Settings(forwarded_allow_ips=value).forwarded_allow_ips == value
    compose = yaml.safe_load((ROOT / "docker" / "compose.yaml").read_text())
    assert {"MORPHSERVE_FORWARDED_ALLOW_IPS", "MORPHSERVE_PUBLIC_URL"} <= set(
        compose["services"]["api"]["environment"])
