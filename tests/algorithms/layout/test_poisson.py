"""Tests for layout.poisson: a hand case, exact recovery from consistent edge vectors,
agreement with a dense least-squares solve of the same objective (numpy), pins, free
components, and every error branch."""

from __future__ import annotations

import numpy as np
import pytest

from algorithms.core import DegenerateInputError, InvalidInputError
from algorithms.core.laplacian import cotangent_weights
from algorithms.core.mesh import edges as mesh_edges
from algorithms.layout import PoissonLayoutResult, poisson

PATH = {"nodes": 3, "edges": [[0, 1], [1, 2]]}


def random_graph(rng: np.random.Generator, n: int, extra: int) -> np.ndarray:
    """A connected graph: a random spanning tree plus ``extra`` random edges."""
    order = rng.permutation(n)
    tree = [[order[i], order[rng.integers(0, i)]] for i in range(1, n)]
    more = rng.integers(0, n, size=(extra, 2))
    more = more[more[:, 0] != more[:, 1]]
    return np.concatenate([np.array(tree), more]).astype(np.int64)


def dense_solution(n, e, w, v, anchors=None, u=None):  # noqa: ANN001, ANN201
    """Stack √w (p_i - p_j - v) and √u (p_i - z) and solve by numpy's least squares."""
    rows, rhs = [], []
    for (i, j), wi, vi in zip(e, w, v, strict=True):
        r = np.zeros(n)
        r[i], r[j] = 1.0, -1.0
        rows.append(np.sqrt(wi) * r)
        rhs.append(np.sqrt(wi) * vi)
    if anchors is not None:
        for (idx, z), ui in zip(anchors, u, strict=True):
            r = np.zeros(n)
            r[idx] = 1.0
            rows.append(np.sqrt(ui) * r)
            rhs.append(np.sqrt(ui) * z)
    return np.linalg.lstsq(np.array(rows), np.array(rhs), rcond=None)[0]


# --- layer 1: by hand -----------------------------------------------------------------------
def test_hand_path_with_anchor():
    res = poisson(graph=PATH, vectors=[[-1.0, 0.0], [-1.0, 0.0]],
                  anchors={"indices": [0], "positions": [[0.0, 0.0]]})
    assert isinstance(res, PoissonLayoutResult)
    np.testing.assert_allclose(res.positions, [[0, 0], [1, 0], [2, 0]], atol=1e-14)
    assert res.energy < 1e-24 and res.edge_rmse < 1e-12 and res.anchor_rmse < 1e-12
    assert res.free_components == 0


def test_hand_conflicting_vectors_and_anchor():
    # edge asks p0 - p1 = (2, 0); anchors pull p0 to 0 (u=1) and p1 to 0 (u=1):
    # p0 = (2/3, 0), p1 = (-2/3, 0): residuals 4/3 (edge) and 2/3 twice (anchors)
    res = poisson(graph={"nodes": 2, "edges": [[0, 1]]}, vectors=[[2.0, 0.0]],
                  anchors={"indices": [0, 1], "positions": [[0.0, 0.0], [0.0, 0.0]]})
    np.testing.assert_allclose(res.positions, [[2 / 3, 0], [-2 / 3, 0]], atol=1e-14)
    assert res.energy == pytest.approx((2 - 4 / 3) ** 2 + 2 * (2 / 3) ** 2, rel=1e-13)
    assert res.edge_rmse == pytest.approx(2 / 3, rel=1e-13)
    assert res.anchor_rmse == pytest.approx(2 / 3, rel=1e-13)


# --- layer 2: recovery and invariants -------------------------------------------------------
@pytest.mark.parametrize("seed", range(10))
def test_consistent_vectors_are_recovered(seed):
    rng = np.random.default_rng(seed)
    n = 30
    p = rng.standard_normal((n, 3))
    e = random_graph(rng, n, 40)
    v = p[e[:, 0]] - p[e[:, 1]]
    res = poisson(graph={"nodes": n, "edges": e}, vectors=v,
                  anchors={"indices": [5], "positions": p[[5]]})
    np.testing.assert_allclose(res.positions, p, atol=1e-10)
    assert res.edge_rmse < 1e-10
    # without anchors: the same up to translation, centred at the origin
    free = poisson(graph={"nodes": n, "edges": e}, vectors=v)
    np.testing.assert_allclose(free.positions, p - p.mean(axis=0), atol=1e-10)
    assert free.free_components == 1


def test_mesh_edge_vectors_reproduce_the_mesh(meshes):
    v, f = meshes["squashed_disk"](4)
    e = mesh_edges(f)
    vec = v[e[:, 0]] - v[e[:, 1]]
    for weighting in ("uniform", "cotangent", "tangent"):
        res = poisson((v, f), vectors=vec, pins={"indices": [0], "positions": v[[0]]},
                      weighting=weighting)
        np.testing.assert_allclose(res.positions, v, atol=1e-9)


@pytest.mark.parametrize("seed", range(5))
def test_matches_dense_least_squares(seed):
    rng = np.random.default_rng(seed)
    n = 25
    e = random_graph(rng, n, 30)
    w = rng.uniform(0.1, 2.0, len(e))
    v = rng.standard_normal((len(e), 2))
    idx = rng.choice(n, 4, replace=False)
    z = rng.standard_normal((4, 2))
    u = rng.uniform(0.5, 3.0, 4)
    res = poisson(graph={"nodes": n, "edges": e, "weights": w}, vectors=v,
                  anchors={"indices": idx, "positions": z}, anchor_weights=u)
    expected = dense_solution(n, e, w, v, list(zip(idx, z, strict=True)), u)
    np.testing.assert_allclose(res.positions, expected, atol=1e-10)
    r = expected[e[:, 0]] - expected[e[:, 1]] - v
    a = expected[idx] - z
    assert res.energy == pytest.approx(np.sum(w[:, None] * r * r) + np.sum(u[:, None] * a * a),
                                       rel=1e-10)


def test_cotangent_weights_are_taken_per_edge(meshes):
    v, f = meshes["disk"](3)
    e = mesh_edges(f)
    rng = np.random.default_rng(3)
    vec = rng.standard_normal((len(e), 2))
    res = poisson((v, f), vectors=vec, weighting="cotangent",
                  anchors={"indices": [0], "positions": [[0.0, 0.0]]})
    w = np.asarray(cotangent_weights(v, f)[e[:, 0], e[:, 1]]).ravel()
    assert (w > 0).all()  # Delaunay: the dense reference needs square roots
    expected = dense_solution(len(v), e, w, vec, [(0, np.zeros(2))], [1.0])
    np.testing.assert_allclose(res.positions, expected, atol=1e-10)


def test_pins_are_met_exactly_and_big_anchors_approach_them():
    rng = np.random.default_rng(7)
    n = 20
    e = random_graph(rng, n, 20)
    v = rng.standard_normal((len(e), 2))
    pins = {"indices": [0, 7], "positions": [[0.0, 0.0], [3.0, 1.0]]}
    hard = poisson(graph={"nodes": n, "edges": e}, vectors=v, pins=pins)
    np.testing.assert_array_equal(hard.positions[[0, 7]], pins["positions"])
    soft = poisson(graph={"nodes": n, "edges": e}, vectors=v, anchors=pins,
                   anchor_weights=[1e8, 1e8])
    np.testing.assert_allclose(soft.positions, hard.positions, atol=1e-6)


def test_separate_components_are_each_centred_or_anchored():
    g = {"nodes": 5, "edges": [[0, 1], [1, 2], [3, 4]]}
    v = [[1.0, 0.0], [1.0, 0.0], [0.0, 2.0]]
    res = poisson(graph=g, vectors=v, anchors={"indices": [2], "positions": [[10.0, 10.0]]})
    np.testing.assert_allclose(res.positions[:3], [[12, 10], [11, 10], [10, 10]], atol=1e-12)
    np.testing.assert_allclose(res.positions[3:], [[0, 1], [0, -1]], atol=1e-12)
    assert res.free_components == 1
    # an anchor of weight 0 anchors nothing
    res0 = poisson(graph=g, vectors=v, anchors={"indices": [2, 3], "positions": [[1, 1], [9, 9]]},
                   anchor_weights=[1.0, 0.0])
    np.testing.assert_allclose(res0.positions[3:], [[0, 1], [0, -1]], atol=1e-12)


# --- errors ---------------------------------------------------------------------------------
V2 = [[1.0, 0.0], [1.0, 0.0]]


@pytest.mark.parametrize("kwargs, error, field, match", [
    ({"vectors": V2}, InvalidInputError, "mesh", "exactly one of `mesh` and `graph`, got none"),
    ({"graph": PATH, "vectors": [[1.0, 0.0]]}, InvalidInputError, "vectors",
     r"one row per edge of `graph` \(2\), got 1"),
    ({"graph": PATH, "vectors": [[1.0, np.inf], [1.0, 0.0]]}, InvalidInputError, "vectors",
     "inf at row 0"),
    ({"graph": PATH, "vectors": [[1.0], [1.0]]}, InvalidInputError, "vectors", "d >= 2"),
    ({"graph": PATH, "vectors": V2, "anchors": {"indices": [0], "positions": [[0, 0, 0]]}},
     InvalidInputError, "anchors.positions", r"dimension of `vectors` \(2\)"),
    ({"graph": PATH, "vectors": V2, "pins": {"indices": [9], "positions": [[0, 0]]}},
     InvalidInputError, "pins.indices", "below 3"),
    ({"graph": PATH, "vectors": V2, "pins": {"indices": [0], "positions": [[0, 0, 1]]}},
     InvalidInputError, "pins.positions", "dimension"),
    ({"graph": PATH, "vectors": V2, "anchor_weights": [1.0]}, InvalidInputError,
     "anchor_weights", "only together with `anchors`"),
    ({"graph": PATH, "vectors": V2, "anchors": {"indices": [0], "positions": [[0, 0]]},
      "anchor_weights": [-1.0]}, InvalidInputError, "anchor_weights", "non-negative"),
    ({"graph": PATH, "vectors": V2, "anchors": {"indices": [0], "positions": [[0, 0]]},
      "anchor_weights": [1.0, 2.0]}, InvalidInputError, "anchor_weights", "shape"),
    ({"graph": PATH, "vectors": V2, "weighting": "tangent"}, InvalidInputError, "weighting",
     "need a mesh"),
    ({"graph": PATH, "vectors": V2, "weighting": "harmonic"}, InvalidInputError, "weighting",
     "one of 'uniform', 'cotangent', 'tangent'"),
    ({"graph": {"nodes": 3, "edges": [[0, 1], [1, -1]]}, "vectors": V2}, InvalidInputError,
     "graph.edges", "non-negative"),
    ({"mesh": ([[0, 0], [1, 0], [1, 0]], [[0, 1, 2]]), "vectors": V2},
     DegenerateInputError, "mesh.faces", "zero-area"),
])
def test_errors(kwargs, error, field, match):
    with pytest.raises(error, match=match) as info:
        poisson(**kwargs)
    assert info.value.field == field


def test_mesh_vector_count_names_the_edge_order(meshes):
    v, f = meshes["grid"](3)
    with pytest.raises(InvalidInputError, match=r"one row per edge of `mesh` \(16, its unique "
                       r"edges i < j sorted\), got 3") as info:
        poisson((v, f), vectors=np.zeros((3, 2)))
    assert info.value.field == "vectors"
