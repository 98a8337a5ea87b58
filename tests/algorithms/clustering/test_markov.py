"""Markov clustering: a hand-made graph, a planted partition, points, progress and
cancellation."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.metrics import adjusted_rand_score

from algorithms.clustering import markov
from algorithms.core.errors import Cancelled, InvalidInputError

TWO_TRIANGLES = {"nodes": 6, "edges": [[0, 1], [1, 2], [0, 2], [3, 4], [4, 5], [3, 5], [2, 3]]}


def test_two_triangles_joined_by_an_edge() -> None:
    res = markov(graph=TWO_TRIANGLES)
    assert res.labels.tolist() == [0, 0, 0, 1, 1, 1]
    assert res.sizes.tolist() == [3, 3] and res.n_clusters == 2 and res.converged
    assert len(res.attractors) >= 2


def _planted(sizes, p_in, p_out, seed):
    rng = np.random.default_rng(seed)
    y = np.repeat(np.arange(len(sizes)), sizes)
    p = np.where(y[:, None] == y[None, :], p_in, p_out)
    edges = np.argwhere(np.triu(rng.random(p.shape) < p, 1))
    return y, {"nodes": int(y.size), "edges": edges.tolist()}


@pytest.mark.parametrize("seed", range(5))
def test_recovers_a_planted_partition(seed) -> None:
    y, g = _planted([30, 25, 20, 25], 0.5, 0.02, seed)
    res = markov(graph=g)
    assert adjusted_rand_score(y, res.labels) == 1.0
    assert sorted(res.sizes.tolist()) == [20, 25, 25, 30]


def test_disconnected_graph_and_weights() -> None:
    # a weak bridge keeps the triangles apart
    g = dict(TWO_TRIANGLES, weights=[1, 1, 1, 1, 1, 1, 0.01])
    assert markov(graph=g).n_clusters == 2
    iso = {"nodes": 7, "edges": TWO_TRIANGLES["edges"]}
    res = markov(graph=iso)  # node 6 has no edge: its own cluster (self-loop)
    assert res.n_clusters == 3 and res.labels[6] == 2


def test_points_with_a_neighbour_graph() -> None:
    rng = np.random.default_rng(0)
    centres = np.array([[0, 0], [10, 0], [0, 10]])
    x = np.repeat(centres, 40, axis=0) + rng.normal(0, 0.7, (120, 2))
    res = markov(x, n_neighbors=8, inflation=1.2)
    assert adjusted_rand_score(np.repeat([0, 1, 2], 40), res.labels) == 1.0


def test_progress_and_cancel() -> None:
    seen = []
    markov(graph=TWO_TRIANGLES, progress=lambda *a: seen.append(a))
    assert [s[0] for s in seen] == list(range(1, len(seen) + 1)) and seen[0][1] == 100

    def stop(done, total, message=""):
        if done == 2:
            raise Cancelled("stop")

    with pytest.raises(Cancelled):
        markov(graph=TWO_TRIANGLES, progress=stop)


@pytest.mark.parametrize("kwargs, field, match", [
    ({}, "points", "exactly one of"),
    ({"graph": TWO_TRIANGLES, "points": [[0, 0], [1, 1]]}, "graph", "exactly one"),
    ({"points": [[0, 0], [1, 1], [2, 2]], "n_neighbors": 5}, "n_neighbors", "minus one"),
    ({"graph": TWO_TRIANGLES, "inflation": 1.0}, "inflation", "a number > 1"),
    ({"graph": TWO_TRIANGLES, "expansion": 1}, "expansion", ">= 2"),
    ({"graph": TWO_TRIANGLES, "self_loops": -1.0}, "self_loops", ">= 0"),
    ({"graph": TWO_TRIANGLES, "pruning_threshold": 1.0}, "pruning_threshold", "< 1"),
    ({"graph": TWO_TRIANGLES, "max_iterations": 0}, "max_iterations", ">= 1"),
    ({"graph": TWO_TRIANGLES, "tolerance": -1e-3}, "tolerance", ">= 0"),
    ({"graph": TWO_TRIANGLES, "neighbors": "grid"}, "neighbors", "one of"),
    ({"graph": {"nodes": 3, "edges": [[0, 1]]}, "self_loops": 0}, "graph", "node 2"),
    ({"graph": {"nodes": 3, "edges": [[0, 5]]}}, "graph.edges", "below 3"),
])
def test_bad_input(kwargs, field, match) -> None:
    with pytest.raises(InvalidInputError, match=match) as err:
        markov(**kwargs)
    assert err.value.field == field
