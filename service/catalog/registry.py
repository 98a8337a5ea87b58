"""The registry: process id -> :class:`Process`.

A :class:`Process` ties one algorithm function to the service. Everything the function
declares is read from it, never restated:

- the **inputs**: one per parameter of the signature (``progress`` aside), with the type,
  choices, bounds and default of the signature (:func:`algorithms.core.params.declarations`)
  and the description of the docstring's numpydoc ``Parameters``; array inputs get the JSON
  form of their declared :class:`~algorithms.core.params.Kind` (:data:`KIND_TYPES`);
- the **outputs**: the fields of the result dataclass the function's return annotation
  names, described by its numpydoc ``Attributes``.

- the **id**, ``family.name``: the function's family package and its name;
- the **title** and **description**: the docstring's short summary and the first paragraph of
  its extended summary.

A catalog entry adds only what is the service's own: an example of each required input,
service caps on sizes (``limits``), the cost hints (``long``, ``fast_path``), the checks
across inputs that refuse a request before it is queued (``check``: the algorithm's own
``check_*`` function, called with the inputs its parameters name), JSON types for inputs
whose kind has no general form (``inputs``), the GLB scene of a result (``geometry``), the
inputs only that scene reads (``display``: :data:`DISPLAY_INPUTS`, never passed to the
function) and search keywords. Routes, the OpenAPI document, the SDK's method list and the
docs all read this registry; nothing else lists methods.
"""

from __future__ import annotations

import dataclasses
import inspect
import re
import typing
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Annotated, Any

import numpy as np
from annotated_types import BaseMetadata, Ge, GroupedMetadata, Gt, Le, Lt
from pydantic import (
    BaseModel,
    Field,
    PlainValidator,
    TypeAdapter,
    WithJsonSchema,
    create_model,
    model_validator,
)

from algorithms.core.errors import InvalidInputError
from algorithms.core.params import Declaration, Kind, declarations
from service.catalog.base import Params
from service.catalog.inputs import KIND_TYPES, Labels
from service.docstrings import (
    numpydoc_entries,
    numpydoc_references,
    numpydoc_section,
    numpydoc_summary,
    plain,
)

__all__ = ["Process", "Output", "Registry", "registry", "input_description", "outputs_of",
           "build_inputs"]

Scene = Callable[[Mapping[str, Any], Mapping[str, Any], str], "bytes | None"]
"""Builds the GLB of a result from its outputs, the job's validated inputs and the process
id (the mesh's name); None when that result has no geometry to show (:mod:`service.scenes`)."""


@dataclass(frozen=True)
class Output:
    """One output of a process: a field of its result dataclass."""

    name: str
    title: str
    description: str
    schema: dict[str, Any]


def input_description(decl: Declaration, type_text: str, description: str) -> str:
    """The description of an input: its numpydoc description, for an array whose documented
    type starts with its shape preceded by it (``(n, d) float array.``), as plain text."""
    text = plain(description)
    if decl.kind is not None and type_text.startswith("("):  # "(n, d) float array"
        shape = re.sub(r",\s*(optional|default\b.*)$", "", type_text).strip()
        text = f"{plain(shape)}. {text}" if text else plain(shape)
    return text


# -- outputs -------------------------------------------------------------------------------
def _schema_of(hint: Any) -> dict[str, Any]:
    if hint is bool:
        return {"type": "boolean"}
    if hint is int:
        return {"type": "integer"}
    if hint is float:
        return {"type": "number"}
    if hint is str:
        return {"type": "string"}
    origin = typing.get_origin(hint)
    if origin in (typing.Union, getattr(__import__("types"), "UnionType", None)):
        args = [a for a in typing.get_args(hint) if a is not type(None)]
        inner = _schema_of(args[0]) if len(args) == 1 else {}
        return {**inner, "nullable": True} if inner else {}
    if hint is np.ndarray or origin is np.ndarray:
        return {"type": "array"}
    if origin in (list, tuple) or hint in (list, tuple):
        return {"type": "array"}
    if origin is dict or hint is dict:
        return {"type": "object"}
    if dataclasses.is_dataclass(hint):  # a nested result, such as a Mesh: its fields
        hints = typing.get_type_hints(hint)
        return {"type": "object", "properties": {
            f.name: _schema_of(hints.get(f.name)) for f in dataclasses.fields(hint)}}
    return {}


def outputs_of(result_type: type) -> dict[str, Output]:
    """The outputs of a result dataclass: its fields, documented by its docstring."""
    docs = numpydoc_section(result_type.__doc__, "Attributes")
    hints = typing.get_type_hints(result_type)
    outs = {}
    for f in dataclasses.fields(result_type):
        desc = docs.get(f.name, "")
        title = desc.split(". ")[0].rstrip(".") if desc else f.name.replace("_", " ")
        outs[f.name] = Output(f.name, title, desc, _schema_of(hints.get(f.name)))
    return outs


# -- inputs --------------------------------------------------------------------------------
def _seed_type() -> Any:
    return Annotated[int, Ge(0)]


def _service_hint(hint: Any, kinds: Mapping[Kind, Any]) -> Any:
    """The signature's annotation with every declared kind replaced by its JSON input type
    (``PointsLike`` -> ``Points`` …) and seeds by integers >= 0; scalars stay as declared."""
    origin = typing.get_origin(hint)
    if origin is Annotated:
        base, *meta = typing.get_args(hint)
        kind = next((m for m in meta if isinstance(m, Kind)), None)
        if kind is Kind.SEED:
            return _seed_type()
        if kind is not None:
            if kind not in kinds:
                raise TypeError(f"no JSON input type for kind {kind!r}; give one in the "
                                "entry's inputs")
            optional = type(None) in typing.get_args(base)
            return kinds[kind] | None if optional else kinds[kind]
        return hint
    if origin is typing.Union or origin is __import__("types").UnionType:
        args = [_service_hint(a, kinds) for a in typing.get_args(hint)]
        out = args[0]
        for a in args[1:]:
            out = out | a if a is not type(None) else out | None
        return out
    return hint


def _scalar_union(decl: Declaration, hint: Any) -> Any:
    """A union of scalars (``float | Literal["auto"]``) checked as the library checks it:
    one refusal naming the input ("Expected `learning_rate` to be a number > 0 or one of
    'auto', got 'fast'.") where pydantic would report each member under its own tag
    (``learning_rate.constrained-float``); its JSON Schema is the union's."""
    return Annotated[Any, PlainValidator(decl.check),
                     WithJsonSchema(_enum_not_const(TypeAdapter(hint).json_schema()))]


def _enum_not_const(schema: Any) -> Any:
    """A single choice as ``enum: [x]``, not ``const: x``: OpenAPI 3.0's schema objects, which
    the OGC process description uses, have no ``const``."""
    if isinstance(schema, dict):
        out = {k: _enum_not_const(v) for k, v in schema.items() if k != "const"}
        if "const" in schema:
            out["enum"] = [schema["const"]]
        return out
    if isinstance(schema, list):
        return [_enum_not_const(v) for v in schema]
    return schema


_FIELD_BOUNDS = {Ge: "ge", Gt: "gt", Le: "le", Lt: "lt"}


def _limit_kwargs(name: str, limit: Any) -> dict[str, Any]:
    items = list(limit) if isinstance(limit, (GroupedMetadata, tuple, list)) else [limit]
    out = {}
    for m in items:
        if not isinstance(m, BaseMetadata) or type(m) not in _FIELD_BOUNDS:
            raise TypeError(f"limits[{name!r}]: expected Ge/Gt/Le/Lt, got {m!r}")
        key = _FIELD_BOUNDS[type(m)]
        out[key] = getattr(m, key)
    return out


def _model_name(process_id: str) -> str:
    return "".join(part.title() for part in re.split(r"[._]", process_id)) + "Inputs"


def _points_of(params: BaseModel) -> tuple[str, int] | None:
    """The input that holds one row per point (``points``, else a graph's nodes) and its
    count, or None when neither is given."""
    points = getattr(params, "points", None)
    if points is not None:
        return "points", len(points)
    graph = getattr(params, "graph", None)
    return ("graph", int(graph.n_nodes)) if graph is not None else None


def _check_display_labels(params: BaseModel) -> None:
    labels = getattr(params, "labels", None)
    points = _points_of(params)
    if labels is not None and points is not None and len(labels) != points[1]:
        raise InvalidInputError(f"Expected `labels` to hold one label per point of "
                                f"`{points[0]}` ({points[1]}), got {len(labels)}.",
                                field="labels")


#: The inputs a catalog entry may add for the display of its results (``Process.display``):
#: name -> (JSON type, description, the check against the other inputs). The algorithm never
#: sees them; the GLB scene (:mod:`service.scenes`) and the workbench read them from the
#: job's inputs.
DISPLAY_INPUTS: dict[str, tuple[Any, str, Callable[[BaseModel], None]]] = {
    "labels": (Labels | None, "Optional class labels, one per point (integers or strings), "
               "for the display only: the result's GLB and the workbench colour the points by "
               "class (a clustering's clusters take the colour of the class they match best). "
               "The method does not read them.", _check_display_labels),
}


def build_inputs(process_id: str, function: Callable[..., Any], *,
                 kinds: Mapping[Kind, Any], inputs: Mapping[str, Any],
                 examples: Mapping[str, Any], limits: Mapping[str, Any],
                 hidden: tuple[str, ...],
                 check: Callable[..., Any] | None,
                 display: tuple[str, ...] = ()) -> type[BaseModel]:
    """The pydantic model of a process's inputs, from its function's signature and
    docstring plus the entry's service additions."""
    decls = declarations(function)
    hints = typing.get_type_hints(inspect.unwrap(function), include_extras=True)
    docs = numpydoc_entries(inspect.getdoc(function), "Parameters")
    for what, names in (("inputs", inputs), ("examples", examples), ("limits", limits),
                        ("hidden", hidden)):
        unknown = sorted(set(names) - set(decls))
        if unknown:
            raise TypeError(f"{process_id}: {what} names no parameter: {unknown}")
    fields: dict[str, Any] = {}
    for name, decl in decls.items():
        if name in hidden:
            if decl.required:
                raise TypeError(f"{process_id}: a required parameter cannot be hidden: {name}")
            continue
        if name in inputs:
            hint = inputs[name]
        else:
            hint = _service_hint(hints.get(name, Any), kinds)
            if len(decl.scalars) > 1 and decl.kind is None:
                if name in limits:
                    raise TypeError(f"{process_id}: limits on the union input {name!r}")
                hint = _scalar_union(decl, hint)
        kwargs: dict[str, Any] = {"description": input_description(decl, *docs.get(name, ("", "")))}
        if name in examples:
            kwargs["examples"] = [examples[name]]
        kwargs.update(_limit_kwargs(name, limits[name]) if name in limits else {})
        default = ... if decl.required else decl.default
        fields[name] = (hint, Field(default, **kwargs))
    for name in display:
        if name in decls:
            raise TypeError(f"{process_id}: display input {name!r} is a parameter")
        hint, description, _ = DISPLAY_INPUTS[name]
        fields[name] = (hint, Field(None, description=description))
    # pydantic annotates __validators__ as dict[str, Callable], but what it documents
    # there are decorated validators: descriptor proxies, which are not callable (its
    # successor __namespace__, a dict[str, Any], needs pydantic 2.14; we allow 2.6)
    validators: dict[str, Any] = {}
    if check is not None:
        taken = _check_inputs(process_id, check, fields)
        validators["_check"] = _after(lambda p: check(**{n: getattr(p, n) for n in taken}),
                                      check.__doc__)
    for name in display:
        validators[f"_display_{name}"] = _after(DISPLAY_INPUTS[name][2])
    return create_model(_model_name(process_id), __base__=Params,
                        __validators__=validators, **fields)


def _after(check: Callable[[BaseModel], None], doc: str | None = None) -> Any:
    """``check`` of the validated model as a pydantic after-validator."""
    def _checked(self: BaseModel) -> BaseModel:
        check(self)
        return self
    _checked.__doc__ = doc
    return model_validator(mode="after")(_checked)


def _check_inputs(process_id: str, check: Callable[..., Any], fields: Mapping[str, Any]
                  ) -> list[str]:
    """The inputs a check takes: those its parameters name (a parameter with a default and
    no input of its name keeps its default, such as ``name="mesh"``)."""
    params = inspect.signature(check).parameters
    missing = [n for n, prm in params.items() if n not in fields
               and prm.default is inspect.Parameter.empty
               and prm.kind not in (prm.VAR_POSITIONAL, prm.VAR_KEYWORD)]
    if missing:
        raise TypeError(f"{process_id}: check {check.__name__} takes no input {missing}")
    return [n for n in params if n in fields]


def references_text(function: Callable[..., Any]) -> str | None:
    """A function's numpydoc References as one line: the entries joined by "; "."""
    refs = [r.rstrip(".") for r in numpydoc_references(inspect.getdoc(function))]
    return "; ".join(refs) + "." if refs else None


@dataclass(frozen=True)
class Process:
    """One method of the catalog, offered as one OGC process.

    Only ``function`` is required. ``id``, ``title`` and ``description`` are derived from it
    unless given (see the module's docstring); ``params`` (the pydantic model of the inputs:
    ``function(**params)`` runs it), ``result`` (the dataclass the function returns),
    ``outputs``, ``kinds`` and ``reference`` are derived and cannot be given.
    """

    function: Callable[..., Any]
    id: str = ""
    title: str = ""
    description: str = ""
    examples: Mapping[str, Any] = field(default_factory=dict)
    """One example value per input (every required input has one): the process description
    shows it and the tests run the process on the examples."""
    inputs: Mapping[str, Any] = field(default_factory=dict)
    """JSON input types (pydantic ``Annotated`` types) for parameters whose declared kind
    has no general form here (a matrix, a list of point sets, a mesh-or-points variant)."""
    limits: Mapping[str, Any] = field(default_factory=dict)
    """Service caps beyond the signature's bounds, e.g. ``{"max_iterations": Le(10_000)}``:
    what a shared service refuses to run although the algorithm could."""
    check: Callable[..., Any] | None = None
    """Checks across inputs run when a request is validated, so that a request that must
    fail is refused with 422 before it is queued: a function (the algorithm's ``check_*``)
    called with the inputs its parameters name."""
    hidden: tuple[str, ...] = ()
    """Parameters the service does not offer (local tuning, such as ``workers``)."""
    geometry: Scene | None = None
    """The GLB scene of a result, or None when its results hold no geometry."""
    version: str = "1.0.0"
    long: bool = False
    """Long methods run asynchronously when the client states no preference."""
    fast_path: bool = False
    """Small inputs may run in the service's own threads (closed forms that take milliseconds;
    see :mod:`service.jobs.engine`)."""
    display: tuple[str, ...] = ()
    """Inputs only the result's display reads (:data:`DISPLAY_INPUTS`), such as ``labels``
    to colour an embedding by class; :meth:`run` does not pass them to the function."""
    time_limit: float | None = None
    """Upper bound of the job time limit for this process (the settings' default applies too)."""
    keywords: tuple[str, ...] = ()
    params: type[BaseModel] = field(init=False)
    """The pydantic model of the inputs, built from the function (:func:`build_inputs`)."""
    result: type = field(init=False)
    """The result dataclass: the function's return annotation."""
    reference: str | None = field(init=False)
    """The function's numpydoc References, joined (:func:`references_text`)."""
    outputs: dict[str, Output] = field(init=False)
    kinds: dict[str, Kind] = field(init=False)
    """The declared kind of each array input (points, mesh, shape …)."""
    takes_progress: bool = field(init=False)

    def __post_init__(self) -> None:
        fn = inspect.unwrap(self.function)
        title, description = numpydoc_summary(inspect.getdoc(fn))
        family = fn.__module__.split(".")[-2 if "." in fn.__module__ else -1]
        for name, derived in (("id", f"{family}.{fn.__name__}"),
                              ("title", title.rstrip(".")), ("description", description)):
            if not getattr(self, name):
                object.__setattr__(self, name, derived)
        object.__setattr__(self, "params", build_inputs(
            self.id, self.function, kinds=KIND_TYPES, inputs=self.inputs,
            examples=self.examples, limits=self.limits, hidden=self.hidden, check=self.check,
            display=self.display))
        hints = typing.get_type_hints(inspect.unwrap(self.function))
        object.__setattr__(self, "result", hints["return"])
        object.__setattr__(self, "outputs", outputs_of(self.result))
        object.__setattr__(self, "reference", references_text(self.function))
        decls = declarations(self.function)
        object.__setattr__(self, "kinds", {
            n: d.kind for n, d in decls.items()
            if d.kind is not None and n in self.params.model_fields})
        sig = inspect.signature(self.function)
        object.__setattr__(self, "takes_progress", "progress" in sig.parameters)

    @property
    def family(self) -> str:
        return self.id.split(".", 1)[0]

    def kwargs(self, params: BaseModel) -> dict[str, Any]:
        """The validated inputs as keyword arguments of :attr:`function` (arrays stay arrays)."""
        return {name: getattr(params, name) for name in type(params).model_fields}

    def glb(self, outputs: Mapping[str, Any], inputs: Mapping[str, Any]) -> bytes | None:
        """The GLB of a result of this process, or None when it has no geometry."""
        return None if self.geometry is None else self.geometry(outputs, inputs, self.id)

    def run(self, kwargs: Mapping[str, Any], progress: Callable[..., None] | None = None
            ) -> dict[str, Any]:
        """Call the algorithm and return its result as ``{output name: value}``."""
        extra = {"progress": progress} if self.takes_progress and progress is not None else {}
        args = {k: v for k, v in kwargs.items() if k not in self.display}
        result = self.function(**args, **extra)
        return {name: getattr(result, name) for name in self.outputs}


class Registry(Mapping[str, Process]):
    """Process id -> :class:`Process`, in the order of registration."""

    def __init__(self) -> None:
        self._processes: dict[str, Process] = {}

    def add(self, process: Process) -> Process:
        if process.id in self._processes:
            raise ValueError(f"process {process.id!r} registered twice")
        self._processes[process.id] = process
        return process

    def __getitem__(self, key: str) -> Process:
        return self._processes[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._processes)

    def __len__(self) -> int:
        return len(self._processes)


registry = Registry()
"""The catalog of geometry methods. Diagnostic processes live in their own registry."""
