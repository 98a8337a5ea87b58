"""The typed calls (``client.registration.icp(...)``): generated from the catalog, fresh, with
the algorithms' signatures, and working against a live server, sync and async."""

from __future__ import annotations

import asyncio
import inspect
import json
import typing
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest

from algorithms.core.params import declarations
from morphserve import AsyncClient, AsyncJob, Client, InvalidInput, Job
from service.catalog import registry
from service.sdkgen import render

TYPED = Path(__file__).resolve().parents[2] / "morphserve" / "_typed.py"


def test_the_committed_module_is_fresh() -> None:
    """``morphserve/_typed.py`` is what the generator writes from today's catalog: run
    ``make sdk`` after changing a signature or an entry."""
    assert TYPED.read_text(encoding="utf-8") == render(), "stale: run `make sdk`"


def _method(client: Any, process_id: str) -> Any:
    family, name = process_id.split(".", 1)
    return getattr(getattr(client, family), name)


@pytest.mark.parametrize("process_id", list(registry))
def test_each_method_has_the_algorithms_signature(process_id: str) -> None:
    """Same inputs, in the same order, kind (positional or keyword-only) and defaults as the
    algorithm's signature, without what the service does not offer; then the execution
    options; for the sync and the async client alike."""
    process = registry[process_id]
    offered = process.params.model_fields
    expected = [p for name, p in inspect.signature(process.function).parameters.items()
                if name in offered]
    for client in (Client("http://127.0.0.1:9"), AsyncClient("http://127.0.0.1:9")):
        method = _method(client, process_id)
        params = list(inspect.signature(method).parameters.values())
        inputs, options = params[:-4], params[-4:]
        # the display inputs (labels to colour a result by) follow, keyword-only, None
        display = inputs[len(inputs) - len(process.display):]
        inputs = inputs[:len(inputs) - len(process.display)]
        assert [p.name for p in inputs] == [p.name for p in expected]
        assert [p.kind for p in inputs] == [p.kind for p in expected]
        assert [p.default for p in inputs] == [p.default for p in expected]
        assert [(p.name, p.kind, p.default) for p in display] == [
            (name, inspect.Parameter.KEYWORD_ONLY, None) for name in process.display]
        assert [p.name for p in options] == ["wait", "outputs", "idempotency_key", "time_limit"]
        assert all(p.kind is inspect.Parameter.KEYWORD_ONLY for p in options)
        assert inspect.iscoroutinefunction(method) == isinstance(client, AsyncClient)
        assert "progress" not in inspect.signature(method).parameters


def test_choices_and_types_are_the_signatures() -> None:
    """The ``Literal`` choices are the function's (read from its annotations, the peer here),
    a bounded integer is an ``int``, an optional bound admits None."""
    from algorithms.registration import icp

    hints = typing.get_type_hints(icp)
    sig = inspect.signature(Client("http://127.0.0.1:9").registration.icp)
    model = sig.parameters["model"]
    assert model.default == "rigid" and model.kind is inspect.Parameter.KEYWORD_ONLY
    assert model.annotation.replace("'", '"') == 'Literal["rigid", "similarity", "affine"]'
    assert typing.get_args(hints["model"]) == ("rigid", "similarity", "affine")
    assert sig.parameters["max_iterations"].annotation == "int"
    assert sig.parameters["max_iterations"].default == 30
    assert sig.parameters["max_correspondence_distance"].annotation == "float | None"
    assert sig.parameters["source"].kind is inspect.Parameter.POSITIONAL_OR_KEYWORD
    assert sig.return_annotation == "Job"
    asig = inspect.signature(AsyncClient("http://127.0.0.1:9").registration.icp)
    assert asig.return_annotation == "AsyncJob"


def test_the_docstring_is_the_functions() -> None:
    """The summary and each offered parameter's numpydoc entry come from the function; the
    parameters the service hides (``workers``) and ``progress`` are not documented."""
    from algorithms.assignment import nearest

    doc = Client("http://127.0.0.1:9").assignment.nearest.__doc__ or ""
    source = inspect.getdoc(nearest) or ""
    assert doc.splitlines()[0] == source.splitlines()[0]
    assert "direction : " in doc and "k : " in doc
    assert "workers" in declarations(nearest) and "workers :" not in doc
    assert "Returns\n        -------\n        Job" in doc
    assert "``n_pairs``" in doc  # the outputs are named


class _Recorder:
    """A fake service that records what it is sent and accepts every job."""

    def __init__(self) -> None:
        self.requests: list[httpx.Request] = []

    def __call__(self, request: httpx.Request) -> httpx.Response:
        self.requests.append(request)
        if request.method == "GET":  # the SDK may read a description to place its inputs
            from service.representation import process_description

            process = registry[request.url.path.rsplit("/", 1)[1]]
            return httpx.Response(200, json=process_description(process))
        return httpx.Response(201, headers={"Location": "/jobs/j1"}, json={
            "jobID": "j1", "processID": "registration.icp", "status": "accepted",
            "type": "process"})


#: The inputs of registration.icp, as the refusal of a mistyped keyword lists them.
_ICP_INPUTS = ", ".join(f"`{name}`" for name in registry["registration.icp"].params.model_fields)


def test_a_mistyped_keyword_is_a_type_error_before_any_request() -> None:
    """Python's TypeError, naming the closest keyword there is (as the service's 422 names
    the closest input) and listing the inputs; nothing is sent."""
    fake = _Recorder()
    with Client("http://morph.test", transport=httpx.MockTransport(fake)) as client:
        with pytest.raises(TypeError) as mistyped:
            client.registration.icp([[0, 0]], [[0, 0]], max_iter=5)  # type: ignore[call-arg]
        assert str(mistyped.value) == (
            "Registration.icp() got an unexpected keyword argument 'max_iter'; did you mean "
            f"`max_iterations`? The inputs are {_ICP_INPUTS}.")
        with pytest.raises(TypeError, match=r"'wiat'; did you mean `wait`\?"):  # an option
            client.registration.icp([[0, 0]], [[0, 0]], wiat=5)  # type: ignore[call-arg]
        with pytest.raises(TypeError, match=r"argument 'zzz'\. The inputs are `source`, "):
            client.registration.icp([[0, 0]], [[0, 0]], zzz=5)  # type: ignore[call-arg]
        with pytest.raises(TypeError, match="target"):
            client.registration.icp([[0, 0]])  # type: ignore[call-arg]
        with pytest.raises(TypeError):  # options are keyword-only
            client.registration.icp([[0, 0]], [[0, 0]], "rigid")  # type: ignore[misc]
    assert fake.requests == []


def test_a_mistyped_keyword_is_a_type_error_before_any_request_async() -> None:
    fake = _Recorder()

    async def main() -> None:
        async with AsyncClient("http://morph.test", transport=httpx.MockTransport(fake)) as c:
            with pytest.raises(TypeError) as mistyped:
                await c.registration.icp([[0, 0]], [[0, 0]], max_iter=5)  # type: ignore[call-arg]
            assert str(mistyped.value) == (
                "AsyncRegistration.icp() got an unexpected keyword argument 'max_iter'; did "
                f"you mean `max_iterations`? The inputs are {_ICP_INPUTS}.")
            with pytest.raises(TypeError, match="target"):
                await c.registration.icp([[0, 0]])  # type: ignore[call-arg]

    asyncio.run(main())
    assert fake.requests == []


def test_only_the_inputs_given_or_changed_are_sent() -> None:
    """Inputs left at their defaults are not sent (the service has the same defaults);
    one given equal to its default is not either, one changed is."""
    fake = _Recorder()
    with Client("http://morph.test", transport=httpx.MockTransport(fake)) as client:
        job = client.registration.icp([[0.0, 0.0]], [[1.0, 0.0]], max_iterations=5,
                                      model="rigid", idempotency_key="k-1")
    assert isinstance(job, Job) and job.id == "j1"
    (request,) = fake.requests
    assert request.url.path == "/processes/registration.icp/execution"
    assert request.headers["Idempotency-Key"] == "k-1"
    body = json.loads(request.content)
    assert body["inputs"] == {"source": [[0.0, 0.0]], "target": [[1.0, 0.0]],
                              "max_iterations": 5}


def _example_call(doc: str) -> str:
    """The call of a docstring's Examples, as Python source."""
    lines = doc.split("Examples\n        --------\n", 1)[1].splitlines()
    call = []
    for line in lines:
        call.append(line.strip()[4:].split("  # doctest")[0])
        if line.strip() == "...     wait=30)":
            break
    return "\n".join(call).removeprefix("job = ")


def test_the_docstring_examples_are_the_catalogs() -> None:
    """Each example in a method's docstring is a call that sends the catalog's example
    inputs (those the service's own tests run), inputs equal to their defaults aside."""
    shown = 0
    for process_id, process in registry.items():
        fake = _Recorder()
        with Client("http://morph.test", transport=httpx.MockTransport(fake)) as client:
            doc = _method(client, process_id).__doc__ or ""
            if "Examples\n" not in doc:
                continue
            shown += 1
            eval(_example_call(doc), {"client": client})  # noqa: S307  our own docstring
        (request,) = [r for r in fake.requests if r.method == "POST"]
        sent = json.loads(request.content)["inputs"]
        fields = process.params.model_fields
        expected = {k: v for k, v in process.examples.items() if v != fields[k].default}
        assert sent == expected, process_id
    assert shown >= 30  # most processes have short examples


def _turned_square() -> tuple[np.ndarray, np.ndarray]:
    """Four points and their copy turned 90° about z and shifted by (1, 2, 3): the README's
    hand case."""
    source = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    target = np.array([[1, 2, 3], [1, 3, 3], [0, 2, 3], [1, 2, 4]], dtype=float)
    return source, target


@pytest.mark.e2e
def test_a_typed_call_runs_on_the_service(server) -> None:  # noqa: ANN001
    source, target = _turned_square()
    with Client(server.url, timeout=30) as client:
        results = client.alignment.rigid(source, target, wait=30).results()
        with pytest.raises(InvalidInput) as refused:
            client.assignment.nearest(source, target, k=0, wait=30)
    turn = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1]], dtype=float)
    np.testing.assert_allclose(results["rotation"], turn, atol=1e-12)
    np.testing.assert_allclose(results["translation"], [1, 2, 3], atol=1e-12)
    assert refused.value.errors[0]["input"] == "k"


@pytest.mark.e2e
def test_a_typed_call_runs_on_the_service_async(server) -> None:  # noqa: ANN001
    source, target = _turned_square()

    async def main() -> tuple[AsyncJob, Any]:
        async with AsyncClient(server.url, timeout=30) as client:
            job = await client.assignment.nearest(target, source, k=1)
            await job.wait(timeout=60)
            return job, await job.results()

    job, results = asyncio.run(main())
    assert isinstance(job, AsyncJob) and job.process_id == "assignment.nearest"
    # forward, k=1: each of the first set's points and its distance to the nearest of the
    # second, by brute force
    distances = np.linalg.norm(target[:, None] - source[None], axis=2)
    pairs = np.asarray(results["pairs"])
    assert sorted(pairs[:, 0]) == [0, 1, 2, 3]
    np.testing.assert_array_equal(pairs[:, 1], distances.argmin(axis=1)[pairs[:, 0]])
    np.testing.assert_allclose(results["distances"], distances.min(axis=1)[pairs[:, 0]],
                               atol=1e-12)


# -- errors that help: unknown input names and process ids -------------------------------


def test_unknown_input_message_names_the_closest_and_lists_all() -> None:
    from service.errors import unknown_input_message

    valid = ["source", "target", "model", "max_iterations"]
    assert unknown_input_message("max_iter", valid) == (
        "Unknown input `max_iter`; did you mean `max_iterations`? The inputs are `source`, "
        "`target`, `model`, `max_iterations`.")
    assert unknown_input_message("zzz", valid) == (
        "Unknown input `zzz`. The inputs are `source`, `target`, `model`, `max_iterations`.")
    assert unknown_input_message("workers", valid, hidden=("workers",)).startswith(
        "`workers` is a setting of the method that this service does not offer")


@pytest.mark.parametrize(("wanted", "meant"), [
    ("registration.icpp", ["registration.icp"]),      # a typo in the method
    ("icp", ["registration.icp"]),                    # the family left out
    ("alignment.icp", ["registration.icp"]),          # the wrong family
    ("registraton.icp", ["registration.icp"]),        # a typo in the family
    ("Registration.ICP", ["registration.icp"]),       # the case
    ("rigid", ["alignment.rigid", "interpolation.rigid"]),  # two equally close
    ("zzz", []),
])
def test_closest_process_ids(wanted: str, meant: list[str]) -> None:
    from service.routes.common import closest_processes

    assert closest_processes(wanted, list(registry)) == meant


@pytest.mark.e2e
def test_unknown_inputs_and_processes_are_told_with_the_closest(http, server) -> None:  # noqa: ANN001
    """The 422 names each unknown input with its likely meaning and the inputs there are;
    the 404 of an unknown process names the likely ids; the SDK's generic ``execute``
    raises them as they are."""
    from morphserve import NoSuchProcess

    source, target = _turned_square()
    r = http.post("/processes/registration.icp/execution", json={"inputs": {
        "source": source.tolist(), "target": target.tolist(), "max_iter": 5, "modle": "rigid"}})
    assert r.status_code == 422 and r.headers["content-type"] == "application/problem+json"
    errors = {e["input"]: e["message"] for e in r.json()["errors"]}
    valid = list(registry["registration.icp"].params.model_fields)
    listed = ", ".join(f"`{name}`" for name in valid)
    assert errors == {
        "max_iter": f"Unknown input `max_iter`; did you mean `max_iterations`? The inputs are "
                    f"{listed}.",
        "modle": f"Unknown input `modle`; did you mean `model`? The inputs are {listed}.",
    }
    assert "max_iter: Unknown input `max_iter`; did you mean `max_iterations`?" in \
        r.json()["detail"]

    r = http.get("/processes/registration.icpp")
    assert r.status_code == 404
    assert "Did you mean `registration.icp`?" in r.json()["detail"]

    with Client(server.url, timeout=30) as client:
        with pytest.raises(InvalidInput, match="did you mean `max_iterations`") as refused:
            client.execute("registration.icp", source=source, target=target, max_iter=5)
        assert refused.value.errors[0]["input"] == "max_iter"
        with pytest.raises(NoSuchProcess, match="Did you mean `alignment.rigid`"):
            client.execute("alignment.rigd", source=source, target=target)
