"""Tests for the layout family's shared input checks (algorithms/layout/_inputs.py), which
the service runs before queuing a request: which alternative input was given, and distance
matrices from a matrix or from listed pairs. The methods' own tests cover them through
each method's errors."""

from __future__ import annotations

import numpy as np
import pytest

from algorithms.core import DegenerateInputError, InvalidInputError
from algorithms.layout import (
    as_distance_matrix,
    distance_pairs_matrix,
    distance_source,
    mesh_or_graph,
)

MESH = {"vertices": [[0, 0], [1, 0], [0, 1]], "faces": [[0, 1, 2]]}
PATH = {"nodes": 3, "edges": [[0, 1], [1, 2]]}


def test_mesh_or_graph_names_the_one_given() -> None:
    assert mesh_or_graph(MESH, None, "cotangent") == "mesh"
    assert mesh_or_graph(None, PATH, "uniform") == "graph"


@pytest.mark.parametrize("mesh, graph, weighting, field, match", [
    (None, None, "uniform", "mesh", "exactly one of `mesh` and `graph`, got none"),
    (MESH, PATH, "uniform", "graph", "exactly one of `mesh` and `graph`, got `mesh` and "
     "`graph`"),
    (None, PATH, "tangent", "weighting", "'uniform' with a `graph` .* tangent weights need a "
     "mesh"),
])
def test_mesh_or_graph_errors(mesh, graph, weighting, field, match) -> None:  # noqa: ANN001
    with pytest.raises(InvalidInputError, match=match) as info:
        mesh_or_graph(mesh, graph, weighting)
    assert info.value.field == field


def test_distance_source_names_the_one_given() -> None:
    assert distance_source([[0, 1], [1, 0]], None, None, None) == "distances"
    assert distance_source(None, [[0, 1, 1.0]], 3, None) == "distance_pairs"
    assert distance_source(None, None, None, PATH) == "graph"


@pytest.mark.parametrize("inputs, field, match", [
    ((None, None, None, None), "distances",
     "exactly one of `distances`, `distance_pairs` and `graph`, got none"),
    (([[0]], [[0, 1, 1.0]], None, PATH), "distance_pairs",
     "got `distances` and `distance_pairs` and `graph`"),
    ((None, None, 4, PATH), "n_points", "only together with `distance_pairs` .* got it with "
     "`graph`"),
])
def test_distance_source_errors(inputs, field, match) -> None:  # noqa: ANN001
    with pytest.raises(InvalidInputError, match=match) as info:
        distance_source(*inputs)
    assert info.value.field == field


def test_distance_matrix_is_symmetrised_with_missing_entries() -> None:
    d = as_distance_matrix([[0, 1, None], [1 + 1e-7, 0, 2], [np.nan, None, 0]])
    assert d[0, 1] == d[1, 0] == pytest.approx(1 + 5e-8, rel=1e-12)  # agree to 1e-5: mean
    assert d[1, 2] == d[2, 1] == 2.0           # one known: that one
    assert np.isnan(d[0, 2]) and np.isnan(d[2, 0])


def test_asymmetric_distances_are_refused() -> None:
    """As scikit-learn's MDS (check_symmetric) and scipy's squareform refuse them: d[i, j]
    and d[j, i] are one distance; two known values that differ are a contradiction."""
    with pytest.raises(InvalidInputError, match=r"symmetric .* got 1.0 at row 0, column 1 "
                       r"and 3.0 at row 1, column 0") as info:
        as_distance_matrix([[0, 1, None], [3, 0, 2], [np.nan, None, 0]])
    assert info.value.field == "distances"
    with pytest.raises(InvalidInputError, match=r"one distance, got 4.0 at row 1 for the pair "
                       r"\(1, 0\) given 2.0 at row 0") as info:
        distance_pairs_matrix([[0, 1, 2.0], [1, 0, 4.0], [1, 2, 5.0]])
    assert info.value.field == "distance_pairs"
    with pytest.raises(InvalidInputError, match="missing distances are not accepted"):
        as_distance_matrix([[0, np.nan], [np.nan, 0]], allow_missing=False)


def test_size_limits_below_the_dense_one() -> None:
    """A caller's limit (the service's most points) holds, not only the dense 4,000."""
    with pytest.raises(InvalidInputError, match="at most 3 points, got 4") as info:
        as_distance_matrix(np.zeros((4, 4)), max_points=3)
    assert info.value.field == "distances"
    with pytest.raises(InvalidInputError, match="at most 3 points, got 5") as info:
        distance_pairs_matrix([[0, 1, 1.0]], 5, max_points=3)
    assert info.value.field == "n_points"
    with pytest.raises(InvalidInputError, match="at most 4,000 points .* got 4,001"):
        distance_pairs_matrix([[0, 4000, 1.0]], max_points=3)


def test_pairs_matrix_counts_a_repeated_pair_once() -> None:
    d = distance_pairs_matrix([[0, 1, 2.0], [1, 0, 2.0], [1, 2, 1.0]])
    assert d.shape == (3, 3) and d[0, 1] == d[1, 0] == 2.0 and np.isnan(d[0, 2])
    with pytest.raises(DegenerateInputError, match="none for point 3") as info:
        distance_pairs_matrix([[0, 1, 1.0], [1, 2, 1.0]], 4)
    assert info.value.field == "distance_pairs"
