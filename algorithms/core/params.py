"""Parameter declarations: an algorithm's signature is its specification.

Every option is declared once, in the function's signature — its type, its choices as a
``Literal``, its bounds as annotated-types constraints, its default — and its meaning once,
in the docstring's numpydoc Parameters::

    @validate_params
    def icp(
        source: PointsLike,
        target: PointsLike,
        *,
        model: Literal["rigid", "similarity", "affine"] = "rigid",
        max_iterations: Annotated[int, Ge(1)] = 30,
        tolerance: Annotated[float, Ge(0)] = 1e-6,
        max_correspondence_distance: Annotated[float, Gt(0)] | None = None,
        seed: Seed = 0,
    ) -> ICPResult: ...

:func:`validate_params` enforces those declarations on every call, with the messages of
:mod:`algorithms.core.validation` ("Expected `max_iterations` to be an integer >= 1, got
-3."), and hands the function the checked values (Python ``int``/``float``/``bool``/``str``).
What a declaration cannot say — a bound that depends on another input, the shape of an
array — stays in the function's body.

Array inputs are declared by their :class:`Kind` (``PointsLike``, ``MeshLike`` …): the
function checks them itself (``as_points``, ``as_mesh``), because their shapes depend on one
another; the kind tells a caller what the input *is*, so that the service can offer the right
JSON form and read an uploaded file as points or as a mesh, without guessing from names.

:func:`declarations` is the one reader of these annotations: the validator and the service
(which builds its request models from them) both use it.
"""

from __future__ import annotations

import functools
import inspect
import math
import numbers
import types
import typing
from collections.abc import Callable
from dataclasses import dataclass
from enum import StrEnum
from typing import Annotated, Any, Literal, TypeVar

import numpy as np
from annotated_types import BaseMetadata, Ge, GroupedMetadata, Gt, Interval, Le, Lt
from numpy.typing import ArrayLike

from algorithms.core.errors import InvalidInputError
from algorithms.core.types import RngLike
from algorithms.core.validation import as_bool, as_choice, as_float, as_int

__all__ = [
    "Ge",
    "Gt",
    "Le",
    "Lt",
    "Interval",
    "Kind",
    "PointsLike",
    "WeightsLike",
    "LabelsLike",
    "MeshLike",
    "HandlesLike",
    "GraphLike",
    "ShapeLike",
    "ArrayInput",
    "Seed",
    "Scalar",
    "Declaration",
    "declarations",
    "validate_params",
]


class Kind(StrEnum):
    """What an array input is. The function checks its value; the kind tells its callers."""

    POINTS = "points"
    """An ``(n, d)`` array of point coordinates, one row per point."""
    WEIGHTS = "weights"
    """A flat array of non-negative numbers, one per item."""
    LABELS = "labels"
    """A flat array of class labels (integers or strings), one per point."""
    MESH = "mesh"
    """A triangle mesh: vertices and faces (:class:`~algorithms.core.mesh.Mesh`)."""
    HANDLES = "handles"
    """Vertex indices and their positions (:class:`~algorithms.core.mesh.Handles`)."""
    GRAPH = "graph"
    """A graph: node count, edges and optional edge weights."""
    SHAPE = "shape"
    """A point set or a mesh."""
    ARRAY = "array"
    """Another numeric array: a matrix, times, distances."""
    SEED = "seed"
    """A seed of the random generator: an integer >= 0, a ``numpy.random.Generator`` or None."""


PointsLike = Annotated[ArrayLike, Kind.POINTS]
WeightsLike = Annotated[ArrayLike, Kind.WEIGHTS]
LabelsLike = Annotated[ArrayLike, Kind.LABELS]
MeshLike = Annotated[Any, Kind.MESH]
HandlesLike = Annotated[Any, Kind.HANDLES]
GraphLike = Annotated[Any, Kind.GRAPH]
ShapeLike = Annotated[Any, Kind.SHAPE]
ArrayInput = Annotated[ArrayLike, Kind.ARRAY]
Seed = Annotated[RngLike, Kind.SEED]


_TYPE_WORDS = {bool: "true or false", int: "an integer", float: "a number", str: "a string"}


@dataclass(frozen=True)
class Scalar:
    """One scalar alternative of a declaration: its type, its choices (strings) and bounds.

    Bounds hold as declared: ``Gt(0)`` on a float is ``minimum=0`` exclusive; on an integer
    it is ``minimum=1`` inclusive (integers have no open bounds worth keeping).
    """

    type: type
    choices: tuple[str, ...] = ()
    minimum: float | None = None
    maximum: float | None = None
    inclusive: tuple[bool, bool] = (True, True)

    def accepts(self, value: Any) -> bool:
        """Whether ``value`` is of this alternative's type (before its bounds)."""
        if self.type is bool:
            return isinstance(value, (bool, np.bool_))
        if isinstance(value, (bool, np.bool_)):
            return False
        if self.type is str:
            return isinstance(value, str)
        if self.type is int:
            return isinstance(value, numbers.Integral) or (
                isinstance(value, numbers.Real) and float(value).is_integer())
        return isinstance(value, numbers.Real)

    def check(self, value: Any, name: str) -> Any:
        """``value`` checked and converted, or :class:`InvalidInputError` naming ``name``."""
        if self.type is bool:
            return as_bool(value, name=name)
        if self.type is str:
            return as_choice(value, self.choices, name=name)
        if self.type is int:
            lo = None if self.minimum is None else int(self.minimum)
            hi = None if self.maximum is None else int(self.maximum)
            return as_int(value, name=name, minimum=lo, maximum=hi)
        return as_float(value, name=name, minimum=self.minimum, maximum=self.maximum,
                        inclusive=self.inclusive)

    def words(self) -> str:
        """The alternative in words, for messages: "one of 'auto'" or "a number > 0"."""
        if self.type is str:
            return "one of " + ", ".join(repr(c) for c in self.choices)
        parts = []
        if self.minimum is not None:
            parts.append(f"{'>=' if self.inclusive[0] else '>'} {self.minimum:g}")
        if self.maximum is not None:
            parts.append(f"{'<=' if self.inclusive[1] else '<'} {self.maximum:g}")
        return " ".join([_TYPE_WORDS[self.type], " and ".join(parts)]).strip()


_REQUIRED = inspect.Parameter.empty


@dataclass(frozen=True)
class Declaration:
    """What a signature declares about one parameter.

    Attributes
    ----------
    name : str
        The parameter's name.
    scalars : tuple of Scalar
        Its scalar alternatives (empty for an array input): usually one; two for a union
        such as ``float | Literal["auto"]``.
    kind : Kind or None
        What it is when it is an array input (points, mesh …), else None.
    optional : bool
        Whether ``None`` is accepted (the annotation includes ``None``).
    default : Any
        The signature's default; ``inspect.Parameter.empty`` when required.
    """

    name: str
    scalars: tuple[Scalar, ...]
    kind: Kind | None
    optional: bool
    default: Any

    @property
    def required(self) -> bool:
        return self.default is _REQUIRED

    @property
    def checked(self) -> bool:
        """Whether :func:`validate_params` checks it (scalars and seeds; arrays are the
        function's own business)."""
        return bool(self.scalars) or self.kind is Kind.SEED

    def check(self, value: Any) -> Any:
        """``value`` checked against the declaration and converted."""
        if value is None and self.optional:
            return None
        if self.kind is Kind.SEED:
            if isinstance(value, np.random.Generator):
                return value
            return as_int(value, name=self.name, minimum=0)
        if len(self.scalars) == 1 and self.kind is None:
            return self.scalars[0].check(value, self.name)
        for scalar in self.scalars:
            if scalar.accepts(value):
                return scalar.check(value, self.name)
        if self.kind is not None and not isinstance(value, (str, numbers.Number)):
            return value  # the array alternative: checked by the function
        words = [s.words() for s in self.scalars]
        if self.kind is not None:
            words.append(f"an array ({self.kind})")
        if self.optional:
            words.append("null")
        raise InvalidInputError(
            f"Expected `{self.name}` to be {' or '.join(words)}, got {value!r}.",
            field=self.name)


def _bounds(meta: list[Any], base: type) -> tuple[float | None, float | None, tuple[bool, bool]]:
    lo: float | None = None
    hi: float | None = None
    incl = [True, True]
    flat: list[Any] = []
    for m in meta:
        flat.extend(m if isinstance(m, GroupedMetadata) else [m])
    # annotated-types types a bound as any comparable (SupportsGe …); the bounds of an int or
    # float parameter are numbers, so they are taken as such
    for m in flat:
        if isinstance(m, Ge):
            lo, incl[0] = typing.cast(float, m.ge), True
        elif isinstance(m, Gt):
            lo, incl[0] = typing.cast(float, m.gt), False
        elif isinstance(m, Le):
            hi, incl[1] = typing.cast(float, m.le), True
        elif isinstance(m, Lt):
            hi, incl[1] = typing.cast(float, m.lt), False
        elif isinstance(m, BaseMetadata):
            raise TypeError(f"unsupported constraint {m!r}")
    if base is int:  # integers: open bounds become closed ones
        if lo is not None and not incl[0]:
            lo, incl[0] = math.floor(lo) + 1, True
        if hi is not None and not incl[1]:
            hi, incl[1] = math.ceil(hi) - 1, True
    return lo, hi, (incl[0], incl[1])


def _parse(name: str, hint: Any) -> tuple[list[Scalar], Kind | None, bool]:
    """The scalar alternatives, the array kind and the optionality of one annotation."""
    scalars: list[Scalar] = []
    kind: Kind | None = None
    optional = False
    origin = typing.get_origin(hint)
    if origin is typing.Union or origin is types.UnionType:
        for arg in typing.get_args(hint):
            s, k, o = _parse(name, arg)
            scalars += s
            kind = kind or k
            optional = optional or o
        return scalars, kind, optional
    if hint is type(None) or hint is None:
        return [], None, True
    meta: list[Any] = []
    if origin is Annotated:
        hint, *meta = typing.get_args(hint)
        kinds = [m for m in meta if isinstance(m, Kind)]
        if kinds:
            _, _, optional = _parse(name, hint)
            return [], kinds[0], optional
        origin = typing.get_origin(hint)
    if origin is Literal:
        choices = typing.get_args(hint)
        if not all(isinstance(c, str) for c in choices):
            raise TypeError(f"{name}: Literal choices must be strings, got {choices!r}")
        return [Scalar(str, tuple(choices))], None, False
    if hint in (bool, int, float):
        lo, hi, incl = _bounds(meta, hint)
        return [Scalar(hint, (), lo, hi, incl)], None, False
    return [], None, False  # not declared for checking (a callable, an array without kind)


@functools.cache
def declarations(function: Callable[..., Any]) -> dict[str, Declaration]:
    """The declaration of every parameter of ``function`` (``progress`` excluded), in order.

    Raises ``TypeError`` when an annotation uses a constraint this module does not know.
    """
    sig = inspect.signature(function)
    hints = typing.get_type_hints(function, include_extras=True)
    out = {}
    for name, param in sig.parameters.items():
        if name == "progress" or param.kind in (param.VAR_POSITIONAL, param.VAR_KEYWORD):
            continue
        scalars, kind, optional = _parse(name, hints.get(name, Any))
        out[name] = Declaration(name, tuple(scalars), kind, optional, param.default)
    return out


F = TypeVar("F", bound=Callable[..., Any])


def validate_params(function: F) -> F:
    """Check every declared scalar argument of ``function`` on each call (defaults are
    trusted: a test checks each against its declaration), and pass the checked values on.

    The declarations are read on the first call, when the annotations can be resolved.
    """
    sig = inspect.signature(function)
    positional = [n for n, p in sig.parameters.items()
                  if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    plan: dict[str, Declaration] | None = None

    @functools.wraps(function)
    def checked(*args: Any, **kwargs: Any) -> Any:
        nonlocal plan
        if plan is None:
            plan = {n: d for n, d in declarations(function).items() if d.checked}
        if args:
            values = list(args)
            for i, name in enumerate(positional[:len(values)]):
                if name in plan:
                    values[i] = plan[name].check(values[i])
            args = tuple(values)
        for name in kwargs.keys() & plan.keys():
            kwargs[name] = plan[name].check(kwargs[name])
        return function(*args, **kwargs)

    return typing.cast(F, checked)
