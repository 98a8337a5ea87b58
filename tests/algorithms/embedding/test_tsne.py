"""t-SNE: perplexity calibration (entropy = log perplexity), the exact gradient against finite
differences, the FFT repulsion against the all-pairs sums, the exact neighbour search
against a full sort (single-precision screen, ties, double-precision redo), the
trustworthiness from neighbour lists against scikit-learn's, agreement with scikit-learn's
TSNE (exact and Barnes–Hut) in trustworthiness and KL, determinism, progress and
cancellation, every error branch; and the same bits for t-SNE and SNE (which shares the
affinities and the descent) whatever the memory layout of the points."""

from __future__ import annotations

import pickle
import sys

import numpy as np
import pytest
from sklearn.datasets import load_digits, make_blobs
from sklearn.manifold import TSNE, trustworthiness
from threadpoolctl import threadpool_limits

from algorithms.core.errors import Cancelled, InvalidInputError
from algorithms.embedding import sne, tsne
from algorithms.embedding import trustworthiness as package_trustworthiness
from algorithms.embedding._fft_gradients import FFTRepulsion, _kernels, _stencils, repulsion_fft
from algorithms.embedding._quality import _nearest_neighbors
from algorithms.embedding.tsne import (
    _calibrate,
    _exact_kl_gradient,
    _row_entropy,
    _SparseAttraction,
    affinities,
    initial_embedding,
)

DIGITS = load_digits().data


def _kl(p: np.ndarray, y: np.ndarray) -> float:
    """KL(P‖Q) over all pairs, by hand: the same formula for both embeddings compared."""
    d2 = ((y[:, None, :] - y[None, :, :]) ** 2).sum(-1)
    w = 1.0 / (1.0 + d2)
    np.fill_diagonal(w, 0.0)
    q = w / w.sum()
    m = p > 0
    return float((p[m] * np.log(p[m] / q[m])).sum())


def test_two_points_by_hand() -> None:
    # one neighbour each: p_{j|i} = 1, so p_12 = p_21 = 1/2 whatever the perplexity
    p = affinities(np.array([[0.0, 0.0], [3.0, 4.0]]), 0.5, dense=True)
    np.testing.assert_allclose(p, [[0.0, 0.5], [0.5, 0.0]])
    # KL = 0 at any embedding (q_12 = q_21 = 1/2 too) and the gradient vanishes
    kl, grad = _exact_kl_gradient(p, np.array([[0.0, 0.0], [1.0, 2.0]]))
    assert kl == pytest.approx(0.0, abs=1e-15)
    np.testing.assert_allclose(grad, 0.0, atol=1e-15)


@pytest.mark.parametrize("perplexity", [2.0, 5.0, 30.0])
def test_calibration_reaches_log_perplexity(perplexity: float) -> None:
    x = DIGITS[:400]
    d2 = ((x[:, None, :] - x[None, :, :]) ** 2).sum(-1)
    d2 = d2[~np.eye(400, dtype=bool)].reshape(400, 399)
    p, beta = _calibrate(d2, perplexity)
    np.testing.assert_allclose(p.sum(axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(_row_entropy(p), np.log(perplexity), atol=1e-5)
    # p_{j|i} ∝ exp(−β_i d²): the ratio of any two entries is the Gaussian's
    i, a, b = 7, 3, 11
    assert p[i, a] / p[i, b] == pytest.approx(np.exp(-beta[i] * (d2[i, a] - d2[i, b])))


def test_sparse_affinities_are_symmetric_and_on_the_nearest_neighbours() -> None:
    x = DIGITS[:300]
    p = affinities(x, 10.0, dense=False)
    assert abs(p - p.T).max() < 1e-15 and p.sum() == pytest.approx(1.0)
    assert (p.diagonal() == 0).all()
    # each row holds at least its 30 nearest neighbours (union with the reverse ones)
    d2 = ((x[:, None, :] - x[None, :, :]) ** 2).sum(-1)
    np.fill_diagonal(d2, np.inf)
    near = np.argsort(d2, axis=1)[:, :29]
    dense = p.toarray()
    assert (np.take_along_axis(dense, near, axis=1) > 0).all()
    assert p.nnz <= 2 * 30 * 300


@pytest.mark.parametrize("exaggeration", [1.0, 12.0])
def test_exact_gradient_matches_finite_differences(exaggeration: float) -> None:
    rng = np.random.default_rng(0)
    x = rng.normal(size=(25, 6))
    p = affinities(x, 5.0, dense=True)
    y = rng.normal(size=(25, 2))
    _, grad = _exact_kl_gradient(p, y, exaggeration)

    def cost(yy: np.ndarray) -> float:
        # −α Σ p log w + log Z: KL(P‖Q) up to a constant when α = 1; its gradient is
        # 4 Σ_j (α p_ij − q_ij) w_ij (y_i − y_j)
        d2 = ((yy[:, None] - yy[None]) ** 2).sum(-1)
        w = 1.0 / (1.0 + d2)
        np.fill_diagonal(w, 0.0)
        return exaggeration * float((p * np.log1p(d2)).sum()) + np.log(w.sum())

    h = 1e-6
    fd = np.zeros_like(y)
    for i in range(25):
        for k in range(2):
            e = np.zeros_like(y)
            e[i, k] = h
            fd[i, k] = (cost(y + e) - cost(y - e)) / (2 * h)
    np.testing.assert_allclose(grad, fd, rtol=1e-6, atol=1e-9)
    assert _exact_kl_gradient(p, y)[0] == pytest.approx(_kl(p, y), rel=1e-12)


@pytest.mark.parametrize("d, scale, tol", [(1, 1.0, 1e-3), (2, 1e-3, 1e-5), (2, 1.0, 1e-3),
                                           (2, 10.0, 3e-2)])
def test_fft_repulsion_matches_all_pairs(d: int, scale: float, tol: float) -> None:
    # two clumps; at scale 10 the points are sparse (a few units apart), the interpolation's
    # worst case: its error grows with the kernel's variation across a node spacing
    rng = np.random.default_rng(d)
    y = np.r_[rng.normal(size=(300, d)), rng.normal(size=(300, d)) + 4.0] * scale
    diff = y[:, None, :] - y[None, :, :]
    w = 1.0 / (1.0 + (diff ** 2).sum(-1))
    np.fill_diagonal(w, 0.0)
    rep_exact = ((w ** 2)[:, :, None] * diff).sum(1)
    rep, z = repulsion_fft(y)
    assert z == pytest.approx(w.sum(), rel=tol / 10)
    err = np.linalg.norm(rep - rep_exact) / np.linalg.norm(rep_exact)
    assert err < tol


@pytest.mark.parametrize("d, scale", [(1, 10.0), (1, 30.0), (2, 10.0), (2, 30.0)])
def test_fft_z_removes_each_points_own_term_on_the_grid(d: int, scale: float) -> None:
    # sparse points: the grid's interpolated self-interaction w_i^T K1 w_i is far from 1,
    # and Z = sum over pairs is small; subtracting n instead of those terms leaves Z off by
    # 2e-4 to 2e-2 here (measured), removing them by about 1e-4
    rng = np.random.default_rng(d)
    y = np.r_[rng.normal(size=(300, d)), rng.normal(size=(300, d)) + 4.0] * scale
    d2 = ((y[:, None, :] - y[None, :, :]) ** 2).sum(-1)
    w = 1.0 / (1.0 + d2)
    np.fill_diagonal(w, 0.0)
    assert repulsion_fft(y)[1] == pytest.approx(w.sum(), rel=3e-4)


@pytest.mark.parametrize("p", [3, 4, 5])
def test_fft_stencils_are_the_nearest_nodes_and_reproduce_polynomials(p: int) -> None:
    # positions in node spacings on a grid of 40 nodes: each stencil is p consecutive nodes
    # inside the grid, the position in its middle interval (or within half a spacing of the
    # middle node) unless the grid's end is nearer, and the weights reproduce 1, t, ..., t^(p-1)
    rng = np.random.default_rng(p)
    t = np.r_[rng.uniform(0.0, 39.0, 500), 0.0, 39.0, 0.3, 38.7]
    first, w = _stencils(t, p, 40)
    assert ((first >= 0) & (first + p <= 40)).all()
    inner = (t >= p) & (t <= 39 - p)
    centre = first[inner] + (p - 1) / 2
    assert (np.abs(t[inner] - centre) <= 0.5 + 1e-12).all()
    nodes = first[:, None] + np.arange(p)
    for j in range(p):
        np.testing.assert_allclose((w * nodes ** j).sum(1), t ** j, rtol=1e-10, atol=1e-9)


@pytest.mark.parametrize("d", [1, 2])
def test_fft_kernels_quarters_are_the_full_transforms(d: int) -> None:
    # the circulant grid of offsets built by hand (side m = 2N, zero at offset N), its
    # kernels transformed in double precision by rfftn: the quarter spectra kept in single
    # precision are their imaginary part (G) and real part (K1), the rest of the spectrum
    # the odd / even mirror, and G's second component the transpose of the first
    nodes, spacing = 12, 0.25
    m = 2 * nodes
    a = np.arange(m)
    off = np.where(a < nodes, a, a - m) * spacing
    grids = np.meshgrid(*([off] * d), indexing="ij")
    k1 = 1.0 / (1.0 + sum(g * g for g in grids))
    for axis in range(d):
        k1[(slice(None),) * axis + (nodes,)] = 0.0
    g_full = [np.fft.rfftn(k1 * k1 * g) for g in grids]
    k1_full = np.fft.rfftn(k1)
    g_q, w_q = _kernels(d, nodes, spacing)
    assert g_q.dtype == w_q.dtype == np.float32
    mult = np.full(nodes + 1, 2.0)
    mult[[0, -1]] = 1.0
    scale = mult / float(m) ** d
    for full in [*g_full, k1_full]:  # imaginary (odd G) and real (even K1) transforms
        part = full.real if full is k1_full else full.imag
        assert np.abs(full.imag if full is k1_full else full.real).max() < 1e-12
        assert np.abs(part).max() > 1.0
    if d == 1:
        np.testing.assert_allclose(g_q, g_full[0].imag, atol=2e-6 * np.abs(g_q).max())
        w = k1_full.real * scale
        np.testing.assert_allclose(w_q, w, atol=2e-6 * np.abs(w).max())
        return
    tol = 2e-6 * np.abs(g_full[0]).max()
    np.testing.assert_allclose(g_q, g_full[0].imag[:nodes + 1], atol=tol)
    np.testing.assert_allclose(-g_q[nodes - 1:0:-1], g_full[0].imag[nodes + 1:], atol=tol)
    np.testing.assert_allclose(g_q.T, g_full[1].imag[:nodes + 1], atol=tol)
    np.testing.assert_allclose(g_q.T[nodes - 1:0:-1], g_full[1].imag[nodes + 1:], atol=tol)
    w = k1_full.real * scale
    tol = 2e-6 * np.abs(w).max()
    np.testing.assert_allclose(w_q, w[:nodes + 1], atol=tol)
    np.testing.assert_allclose(w_q[nodes - 1:0:-1], w[nodes + 1:], atol=tol)


def test_fft_repulsion_keeps_one_grid_and_the_same_sums() -> None:
    # the cache of a run gives the sums of the uncached function; a grown embedding
    # (another grid) replaces the kept kernels, it does not add to them
    rng = np.random.default_rng(3)
    y = rng.normal(size=(500, 2))
    rep = FFTRepulsion()
    for scale in (1.0, 1.0, 40.0):
        got, z = rep(y * scale)
        want, z_want = repulsion_fft(y * scale)
        np.testing.assert_array_equal(got, want)
        assert z == z_want
    key = rep._key
    assert key is not None and key[1] > 200 and len(vars(rep)) == 2


@pytest.mark.parametrize("dim", [3, 20])
def test_nearest_neighbors_are_exact_and_sorted(dim: int) -> None:
    # kd-tree (3-D) and BLAS blocks (20-D) against a full sort; coincident points too
    rng = np.random.default_rng(dim)
    x = rng.normal(size=(300, dim))
    x[10] = x[11] = x[12]
    d2, nbr = _nearest_neighbors(x, 25)
    full = ((x[:, None, :] - x[None, :, :]) ** 2).sum(-1)
    np.fill_diagonal(full, np.inf)
    # the 25 smallest distances of each row, in order, and the points that have them
    np.testing.assert_allclose(d2, np.sort(full, axis=1)[:, :25], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(np.take_along_axis(full, nbr, axis=1), d2, rtol=1e-12,
                               atol=1e-12)
    assert (np.diff(d2, axis=1) >= 0).all() and (nbr != np.arange(300)[:, None]).all()
    assert all(len(set(row)) == 25 for row in nbr)
    assert list(nbr[10, :2]) == [11, 12] and d2[10, 0] == d2[10, 1] == 0.0


def test_nearest_neighbors_with_many_ties() -> None:
    # integer points in 12-D: many equal distances at the k-th place, so that the single
    # precision screen cannot prove its candidates and rows are redone in double
    x = np.random.default_rng(4).integers(0, 2, size=(400, 12)).astype(float)
    d2, nbr = _nearest_neighbors(x, 30)
    full = ((x[:, None, :] - x[None, :, :]) ** 2).sum(-1)
    np.fill_diagonal(full, np.inf)
    np.testing.assert_array_equal(d2, np.sort(full, axis=1)[:, :30])
    np.testing.assert_array_equal(np.take_along_axis(full, nbr, axis=1), d2)
    assert all(len(set(row)) == 30 for row in nbr)


def test_trustworthiness_from_neighbour_lists_matches_sklearn() -> None:
    # a poor embedding (random), so that many embedded neighbours lie beyond the lists
    x, _ = make_blobs(400, n_features=10, centers=4, random_state=5)
    rng = np.random.default_rng(2)
    for y in (rng.normal(size=(400, 2)), x[:, :2] + 0.3 * rng.normal(size=(400, 2))):
        for width in (5, 12, 60):
            d2, nbr = _nearest_neighbors(x, width)
            for k in (1, 5):
                lists = package_trustworthiness(x, y, n_neighbors=k, input_neighbours=(d2, nbr))
                assert lists == pytest.approx(trustworthiness(x, y, n_neighbors=k), abs=1e-12)
    # integer inputs: many distances tie with the threshold, decided in double precision;
    # the same count as the package's own function (rank = 1 + #{strictly closer})
    xi = np.random.default_rng(5).integers(0, 3, size=(300, 12)).astype(float)
    yi = rng.normal(size=(300, 2))
    d2, nbr = _nearest_neighbors(xi, 10)
    lists = package_trustworthiness(xi, yi, n_neighbors=5, input_neighbours=(d2, nbr))
    assert lists == pytest.approx(package_trustworthiness(xi, yi, n_neighbors=5), abs=1e-12)


def test_sparse_attraction_matches_dense(monkeypatch: pytest.MonkeyPatch) -> None:
    x = DIGITS[:200]
    p = affinities(x, 10.0, dense=False)
    y = np.random.default_rng(1).normal(size=(200, 2))
    att, plogw = _SparseAttraction(p)(y, True)
    monkeypatch.setattr(sys.modules["algorithms.embedding.tsne"], "_PAIR_CHUNK", 1000)
    att_chunks, plogw_chunks = _SparseAttraction(p)(y, True)
    # single precision (complex64) forces: the chunks change numpy's loops, not the sums'
    # order, and the results agree to float32's rounding
    scale = float(np.abs(att).max())
    np.testing.assert_allclose(att_chunks, att, rtol=1e-5, atol=1e-6 * scale)
    assert plogw_chunks == pytest.approx(plogw, rel=1e-12)
    pd = p.toarray()
    diff = y[:, None, :] - y[None, :, :]
    w = 1.0 / (1.0 + (diff ** 2).sum(-1))
    np.testing.assert_allclose(att, ((pd * w)[:, :, None] * diff).sum(1), rtol=1e-5,
                               atol=1e-6 * scale)
    assert plogw == pytest.approx(float((pd[pd > 0] * np.log(w[pd > 0])).sum()), rel=1e-6)


#: scikit-learn's exact t-SNE with every part of its schedule stated, so that the comparison
#: does not follow the installed version's defaults (``max_iter`` is ``n_iter`` before 1.5).
#: Its own start is not used: from 1.8 its PCA start is an exact SVD, before a randomized
#: one, and t-SNE is chaotic in its start (a relative change of 1e-9 in it moves the final
#: KL of one run on these points anywhere in 0.20-0.26, ours and scikit-learn's alike), so
#: one run against one run compares two draws, not two optimisers.
_PEER_SCHEDULE = {"method": "exact", "perplexity": 20.0, "early_exaggeration": 12.0,
                  "learning_rate": 50.0, "min_grad_norm": 1e-7,
                  "n_iter_without_progress": 1000,       # never: all 1000 steps run
                  ("max_iter" if "max_iter" in TSNE().get_params() else "n_iter"): 1000}
_STARTS = 12


@pytest.mark.slow
def test_exact_agrees_with_sklearn_exact() -> None:
    x = DIGITS[:150]
    p = affinities(x, 20.0, dense=True)          # the same P as scikit-learn's exact
    # our defaults (PCA start, 750 steps): a sound result, the KL the one of the embedding
    ours = tsne(x, method="exact", perplexity=20)
    assert ours.method == "exact" and ours.iterations <= 750
    # scikit-learn's function, up to ties of equal distances (digits are integers)
    assert ours.trustworthiness == pytest.approx(trustworthiness(x, ours.embedding), abs=1e-4)
    assert ours.kl_divergence == pytest.approx(_kl(p, ours.embedding), rel=1e-9)
    # the two optimisers on equal terms: the same starts (ours from each seed, given to
    # scikit-learn as its init), the same schedule (250 exaggerated steps of 12 with
    # momentum 0.5, then 0.8; step 50 throughout, which is also both "auto"s at n = 150;
    # 1000 steps in all), and the mean KL over the starts
    kl_ours, kl_peer, kl_peer_own, t_ours, t_peer = [], [], [], [], []
    for seed in range(_STARTS):
        run = tsne(x, method="exact", perplexity=20, init="random", seed=seed,
                   learning_rate=50.0, early_exaggeration=12.0, exaggeration_iterations=250,
                   max_iterations=1000, min_grad_norm=1e-7)
        start = initial_embedding(x, 2, "random", np.random.default_rng(seed))
        with threadpool_limits(1):
            peer = TSNE(init=start, **_PEER_SCHEDULE).fit(x)
        assert run.iterations == 1000 and peer.n_iter_ == 999     # its last step's index
        kl_ours.append(run.kl_divergence)
        kl_peer.append(_kl(p, peer.embedding_))
        kl_peer_own.append(peer.kl_divergence_)
        t_ours.append(run.trustworthiness)
        t_peer.append(trustworthiness(x, peer.embedding_, n_neighbors=5))
    assert np.mean(kl_ours) <= 1.03 * np.mean(kl_peer)
    assert np.mean(kl_ours) <= 1.03 * np.mean(kl_peer_own)
    assert np.mean(t_ours) >= np.mean(t_peer) - 0.005
    assert ours.trustworthiness >= np.mean(t_peer) - 0.005


def test_fft_agrees_with_sklearn_barnes_hut() -> None:
    x, _ = make_blobs(400, n_features=20, centers=6, cluster_std=3.0, random_state=1)
    ours = tsne(x, method="fft", max_iterations=500)
    with threadpool_limits(1):      # scikit-learn's OpenMP threads spin on a busy machine
        peer = TSNE(method="barnes_hut", init="pca", max_iter=500, random_state=0).fit(x)
    p = affinities(x, 30.0, dense=False).toarray()   # the kNN P both optimise
    t_peer = trustworthiness(x, peer.embedding_, n_neighbors=5)
    assert ours.method == "fft"
    assert ours.trustworthiness >= t_peer - 0.005
    kl_ours = _kl(p, ours.embedding)
    assert ours.kl_divergence == pytest.approx(kl_ours, rel=0.01)   # interpolated Z
    assert kl_ours <= 1.03 * _kl(p, peer.embedding_)


def test_same_seed_same_embedding_signs_fixed_and_progress() -> None:
    x, _ = make_blobs(120, n_features=5, centers=3, random_state=2)
    seen: list[tuple] = []
    a = tsne(x, init="random", seed=4, max_iterations=120, exaggeration_iterations=60,
             progress=lambda *m: seen.append(m))
    b = tsne(x, init="random", seed=4, max_iterations=120, exaggeration_iterations=60)
    c = tsne(x, init="random", seed=5, max_iterations=120, exaggeration_iterations=60)
    assert np.array_equal(a.embedding, b.embedding)
    assert not np.array_equal(a.embedding, c.embedding)
    assert seen[0][0] == 0 and seen[-1][:2] == (120, 120) and len(seen) == 121
    assert "KL" in seen[50][2]
    big = np.abs(a.embedding).argmax(axis=0)
    assert (a.embedding[big, [0, 1]] > 0).all()
    np.testing.assert_allclose(a.embedding.mean(axis=0), 0.0, atol=1e-9)
    f1 = tsne(x, method="fft", max_iterations=60, exaggeration_iterations=30)
    f2 = tsne(x, method="fft", max_iterations=60, exaggeration_iterations=30)
    assert np.array_equal(f1.embedding, f2.embedding)


def test_cancel_and_one_dimension() -> None:
    x, _ = make_blobs(600, n_features=4, centers=3, random_state=3)

    def stop(done, total, message=""):  # noqa: ANN001, ANN202
        if done >= 5:
            raise Cancelled("stop")

    with pytest.raises(Cancelled):
        tsne(x, progress=stop)
    one = tsne(x, n_components=1, max_iterations=300, exaggeration_iterations=100)
    assert one.method == "fft" and one.embedding.shape == (600, 1)
    assert one.trustworthiness > 0.85
    three = tsne(x[:100], n_components=3, max_iterations=200)
    assert three.method == "exact" and three.embedding.shape == (100, 3)


@pytest.mark.parametrize("kwargs, field, match", [
    ({"perplexity": 40}, "perplexity", "below the number of `points` \\(40\\)"),
    ({"perplexity": 0}, "perplexity", "perplexity"),
    ({"method": "barnes"}, "method", "'exact'"),
    ({"method": "fft", "n_components": 3}, "n_components", "<= 2"),
    ({"init": "spectral"}, "init", "'pca'"),
    ({"learning_rate": -1.0}, "learning_rate", "learning_rate"),
    ({"learning_rate": "fast"}, "learning_rate", "'auto'"),
    ({"learning_rate": None}, "learning_rate", "a number > 0 or one of 'auto'"),
    ({"max_iterations": 0}, "max_iterations", ">= 1"),
    ({"early_exaggeration": 0.5}, "early_exaggeration", ">= 1"),
])
def test_bad_parameters(kwargs: dict, field: str, match: str) -> None:
    x = np.random.default_rng(0).normal(size=(40, 3))
    with pytest.raises(InvalidInputError, match=match) as err:
        tsne(x, **kwargs)
    assert err.value.field == field


def test_bad_points_and_too_many_for_exact() -> None:
    with pytest.raises(InvalidInputError, match="row 1") as err:
        tsne([[0.0, 0.0], [np.nan, 1.0], [2.0, 2.0]], perplexity=1)
    assert err.value.field == "points"
    with pytest.raises(InvalidInputError, match="at least 2") as err:
        tsne([[0.0, 0.0]], perplexity=0.5)
    with pytest.raises(InvalidInputError, match="5,000") as err:
        tsne(np.zeros((5001, 2)), method="exact")
    assert err.value.field == "method"
    # "auto" takes the exact gradient for 3 dimensions: the dimension is what to change
    with pytest.raises(InvalidInputError, match="n_components.*<= 2 for 5,001") as err:
        tsne(np.zeros((5001, 2)), n_components=3)
    assert err.value.field == "n_components"


# -- the same bits whatever the memory layout ------------------------------------------------
# A view at an odd byte offset (as an array unpickled from a network frame in a Dask worker),
# a view of a protocol-5 pickle buffer, Fortran order, strided views, nested lists. A
# misaligned input once changed the last bits of ``x @ x.T`` (numpy then calls BLAS ``gemm``
# on per-operand copies instead of ``syrk``), hence of ``P``, and the descent amplified them
# to differences of order 1 in the embedding: the service's answer was not the library's.

LAYOUT_BLOBS = make_blobs(60, n_features=5, centers=3, random_state=0)[0]
LAYOUT_FAST = {"perplexity": 8, "max_iterations": 120, "exaggeration_iterations": 50}


def _at_offset(a: np.ndarray, offset: int) -> np.ndarray:
    """A copy of ``a`` in a buffer ``offset`` bytes past a 64-byte boundary."""
    buf = np.zeros(a.nbytes + 128, dtype=np.uint8)
    start = (-buf.ctypes.data) % 64 + offset
    v = np.frombuffer(buf, dtype=a.dtype, count=a.size, offset=start).reshape(a.shape)
    v[...] = a
    return v


def _unpickled_at_offset(a: np.ndarray, offset: int) -> np.ndarray:
    """``a`` through a protocol-5 pickle whose out-of-band buffer sits ``offset`` bytes into
    a frame (as the service's Dask worker receives a job's inputs)."""
    buffers: list[pickle.PickleBuffer] = []
    stream = pickle.dumps(a, protocol=5, buffer_callback=buffers.append)
    raw = buffers[0].raw()
    frame = bytearray(offset + raw.nbytes)
    frame[offset:] = raw
    return pickle.loads(stream, buffers=[memoryview(frame)[offset:]])


def _layouts(x: np.ndarray) -> dict[str, object]:
    wide = np.repeat(x, 2, axis=1)
    tall = np.repeat(x, 2, axis=0)
    out: dict[str, object] = {f"offset {o}": _at_offset(x, o) for o in (1, 3, 4, 7, 8, 40)}
    out.update({"pickle frame +3": _unpickled_at_offset(x, 3),
                "fortran": np.asfortranarray(x), "strided columns": wide[:, ::2],
                "strided rows": tall[::2], "list": x.tolist()})
    return out


def test_the_layouts_are_what_they_claim() -> None:
    lay = _layouts(LAYOUT_BLOBS)
    for name in ("offset 1", "offset 3", "offset 7", "pickle frame +3"):
        assert not lay[name].flags.aligned, name
    assert lay["offset 8"].flags.aligned and lay["offset 40"].flags.aligned
    for name, x in lay.items():
        np.testing.assert_array_equal(x, LAYOUT_BLOBS, err_msg=name)


def test_dense_affinities_do_not_depend_on_the_layout() -> None:
    ref = affinities(LAYOUT_BLOBS, 8.0, dense=True)
    for name, x in _layouts(LAYOUT_BLOBS).items():
        if isinstance(x, np.ndarray):
            np.testing.assert_array_equal(affinities(x, 8.0, dense=True), ref, err_msg=name)


@pytest.mark.parametrize("function, inputs", [
    (sne, {}),
    (tsne, {"method": "exact"}),
    (tsne, {"method": "exact", "n_components": 1, "learning_rate": 20.0}),
    (tsne, {"method": "fft", "init": "random", "seed": 2}),
])
def test_same_bits_whatever_the_layout(function, inputs) -> None:  # noqa: ANN001
    ref = function(LAYOUT_BLOBS, **LAYOUT_FAST, **inputs)
    for name, x in _layouts(LAYOUT_BLOBS).items():
        res = function(x, **LAYOUT_FAST, **inputs)
        np.testing.assert_array_equal(res.embedding, ref.embedding, err_msg=name)
        assert res.kl_divergence == ref.kl_divergence, name
        assert res.trustworthiness == ref.trustworthiness, name
        assert res.iterations == ref.iterations, name
