"""The registry: process id -> :class:`Process`.

A :class:`Process` ties one algorithm function to its parameter model (pydantic: validation,
defaults and the JSON Schema of every input), and derives its outputs from the function's
result dataclass: each field is an output, described by the class docstring's numpydoc
``Attributes`` section. Routes, the OpenAPI document, the SDK's method list and the docs all
read this registry; nothing else lists methods.
"""

from __future__ import annotations

import dataclasses
import inspect
import re
import typing
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from pydantic import BaseModel

__all__ = ["Process", "Output", "Registry", "registry"]


@dataclass(frozen=True)
class Output:
    """One output of a process: a field of its result dataclass."""

    name: str
    title: str
    description: str
    schema: dict[str, Any]


def _numpydoc_attributes(doc: str | None) -> dict[str, str]:
    """``name : type`` + indented description lines of an ``Attributes`` section."""
    if not doc:
        return {}
    lines = inspect.cleandoc(doc).splitlines()
    out: dict[str, str] = {}
    try:
        start = next(i for i, ln in enumerate(lines)
                     if ln.strip() == "Attributes" and i + 1 < len(lines)
                     and set(lines[i + 1].strip()) == {"-"})
    except StopIteration:
        return {}
    body = lines[start + 2:]
    name = None
    for i, ln in enumerate(body):
        nxt = body[i + 1].strip() if i + 1 < len(body) else ""
        if ln.strip() and nxt and set(nxt) == {"-"}:  # the title of the next section
            break
        m = re.match(r"^(\w+)\s*:", ln)
        if m and not ln.startswith(" "):
            name = m.group(1)
            out[name] = ""
        elif name is not None and ln.strip():
            out[name] = (out[name] + " " + ln.strip()).strip()
    return out


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
    docs = _numpydoc_attributes(result_type.__doc__)
    hints = typing.get_type_hints(result_type)
    outs = {}
    for f in dataclasses.fields(result_type):
        desc = docs.get(f.name, "")
        title = desc.split(". ")[0].rstrip(".") if desc else f.name.replace("_", " ")
        outs[f.name] = Output(f.name, title, desc, _schema_of(hints.get(f.name)))
    return outs


@dataclass(frozen=True)
class Process:
    """One method of the catalog, offered as one OGC process.

    ``params`` is the pydantic model of its inputs; its field names are the algorithm's
    parameter names, so ``function(**params)`` runs it. ``result`` is the dataclass the
    function returns; its fields are the outputs.
    """

    id: str
    title: str
    description: str
    function: Callable[..., Any]
    params: type[BaseModel]
    result: type
    version: str = "1.0.0"
    reference: str | None = None
    long: bool = False
    """Long methods run asynchronously when the client states no preference."""
    fast_path: bool = False
    """Small inputs may run in the service's own threads (closed forms that take milliseconds;
    see :mod:`service.jobs.engine`)."""
    time_limit: float | None = None
    """Upper bound of the job time limit for this process (the settings' default applies too)."""
    keywords: tuple[str, ...] = ()
    outputs: dict[str, Output] = field(init=False)
    takes_progress: bool = field(init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "outputs", outputs_of(self.result))
        sig = inspect.signature(self.function)
        object.__setattr__(self, "takes_progress", "progress" in sig.parameters)

    @property
    def family(self) -> str:
        return self.id.split(".", 1)[0]

    def kwargs(self, params: BaseModel) -> dict[str, Any]:
        """The validated inputs as keyword arguments of :attr:`function` (arrays stay arrays)."""
        return {name: getattr(params, name) for name in type(params).model_fields}

    def run(self, kwargs: Mapping[str, Any], progress: Callable[..., None] | None = None
            ) -> dict[str, Any]:
        """Call the algorithm and return its result as ``{output name: value}``."""
        extra = {"progress": progress} if self.takes_progress and progress is not None else {}
        result = self.function(**kwargs, **extra)
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
