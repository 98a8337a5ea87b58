"""The partition that prunes t-SNE's exact neighbour search and trustworthiness's rank
counts: every point in one group, radii that bound the members, gaps that bound every
distance between two groups; the grouped searches against a full sort (clustered data,
where most groups are pruned; data without clusters; ties) and against scikit-learn's
trustworthiness."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.datasets import make_blobs
from sklearn.manifold import trustworthiness

from algorithms.embedding import _groups
from algorithms.embedding import trustworthiness as package_trustworthiness
from algorithms.embedding._groups import group_count, partition
from algorithms.embedding._quality import _nearest_neighbors


def _full(x: np.ndarray) -> np.ndarray:
    d2 = ((x[:, None, :] - x[None, :, :]) ** 2).sum(-1)
    np.fill_diagonal(d2, np.inf)
    return d2


@pytest.fixture
def grouped(monkeypatch: pytest.MonkeyPatch) -> None:
    """Groups from 100 points on (the package's threshold is 5,000: tests stay small)."""
    monkeypatch.setattr(_groups, "GROUPED_FROM", 100)


def test_group_count() -> None:
    assert group_count(4_999) == 1 and group_count(5_000) == 35
    assert group_count(100_000) == 158 and group_count(10**8) == 1024


def test_partition_bounds_every_distance() -> None:
    x, _ = make_blobs(600, n_features=8, centers=5, random_state=0)
    xc = x - x.mean(axis=0)
    g = partition(xc, 12)
    assert sorted(g.order) == list(range(600)) and g.starts[-1] == 600
    for h in range(len(g)):
        assert (g.label[g.members(h)] == h).all()
    d = np.sqrt(((xc[:, None, :] - xc[None, :, :]) ** 2).sum(-1))
    for a in range(len(g)):
        for b in range(len(g)):
            block = d[np.ix_(g.members(a), g.members(b))]
            assert block.min() >= g.gap[a, b] - 1e-9
    assert (np.diag(g.gap) == 0).all()
    # the same input gives the same groups
    assert np.array_equal(partition(xc, 12).label, g.label)


@pytest.mark.usefixtures("grouped")
@pytest.mark.parametrize("kind", ["clusters", "uniform", "ties"])
def test_grouped_search_is_exact(kind: str) -> None:
    rng = np.random.default_rng(3)
    if kind == "clusters":
        x, _ = make_blobs(900, n_features=20, centers=12, cluster_std=np.linspace(0.5, 3, 12),
                          center_box=(-30, 30), random_state=1)
    elif kind == "uniform":
        x = rng.uniform(size=(700, 15))
    else:
        x = rng.integers(0, 2, size=(700, 12)).astype(float)
    k = 30
    d2, nbr = _nearest_neighbors(x, k)
    full = _full(x)
    np.testing.assert_allclose(d2, np.sort(full, axis=1)[:, :k], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(np.take_along_axis(full, nbr, axis=1), d2, rtol=1e-12,
                               atol=1e-12)
    assert all(len(set(row)) == k for row in nbr)
    if kind == "clusters":
        # most of the n × n is pruned: a group's reach holds about its own cluster
        xc = x - x.mean(axis=0)
        g = partition(xc, group_count(len(x)))
        reach = [g.reach(h, float(d2[g.members(h), -1].max())).size for h in range(len(g))]
        assert np.median(reach) < len(x) / 4


@pytest.mark.usefixtures("grouped")
def test_grouped_trustworthiness_from_lists_matches_sklearn() -> None:
    x, _ = make_blobs(800, n_features=20, centers=10, random_state=2)
    rng = np.random.default_rng(4)
    d2, nbr = _nearest_neighbors(x, 20)
    for y in (rng.normal(size=(800, 2)),                        # poor: whole rows counted
              x[:, :2] + 0.3 * rng.normal(size=(800, 2))):       # good: few candidates
        for k in (1, 5, 12):
            lists = package_trustworthiness(x, y, n_neighbors=k, input_neighbours=(d2, nbr))
            assert lists == pytest.approx(trustworthiness(x, y, n_neighbors=k), abs=1e-12)
    xi = rng.integers(0, 3, size=(500, 12)).astype(float)     # ties with the thresholds
    yi = rng.normal(size=(500, 2))
    d2, nbr = _nearest_neighbors(xi, 10)
    lists = package_trustworthiness(xi, yi, n_neighbors=5, input_neighbours=(d2, nbr))
    assert lists == pytest.approx(package_trustworthiness(xi, yi, n_neighbors=5), abs=1e-12)
