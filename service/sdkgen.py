"""Write the SDK's typed calls: ``python -m service.sdkgen [PATH]`` (``make sdk``).

The SDK (:mod:`morphserve`) imports neither the service nor the algorithms, yet its users want
``client.registration.icp(source, target, *, model="rigid", max_iterations=30, ...)`` with the
real signature, the choices and the docstring in their editor. So this module reads the
catalog and writes ``morphserve/_typed.py``: per family a namespace class with one method per
process, for the synchronous and the asynchronous client. It is generated and committed, like
``openapi/openapi.json``; ``tests/sdk/test_typed.py`` fails when it is stale.

Each method's parameters are the process's inputs, in the order, kind (positional or
keyword-only) and with the defaults of the algorithm's signature (hidden parameters and
``progress`` left out). Type hints follow the declarations: ``Literal`` choices, ``bool``,
``int``, ``float``, ``str``, ``None`` where accepted, and for an array input the alias of its
kind (``PointsLike``, ``MeshLike`` ...), loose aliases of ``Any`` because the SDK accepts
arrays, lists, geometry objects and file paths there. Then come the options of every
execution (``wait``, ``outputs``, ``idempotency_key``, ``time_limit``). The docstring is the
function's numpydoc: its summary, the Parameters of the inputs offered and its References,
with the SDK's own Returns (the outputs named) and Raises; its Notes, Examples (which call the
library, not the service) and Raises (the library's exceptions) are left out, which keeps
the module to half a megabyte for the two clients.

A method sends only the inputs given a value other than their default (a comparison of type
and value, so an array is never compared as a truth value): the request is then the one
:meth:`Client.execute` makes with the same arguments.
"""

from __future__ import annotations

import inspect
import json
import keyword
import re
import sys
import textwrap
import types
import typing
from collections.abc import Iterable
from typing import Annotated, Any, Literal

from pydantic_core import PydanticUndefined

from algorithms.core.params import Kind
from service.catalog import FAMILIES, Process, registry
from service.catalog.registry import DISPLAY_INPUTS

__all__ = ["render", "main"]

#: The alias each kind of array input is hinted with in the generated module.
KIND_ALIASES = {
    Kind.POINTS: "PointsLike",
    Kind.WEIGHTS: "ArrayLike",
    Kind.LABELS: "ArrayLike",
    Kind.MESH: "MeshLike",
    Kind.HANDLES: "HandlesLike",
    Kind.GRAPH: "GraphLike",
    Kind.SHAPE: "ShapeLike",
    Kind.ARRAY: "ArrayLike",
}

_ALIAS_DOCS = {
    "ArrayLike": "A numeric array: a numpy array, nested lists, or a ``.npy`` file path.",
    "PointsLike": "An ``(n, d)`` point set: an array or nested lists, a point cloud or mesh "
                  "object (trimesh, Open3D, PyVista: its points), or the path of a geometry "
                  "file (.ply, .obj, .stl, .off, .glb, .npy).",
    "MeshLike": "A triangle mesh: ``{\"vertices\": ..., \"faces\": ...}``, a mesh object "
                "(trimesh, Open3D, PyVista) or the path of a mesh file (.ply, .obj, .stl, "
                ".off, .glb).",
    "HandlesLike": "Vertex indices and their positions: ``{\"indices\": ..., "
                   "\"positions\": ...}``.",
    "GraphLike": "A graph: ``{\"n_nodes\": ..., \"edges\": ..., \"weights\": ...}``.",
    "ShapeLike": "A point set or a mesh (see ``PointsLike`` and ``MeshLike``).",
}

#: The options of every execution, after the inputs: (signature text, numpydoc entry).
_OPTIONS = (
    ("wait: float | None = None",
     "wait : float, optional\n"
     "    Answer with the results if the job ends within this many seconds; None (default):\n"
     "    answer at once, the job runs in the background."),
    ("outputs: Iterable[str] | Mapping[str, Any] | None = None",
     "outputs : names, optional\n"
     "    Only these outputs are wanted."),
    ("idempotency_key: str | None = None",
     "idempotency_key : str, optional\n"
     "    Retrying with the same key returns the first job instead of starting another."),
    ("time_limit: float | None = None",
     "time_limit : float, optional\n"
     "    Stop the job after this many seconds of running (never more than the service's\n"
     "    own limit)."),
)
_OPTION_NAMES = ("wait", "outputs", "idempotency_key", "time_limit")

#: numpydoc sections kept from the function's docstring, besides its Parameters.
_KEPT_SECTIONS = ("References",)

_HEADER = '''\
"""Typed calls: one method per process, ``client.<family>.<method>(...)``.

Generated from the service's catalog by ``python -m service.sdkgen morphserve/_typed.py``
(``make sdk``); do not edit it by hand. Each method has the signature of its algorithm:
the same inputs, defaults and choices, so that a mistyped keyword is a ``TypeError`` before
any request is sent (naming the closest keyword there is: "did you mean `max_iterations`?"),
and the editor shows the documentation. A method starts a job as
:meth:`Client.execute` does (inputs left at their defaults are not sent) and returns the
:class:`Job` (with :class:`AsyncClient`: an awaitable of the :class:`AsyncJob`).
"""

# ruff: noqa: E501  (the docstrings are the algorithms', indented one level deeper)

from __future__ import annotations

import difflib
import functools
import inspect
from collections.abc import Callable, Iterable, Mapping
from typing import TYPE_CHECKING, Any, Literal, TypeAlias, cast

if TYPE_CHECKING:
    from ._client import AsyncClient, AsyncJob, Client, Job

__all__ = ["AsyncTypedCalls", "TypedCalls"]

'''

_HELPERS = '''

def _changed(inputs: dict[str, Any], defaults: dict[str, Any]) -> dict[str, Any]:
    """The inputs to send: all but those left at their defaults (the service has the same)."""
    return {
        name: value
        for name, value in inputs.items()
        if name not in defaults
        or not (value is None and defaults[name] is None
                or type(value) is type(defaults[name]) and value == defaults[name])
    }


#: The options of every execution, after a method's inputs.
_OPTIONS = ("wait", "outputs", "idempotency_key", "time_limit")


def _unknown_keyword_message(method: str, name: str, valid: list[str]) -> str:
    """Python's refusal of a keyword a method does not take, with the closest it does take
    and the inputs there are (as the service's 422 tells an unknown input)."""
    guess = difflib.get_close_matches(name, valid, n=1, cutoff=0.6)
    hint = f"; did you mean `{guess[0]}`?" if guess else "."
    inputs = ", ".join(f"`{v}`" for v in valid if v not in _OPTIONS)
    return (f"{method}() got an unexpected keyword argument {name!r}{hint} "
            f"The inputs are {inputs}.")


def _refusing_unknown_keywords(method: Callable[..., Any]) -> Callable[..., Any]:
    """``method`` (a sync or async one), refusing a keyword it does not take with
    :func:`_unknown_keyword_message`: a ``TypeError`` before any request. The signature and
    docstring stay the method's (``functools.wraps``)."""
    keywords = [name for name, p in inspect.signature(method).parameters.items()
                if name != "self" and p.kind in (inspect.Parameter.POSITIONAL_OR_KEYWORD,
                                                 inspect.Parameter.KEYWORD_ONLY)]
    known = frozenset(keywords)

    def check(given: Mapping[str, Any]) -> None:
        for name in given:
            if name not in known:
                raise TypeError(_unknown_keyword_message(method.__qualname__, name, keywords))

    if inspect.iscoroutinefunction(method):
        @functools.wraps(method)
        async def refusing_async(self: Any, *args: Any, **kwargs: Any) -> Any:
            check(kwargs)
            return await method(self, *args, **kwargs)

        return refusing_async

    @functools.wraps(method)
    def refusing(self: Any, *args: Any, **kwargs: Any) -> Any:
        check(kwargs)
        return method(self, *args, **kwargs)

    return refusing


class _Family:
    """The processes of one family, called through a :class:`Client`."""

    def __init__(self, client: Client) -> None:
        self._client = client

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        for name, value in list(vars(cls).items()):
            if not name.startswith("_") and inspect.isfunction(value):
                setattr(cls, name, _refusing_unknown_keywords(value))

    def __repr__(self) -> str:
        return f"<{type(self).__name__} of {self._client!r}>"


class _AsyncFamily:
    """The processes of one family, called through an :class:`AsyncClient`."""

    def __init__(self, client: AsyncClient) -> None:
        self._client = client

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        for name, value in list(vars(cls).items()):
            if not name.startswith("_") and inspect.isfunction(value):
                setattr(cls, name, _refusing_unknown_keywords(value))

    def __repr__(self) -> str:
        return f"<{type(self).__name__} of {self._client!r}>"
'''


# -- type hints ----------------------------------------------------------------------------


def hint_text(hint: Any) -> str:
    """The generated module's type hint for a signature's annotation."""
    origin = typing.get_origin(hint)
    if origin is Annotated:
        base, *meta = typing.get_args(hint)
        kind = next((m for m in meta if isinstance(m, Kind)), None)
        if kind is Kind.SEED:
            return "int"  # the service takes an integer seed >= 0
        if kind is not None:
            return KIND_ALIASES[kind]
        return hint_text(base)
    if origin is Literal:
        return "Literal[" + ", ".join(_literal(a) for a in typing.get_args(hint)) + "]"
    if origin is typing.Union or origin is types.UnionType:
        parts: list[str] = []
        for arg in typing.get_args(hint):
            text = hint_text(arg)
            if text not in parts:
                parts.append(text)
        if "Any" in parts:
            return "Any"
        if "None" in parts:  # None last, as the signatures write it
            parts = [p for p in parts if p != "None"] + ["None"]
        return " | ".join(parts)
    if hint is type(None) or hint is None:
        return "None"
    if hint in (bool, int, float, str):
        return str(hint.__name__)
    return "Any"


def _literal(value: Any) -> str:
    """A Python literal of a scalar, strings in double quotes (as the signatures write them)."""
    return json.dumps(value) if isinstance(value, str) else repr(value)


def _default_text(name: str, value: Any, process_id: str) -> str:
    if value is None or isinstance(value, (bool, int, float, str)):
        text = _literal(value)
        if isinstance(value, float) and not re.fullmatch(r"-?[\d.e+-]+", text):
            raise TypeError(f"{process_id}: the default of {name} ({text}) is not a literal")
        return text
    raise TypeError(f"{process_id}: the default of {name} ({value!r}) is not a literal")


# -- docstrings ----------------------------------------------------------------------------


def _sections(doc: str) -> tuple[list[str], dict[str, list[str]]]:
    """A numpydoc docstring as (the lines before any section, {title: the section's lines
    below its underline})."""
    lines = doc.splitlines()
    starts = [i for i in range(len(lines) - 1)
              if lines[i].strip() and not lines[i].startswith(" ")
              and lines[i + 1].strip() and set(lines[i + 1].strip()) == {"-"}]
    head = lines[:starts[0]] if starts else lines
    out: dict[str, list[str]] = {}
    for k, start in enumerate(starts):
        end = starts[k + 1] if k + 1 < len(starts) else len(lines)
        out[lines[start].strip()] = lines[start + 2:end]
    return head, out


def _parameter_entries(lines: list[str], keep: Iterable[str]) -> list[str]:
    """The entries of a Parameters section whose names are in ``keep`` (an entry
    documenting ``a, b`` is kept when either is)."""
    wanted, out, keeping = set(keep), [], False
    for ln in lines:
        if ln.strip() and not ln.startswith(" "):
            names = {n.strip() for n in ln.split(":", 1)[0].split(",")}
            keeping = bool(names & wanted)
        if keeping:
            out.append(ln)
    while out and not out[-1].strip():
        out.pop()
    return out


def _strip(lines: list[str]) -> list[str]:
    while lines and not lines[0].strip():
        lines = lines[1:]
    while lines and not lines[-1].strip():
        lines = lines[:-1]
    return lines


def docstring(process: Process, names: list[str], asynchronous: bool) -> str:
    """The method's docstring, from the function's (see the module's docstring)."""
    head, sections = _sections(inspect.getdoc(process.function) or "")
    parts = [_strip(head) or [process.title + "."]]
    params = _parameter_entries(sections.get("Parameters", []), names)
    for name in process.display:
        params += [f"{name} : array_like, optional",
                   *textwrap.wrap(DISPLAY_INPUTS[name][1], 88, initial_indent="    ",
                                  subsequent_indent="    ")]
    params += [ln for _, entry in _OPTIONS for ln in entry.splitlines()]
    parts.append(["Parameters", "----------", *params])
    job = "AsyncJob" if asynchronous else "Job"
    outputs = ", ".join(f"``{name}``" for name in process.outputs)
    parts.append(["Returns", "-------", job,
                  f"    The job of ``{process.id}``; its results hold {outputs}."])
    parts.append(["Raises", "------", "InvalidInput",
                  "    The service refused an input; ``errors`` names it.",
                  "QueueFull", "    Too many jobs are queued; retry after ``retry_after`` "
                  "seconds."])
    for title in _KEPT_SECTIONS:
        if _strip(sections.get(title, [])):
            parts.append([title, "-" * len(title), *_strip(sections[title])])
    example = _example(process, asynchronous)
    if example:
        parts.append(["Examples", "--------", *example])
    text = "\n\n".join("\n".join(p) for p in parts)
    if '"""' in text:
        raise ValueError(f"{process.id}: the docstring holds a triple quote")
    body = "\n".join(("        " + ln).rstrip() for ln in text.splitlines())
    return f'        r"""{body.lstrip()}\n        """'


#: The longest example inputs (as JSON text) shown in a docstring: the catalog's examples
#: of meshes and larger point sets would drown the text.
EXAMPLE_CHARS = 240


def _example(process: Process, asynchronous: bool) -> list[str]:
    """The docstring's Examples: the call on the catalog's example inputs (the ones the
    service's own tests run), when they are short."""
    if not process.examples or len(json.dumps(process.examples)) > EXAMPLE_CHARS:
        return []
    args, positional = [], True  # in the signature's order; after a keyword, keywords only
    for name, parameter in inspect.signature(process.function).parameters.items():
        positional = positional and name in process.examples and (
            parameter.kind is inspect.Parameter.POSITIONAL_OR_KEYWORD
            and parameter.default is inspect.Parameter.empty)
        if name in process.examples:
            value = process.examples[name]
            args.append(repr(value) if positional else f"{name}={value!r}")
    family, method = process.id.split(".", 1)
    wait = "await " if asynchronous else ""
    first = next(iter(process.outputs))
    return [f">>> job = {wait}client.{family}.{method}(  # doctest: +SKIP",
            *(f"...     {a}," for a in args),
            "...     wait=30)",
            f">>> ({wait}job.results())[{_literal(first)}]  # doctest: +SKIP"
            if asynchronous else f'>>> job.results()[{_literal(first)}]  # doctest: +SKIP']


# -- methods and classes -------------------------------------------------------------------


def _method(process: Process, asynchronous: bool) -> tuple[str, str]:
    """(the method's source, its defaults constant's source)."""
    function = process.function
    signature = inspect.signature(function)
    hints = typing.get_type_hints(inspect.unwrap(function), include_extras=True)
    fields = process.params.model_fields
    name = process.id.split(".", 1)[1]
    if not name.isidentifier() or keyword.iskeyword(name):
        raise ValueError(f"{process.id}: {name!r} is not a method name")
    clash = sorted(set(fields) & {*_OPTION_NAMES, "self"})
    if clash:
        raise ValueError(f"{process.id}: inputs named like an execution option: {clash}")
    lines, star, names, defaults = ["self"], False, [], {}
    for pname, parameter in signature.parameters.items():
        if pname not in fields:
            continue  # progress, and the parameters the service hides
        if parameter.kind is inspect.Parameter.KEYWORD_ONLY and not star:
            lines.append("*")
            star = True
        elif parameter.kind not in (inspect.Parameter.KEYWORD_ONLY,
                                    inspect.Parameter.POSITIONAL_OR_KEYWORD):
            raise ValueError(f"{process.id}: parameter {pname} is {parameter.kind}")
        text = f"{pname}: {hint_text(hints.get(pname, Any))}"
        default = fields[pname].default
        if default is not PydanticUndefined:
            defaults[pname] = _default_text(pname, default, process.id)
            text += f" = {defaults[pname]}"
        lines.append(text)
        names.append(pname)
    for pname in process.display:  # the service's own inputs, for the result's display
        if not star:
            lines.append("*")
            star = True
        lines.append(f"{pname}: ArrayLike | None = None")
        names.append(pname)
        defaults[pname] = "None"  # not sent unless given
    missing = sorted(set(fields) - set(names))
    if missing:
        raise ValueError(f"{process.id}: inputs not in the function's signature: {missing}")
    if not star:
        lines.append("*")
    lines += [option for option, _ in _OPTIONS]
    job = "AsyncJob" if asynchronous else "Job"
    constant = "_DEFAULTS_" + re.sub(r"\W", "_", process.id).upper()
    source = [f"    {'async ' if asynchronous else ''}def {name}(",
              *(f"        {ln}," for ln in lines),
              f"    ) -> {job}:",
              docstring(process, names, asynchronous),
              "        inputs = {" + ", ".join(f"{_literal(n)}: {n}" for n in names) + "}",
              f"        return {'await ' if asynchronous else ''}self._client.execute(",
              f"            {_literal(process.id)},",
              "            wait=wait,",
              "            outputs=outputs,",
              "            idempotency_key=idempotency_key,",
              "            time_limit=time_limit,",
              f"            **_changed(inputs, {constant}),",
              "        )"]
    const = (f"{constant}: dict[str, Any] = {{"
             + ", ".join(f"{_literal(k)}: {v}" for k, v in defaults.items()) + "}")
    return "\n".join(source), const


def _class_name(family: str, asynchronous: bool) -> str:
    return ("Async" if asynchronous else "") + "".join(p.title() for p in family.split("_"))


def _family_class(family: str, processes: list[Process], asynchronous: bool) -> str:
    base = "_AsyncFamily" if asynchronous else "_Family"
    client = "AsyncClient" if asynchronous else "Client"
    listing = ", ".join(f"``{p.id.split('.', 1)[1]}``" for p in processes)
    out = [f"class {_class_name(family, asynchronous)}({base}):",
           f'    """The {family} processes, through a :class:`{client}`: {listing}."""']
    for process in processes:
        out += ["", _method(process, asynchronous)[0]]
    return "\n".join(out)


def _mixin(families: list[str], asynchronous: bool) -> str:
    name = "AsyncTypedCalls" if asynchronous else "TypedCalls"
    client = "AsyncClient" if asynchronous else "Client"
    out = [f"class {name}:",
           f'    """The typed calls of :class:`{client}`: one attribute per family of '
           'processes."""',
           "",
           "    __slots__ = ()"]
    for family in families:
        cls = _class_name(family, asynchronous)
        out += ["", "    @property", f"    def {family}(self) -> {cls}:",
                f'        """The {family} processes."""',
                f'        return {cls}(cast("{client}", self))']
    return "\n".join(out)


def render(processes: Iterable[Process] | None = None) -> str:
    """The source of ``morphserve/_typed.py`` for ``processes`` (default: the catalog)."""
    chosen = list(registry.values() if processes is None else processes)
    by_family: dict[str, list[Process]] = {}
    order = {f: i for i, f in enumerate(FAMILIES)}
    for process in sorted(chosen, key=lambda p: (order.get(p.family, len(order)), p.id)):
        by_family.setdefault(process.family, []).append(process)
    families = list(by_family)
    for family in families:
        if not family.isidentifier() or keyword.iskeyword(family):
            raise ValueError(f"{family!r} is not an attribute name")
    parts = [_HEADER.rstrip("\n")]
    for alias in ("ArrayLike", "PointsLike", "MeshLike", "HandlesLike", "GraphLike",
                  "ShapeLike"):
        parts.append(f'{alias}: TypeAlias = Any\n"""{_ALIAS_DOCS[alias]}"""')
    parts.append(_HELPERS.strip("\n"))
    parts.append("\n".join(_method(p, False)[1] for members in by_family.values()
                            for p in members))
    for asynchronous in (False, True):
        for family, members in by_family.items():
            parts.append(_family_class(family, members, asynchronous))
        parts.append(_mixin(families, asynchronous))
    return "\n\n\n".join(parts) + "\n"


def main(argv: list[str]) -> int:
    from service import generated

    return generated.main(argv, prog="python -m service.sdkgen",
                          description="Write the SDK's typed calls.", render=render)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
