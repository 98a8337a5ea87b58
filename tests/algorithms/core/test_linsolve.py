"""Tests for algorithms.core.linsolve: Factor (every backend) and PinnedSystem.

CHOLMOD (cvxopt, GPL-3.0) is an optional extra: the tests of every backend run it when cvxopt
is installed (the test extra installs it) and report it skipped when not, and the default
install's path, without cvxopt, is tested on its own in a subprocess that hides it.
"""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
import textwrap
from pathlib import Path

import igl
import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as sla
import trimesh

from algorithms.core import DegenerateInputError, InvalidInputError, linsolve
from algorithms.core.laplacian import cotangent_laplacian, mesh_laplacian
from algorithms.core.linsolve import BACKENDS, Factor, PinnedSystem, available_backends
from algorithms.core.mesh import boundary_loops


def grid(nx: int = 12, ny: int = 10, jitter: float = 0.3, seed: int = 0):
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.linspace(0, 1, nx), np.linspace(0, 1, ny))
    v = np.c_[x.ravel(), y.ravel()]
    inner = (x.ravel() > 0) & (x.ravel() < 1) & (y.ravel() > 0) & (y.ravel() < 1)
    v[inner] += rng.uniform(-jitter, jitter, (inner.sum(), 2)) / nx
    idx = np.arange(nx * ny).reshape(ny, nx)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    return v, np.r_[np.c_[a, b, d], np.c_[a, d, c]].astype(np.int64)


def spd(n: int = 60, seed: int = 0) -> sp.csr_array:
    v, f = grid(10, 6, seed=seed)
    L = cotangent_laplacian(v, f)
    return (L + sp.eye_array(L.shape[0]) * 1e-2).tocsr()


HAVE_CVXOPT = importlib.util.find_spec("cvxopt") is not None
#: every backend; CHOLMOD reported as skipped (not passed) without the cholmod extra
EVERY_BACKEND = [pytest.param(b, marks=pytest.mark.skipif(
    b == "cholmod" and not HAVE_CVXOPT, reason="cvxopt (the cholmod extra) not installed"))
    for b in BACKENDS]
ROOT = Path(__file__).resolve().parents[3]


def test_installed_backends():
    # SuperLU is always there; the two CHOLMODs exactly when their packages are (the test
    # extra installs both)
    assert available_backends() == tuple(b for b in BACKENDS if b != "cholmod" or HAVE_CVXOPT)
    assert {"superlu", "cholespy"} <= set(available_backends())


def test_backend_orders():
    # bench/linsolve.py: CHOLMOD factors fastest, so it leads when installed; then our
    # multifrontal Cholesky, then SuperLU, then cholespy; cholespy solves fastest, then
    # SuperLU, then the multifrontal Cholesky, then CHOLMOD
    assert BACKENDS == ("cholmod", "multifrontal", "superlu", "cholespy")
    assert linsolve.SOLVE_ORDER == ("cholespy", "superlu", "multifrontal", "cholmod")


@pytest.mark.parametrize("backend", EVERY_BACKEND)
def test_factor_solves_like_spsolve(backend):
    A = spd()
    rng = np.random.default_rng(1)
    b1 = rng.standard_normal(A.shape[0])
    b3 = rng.standard_normal((A.shape[0], 3))
    f = Factor(A, backend=backend)
    assert f.backend == backend and f.shape == A.shape
    x1 = f.solve(b1)
    x3 = f.solve(b3)
    assert x1.shape == b1.shape and x3.shape == b3.shape
    np.testing.assert_allclose(x1, sla.spsolve(A.tocsc(), b1), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(x3, sla.spsolve(A.tocsc(), b3), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(f.solve(b3[:, 1]), x3[:, 1], rtol=1e-12, atol=1e-14)
    assert backend in repr(f)


def test_factor_auto_takes_the_first_backend():
    first = "cholmod" if HAVE_CVXOPT else "superlu"
    assert Factor(spd()).backend == first
    # below the break-even count the fast factorization wins, from it the fast solves
    assert Factor(spd(), solves=linsolve.BREAK_EVEN[first] - 1).backend == first
    assert Factor(spd(), solves=linsolve.BREAK_EVEN[first]).backend == linsolve.SOLVE_ORDER[0]
    assert PinnedSystem(spd(), [0], solves=1000).factor.backend == "cholespy"


def test_break_even_counts_follow_the_measured_table():
    # the module docstring's rows (factor s, solve of 3 rhs ms) at 50k and 200k vertices:
    # factor + k solves, cholespy is the cheaper from k = (Δ factor) / (Δ solve)
    # (columns: factor cholmod 3, multifrontal 4, superlu 5, cholespy 6; solve 7-10)
    table = linsolve.__doc__.split("system           unknowns")[1].split("(cvxopt")[0]
    rows = [line.split() for line in table.strip().splitlines()[1:]]
    assert len(rows) == 9
    for name, fac, sol, fast_fac, fast_sol in (("cholmod", 3, 7, 6, 10),
                                               ("superlu", 5, 9, 6, 10),
                                               ("multifrontal", 4, 8, 5, 9)):
        # the multifrontal Cholesky against the first installed of SOLVE_ORDER after
        # cholespy (which comes with cvxopt, and CHOLMOD leads then): SuperLU
        counts = []
        for r in rows:
            if r[1] == "5k":
                continue
            gain = float(r[fast_fac]) - float(r[fac])
            loss = (float(r[sol]) - float(r[fast_sol])) / 1e3
            counts.append(max(gain / loss, 0.0) if loss > 0 else np.inf)  # inf: never
        assert min(counts) <= linsolve.BREAK_EVEN[name] <= np.median(counts) + 1, (name, counts)


@pytest.mark.parametrize("backend", EVERY_BACKEND)
def test_zero_columns_are_not_solved(backend):
    A = spd()
    b = np.random.default_rng(6).standard_normal((A.shape[0], 3))
    b[:, 1] = 0.0
    f = Factor(A, backend=backend)
    seen = []
    solve = f._impl.solve
    f._impl.solve = lambda rhs: seen.append(rhs.shape) or solve(rhs)
    x = f.solve(b)
    assert seen == [(A.shape[0], 2)]                      # only the two live columns
    assert np.all(x[:, 1] == 0.0)
    np.testing.assert_allclose(x, sla.spsolve(A.tocsc(), b), rtol=1e-10, atol=1e-12)
    assert np.all(f.solve(np.zeros((A.shape[0], 2))) == 0.0) and len(seen) == 1


def test_factor_accepts_dense_and_fortran_rhs():
    A = np.array([[4.0, 1.0], [1.0, 3.0]])
    b = np.asfortranarray(np.array([[1.0, 0.0], [2.0, 1.0]]))
    for backend in available_backends():
        np.testing.assert_allclose(Factor(A, backend=backend).solve(b), np.linalg.solve(A, b))


@pytest.mark.parametrize("backend", [p for p in EVERY_BACKEND if p.values[0] != "superlu"])
def test_indefinite_matrix_falls_back_to_superlu(backend):
    A = sp.csr_array(np.array([[1.0, 2.0], [2.0, 1.0]]))
    f = Factor(A, backend=backend)
    assert f.backend == "superlu"
    np.testing.assert_allclose(f.solve(np.array([3.0, 3.0])), [1.0, 1.0])


def test_factor_needing_pivoting_uses_pivoting_superlu():
    A = sp.csr_array(np.array([[0.0, 1.0], [1.0, 0.0]]))
    np.testing.assert_allclose(Factor(A).solve(np.array([2.0, 5.0])), [5.0, 2.0])


@pytest.mark.parametrize("backend", ["auto", "superlu"])
def test_singular_matrix_is_a_degenerate_input(backend):
    A = sp.csr_array(np.array([[1.0, -1.0], [-1.0, 1.0]]))
    with pytest.raises(DegenerateInputError, match=r"`L` to be non-singular, got a singular "
                       r"2×2 matrix\.") as info:
        Factor(A, backend=backend, name="L")
    assert info.value.field == "L"


def test_factor_rejects_non_square_and_bad_rhs():
    with pytest.raises(InvalidInputError, match=r"`A` to be a square \(n, n\) matrix, got shape "
                       r"\(2, 3\)\."):
        Factor(np.zeros((2, 3)))
    f = Factor(np.eye(3))
    with pytest.raises(InvalidInputError, match=r"`b` to have shape \(3,\) or \(3, k\), got "
                       r"\(4,\)\."):
        f.solve(np.ones(4))
    with pytest.raises(InvalidInputError, match=r"got \(3, 1, 1\)"):
        f.solve(np.ones((3, 1, 1)))


def test_factor_rejects_unknown_backend():
    with pytest.raises(InvalidInputError, match=r"`backend` to be one of 'auto', 'cholmod', "
                       r"'multifrontal', 'superlu', 'cholespy', got 'pardiso'\."):
        Factor(np.eye(2), backend="pardiso")


def test_factor_rejects_uninstalled_backend(monkeypatch):
    monkeypatch.setattr(linsolve, "available_backends", lambda: ("superlu",))
    with pytest.raises(InvalidInputError, match=r"installed solver backend \(superlu\), got "
                       r"'cholmod' \(to install it: pip install 'morphserve\[cholmod\]' "
                       r"\(cvxopt, GPL-3\.0\)\)\.") as info:
        Factor(np.eye(2), backend="cholmod")
    assert info.value.field == "backend"
    assert Factor(np.eye(2)).backend == "superlu"


def hermitian(seed: int = 0) -> sp.csr_array:
    """A complex Hermitian positive definite matrix on the grid's pattern: the SPD one plus
    ``iS + D``, ``S`` antisymmetric and ``D`` the diagonal of its rows' absolute sums (so
    ``iS + D`` is diagonally dominant: positive semidefinite)."""
    A = spd(seed=seed)
    rng = np.random.default_rng(seed)
    up = sp.triu(A, k=1).tocoo()
    R = sp.coo_array((rng.uniform(-0.5, 0.5, up.nnz) * np.abs(up.data), (up.row, up.col)),
                     shape=A.shape)
    S = (R - R.T).tocsr()
    return (A + 1j * S + sp.diags_array(abs(S).sum(axis=1))).tocsr()


@pytest.mark.parametrize("backend", [p for p in EVERY_BACKEND
                                     if p.values[0] not in ("cholespy", "multifrontal")])
def test_factor_solves_complex_hermitian_systems(backend):
    H = hermitian()
    dense = H.toarray()
    assert np.allclose(dense, dense.conj().T) and np.linalg.eigvalsh(dense)[0] > 0
    rng = np.random.default_rng(2)
    b = rng.standard_normal((H.shape[0], 3)) + 1j * rng.standard_normal((H.shape[0], 3))
    f = Factor(H, backend=backend)
    assert f.backend == backend and f.dtype == np.complex128
    x = f.solve(b)
    assert x.dtype == np.complex128
    np.testing.assert_allclose(x, np.linalg.solve(dense, b), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(f.solve(b[:, 0]), x[:, 0], rtol=1e-12, atol=1e-14)
    # a real right-hand side of a complex matrix: the complex solution
    np.testing.assert_allclose(f.solve(b.real), np.linalg.solve(dense, b.real), rtol=1e-10,
                               atol=1e-12)


def test_complex_system_equals_its_real_form():
    # K = P + iR Hermitian <-> Q = [[P, -R], [R, P]]: K z = b_x + i b_y iff Q [x; y] = [b_x; b_y]
    H = hermitian(seed=3)
    Q = sp.block_array([[H.real, -H.imag], [H.imag, H.real]]).tocsc()
    n = H.shape[0]
    b = np.random.default_rng(4).standard_normal((2 * n, 2))
    z = Factor(H).solve(b[:n] + 1j * b[n:])
    x = sla.spsolve(Q, b)
    np.testing.assert_allclose(np.r_[z.real, z.imag], x, rtol=1e-10, atol=1e-12)


def test_auto_and_solves_skip_cholespy_for_complex_matrices():
    H = hermitian()
    first = "cholmod" if HAVE_CVXOPT else "superlu"
    assert Factor(H).backend == first
    assert Factor(H, solves=10_000).backend == first     # cholespy factors real matrices only
    with pytest.raises(InvalidInputError, match=r"`backend` to be one that factors complex "
                       r"Hermitian matrices \((cholmod, )?superlu\), got 'cholespy'\.") as info:
        Factor(H, backend="cholespy")
    assert info.value.field == "backend"


def test_real_factor_solves_a_complex_right_hand_side():
    A = spd()
    rng = np.random.default_rng(5)
    b = rng.standard_normal((A.shape[0], 2)) + 1j * rng.standard_normal((A.shape[0], 2))
    for backend in available_backends():
        f = Factor(A, backend=backend)
        assert f.dtype == np.float64
        x = f.solve(b)
        assert x.dtype == np.complex128 and x.shape == b.shape
        np.testing.assert_allclose(x, np.linalg.solve(A.toarray(), b), rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(f.solve(b[:, 1]), x[:, 1], rtol=1e-12, atol=1e-14)


def test_empty_factor():
    f = Factor(sp.csr_array((0, 0)))
    assert f.solve(np.zeros((0, 2))).shape == (0, 2)
    z = f.solve(np.zeros((0, 2), dtype=complex))
    assert z.shape == (0, 2) and z.dtype == np.complex128
    assert Factor(sp.csr_array((0, 0), dtype=complex)).solve(np.zeros(0)).dtype == np.complex128


# --- PinnedSystem -------------------------------------------------------------------------


def test_pinned_path_by_hand():
    L = sp.csr_array([[1.0, -1, 0], [-1, 2, -1], [0, -1, 1]])
    ps = PinnedSystem(L, [0, 2])
    assert ps.free.tolist() == [1] and ps.pinned.tolist() == [0, 2]
    np.testing.assert_allclose(ps.solve([[0.0], [1.0]]), [[0.0], [0.5], [1.0]])
    np.testing.assert_allclose(ps.solve([0.0, 1.0]), [0.0, 0.5, 1.0])
    # with a source term: x1 = (b1 + 0 + 1) / 2
    np.testing.assert_allclose(ps.solve([0.0, 1.0], rhs=[9.0, 3.0, 9.0]), [0.0, 2.0, 1.0])


def test_pinned_complex_system_by_hand():
    # the path 0 - 1 - 2 with its ends pinned to 0 and 1 + 2i: the middle lands half-way;
    # with a Hermitian coupling i/4 on the edge 0 -> 1, row 1 reads
    # (-1 - i/4) z0 + 2 x1 - z2 = 0
    L = sp.csr_array([[1.0, -1, 0], [-1, 2, -1], [0, -1, 1]])
    ps = PinnedSystem(L, [0, 2])
    np.testing.assert_allclose(ps.solve([0.0, 1.0 + 2.0j]), [0.0, 0.5 + 1.0j, 1.0 + 2.0j])
    H = L + 1j * sp.csr_array([[0.0, 0.25, 0], [-0.25, 0, 0], [0, 0, 0]])
    hs = PinnedSystem(H, [0, 2])
    z0, z2 = 2.0 - 1.0j, 1.0 + 2.0j
    got = hs.solve([z0, z2])
    assert got.dtype == np.complex128 and got[0] == z0 and got[2] == z2
    np.testing.assert_allclose(got[1], ((1 + 0.25j) * z0 + z2) / 2, rtol=1e-14)
    np.testing.assert_allclose(hs.solve([[z0], [z2]], rhs=[[0.0], [4.0j], [0.0]])[1, 0],
                               ((1 + 0.25j) * z0 + z2 + 4.0j) / 2, rtol=1e-14)


@pytest.mark.parametrize("backend", EVERY_BACKEND)
def test_harmonic_interpolation_matches_igl(backend):
    v, f = grid()
    v3 = np.c_[v, np.zeros(len(v))]
    b = boundary_loops(f)[0]
    rng = np.random.default_rng(2)
    c = rng.standard_normal((len(b), 2))
    ours = PinnedSystem(cotangent_laplacian(v, f), b, backend=backend).solve(c)
    ref = igl.harmonic(v3, f, b.astype(np.int64), c, 1)
    np.testing.assert_allclose(ours, ref, atol=1e-10)
    np.testing.assert_array_equal(ours[b], c)                  # pins met exactly


def test_cotangent_pinned_system_reproduces_linear_functions():
    v, f = grid()
    b = boundary_loops(f)[0]
    g = v @ np.array([[2.0, -1.0], [0.5, 3.0]]) + 0.25
    out = PinnedSystem(cotangent_laplacian(v, f), b).solve(g[b])
    np.testing.assert_allclose(out, g, atol=1e-11)


def test_rhs_enters_the_free_rows():
    v, f = grid(6, 5)
    L = mesh_laplacian(v, f, "tangent")
    pins = np.array([0, 7, 29])
    ps = PinnedSystem(L, pins)
    rng = np.random.default_rng(0)
    c, rhs = rng.standard_normal((3, 2)), rng.standard_normal((len(v), 2))
    x = ps.solve(c, rhs)
    residual = (L @ x - rhs)[ps.free]
    np.testing.assert_allclose(residual, 0, atol=1e-10)
    np.testing.assert_array_equal(x[pins], c)


def test_backends_agree():
    v, f = grid()
    L = cotangent_laplacian(v, f)
    pins = [0, 50, 119]
    c = np.random.default_rng(3).standard_normal((3, 3))
    backends = available_backends()
    assert len(backends) >= 2
    sols = [PinnedSystem(L, pins, backend=b).solve(c) for b in backends]
    for s in sols[1:]:
        np.testing.assert_allclose(s, sols[0], atol=1e-10)


def test_every_vertex_pinned():
    L = sp.csr_array([[1.0, -1], [-1, 1]])
    np.testing.assert_array_equal(PinnedSystem(L, [1, 0]).solve([[3.0], [4.0]]), [[4.0], [3.0]])


def test_component_without_pin_names_size_and_vertex():
    v, f = grid(4, 3)
    f2 = np.vstack([f, f + len(v)])
    L = mesh_laplacian(np.vstack([v, v + 5]), f2, "uniform")
    with pytest.raises(DegenerateInputError, match=r"every connected component to hold at least "
                       r"one of `handles`, got a component of 12 vertices \(vertex 12 among "
                       r"them\) without one\.") as info:
        PinnedSystem(L, [0, 3])
    assert info.value.field == "handles"
    assert isinstance(info.value, InvalidInputError)


def test_several_components_without_pin_are_counted():
    L = sp.block_diag([sp.csr_array([[1.0, -1], [-1, 1]])] * 3).tocsr()
    with pytest.raises(DegenerateInputError, match=r"\(vertex 2 among them\) without one; 2 of the "
                       r"3 components have none\."):
        PinnedSystem(L, [1], name="boundary")


def test_isolated_vertex_is_named_as_such():
    L = sp.block_diag([sp.csr_array([[1.0, -1], [-1, 1]]), sp.csr_array((1, 1))]).tocsr()
    with pytest.raises(DegenerateInputError, match=r"a component of 1 vertex \(vertex 2, isolated: "
                       r"in no face or edge\) without one\."):
        PinnedSystem(L, [0])


def test_no_pins_at_all():
    L = sp.csr_array([[1.0, -1], [-1, 1]])
    with pytest.raises(DegenerateInputError, match=r"a component of 2 vertices"):
        PinnedSystem(L, np.zeros(0, dtype=int))


def test_check_components_off_for_definite_matrices():
    A = spd()
    x = PinnedSystem(A, np.zeros(0, dtype=int), check_components=False).solve(
        np.zeros((0, 1)), rhs=np.ones((A.shape[0], 1)))
    np.testing.assert_allclose(A @ x, 1.0, atol=1e-10)


def test_pinned_system_rejects_bad_pins():
    L = sp.csr_array([[1.0, -1, 0], [-1, 2, -1], [0, -1, 1]])
    with pytest.raises(InvalidInputError, match=r"`handles` to be unique, got 2 twice \(positions "
                       r"0 and 2\)\.") as info:
        PinnedSystem(L, [2, 0, 2])
    assert info.value.field == "handles"
    with pytest.raises(InvalidInputError, match=r"`handles` to hold vertex indices below 3, got 3"):
        PinnedSystem(L, [3])
    with pytest.raises(InvalidInputError, match=r"`handles` to be a flat list of vertex indices, "
                       r"got shape \(1, 2\)"):
        PinnedSystem(L, [[0, 2]])
    with pytest.raises(InvalidInputError, match=r"`L` to be a square"):
        PinnedSystem(np.zeros((2, 3)), [0])


def test_pinned_solve_rejects_bad_shapes():
    L = sp.csr_array([[1.0, -1, 0], [-1, 2, -1], [0, -1, 1]])
    ps = PinnedSystem(L, [0, 2])
    with pytest.raises(InvalidInputError, match=r"values of `handles` to have shape \(2, k\), got "
                       r"\(3, 1\)\.") as info:
        ps.solve(np.zeros((3, 1)))
    assert info.value.field == "handles"
    with pytest.raises(InvalidInputError, match=r"`rhs` to have shape \(3, 2\), got \(3, 1\)\."):
        ps.solve(np.zeros((2, 2)), rhs=np.zeros((3, 1)))


def test_sphere_with_one_pin_per_component_is_solvable():
    m = trimesh.creation.icosphere(subdivisions=2)
    v, f = np.asarray(m.vertices), np.asarray(m.faces, dtype=np.int64)
    L = cotangent_laplacian(v, f)
    x = PinnedSystem(L, [5]).solve([[1.0]])
    np.testing.assert_allclose(x, 1.0, atol=1e-12)          # constant is the harmonic function


# --- the default install: no cvxopt, no cholespy ----------------------------------------------------------

_WITHOUT_CHOLMOD = textwrap.dedent("""
    import json, pkgutil, sys
    sys.modules["cvxopt"] = None          # as if not installed: every import of it fails
    sys.modules["cholespy"] = None
    import importlib
    import numpy as np
    import scipy.sparse as sp
    import scipy.sparse.linalg as sla
    import algorithms
    for m in pkgutil.walk_packages(algorithms.__path__, "algorithms."):
        importlib.import_module(m.name)   # every module imports without them
    from algorithms.core.errors import InvalidInputError
    from algorithms.core.linsolve import Factor, PinnedSystem, available_backends
    n = 40
    a = sp.diags_array([-np.ones(n - 1), 2.0 + np.linspace(0, 1, n), -np.ones(n - 1)],
                       offsets=[-1, 0, 1], format="csc")
    b = np.random.default_rng(0).standard_normal((n, 3))
    f, g = Factor(a), Factor(a, solves=16)
    many = Factor(a, solves=10_000).backend
    complex_ = Factor(a.astype(complex)).backend
    lap = sp.csr_array([[1.0, -1, 0], [-1, 2, -1], [0, -1, 1]])
    refused = []
    for backend in ("cholmod", "cholespy"):
        try:
            Factor(a, backend=backend)
        except InvalidInputError as e:
            refused.append(str(e))
    print(json.dumps({
        "available": available_backends(), "auto": f.backend, "solve": g.backend,
        "error": float(max(abs(f.solve(b) - sla.spsolve(a, b)).max(),
                           abs(g.solve(b) - sla.spsolve(a, b)).max())),
        "indefinite": Factor(sp.csr_array([[1.0, 2.0], [2.0, 1.0]])).backend,
        "pinned": PinnedSystem(lap, [0, 2]).solve([0.0, 1.0]).tolist(),
        "refused": refused, "many": many, "complex": complex_,
        "loaded": [m for m in ("cvxopt", "cholespy") if sys.modules.get(m) is not None]}))
""")


def test_default_install_works_without_cvxopt_and_cholespy():
    out = subprocess.run([sys.executable, "-c", _WITHOUT_CHOLMOD], cwd=ROOT, check=True,
                         capture_output=True, text=True, timeout=240).stdout
    got = json.loads(out.strip().splitlines()[-1])
    assert got["available"] == ["multifrontal", "superlu"]
    # SuperLU serves many solves (from BREAK_EVEN["multifrontal"])
    assert got["auto"] == "multifrontal" and got["solve"] == "multifrontal"
    assert got["many"] == "superlu" and got["complex"] == "superlu"
    assert got["error"] < 1e-10
    assert got["indefinite"] == "superlu"
    # the pins exactly; the free vertex 1 / (√2 √2) (a Cholesky), 1/2 to rounding
    assert got["pinned"][0] == 0.0 and got["pinned"][2] == 1.0
    assert abs(got["pinned"][1] - 0.5) <= 1e-15
    assert len(got["refused"]) == 2
    assert all("pip install 'morphserve[cholmod]'" in e for e in got["refused"])
    assert got["loaded"] == []


def test_auto_order_without_cholmod(monkeypatch):
    # the same choice in-process, with CHOLMOD reported missing
    monkeypatch.setattr(linsolve, "available_backends", lambda: ("superlu", "cholespy"))
    A = spd()
    f = Factor(A)
    assert f.backend == "superlu"
    assert Factor(A, solves=linsolve.BREAK_EVEN["superlu"] - 1).backend == "superlu"
    assert Factor(A, solves=linsolve.BREAK_EVEN["superlu"]).backend == "cholespy"
    b = np.random.default_rng(4).standard_normal(A.shape[0])
    np.testing.assert_allclose(f.solve(b), sla.spsolve(A.tocsc(), b), rtol=1e-10, atol=1e-12)
