"""k-means with k-means++ seeding (the clustering family's private helper)."""

from __future__ import annotations

import numpy as np

from algorithms.clustering._kmeans import kmeans


def test_kmeans_plus_plus_finds_obvious_centres_and_is_deterministic() -> None:
    rng = np.random.default_rng(1)
    centres = np.array([[0, 0], [20, 0], [0, 20]])
    x = np.repeat(centres, 30, axis=0) + rng.normal(0, 0.5, (90, 2))
    a, b = kmeans(x, 3, seed=7), kmeans(x, 3, seed=7)
    assert np.array_equal(a.labels, b.labels) and np.array_equal(a.centers, b.centers)
    assert a.labels.tolist() == np.repeat([0, 1, 2], 30).tolist()
    np.testing.assert_allclose(a.centers, centres, atol=0.3)
