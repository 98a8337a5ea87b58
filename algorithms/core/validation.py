"""Input checks shared by every algorithm: the one place where inputs are validated.

Every public function here takes the value to check first and the keyword ``name``, the
name of the input as the caller spelled it (``"source"``, ``"k"``). The name appears in
the message, between backticks, and as the ``field`` of the raised error, so the service
can point at the offending input. Messages say what was expected and what came, in the
style of scipy::

    Expected `source` to be an (n, 3) array of finite numbers, got shape (5, 2).
    Expected `source` to hold finite numbers, got nan at row 17.
    Expected `faces` to hold vertex indices below 1024, got 1031 at row 17.

Every failure raises :class:`~algorithms.core.errors.InvalidInputError` (a
:class:`ValueError`); nothing here uses ``assert``. Degenerate geometry (well-formed input
that poses an undetermined problem) is the algorithms' business and raises
:class:`~algorithms.core.errors.DegenerateInputError`.

Arrays that already have the requested dtype and layout are returned as they are, without
a copy: callers must not write into what these functions return.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.linalg import RANK_RTOL, numerical_rank
from algorithms.core.types import FloatArray, IntArray

__all__ = [
    "as_points",
    "as_weights",
    "as_int",
    "as_float",
    "as_choice",
    "as_bool",
    "as_indices",
    "check_min_points",
    "same_shape",
    "same_dim",
    "check_point_sets",
    "check_keys",
    "fmt_shape",
    "MAX_DENSE_POINTS",
    "check_dense_size",
]

_NUMERIC_KINDS = "iuf"  # signed, unsigned, floating; bool and complex are rejected


def fmt_shape(shape: tuple[int, ...]) -> str:
    """A shape as messages write it: ``(5, 2)``, ``(3,)``."""
    return "(" + ", ".join(str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"


def _fmt_number(value: Any) -> str:
    value = value.item() if isinstance(value, np.generic) else value
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    return repr(value)


def _position(index: tuple[int, ...], ndim: int) -> str:
    """Where an element sits: 'row 17' for tables (2-D and up), 'position 17' for vectors."""
    if ndim == 0:
        return "the only position"
    return f"{'row' if ndim >= 2 else 'position'} {index[0]}"


def _as_numeric_array(x: Any, *, name: str, expected: str) -> np.ndarray:
    """``np.asarray`` that turns ragged, non-numeric, bool and complex input into errors."""
    try:
        arr = np.asarray(x)
    except (ValueError, TypeError):  # numpy 2 raises ValueError on ragged input
        raise InvalidInputError(
            f"Expected `{name}` to be {expected}, got a ragged sequence (rows of different "
            "lengths) or one numpy cannot read.",
            field=name,
        ) from None
    if arr.dtype.kind not in _NUMERIC_KINDS:
        what = "bool" if arr.dtype.kind == "b" else str(arr.dtype)
        raise InvalidInputError(
            f"Expected `{name}` to be {expected}, got an array of dtype {what}.", field=name
        )
    return arr


def _first_nonfinite(arr: np.ndarray) -> tuple[tuple[int, ...], Any] | None:
    bad = ~np.isfinite(arr)
    if not bad.any():
        return None
    index = tuple(int(i) for i in np.unravel_index(int(np.argmax(bad)), arr.shape))
    return index, arr[index]


_SUM_CHECK_ABOVE = 1 << 16  # elements; below this ``isfinite(...).all()`` is cheaper


def _check_finite(arr: np.ndarray, *, name: str) -> None:
    """Raise on the first NaN/Inf. Large arrays take a fast path, one sum (no boolean
    temporary); a sum that overflows to inf (huge but finite values) falls through to the
    element-wise check, which then finds nothing."""
    if arr.dtype.kind != "f" or arr.size == 0:
        return
    if arr.size < _SUM_CHECK_ABOVE:
        if np.isfinite(arr).all():
            return
    else:
        with np.errstate(over="ignore", invalid="ignore"):
            total = arr.sum()
        if np.isfinite(total):
            return
    found = _first_nonfinite(arr)
    if found is not None:
        index, value = found
        raise InvalidInputError(
            f"Expected `{name}` to hold finite numbers, got {_fmt_number(value)} at "
            f"{_position(index, arr.ndim)}.",
            field=name,
        )


#: Largest coordinate magnitude :func:`as_points` accepts: squared distances and their sums
#: over many points must stay finite (1e100 squared is 1e200), and no measured geometry comes
#: near it; beyond it results would overflow to Inf and fail the job instead of the input.
MAX_COORDINATE = 1e100


def as_points(
    x: Any,
    *,
    name: str,
    dim: int | None = None,
    min_dim: int = 1,
    min_points: int = 1,
    max_points: int | None = None,
) -> FloatArray:
    """Check a point set and return it as a C-contiguous, aligned float64 ``(n, d)`` array
    (a view at an odd byte offset, as unpickled from a network frame, is copied: BLAS
    takes other paths for misaligned operands, whose last bits differ).

    Parameters
    ----------
    x : array_like, (n, d)
        Nested lists or an array of any integer or floating dtype. A 1-D input is an error,
        never silently reshaped (is it one point or ``n`` points on a line?).
    name : str
        The input's name, used in messages and as the error's ``field``.
    dim : int, optional
        The required dimension ``d``; any ``d >= min_dim`` when omitted.
    min_dim : int, default 1
        The smallest accepted ``d`` when ``dim`` is not given.
    min_points, max_points : int, optional
        Bounds on the number of points ``n`` (inclusive).

    Returns
    -------
    (n, d) float64 array
        ``x`` itself when it already is one (no copy), else a converted copy.

    Raises
    ------
    InvalidInputError
        Ragged or non-numeric input (bool and complex included), not 2-D, ``d`` wrong,
        ``n`` out of bounds, or a NaN/Inf (the message names its row).
    """
    want_d = "d" if dim is None else str(dim)
    expected = f"an (n, {want_d}) array of finite numbers"
    arr = _as_numeric_array(x, name=name, expected=expected)
    if arr.ndim != 2:
        raise InvalidInputError(
            f"Expected `{name}` to be {expected}, got shape {fmt_shape(arr.shape)}.",
            field=name,
        )
    n, d = arr.shape
    if dim is not None and d != dim:
        raise InvalidInputError(
            f"Expected `{name}` to be {expected}, got shape {fmt_shape(arr.shape)}.",
            field=name,
        )
    if d < max(min_dim, 1):
        raise InvalidInputError(
            f"Expected `{name}` to be an (n, d) array with d >= {max(min_dim, 1)} "
            f"coordinates per point, got shape {fmt_shape(arr.shape)}.",
            field=name,
        )
    if n < min_points:
        raise InvalidInputError(
            f"Expected `{name}` to hold at least {min_points} "
            f"point{'s' if min_points != 1 else ''}, got {n}.",
            field=name,
        )
    if max_points is not None and n > max_points:
        raise InvalidInputError(
            f"Expected `{name}` to hold at most {max_points} "
            f"point{'s' if max_points != 1 else ''}, got {n}.",
            field=name,
        )
    out = np.require(arr, dtype=np.float64, requirements=("C_CONTIGUOUS", "ALIGNED"))
    _check_finite(out, name=name)
    if out.size and max(out.max(), -out.min()) > MAX_COORDINATE:
        row = int(np.argmax(np.abs(out).max(axis=1)))
        raise InvalidInputError(
            f"Expected `{name}` to hold coordinates of magnitude at most {MAX_COORDINATE:g} "
            f"(sums of their squares must fit a float64), got "
            f"{_fmt_number(out[row][np.argmax(np.abs(out[row]))])} at row {row}.",
            field=name,
        )
    return out


def check_min_points(points: np.ndarray, minimum: int, *, name: str, reason: str = "") -> None:
    """Raise unless ``points`` (already checked by :func:`as_points`) has ``minimum`` rows.

    For bounds that depend on the data, e.g. "at least ``d`` points in ``d`` dimensions".
    ``reason`` is appended in parentheses: ``"one per dimension"``.
    """
    n = points.shape[0]
    if n < minimum:
        why = f" ({reason})" if reason else ""
        raise InvalidInputError(
            f"Expected `{name}` to hold at least {minimum} "
            f"point{'s' if minimum != 1 else ''}{why}, got {n}.",
            field=name,
        )


def same_shape(a: np.ndarray, b: np.ndarray, *, names: tuple[str, str]) -> None:
    """Raise unless two paired point sets have the same shape (row ``i`` pairs with row ``i``).

    The error names the second input: the first is taken as the reference.
    """
    first, second = names
    if a.shape == b.shape:
        return
    if a.ndim == 2 and b.ndim == 2:
        if a.shape[1] != b.shape[1]:
            msg = (
                f"Expected `{second}` to have the same dimension as `{first}` "
                f"({a.shape[1]}), got shape {fmt_shape(b.shape)}."
            )
        else:
            msg = (
                f"Expected `{second}` to hold as many points as `{first}` "
                f"({a.shape[0]}, paired row by row), got {b.shape[0]}."
            )
    else:
        msg = (
            f"Expected `{second}` to have the same shape as `{first}`, "
            f"{fmt_shape(a.shape)}, got {fmt_shape(b.shape)}."
        )
    raise InvalidInputError(msg, field=second)


def check_keys(value: Mapping[Any, Any], required: Sequence[str], optional: Sequence[str] = (),
               *, name: str, expected: str) -> None:
    """Raise unless the mapping ``value`` (an object as JSON delivers it) has every key of
    ``required`` and none but those and ``optional``: "Expected `mesh` to be an object with
    keys 'vertices' and 'faces', got missing 'faces'." (or "got unknown key 'normals'");
    ``expected`` is the part after "to be"."""
    missing = [k for k in required if k not in value]
    extra = sorted(str(k) for k in value if k not in required and k not in optional)
    if missing or extra:
        what = (f"missing {', '.join(repr(k) for k in missing)}" if missing
                else f"unknown key{'s' if len(extra) > 1 else ''} "
                     f"{', '.join(repr(k) for k in extra)}")
        raise InvalidInputError(f"Expected `{name}` to be {expected}, got {what}.", field=name)


def same_dim(a: np.ndarray, b: np.ndarray, *, names: tuple[str, str]) -> None:
    """Raise unless two ``(n, d)`` and ``(m, d)`` point sets share ``d`` (counts may differ).

    The error names the second input.
    """
    first, second = names
    if a.shape[1:] != b.shape[1:]:
        raise InvalidInputError(
            f"Expected `{second}` to have the same dimension as `{first}` "
            f"({a.shape[1]}), got shape {fmt_shape(b.shape)}.",
            field=second,
        )


def check_point_sets(source: Any, target: Any) -> tuple[FloatArray, FloatArray]:
    """Check two point sets of one dimension, their sizes free: ``source`` and ``target`` as
    :func:`as_points` reads them, ``target`` in ``source``'s dimension. Returns both."""
    src = as_points(source, name="source")
    dst = as_points(target, name="target")
    same_dim(src, dst, names=("source", "target"))
    return src, dst


def as_weights(w: Any, n: int, *, name: str) -> FloatArray | None:
    """Check per-item weights and return them as a float64 ``(n,)`` array.

    ``None`` passes through as ``None`` (meaning "all equal"), so callers can write
    ``w = as_weights(weights, n, name="weights")`` and branch on ``w is None``.

    Raises
    ------
    InvalidInputError
        Not of shape ``(n,)``, non-numeric, NaN/Inf, a negative entry, or all zeros (the
        sum must be positive). Zero entries are allowed: they drop their items.
    """
    if w is None:
        return None
    expected = f"an ({n},) array of finite non-negative numbers"
    arr = _as_numeric_array(w, name=name, expected=expected)
    if arr.shape != (n,):
        raise InvalidInputError(
            f"Expected `{name}` to be {expected}, got shape {fmt_shape(arr.shape)}.",
            field=name,
        )
    out = np.ascontiguousarray(arr, dtype=np.float64)
    _check_finite(out, name=name)
    negative = out < 0
    if negative.any():
        i = int(np.argmax(negative))
        raise InvalidInputError(
            f"Expected `{name}` to be non-negative, got {_fmt_number(out[i])} at position {i}.",
            field=name,
        )
    if n == 0 or not out.max() > 0:  # max, not sum: a sum of huge weights may overflow
        raise InvalidInputError(
            f"Expected `{name}` to have a positive sum, got all zeros.", field=name
        )
    return out


def _bounds_text(minimum: float | None, maximum: float | None, incl: tuple[bool, bool]) -> str:
    parts = []
    if minimum is not None:
        parts.append(f"{'>=' if incl[0] else '>'} {minimum}")
    if maximum is not None:
        parts.append(f"{'<=' if incl[1] else '<'} {maximum}")
    return " and ".join(parts)


def as_int(
    value: Any,
    *,
    name: str,
    minimum: int | None = None,
    maximum: int | None = None,
    reason: str = "",
) -> int:
    """Check an integer parameter and return it as a Python ``int``.

    Accepts Python and numpy integers and integral floats (``3.0``, as JSON may deliver);
    rejects bools, strings, non-integral or non-finite floats. Bounds are inclusive;
    ``reason`` explains them in the message, e.g. ``"the number of `target` points"``
    gives "Expected `k` to be an integer >= 1 and <= 4 (the number of `target` points),
    got 5."
    """
    result: int | None = None
    if isinstance(value, (bool, np.bool_)):
        result = None
    elif isinstance(value, numbers.Integral):
        result = int(value)
    elif isinstance(value, numbers.Real):
        f = float(value)
        if math.isfinite(f) and f.is_integer():
            result = int(f)
    if result is None:
        raise InvalidInputError(
            f"Expected `{name}` to be an integer, got {value!r}.", field=name
        )
    if (minimum is not None and result < minimum) or (maximum is not None and result > maximum):
        raise InvalidInputError(
            f"Expected `{name}` to be an integer {_bounds_text(minimum, maximum, (True, True))}"
            f"{f' ({reason})' if reason else ''}, got {result}.",
            field=name,
        )
    return result


def as_float(
    value: Any,
    *,
    name: str,
    minimum: float | None = None,
    maximum: float | None = None,
    inclusive: bool | tuple[bool, bool] = True,
) -> float:
    """Check a real parameter and return it as a finite Python ``float``.

    Accepts Python and numpy reals (integers included); rejects bools, strings, NaN and
    Inf. ``inclusive`` says whether the bounds themselves are accepted, for both bounds
    or as ``(lower, upper)``: ``as_float(r, name="radius", minimum=0, inclusive=False)``
    demands ``r > 0``.
    """
    incl: tuple[bool, bool] = (
        (inclusive, inclusive) if isinstance(inclusive, bool) else (inclusive[0], inclusive[1])
    )
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise InvalidInputError(f"Expected `{name}` to be a number, got {value!r}.", field=name)
    result = float(value)
    if not math.isfinite(result):
        raise InvalidInputError(
            f"Expected `{name}` to be a finite number, got {_fmt_number(result)}.", field=name
        )
    low_bad = minimum is not None and (result < minimum if incl[0] else result <= minimum)
    high_bad = maximum is not None and (result > maximum if incl[1] else result >= maximum)
    if low_bad or high_bad:
        raise InvalidInputError(
            f"Expected `{name}` to be a number {_bounds_text(minimum, maximum, incl)}"
            f", got {result!r}.",
            field=name,
        )
    return result


def as_bool(value: Any, *, name: str) -> bool:
    """Check a flag: only ``True``/``False`` (Python or numpy) are accepted, never the
    truthiness of a string or number (``"false"`` would otherwise mean ``True``)."""
    if not isinstance(value, (bool, np.bool_)):
        raise InvalidInputError(f"Expected `{name}` to be true or false, got {value!r}.",
                                field=name)
    return bool(value)


def as_choice(value: Any, choices: Iterable[str], *, name: str) -> str:
    """Check that ``value`` is one of the strings ``choices`` (exact, case-sensitive)."""
    options: Sequence[str] = tuple(choices)
    if not isinstance(value, str) or value not in options:
        listed = ", ".join(repr(c) for c in options)
        raise InvalidInputError(
            f"Expected `{name}` to be one of {listed}, got {value!r}.", field=name
        )
    return value


def as_indices(idx: Any, n: int, *, name: str, what: str = "indices") -> IntArray:
    """Check an array of indices into ``n`` items and return it as int64, shape kept.

    Any shape is accepted: ``(m,)`` handle indices, ``(m, 3)`` faces. Integer dtypes are
    taken as they are; floats only when every entry is integral (JSON may deliver ``3.0``).
    ``what`` names the indices in messages, e.g. ``what="vertex indices"`` gives
    "Expected `faces` to hold vertex indices below 1024, got 1031 at row 17."

    Raises
    ------
    InvalidInputError
        Non-numeric input, a non-integral value, or an index outside ``[0, n)``; the message
        names the first bad row (position, for 1-D input).
    """
    arr = _as_numeric_array(idx, name=name, expected=f"an array of {what}")
    if arr.size == 0:
        return np.zeros(arr.shape, dtype=np.int64)
    if arr.dtype.kind == "f":
        bad = ~(np.isfinite(arr) & (arr == np.round(arr)))
        if bad.any():
            index = tuple(int(i) for i in np.unravel_index(int(np.argmax(bad)), arr.shape))
            raise InvalidInputError(
                f"Expected `{name}` to hold integer {what}, got {_fmt_number(arr[index])} at "
                f"{_position(index, arr.ndim)}.",
                field=name,
            )
    # Range check in the input's own dtype (no overflow for uint64 or huge floats).
    if arr.min() < 0 or arr.max() >= n:
        bad = (arr < 0) | (arr >= n)
        index = tuple(int(i) for i in np.unravel_index(int(np.argmax(bad)), arr.shape))
        value = int(arr[index].item())
        where = _position(index, arr.ndim)
        if value < 0:
            msg = f"Expected `{name}` to hold non-negative {what}, got {value} at {where}."
        else:
            msg = f"Expected `{name}` to hold {what} below {n}, got {value} at {where}."
        raise InvalidInputError(msg, field=name)
    return np.ascontiguousarray(arr, dtype=np.int64)


#: What points spanning 0, 1 or 2 dimensions after centring are.
SHAPES = {0: "coincident", 1: "collinear", 2: "coplanar"}


def check_span(points: FloatArray, name: str, need: int, why: str) -> None:
    """Raise DegenerateInputError (naming ``name``) unless the points, centred, span at
    least ``need`` dimensions; ``why`` ends the message (what the method cannot do then).

    The span is the numerical rank of the covariance's eigenvalues with ``RANK_RTOL``;
    variances are squared extents, so that is a relative 1e-5 on the extents."""
    if need <= 0:
        return
    centred = points - points.mean(axis=0)
    var = np.linalg.eigvalsh(centred.T @ centred / len(points))[::-1]
    span = numerical_rank(np.maximum(var, 0.0), RANK_RTOL)
    if span < need:
        what = SHAPES.get(span, f"confined to a {span}-dimensional flat")
        raise DegenerateInputError(
            f"Expected `{name}` to span at least {need} dimension{'s' if need > 1 else ''} "
            f"after centring, got {span}: the points are {what} and {why}.", field=name)


#: The most points a dense method (``mds``, ``stress``, the embeddings' MDS) accepts: it
#: holds a few ``n×n`` float64 matrices (4,000 points: 128 MB each).
MAX_DENSE_POINTS = 4_000


def check_dense_size(n: int, *, name: str) -> None:
    """Raise when ``n`` points are too many for a dense ``n×n`` method."""
    if n > MAX_DENSE_POINTS:
        raise InvalidInputError(
            f"Expected `{name}` to describe at most {MAX_DENSE_POINTS:,} points (the method "
            f"holds dense n×n matrices), got {n:,}.", field=name)
