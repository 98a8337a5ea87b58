"""Inputs shared by the layout methods: which of the alternative inputs was given (a mesh
or a graph; a distance matrix, a list of pairs or a graph), distance matrices (full, with
missing entries, or as a list of known pairs) and the distances of a graph
(:func:`~algorithms.core.graphs.as_graph`).

Every checker takes the input's ``name`` and raises
:class:`~algorithms.core.errors.InvalidInputError` naming it (``graph.edges``,
``distances``) with the message style of :mod:`algorithms.core.validation`. Structural
problems that make a layout undetermined (a point with no known distance, known distances
that split the points into unrelated groups) raise
:class:`~algorithms.core.errors.DegenerateInputError`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components, shortest_path

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.graphs import Graph, as_graph
from algorithms.core.mesh import Mesh, read_mesh
from algorithms.core.types import FloatArray
from algorithms.core.validation import (
    MAX_DENSE_POINTS,
    as_indices,
    as_int,
    as_points,
    check_dense_size,
    fmt_shape,
)

__all__ = [
    "mesh_or_graph",
    "read_mesh_or_graph",
    "distance_source",
    "as_distance_matrix",
    "distance_pairs_matrix",
    "check_connected",
    "graph_distances",
    "resolve_distances",
    "check_n_components",
    "check_distances",
    "SYMMETRY_RTOL",
    "SYMMETRY_ATOL",
]

#: How far ``d[i, j]`` and ``d[j, i]`` (or a pair listed twice) may differ and still be one
#: distance: ``|a - b| <= SYMMETRY_ATOL + SYMMETRY_RTOL * |b|`` both ways, the tolerances of
#: scikit-learn's ``check_symmetric`` (which its MDS applies); the two are then averaged.
SYMMETRY_RTOL = 1e-5
SYMMETRY_ATOL = 1e-10


def _exactly_one(inputs: dict[str, Any]) -> str:
    """The name of the one input of ``inputs`` that is not None; else an error naming the
    first input (none given) or the second one given."""
    given = [k for k, v in inputs.items() if v is not None]
    if len(given) != 1:
        *first, last = [f"`{k}`" for k in inputs]
        got = "none" if not given else " and ".join(f"`{g}`" for g in given)
        raise InvalidInputError(
            f"Expected exactly one of {', '.join(first)} and {last}, got {got}.",
            field=given[1] if given else next(iter(inputs)))
    return given[0]


def mesh_or_graph(mesh: Any, graph: Any, weighting: str) -> str:
    """``"mesh"`` or ``"graph"``: which of the two is given (exactly one must be, else
    :class:`InvalidInputError`); a graph brings its own edge weights, so it takes only
    ``weighting="uniform"``."""
    given = _exactly_one({"mesh": mesh, "graph": graph})
    if given == "graph" and weighting != "uniform":
        raise InvalidInputError(
            f"Expected `weighting` to be 'uniform' with a `graph` (its own weights are the "
            f"edge weights; {weighting} weights need a mesh), got {weighting!r}.",
            field="weighting")
    return given


def read_mesh_or_graph(mesh: Any, graph: Any, weighting: str) -> Mesh | Graph:
    """The one mesh or graph given (:func:`mesh_or_graph`), checked."""
    if mesh_or_graph(mesh, graph, weighting) == "mesh":
        return read_mesh(mesh)
    return as_graph(graph, name="graph")


def distance_source(distances: Any, distance_pairs: Any, n_points: Any, graph: Any) -> str:
    """The name of the one input that gives the distances (``"distances"``,
    ``"distance_pairs"`` or ``"graph"``; else :class:`InvalidInputError`), checking that
    ``n_points`` comes only with ``distance_pairs``."""
    given = _exactly_one({"distances": distances, "distance_pairs": distance_pairs,
                          "graph": graph})
    if n_points is not None and given != "distance_pairs":
        raise InvalidInputError(
            "Expected `n_points` only together with `distance_pairs` (the other inputs "
            f"fix the number of points), got it with `{given}`.", field="n_points")
    return given


def _as_float_matrix(x: Any, *, name: str, expected: str) -> np.ndarray:
    """A float64 array from nested lists or an array; ``None`` entries become NaN."""
    try:
        raw = np.asarray(x)
    except (ValueError, TypeError):
        raw = None
    if raw is None or raw.dtype.kind not in "iufO":
        what = ("a ragged sequence (rows of different lengths)" if raw is None
                else f"an array of dtype {'bool' if raw.dtype.kind == 'b' else raw.dtype}")
        raise InvalidInputError(f"Expected `{name}` to be {expected}, got {what}.", field=name)
    if raw.dtype.kind == "O":
        flat = raw.ravel()
        for k, v in enumerate(flat):
            if v is not None and (isinstance(v, (bool, np.bool_))
                                  or not isinstance(v, (int, float, np.integer, np.floating))):
                index = np.unravel_index(k, raw.shape)
                where = f"row {index[0]}, column {index[1]}" if raw.ndim == 2 else f"position {k}"
                raise InvalidInputError(
                    f"Expected `{name}` to be {expected}, got {v!r} at {where}.", field=name)
        raw = np.array([np.nan if v is None else v for v in flat],
                       dtype=np.float64).reshape(raw.shape)
    return np.array(raw, dtype=np.float64)  # a copy: callers write into it


def as_distance_matrix(x: Any, *, name: str = "distances", allow_missing: bool = True,
                       max_points: int | None = MAX_DENSE_POINTS) -> FloatArray:
    """Check a matrix of pairwise distances and return it as float64 ``(n, n)``.

    Parameters
    ----------
    x : array_like, (n, n)
        Non-negative finite distances; the diagonal zero (or missing). Missing entries are
        NaN (``None``/``null`` as JSON delivers them) where ``allow_missing``.
    name : str, default "distances"
    allow_missing : bool, default True
        Accept NaN entries off the diagonal as unknown distances.
    max_points : int, optional
        Most points ``n`` accepted.

    Returns
    -------
    (n, n) float64 array
        A new array, symmetric: where both ``x[i, j]`` and ``x[j, i]`` are known their mean
        (they must agree to :data:`SYMMETRY_RTOL`), where one is known that one, NaN where
        neither is (missing); the diagonal zero.

    Raises
    ------
    InvalidInputError
        Not a square matrix of numbers, fewer than 2 points, an infinite or negative entry,
        a non-zero diagonal entry, ``x[i, j]`` and ``x[j, i]`` both known and different
        (an asymmetric matrix is refused, as scikit-learn's and scipy's MDS and
        ``squareform`` refuse it), a NaN where not allowed (the message names its row and
        column).
    DegenerateInputError
        A point without any known distance, or known distances that split the points into
        groups with no known distance between them (their relative placement is
        undetermined).
    """
    expected = "a square (n, n) matrix of non-negative distances"
    d = _as_float_matrix(x, name=name, expected=expected)
    if d.ndim != 2 or d.shape[0] != d.shape[1]:
        raise InvalidInputError(
            f"Expected `{name}` to be {expected}, got shape {fmt_shape(d.shape)}.",
            field=name)
    n = d.shape[0]
    if n < 2:
        raise InvalidInputError(f"Expected `{name}` to relate at least 2 points, got {n}.",
                                field=name)
    _check_size(n, max_points, name=name)
    _check_entries(d, name=name, allow_missing=allow_missing)
    diag = np.diagonal(d).copy()
    off = np.isfinite(diag) & (diag != 0)
    if off.any():
        i = int(np.argmax(off))
        raise InvalidInputError(
            f"Expected the diagonal of `{name}` to be zero (a point's distance to itself), got "
            f"{float(diag[i])!r} at row {i}, column {i}.", field=name)
    np.fill_diagonal(d, 0.0)
    known = ~np.isnan(d)
    _check_agree(d, d.T, known & known.T, name=name)
    if not known.all():
        both = known & known.T
        d = np.where(both, 0.5 * (d + d.T), np.where(known, d, d.T))
    else:
        d = 0.5 * (d + d.T)
    check_connected(~np.isnan(d), name=name)
    return d


def _check_agree(a: FloatArray, b: FloatArray, both: np.ndarray, *, name: str) -> None:
    """Raise unless ``a`` and ``b`` agree where ``both`` (to the symmetry tolerances)."""
    with np.errstate(invalid="ignore"):
        close = np.isclose(a, b, rtol=SYMMETRY_RTOL, atol=SYMMETRY_ATOL) & \
            np.isclose(b, a, rtol=SYMMETRY_RTOL, atol=SYMMETRY_ATOL)
    bad = both & ~close
    if bad.any():
        i, j = (int(v) for v in np.unravel_index(int(np.argmax(bad)), bad.shape))
        raise InvalidInputError(
            f"Expected `{name}` to be symmetric (the distance from i to j is that from j to "
            f"i), got {float(a[i, j])!r} at row {i}, column {j} and {float(b[i, j])!r} at row "
            f"{j}, column {i}.", field=name)


def _check_size(n: int, max_points: int | None, *, name: str) -> None:
    """Raise when ``n`` points are more than ``max_points`` (the dense methods' own limit
    gives its own message)."""
    if max_points is not None and n > max_points:
        check_dense_size(n, name=name)
        raise InvalidInputError(
            f"Expected `{name}` to describe at most {max_points:,} points, got {n:,}.",
            field=name)


def _check_entries(d: FloatArray, *, name: str, allow_missing: bool) -> None:
    """Inf, NaN (when not allowed) and negative entries, named by row and column."""
    nan = np.isnan(d)
    np.fill_diagonal(nan, False)
    bad_nan = nan.any() and not allow_missing
    inf = np.isinf(d)
    for mask, what in ((inf, "finite numbers"), (nan if bad_nan else None, "finite numbers")):
        if mask is not None and mask.any():
            i, j = np.unravel_index(int(np.argmax(mask)), d.shape)
            value = d[i, j]
            text = "nan" if np.isnan(value) else ("inf" if value > 0 else "-inf")
            hint = " (missing distances are not accepted here)" if np.isnan(value) else ""
            raise InvalidInputError(
                f"Expected `{name}` to hold {what}{hint}, got {text} at row {i}, column {j}.",
                field=name)
    with np.errstate(invalid="ignore"):
        neg = d < 0
    if neg.any():
        i, j = np.unravel_index(int(np.argmax(neg)), d.shape)
        raise InvalidInputError(
            f"Expected `{name}` to hold non-negative distances, got {float(d[i, j])!r} at "
            f"row {i}, column {j}.", field=name)


def check_connected(known: np.ndarray, *, name: str) -> None:
    """Raise unless every point has a known distance and the known pairs connect them all.

    ``known`` is the ``(n, n)`` boolean mask of known distances (the diagonal ignored).
    """
    mask = known.copy()
    np.fill_diagonal(mask, False)
    lonely = ~mask.any(axis=1)
    if lonely.any():
        i = int(np.argmax(lonely))
        count = int(lonely.sum())
        more = f" ({count} such points in all)" if count > 1 else ""
        raise DegenerateInputError(
            f"Expected every point of `{name}` to have at least one known distance, got none "
            f"for point {i}{more}; its position is undetermined.", field=name)
    count, labels = connected_components(sp.csr_array(mask), directed=False)
    if count > 1:
        sizes = np.bincount(labels)
        other = int(np.argmax(labels != labels[0]))
        raise DegenerateInputError(
            f"Expected the known distances of `{name}` to connect all points, got {count} "
            f"groups with no known distance between them (point 0 in a group of "
            f"{int(sizes[labels[0]])}, point {other} in one of {int(sizes[labels[other]])}); "
            "their relative placement is undetermined.", field=name)


def distance_pairs_matrix(pairs: Any, n_points: Any = None, *, name: str = "distance_pairs",
                          n_name: str = "n_points",
                          max_points: int | None = MAX_DENSE_POINTS) -> FloatArray:
    """The distance matrix (NaN where unknown) described by a list of known pairs.

    Parameters
    ----------
    pairs : array_like, (m, 3)
        Rows ``(i, j, d)``: points ``i != j`` (integers) are ``d >= 0`` apart. A pair given
        twice (either order) must have one distance (to :data:`SYMMETRY_RTOL`; then the
        mean is taken), as ``d[i, j]`` and ``d[j, i]`` of a matrix.
    n_points : int, optional
        The number of points; by default one more than the largest index listed.

    Returns
    -------
    (n, n) float64 array
        Checked as :func:`as_distance_matrix` does (every point related, all connected).

    Raises
    ------
    InvalidInputError
        Not an ``(m, 3)`` array of finite numbers, non-integral or out-of-range indices, a
        pair of a point with itself, a negative distance, a pair given twice with two
        distances, ``n_points`` not an integer >= 2.
    DegenerateInputError
        As :func:`as_distance_matrix`.
    """
    arr = as_points(pairs, name=name, dim=3, min_points=1)
    idx = arr[:, :2]
    if n_points is None:
        n = int(idx.max()) + 1 if np.all(np.isfinite(idx)) else 0
        n = max(n, 2)
    else:
        n = as_int(n_points, name=n_name, minimum=2)
    _check_size(n, max_points, name=n_name if n_points is not None else name)
    ij = as_indices(idx, n, name=name, what=f"point indices (columns 0 and 1) below {n}"
                    if n_points is not None else "point indices")
    same = ij[:, 0] == ij[:, 1]
    if same.any():
        row = int(np.argmax(same))
        raise InvalidInputError(
            f"Expected `{name}` to pair two distinct points per row, got point "
            f"{int(ij[row, 0])} with itself at row {row}.", field=name)
    dist = arr[:, 2]
    neg = dist < 0
    if neg.any():
        row = int(np.argmax(neg))
        raise InvalidInputError(
            f"Expected `{name}` to hold non-negative distances (column 2), got "
            f"{float(dist[row])!r} at row {row}.", field=name)
    lo, hi = np.minimum(ij[:, 0], ij[:, 1]), np.maximum(ij[:, 0], ij[:, 1])
    keys, first, inverse = np.unique(lo * n + hi, return_index=True, return_inverse=True)
    mean = np.bincount(inverse, weights=dist) / np.bincount(inverse)
    seen = dist[first][inverse]  # each row's pair as its first row gives it
    with np.errstate(invalid="ignore"):
        agree = np.isclose(dist, seen, rtol=SYMMETRY_RTOL, atol=SYMMETRY_ATOL) & \
            np.isclose(seen, dist, rtol=SYMMETRY_RTOL, atol=SYMMETRY_ATOL)
    if not agree.all():
        row = int(np.argmax(~agree))
        raise InvalidInputError(
            f"Expected `{name}` to give each pair one distance, got {float(dist[row])!r} at "
            f"row {row} for the pair ({int(ij[row, 0])}, {int(ij[row, 1])}) given "
            f"{float(seen[row])!r} at row {int(first[inverse[row]])}.", field=name)
    d = np.full((n, n), np.nan)
    d[keys // n, keys % n] = mean
    d[keys % n, keys // n] = mean
    np.fill_diagonal(d, 0.0)
    check_connected(~np.isnan(d), name=name)
    return d


def graph_distances(graph: Any, *, name: str = "graph") -> FloatArray:
    """All shortest-path lengths of a connected graph (``graph.weights`` are edge lengths,
    default 1; of repeated edges the shortest counts)."""
    g = as_graph(graph, name=name, max_nodes=MAX_DENSE_POINTS, positive_weights=True)
    n = g.n_nodes
    if n < 2:
        raise InvalidInputError(f"Expected `{name}.nodes` to be at least 2, got {n}.",
                                field=f"{name}.nodes")
    if g.edges.shape[0] == 0:
        raise DegenerateInputError(
            f"Expected `{name}` to be connected, got no edges; the distances between its "
            f"{n} nodes are undetermined.", field=name)
    lo = np.minimum(g.edges[:, 0], g.edges[:, 1])
    hi = np.maximum(g.edges[:, 0], g.edges[:, 1])
    w = np.ones(lo.shape[0]) if g.weights is None else g.weights
    order = np.lexsort((w, lo * n + hi))
    keys = (lo * n + hi)[order]
    first = np.concatenate([[True], keys[1:] != keys[:-1]])
    keys, w = keys[first], w[order][first]
    adj = sp.csr_array((w, (keys // n, keys % n)), shape=(n, n))
    dist = shortest_path(adj, directed=False, unweighted=g.weights is None)
    if np.isinf(dist).any():
        count, labels = connected_components(adj, directed=False)
        other = int(np.argmax(labels != labels[0]))
        raise DegenerateInputError(
            f"Expected `{name}` to be connected, got {count} components (node 0 and node "
            f"{other} are not joined by any path); the distances between them are "
            "undetermined.", field=name)
    return np.ascontiguousarray(dist)


def check_n_components(n_components: Any, n: int) -> int:
    """``n_components`` of a layout of ``n`` points: ``1 <= k <= n``."""
    return as_int(n_components, name="n_components", minimum=1, maximum=n,
                  reason="the number of points")


def check_distances(distances: Any = None, distance_pairs: Any = None, n_points: Any = None,
                    graph: Any = None, n_components: Any = 2) -> int:
    """Check the distances of a layout without computing a graph's: exactly one of the
    three ways to give them (:func:`distance_source`), a matrix or pairs read as
    :func:`as_distance_matrix` and :func:`distance_pairs_matrix` read them, and
    ``n_components`` at most the number of points (:func:`check_n_components`). Returns
    ``n_components``."""
    given = distance_source(distances, distance_pairs, n_points, graph)
    if given == "distance_pairs":
        n = distance_pairs_matrix(distance_pairs, n_points).shape[0]
    elif given == "distances":
        n = as_distance_matrix(distances).shape[0]
    else:
        n = as_graph(graph, name="graph").n_nodes
    return check_n_components(n_components, n)


def resolve_distances(distances: Any, distance_pairs: Any, n_points: Any, graph: Any
                      ) -> tuple[FloatArray, str]:
    """The checked ``(n, n)`` distance matrix (NaN where unknown) from exactly one of the
    three ways to give it (:func:`distance_source`), and the name of the input it came
    from."""
    given = distance_source(distances, distance_pairs, n_points, graph)
    if given == "distances":
        return as_distance_matrix(distances, name="distances"), given
    if given == "distance_pairs":
        return distance_pairs_matrix(distance_pairs, n_points), given
    return graph_distances(graph), given
