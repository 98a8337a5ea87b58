"""Self-organising map: a hand-made case, invariants (a plane is mapped without folds, the
fit improves on the start, the batch map is a fixed point), determinism, progress."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.manifold import trustworthiness

from algorithms.core.errors import Cancelled, InvalidInputError
from algorithms.embedding.som import som


def test_two_nodes_two_groups_by_hand() -> None:
    pts = [[0.0, 0.0], [0.1, 0.0], [5.0, 5.0], [5.1, 5.0]]
    res = som(pts, rows=1, columns=2, method="batch")
    assert res.bmu[0] == res.bmu[1] != res.bmu[2] == res.bmu[3]
    # sigma decays to 1: each node is the h-weighted mean, h = exp(-1/2) for the other group
    h = np.exp(-0.5)
    a, b = np.array([0.05, 0.0]), np.array([5.05, 5.0])
    expect = {res.bmu[0]: (a + h * b) / (1 + h), res.bmu[2]: (b + h * a) / (1 + h)}
    for node, pos in expect.items():
        np.testing.assert_allclose(res.codebook[node], pos, atol=1e-9)


@pytest.mark.parametrize("method", ["online", "batch"])
def test_a_plane_is_mapped_without_folds(method) -> None:
    rng = np.random.default_rng(0)
    x = rng.random((400, 2)) * [2.0, 1.0]
    start = som(x, rows=6, columns=6, method=method, max_iterations=1, learning_rate=1e-9
                if method == "online" else 0.5)
    res = som(x, rows=6, columns=6, method=method)
    assert res.topographic_error < 0.05
    assert res.quantization_error < 0.2
    assert res.trustworthiness > 0.9
    assert res.trustworthiness == pytest.approx(
        trustworthiness(x, res.embedding, n_neighbors=5), abs=0.02)  # ties on a node
    if method == "online":
        assert res.quantization_error < start.quantization_error
    np.testing.assert_array_equal(res.embedding, np.stack(np.divmod(res.bmu, 6), 1))


def test_same_seed_same_map_and_progress() -> None:
    x = np.random.default_rng(3).normal(size=(100, 4))
    seen = []
    a = som(x, rows=4, columns=5, init="random", seed=9, progress=lambda *p: seen.append(p))
    b = som(x, rows=4, columns=5, init="random", seed=9)
    assert np.array_equal(a.codebook, b.codebook) and np.array_equal(a.bmu, b.bmu)
    assert seen[-1][0] == seen[-1][1] == a.iterations and len(seen) == 100
    c = som(x, rows=4, columns=5, init="random", seed=10)
    assert not np.array_equal(a.codebook, c.codebook)

    def stop(done, total, message=""):
        raise Cancelled("stop")

    with pytest.raises(Cancelled):
        som(x, method="batch", progress=stop)


@pytest.mark.parametrize("kwargs, field, match", [
    ({"rows": 1, "columns": 1}, "rows", "at least 2 nodes"),
    ({"rows": 0}, "rows", ">= 1"),
    ({"learning_rate": 0}, "learning_rate", "> 0"),
    ({"sigma": -1.0}, "sigma", "> 0"),
    ({"method": "gradient"}, "method", "one of"),
    ({"points": [[1.0, 2.0]]}, "points", "at least 2"),
])
def test_bad_input(kwargs, field, match) -> None:
    with pytest.raises(InvalidInputError, match=match) as err:
        som(**{"points": [[0, 0], [1, 1], [2, 0]], **kwargs})
    assert err.value.field == field
