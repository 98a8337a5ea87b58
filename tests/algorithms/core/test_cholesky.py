"""The multifrontal Cholesky (algorithms.core.cholesky) against the definition and against
SciPy: ``P A Pᵀ = L Lᵀ`` rebuilt from the supernodes' blocks, solves against SuperLU and
dense LAPACK, the nested-dissection order a permutation that cuts fill, and a matrix that is
not positive definite refused."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from algorithms.core.cholesky import NotPositiveDefinite, SparseCholesky, nested_dissection
from algorithms.core.laplacian import cotangent_laplacian
from tests.algorithms.core.test_linsolve import grid


def _grid_laplacian(k: int, shift: float = 1e-2) -> sp.csc_array:
    e = np.ones(k)
    t = sp.diags_array([-e[:-1], 2 * e, -e[:-1]], offsets=[-1, 0, 1])
    i = sp.eye_array(k)
    return sp.csc_array(sp.kron(t, i) + sp.kron(i, t) + shift * sp.eye_array(k * k))


def _random_spd(n: int, density: float, seed: int) -> sp.csc_array:
    """A weighted graph Laplacian plus a random positive diagonal: SPD, random pattern
    (possibly disconnected)."""
    rng = np.random.default_rng(seed)
    w = sp.random_array((n, n), density=density, rng=rng)
    w = sp.triu(w, 1)
    w = w + w.T
    lap = sp.diags_array(np.asarray(w.sum(axis=1)).ravel()) - w
    return sp.csc_array(lap + sp.diags_array(rng.uniform(0.01, 1.0, n)))


def _mesh(nx: int, ny: int) -> sp.csc_array:
    v, f = grid(nx, ny)
    lap = cotangent_laplacian(v, f)
    return sp.csc_array(lap + 1e-3 * sp.eye_array(lap.shape[0]))


CASES = {
    "one": sp.csc_array(np.array([[4.0]])),
    "two": sp.csc_array(np.array([[4.0, 1.0], [1.0, 3.0]])),
    "path": sp.csc_array(
        sp.diags_array([-np.ones(199), 2.5 * np.ones(200), -np.ones(199)], offsets=[-1, 0, 1])),
    "star": sp.csc_array(sp.eye_array(150) * 200.0 + sp.coo_array(
        (-np.ones(298), (np.r_[np.zeros(149), np.arange(1, 150)].astype(int),
                         np.r_[np.arange(1, 150), np.zeros(149)].astype(int))),
        shape=(150, 150))),
    "grid 30": _grid_laplacian(30),
    "mesh 40x35": _mesh(40, 35),
    "random sparse": _random_spd(400, 0.01, 1),
    "random, disconnected": _random_spd(300, 0.002, 2),
    "dense": _random_spd(120, 0.5, 3),
}


@pytest.mark.parametrize("name", list(CASES))
def test_the_factor_is_the_matrix(name):
    a = CASES[name]
    f = SparseCholesky(a)
    assert np.array_equal(np.sort(f.perm), np.arange(a.shape[0]))
    low = f.factor()
    assert np.all(low.tocoo().row >= low.tocoo().col)            # lower triangular
    assert np.all(low.diagonal() > 0)
    pa = a.toarray()[np.ix_(f.perm, f.perm)]
    rebuilt = (low @ low.T).toarray()
    assert np.abs(rebuilt - pa).max() <= 1e-13 * np.abs(pa).max()
    # the dense Cholesky of the same permuted matrix: the same factor
    assert np.abs(low.toarray() - la.cholesky(pa, lower=True)).max() <= \
        1e-12 * np.abs(pa).max() ** 0.5


@pytest.mark.parametrize("name", list(CASES))
def test_solves_agree_with_superlu(name):
    a = CASES[name]
    n = a.shape[0]
    rng = np.random.default_rng(7)
    b = rng.normal(size=(n, 3))
    x = SparseCholesky(a).solve(b)
    ref = sla.splu(sp.csc_matrix(a)).solve(b)
    scale = np.abs(ref).max()
    assert np.abs(x - ref).max() <= 1e-10 * scale
    assert np.abs(a @ x - b).max() <= 1e-12 * np.abs(b).max() * max(1.0, np.abs(a).max())
    one = SparseCholesky(a).solve(b[:, 0])                      # a vector in, a vector out
    assert one.shape == (n,) and np.allclose(one, x[:, 0], rtol=0, atol=1e-12 * scale)


def test_nested_dissection_is_a_permutation_that_cuts_the_fill():
    a = _grid_laplacian(60)
    order = nested_dissection(a)
    assert np.array_equal(np.sort(order), np.arange(a.shape[0]))
    ours = SparseCholesky(a).factor().nnz
    # the natural order of a k × k grid: a band of width k, k·k·k entries or so
    natural = sla.splu(sp.csc_matrix(a), permc_spec="NATURAL", diag_pivot_thresh=0.0,
                       options={"SymmetricMode": True}).L.nnz
    assert ours < 0.5 * natural
    # and about SuperLU's own minimum degree order (its L, the same matrix)
    mmd = sla.splu(sp.csc_matrix(a), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                   options={"SymmetricMode": True}).L.nnz
    assert ours < 1.5 * mmd


def test_not_positive_definite_is_refused():
    a = _grid_laplacian(12).toarray()
    a[5, 5] = -1.0
    with pytest.raises(NotPositiveDefinite):
        SparseCholesky(sp.csc_array(a))
    indefinite = sp.csc_array(np.array([[1.0, 2.0], [2.0, 1.0]]))
    with pytest.raises(NotPositiveDefinite):
        SparseCholesky(indefinite)


def test_only_the_lower_triangle_is_read():
    a = CASES["mesh 40x35"]
    b = np.random.default_rng(3).normal(size=(a.shape[0], 2))
    full = SparseCholesky(a).solve(b)
    upper_garbage = sp.csc_array(sp.tril(a) + 5.0 * sp.triu(sp.random_array(
        a.shape, density=0.01, rng=np.random.default_rng(4)), 1))
    assert np.array_equal(SparseCholesky(sp.tril(a)).solve(b), full)
    assert np.array_equal(SparseCholesky(upper_garbage).solve(b), full)
    assert np.array_equal(nested_dissection(sp.tril(a)), nested_dissection(a))


def test_the_postordered_tree_is_the_tree_relabelled():
    """The factorization computes the elimination tree once, in the dissection's order,
    and relabels it after postordering: the tree of the final order, computed afresh, is
    the same."""
    from algorithms.core import cholesky as ch

    a = CASES["mesh 40x35"]
    g = sp.csc_array(a)
    n = g.shape[0]
    ptr, adj = ch._adjacency(n, g.indptr.astype(np.int64), g.indices.astype(np.int64))
    f = SparseCholesky(a)
    inverse = np.empty(n, np.int64)
    inverse[f.perm] = np.arange(n)
    tree = ch._etree(n, ptr, adj, f.perm, inverse)
    first = f._first
    # each supernode's columns chain up the tree, and its last column's parent is the
    # first column of a later supernode's run or a root
    for s in range(first.shape[0] - 1):
        cols = np.arange(first[s], first[s + 1])
        assert np.all(tree[cols[:-1]] == cols[1:])
    assert np.all((tree == -1) | (tree > np.arange(n)))
    # and it is the factor's tree: a column's parent is its first entry below the diagonal
    low = f.factor().tocsc()
    low.sort_indices()
    for j in range(n):
        below = low.indices[low.indptr[j]:low.indptr[j + 1]]
        below = below[below > j]
        assert tree[j] == (below[0] if below.size else -1)


@pytest.mark.parametrize("where", ["diagonal", "off-diagonal"])
def test_a_nan_is_refused_not_factored(where):
    """A NaN anywhere reaches a later pivot (every entry of L below the diagonal updates
    its row's pivot), and a NaN pivot is not positive: refused, as an indefinite matrix
    is, rather than a factor of NaNs."""
    a = _grid_laplacian(12).toarray()
    if where == "diagonal":
        a[7, 7] = np.nan
    else:
        a[7, 8] = a[8, 7] = np.nan
    with pytest.raises(NotPositiveDefinite):
        SparseCholesky(sp.csc_array(a))
