r"""Sparse symmetric positive definite solves: factor once, solve many right-hand sides; and
the pinned block split of a Laplacian system.

Backends
--------
:class:`Factor` takes the first backend that is installed and accepts the matrix, in the
order of :data:`BACKENDS` (fastest factorization first) or, when it is to serve at least
:data:`BREAK_EVEN` solves (``solves=``), of :data:`SOLVE_ORDER` (fastest repeated solves
first):

* ``"cholmod"``: SuiteSparse CHOLMOD (supernodal Cholesky, fill-reducing ordering) through
  ``cvxopt.cholmod``; cvxopt ships CHOLMOD inside its wheels. **Optional**: cvxopt and
  CHOLMOD are GPL-3.0-or-later, so they are not part of the default install; they come
  with ``pip install 'morphserve[cholmod]'`` (or the image's ``EXTRAS=cholmod``). Without
  cvxopt this backend is simply not available, and nothing imports it.
* ``"multifrontal"``: our own sparse Cholesky, :mod:`algorithms.core.cholesky` (nested
  dissection, relaxed supernodes, dense blocks through BLAS; compiled with numba, part of
  this package). The default install's first backend, for real matrices only.
* ``"superlu"``: SciPy's SuperLU (BSD-3-Clause, always there) with the symmetric
  ``MMD_AT_PLUS_A`` ordering and no pivoting threshold (SPD matrices need none); it also
  handles symmetric indefinite matrices, so a matrix a Cholesky backend refuses as not
  positive definite falls back to it. In the default install it factors the complex
  Hermitian matrices, and serves many solves (:data:`SOLVE_ORDER`).
* ``"cholespy"``: CHOLMOD again, through ``cholespy`` (slow to factor, fastest to solve:
  blocked over right-hand sides and multi-threaded). **Optional** as well: cholespy's own
  code is BSD-3-Clause, but its wheels compile in CHOLMOD's Core, Cholesky and Partition
  modules (LGPL-2.1-or-later) and its Supernodal module (GPL-2.0-or-later), so the
  binary is GPL whatever its metadata says (``tests/test_licences.py`` looks inside the
  compiled files for that). It comes with the same ``cholmod`` extra.

The orders come from ``bench/linsolve.py``, which runs every candidate side by side on the
systems this package solves, each at about 5k, 50k and 200k vertices: the pinned cotangent
Laplacian of a jittered wavy grid (harmonic and biharmonic deformation, Tutte and
Laplacian layout), the ARAP free block of a torus with 1 % of its vertices pinned, and the
LSCM matrix ``Q`` (``2n`` unknowns) of the grid with two pins. Medians of 3 interleaved
runs on a 2-core machine (load average 0.3-1.1; CHOLMOD on cvxopt's OpenBLAS with 1
thread, cholespy with its own pool of 2, SuperLU (panels of :data:`SUPERLU_PANEL` columns)
one thread, the multifrontal Cholesky with SciPy's OpenBLAS, 2 threads); on a shared
machine only the ratios within a row mean much. Factor in seconds, the solve of 3
right-hand sides in milliseconds::

                                      factor (s)                          solve, 3 rhs (ms)
    system           unknowns  cholmod multifr. superlu cholespy   cholmod multifr. superlu cholespy
    Laplacian 5k        4,761    0.005   0.008   0.009   0.018       1.5      1.6      1.1      0.5
    ARAP 5k             4,954    0.007   0.009   0.012   0.018       1.4      1.3      1.2      0.5
    LSCM 5k            10,078    0.011   0.016   0.021   0.046       2.7      2.5      2.1      1.0
    Laplacian 50k      49,284    0.062   0.092   0.161   0.293      16.0     14.7     12.4      7.1
    ARAP 50k           49,482    0.095   0.138   0.315   0.369      20.2     19.8     17.7      8.3
    LSCM 50k          100,348    0.176   0.286   0.527   0.944      50.3     38.6     32.5     20.0
    Laplacian 200k    198,916    0.370   0.539   1.314   1.842     102.8     72.3     72.6     37.8
    ARAP 200k         197,942    0.587   0.804   2.175   2.375     116.4     89.9     91.9     39.4
    LSCM 200k         401,404    0.946   1.627   3.726   6.005     221.2    174.0    154.0     87.6

(cvxopt 1.3.3, scipy 1.17.1, cholespy 2.2.0; residuals ``‖A x - b‖∞ / ‖b‖∞`` at most
3e-13, 8e-8 for the ill-conditioned LSCM matrices; the multifrontal Cholesky's are 1-4×
SuperLU's, CHOLMOD's and cholespy's 1-5×.)

* CHOLMOD, when the extra is installed, factors fastest: 1.4-1.7× faster than the
  multifrontal Cholesky and 2.6-3.9× faster than SuperLU at 50k and 200k vertices, so it
  leads :data:`BACKENDS`; its solves of 3 right-hand sides are the slowest (cvxopt's
  ``cholmod.solve`` solves one column at a time), so it comes last in :data:`SOLVE_ORDER`.
* The multifrontal Cholesky factors 1.1-1.3× faster than SuperLU at 5k and 1.7-2.7×
  faster at 50k and 200k, so it comes second; its solves of 3 right-hand sides are
  1.1-1.5× slower than SuperLU's at 5k and 50k and 0.98-1.13× at 200k (its solves of one
  are within 15 % of SuperLU's either way), so SuperLU comes before it in
  :data:`SOLVE_ORDER`: factor plus ``k`` solves, SuperLU is the faster from ``k`` =
  30-105 on the 50k and 200k rows, never on two of them (median 94): :data:`BREAK_EVEN`.
* SuperLU factors faster than cholespy in all 9 systems (1.1-2.2×), so it comes before it
  for one-shot solves (factor once, solve once).
* cholespy solves 1.6-2.4× faster than SuperLU and 2.3-3.0× faster than CHOLMOD with 3
  right-hand sides, so it leads :data:`SOLVE_ORDER` (ARAP's iterations, a factorization
  kept for many solves). Factor plus ``k`` solves, cholespy is the faster from ``k`` =
  23-38 (median 24) against CHOLMOD and from 4-34 (median 20) against SuperLU on the 50k
  and 200k rows: :data:`BREAK_EVEN`.
* qdldl (Apache-2.0, LDLᵀ with an AMD ordering, wheels; an earlier run, not installed for
  this one) factored the 5k systems and the 50k and 200k grids 1.1-1.4× faster than
  SuperLU, and was 1.1-1.3× slower on the 50k and 200k LSCM matrices and 1.5-1.8× on the
  torus at 50k and 200k (its factorization has no supernodes): slower than the
  multifrontal Cholesky at 50k and 200k by the two runs' ratios to SuperLU, so it is not
  a dependency; the bench still times it when it is installed.
* scikit-sparse (CHOLMOD) is GPL and has no wheels; SciPy's ``spsolve`` with UMFPACK
  needs scikit-umfpack (GPL); PARDISO needs Intel's MKL (not an open-source licence).

Complex Hermitian matrices
--------------------------
:class:`Factor` and :class:`PinnedSystem` take complex Hermitian positive definite matrices
too (``"cholmod"`` and ``"superlu"``; cholespy factors real matrices only, so it is left
out of the order, and asking for it is an error). A real quadratic form in ``2n`` unknowns
:math:`x = (u, v)` whose matrix has the block form

.. math::

   Q = \begin{pmatrix} P & -R \\ R & P \end{pmatrix}, \qquad P = P^\mathsf{T},\;
   R = -R^\mathsf{T},

is the real form of the Hermitian :math:`K = P + iR` in :math:`z = u + iv`:
:math:`x^\mathsf{T} Q x = z^* K z` and :math:`Q x = b \iff K z = b_u + i b_v`. LSCM's
conformal energy is of this form (``conformal_energy_hermitian``). Its ``n × n`` complex
system has the sparsity of the mesh, where the ``2n × 2n`` real one couples every vertex's
two unknowns, and it factors 1.9-2.5× faster with SuperLU and 1.5-1.8× with CHOLMOD, at
the same residuals or smaller (``bench/linsolve.py``, systems ``lscm`` and
``lscm_complex``, the grid of the table; three runs, the last's factor times in seconds,
the run of the table)::

    vertices   superlu Q   superlu K   cholmod Q   cholmod K
    5k             0.021       0.009       0.011       0.007
    50k            0.489       0.222       0.165       0.104
    200k           3.408       1.443       0.856       0.578

The pinned split
----------------
For :math:`L x = b` with the rows in ``pinned`` fixed to :math:`c`, reorder the unknowns
into free (``f``) and pinned (``p``):

.. math::

   L_{ff}\, x_f = b_f - L_{fp}\, c, \qquad x_p = c.

:math:`L_{ff}` is positive definite exactly when every connected component of the graph of
:math:`L` holds a pin (for a Laplacian with positive weights on a connected component,
the null space is the constant vector, which any pin removes; the cotangent Laplacian is
the stiffness matrix of linear finite elements, so it is positive semidefinite whatever
the angles). :class:`PinnedSystem` checks that and names the component that has no pin.
"""

from __future__ import annotations

import functools
import importlib
from typing import Any, cast

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.types import FloatArray, IntArray
from algorithms.core.validation import as_choice, as_indices

__all__ = ["Factor", "PinnedSystem", "BACKENDS", "BREAK_EVEN", "SOLVE_ORDER",
           "available_backends"]

#: Backends in order of preference: fastest factorization first (the module docstring has
#: the measurements). ``"cholmod"`` and ``"cholespy"`` are there only with the ``cholmod``
#: extra (cvxopt, cholespy).
BACKENDS = ("cholmod", "multifrontal", "superlu", "cholespy")
#: The order for many solves: fastest repeated solves first.
SOLVE_ORDER = ("cholespy", "superlu", "multifrontal", "cholmod")
#: From how many solves per factorization :data:`SOLVE_ORDER` beats :data:`BACKENDS`, by
#: the backend that would factor (the module docstring has the measurements).
BREAK_EVEN = {"cholmod": 24, "multifrontal": 94, "superlu": 19}
#: Columns per panel of SuperLU's factorization (SciPy's copy defaults to 20, ``sp_ienv(1)``):
#: panels of 6 factored the 5k-200k systems of ``bench/linsolve.py`` 4-15 % faster on one
#: thread (the Laplacians 12-15 %, the ARAP blocks 4-5 %, LSCM's K 9 %); the supernodes and
#: the fill do not depend on it, only the blocking of the updates.
SUPERLU_PANEL = 6

_MODULES = {"cholmod": "cvxopt", "cholespy": "cholespy", "multifrontal": "numba",
            "superlu": "scipy"}
#: The backends that factor real matrices only.
_REAL_ONLY = ("cholespy", "multifrontal")
#: How to get each backend, for the error that asks for one not installed.
_INSTALL = {"cholmod": "pip install 'morphserve[cholmod]' (cvxopt, GPL-3.0)",
            "cholespy": "pip install 'morphserve[cholmod]' (cholespy, CHOLMOD inside: GPL-2.0)",
            "multifrontal": "pip install numba", "superlu": "pip install scipy"}


@functools.cache
def _importable(module: str) -> bool:
    """Whether ``module`` imports: a missing optional backend (cvxopt without the
    ``cholmod`` extra) or one whose import fails (a broken build) is not offered."""
    try:
        importlib.import_module(module)
    except ImportError:
        return False
    return True


def available_backends() -> tuple[str, ...]:
    """The installed backends, in order of preference."""
    return tuple(b for b in BACKENDS if _importable(_MODULES[b]))


def _real_or_complex(*dtypes: np.dtype[Any]) -> np.dtype[Any]:
    """The dtype the solves work in: ``complex128`` when any of ``dtypes`` is complex,
    ``float64`` otherwise."""
    return np.dtype(np.complex128 if any(d.kind == "c" for d in dtypes) else np.float64)


class _NotPositiveDefinite(Exception):
    pass


class _Cholmod:
    name = "cholmod"

    def __init__(self, a: sp.csc_array) -> None:
        import cvxopt
        import cvxopt.cholmod as cholmod

        a = sp.csc_array(a)
        a.sum_duplicates()
        col = np.repeat(np.arange(a.shape[1], dtype=np.int64), np.diff(a.indptr))
        low = a.indices >= col                   # the lower triangle, as triplets
        m = cvxopt.spmatrix(cvxopt.matrix(a.data[low]),
                            cvxopt.matrix(a.indices[low].astype(np.int64)),
                            cvxopt.matrix(col[low]), a.shape)
        self._cvxopt, self._cholmod = cvxopt, cholmod
        self._factor = cholmod.symbolic(m, uplo="L")
        try:
            cholmod.numeric(m, self._factor)
        except ArithmeticError:
            raise _NotPositiveDefinite from None

    def solve(self, b: FloatArray) -> FloatArray:
        x = self._cvxopt.matrix(np.asfortranarray(b))
        self._cholmod.solve(self._factor, x)
        return np.array(x).reshape(b.shape)


class _Cholespy:
    name = "cholespy"

    def __init__(self, a: sp.csc_array) -> None:
        import cholespy

        a = sp.csc_array(a)
        a.sum_duplicates()
        try:
            self._solver = cholespy.CholeskySolverD(
                a.shape[0], a.indptr.astype(np.int32), a.indices.astype(np.int32),
                np.ascontiguousarray(a.data, dtype=np.float64), cholespy.MatrixType.CSC)
        except ValueError:  # "Matrix is not positive definite!"
            raise _NotPositiveDefinite from None

    def solve(self, b: FloatArray) -> FloatArray:
        b = np.ascontiguousarray(b)
        x = np.empty_like(b)
        self._solver.solve(b, x)
        return x


class _Multifrontal:
    name = "multifrontal"

    def __init__(self, a: sp.csc_array) -> None:
        from algorithms.core.cholesky import NotPositiveDefinite, SparseCholesky

        try:
            self._factor = SparseCholesky(a)
        except NotPositiveDefinite:
            raise _NotPositiveDefinite from None

    def solve(self, b: FloatArray) -> FloatArray:
        return self._factor.solve(b)


class _SuperLU:
    name = "superlu"

    def __init__(self, a: sp.csc_array) -> None:
        self._lu = sla.splu(sp.csc_matrix(a), permc_spec="MMD_AT_PLUS_A",
                            diag_pivot_thresh=0.0, options={"SymmetricMode": True},
                            panel_size=SUPERLU_PANEL)

    def solve(self, b: FloatArray) -> FloatArray:
        return self._lu.solve(b)


class _SuperLUPivoting(_SuperLU):
    """Partial pivoting: for symmetric indefinite matrices (the fallback's fallback)."""

    def __init__(self, a: sp.csc_array) -> None:
        self._lu = sla.splu(sp.csc_matrix(a), permc_spec="MMD_AT_PLUS_A")


_Backend = _Cholmod | _Cholespy | _Multifrontal | _SuperLU
_CLASSES: dict[str, type[_Backend]] = {"cholmod": _Cholmod, "cholespy": _Cholespy,
                                       "multifrontal": _Multifrontal, "superlu": _SuperLU}


class Factor:
    r"""A factorization of a sparse symmetric positive definite matrix, for many solves.

    Parameters
    ----------
    A : (n, n) sparse array or matrix
        Symmetric positive definite (the Cholesky backends read its lower triangle only),
        or complex Hermitian positive definite (see the module docstring; not
        ``"cholespy"``). A symmetric indefinite but non-singular matrix is accepted too: a
        Cholesky backend refuses it and SuperLU takes over.
    backend : {"auto", "cholmod", "multifrontal", "superlu", "cholespy"}, default "auto"
        ``"auto"`` takes the first installed of :data:`BACKENDS`, or of
        :data:`SOLVE_ORDER` when ``solves`` reaches the :data:`BREAK_EVEN` of the first
        installed of :data:`BACKENDS`. ``"cholmod"`` and ``"cholespy"`` need the optional
        ``cholmod`` extra (cvxopt, cholespy: CHOLMOD, GPL).
    solves : int, default 1
        How many solves the factorization is expected to serve (iterations, frames,
        interactive handles: a large number): what ``"auto"`` optimises is the
        factorization plus that many solves.
    name : str, default "A"
        Names the matrix in errors.

    Attributes
    ----------
    backend : str
        The backend that factored ``A``.
    shape : tuple of int
        ``(n, n)``.
    dtype : numpy.dtype
        ``float64``, or ``complex128`` for a complex ``A``.

    Raises
    ------
    InvalidInputError
        ``A`` not square, an unknown or uninstalled ``backend``, ``"cholespy"`` for a
        complex ``A``.
    DegenerateInputError
        ``A`` singular (every backend failed).

    Notes
    -----
    See the module docstring for the backends and their measured speed.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> f = Factor(sp.csr_array([[2.0, -1.0], [-1.0, 2.0]]))
    >>> f.solve(np.array([1.0, 1.0])).round(12).tolist()
    [1.0, 1.0]
    """

    def __init__(self, A: Any, *, backend: str = "auto", solves: int = 1,
                 name: str = "A") -> None:
        as_choice(backend, ("auto",) + BACKENDS, name="backend")
        a = sp.csc_array(A)
        if a.ndim != 2 or a.shape[0] != a.shape[1]:
            raise InvalidInputError(
                f"Expected `{name}` to be a square (n, n) matrix, got shape {tuple(a.shape)}.",
                field=name)
        self.dtype = _real_or_complex(a.dtype)
        complex_ = self.dtype.kind == "c"
        a = a.astype(self.dtype, copy=False)
        self.shape: tuple[int, int] = (int(a.shape[0]), int(a.shape[1]))
        installed = available_backends()
        if complex_:  # cholespy factors real matrices only
            installed = tuple(b for b in installed if b not in _REAL_ONLY)
            if backend in _REAL_ONLY:
                raise InvalidInputError(
                    f"Expected `backend` to be one that factors complex Hermitian matrices "
                    f"({', '.join(installed)}), got {backend!r}.", field="backend")
        if backend == "auto":
            order = [b for b in BACKENDS if b in installed]
            # the break-even counts were measured against cholespy: a complex matrix keeps
            # the order of the fastest factorization
            if not complex_ and solves >= BREAK_EVEN.get(order[0], 0):
                order = [b for b in SOLVE_ORDER if b in installed]
        elif backend not in installed:
            raise InvalidInputError(
                f"Expected `backend` to be an installed solver backend ({', '.join(installed)}),"
                f" got {backend!r} (to install it: {_INSTALL[backend]}).", field="backend")
        else:
            order = [backend] + (["superlu"] if backend != "superlu" else [])
        self._impl: _Backend | None = None  # None only when n == 0
        self.backend = "none"
        if self.shape[0] == 0:
            return
        refused = False
        for b in order:
            if refused and b != "superlu":
                continue  # one Cholesky backend refused it: another would too
            try:
                self._impl = _CLASSES[b](a)
            except _NotPositiveDefinite:
                refused = True
                continue
            except RuntimeError:  # SuperLU without pivoting met a zero pivot
                break
            self.backend = b
            break
        if self._impl is None:
            try:  # not positive definite, or singular to SuperLU without pivoting
                self._impl = _SuperLUPivoting(a)
                self.backend = "superlu"
            except RuntimeError:
                raise DegenerateInputError(
                    f"Expected `{name}` to be non-singular, got a singular {self.shape[0]}×"
                    f"{self.shape[1]} matrix.", field=name) from None

    @property
    def n(self) -> int:
        return self.shape[0]

    def solve(self, b: Any) -> FloatArray:
        """Solve ``A x = b``.

        Parameters
        ----------
        b : (n,) or (n, k) float or complex array

        Returns
        -------
        x : array, the shape of ``b``
            Complex when ``A`` or ``b`` is. A column of zeros in ``b`` gives a column of
            zeros, without a solve.

        Raises
        ------
        InvalidInputError
            ``b`` has the wrong number of rows or dimensions.
        """
        arr = np.asarray(b)
        if arr.ndim not in (1, 2) or arr.shape[0] != self.n:
            raise InvalidInputError(
                f"Expected `b` to have shape ({self.n},) or ({self.n}, k), got "
                f"{tuple(arr.shape)}.", field="b")
        if self._impl is None or arr.size == 0:  # no backend: n == 0
            return np.zeros(arr.shape, dtype=_real_or_complex(arr.dtype, self.dtype))
        if arr.dtype.kind == "c" and self.dtype.kind != "c":  # real A: the parts apart
            parts = self.solve(np.stack([arr.real, arr.imag], axis=-1).reshape(
                self.n, -1)).reshape(arr.shape + (2,))
            return cast(FloatArray, parts[..., 0] + 1j * parts[..., 1])
        arr = arr.astype(self.dtype, copy=False)
        if arr.ndim == 2 and arr.shape[1] > 1:
            # a zero column has the zero solution: a handle region moved in a plane leaves
            # one coordinate's displacement zero, and CHOLMOD solves column by column
            live = np.flatnonzero(np.any(arr, axis=0))
            if live.shape[0] < arr.shape[1]:
                out = np.zeros(arr.shape, dtype=self.dtype)
                if live.shape[0]:
                    out[:, live] = self._impl.solve(arr[:, live])
                return cast(FloatArray, out)  # typed as the real case (all callers but LSCM)
        return self._impl.solve(arr)

    def __repr__(self) -> str:
        return f"Factor(n={self.n}, backend={self.backend!r})"


class PinnedSystem:
    r"""Factor a Laplacian with pinned rows once; solve for many pinned values.

    Solves :math:`\min_x \tfrac12 x^\mathsf{T} L x - x^\mathsf{T} b` subject to
    :math:`x_p = c`, i.e. :math:`L_{ff} x_f = b_f - L_{fp} c`, for one or many columns.

    Parameters
    ----------
    L : (n, n) sparse array
        Symmetric positive semidefinite (a Laplacian, ``L = D - W``), or any symmetric
        matrix whose free block is non-singular; or complex Hermitian (see the module
        docstring).
    pinned : (p,) int array
        Distinct indices of the pinned rows.
    name : str, default "handles"
        The input the pins came from: errors name it.
    backend : str, default "auto"
        Passed to :class:`Factor`.
    solves : int, default 1
        Passed to :class:`Factor`: how many times :meth:`solve` will be called.
    check_components : bool, default True
        Check that every connected component of the graph of ``L`` (its off-diagonal
        non-zeros) holds a pin. Turn off for matrices that are positive definite on their
        own (``L + M``).

    Attributes
    ----------
    n : int
        Number of rows of ``L``.
    pinned : (p,) int array
        The pinned indices, as given.
    free : (n - p,) int array
        The other indices, increasing.
    factor : Factor
        The factorization of ``L_ff``.
    L_ff, L_fp : csr_array
        The free-free and free-pinned blocks of ``L``.

    Raises
    ------
    InvalidInputError
        ``L`` not square; ``pinned`` out of range, not flat, or repeating an index (field
        ``name``).
    DegenerateInputError
        A connected component without a pin (field ``name``); the message gives its size
        and one of its vertices.

    Examples
    --------
    A path 0 - 1 - 2 with its ends pinned to 0 and 1: the middle lands half-way.

    >>> import scipy.sparse as sp
    >>> L = sp.csr_array([[1.0, -1, 0], [-1, 2, -1], [0, -1, 1]])
    >>> PinnedSystem(L, [0, 2]).solve([[0.0], [1.0]]).ravel().round(12).tolist()
    [0.0, 0.5, 1.0]
    """

    def __init__(self, L: Any, pinned: Any, *, name: str = "handles", backend: str = "auto",
                 solves: int = 1, check_components: bool = True) -> None:
        lap = sp.csr_array(L)
        lap = lap.astype(_real_or_complex(lap.dtype), copy=False)
        if lap.ndim != 2 or lap.shape[0] != lap.shape[1]:
            raise InvalidInputError(
                f"Expected `L` to be a square (n, n) matrix, got shape {tuple(lap.shape)}.",
                field="L")
        n = int(lap.shape[0])
        pins = as_indices(pinned, n, name=name, what="vertex indices")
        if pins.ndim != 1:
            raise InvalidInputError(
                f"Expected `{name}` to be a flat list of vertex indices, got shape "
                f"{tuple(pins.shape)}.", field=name)
        mask = np.zeros(n, dtype=bool)
        mask[pins] = True
        if np.count_nonzero(mask) != pins.shape[0]:
            order = np.argsort(pins, kind="stable")
            k = int(np.flatnonzero(pins[order][1:] == pins[order][:-1])[0])
            first, second = sorted((int(order[k]), int(order[k + 1])))
            raise InvalidInputError(
                f"Expected `{name}` to be unique, got {int(pins[first])} twice (positions "
                f"{first} and {second}).", field=name)
        if check_components:
            _check_pins(lap, mask, name)
        self.n = n
        self.pinned: IntArray = pins
        self.free: IntArray = np.flatnonzero(~mask).astype(np.int64)
        self._name = name
        rows = lap[self.free]
        self.L_ff: sp.csr_array = rows[:, self.free].tocsr()
        self.L_fp: sp.csr_array = rows[:, pins].tocsr()
        self.factor = Factor(self.L_ff, backend=backend, solves=solves, name="L")

    def solve(self, pinned_values: Any, rhs: Any = None) -> FloatArray:
        """Solve with the pinned rows set to ``pinned_values``.

        Parameters
        ----------
        pinned_values : (p, k) or (p,) float or complex array
            Row ``i`` is the value of ``pinned[i]``.
        rhs : (n, k) or (n,) float or complex array, optional
            The right-hand side ``b`` (rows at pinned indices are ignored); zero when
            omitted (harmonic interpolation of the pinned values).

        Returns
        -------
        (n, k) or (n,) array
            The shape follows ``pinned_values``; complex when ``L``, ``pinned_values`` or
            ``rhs`` is; pinned rows equal ``pinned_values`` exactly.

        Raises
        ------
        InvalidInputError
            ``pinned_values`` without one row per pin, or ``rhs`` of the wrong shape.
        """
        c = np.asarray(pinned_values)
        r = None if rhs is None else np.asarray(rhs)
        dtype = _real_or_complex(c.dtype, self.L_ff.dtype, *([] if r is None else [r.dtype]))
        c = c.astype(dtype, copy=False)
        p = self.pinned.shape[0]
        if c.ndim not in (1, 2) or c.shape[0] != p:
            raise InvalidInputError(
                f"Expected the values of `{self._name}` to have shape ({p}, k), got "
                f"{tuple(c.shape)}.", field=self._name)
        vector = c.ndim == 1
        c2 = c[:, None] if vector else c
        k = c2.shape[1]
        b_f = -(self.L_fp @ c2) if p else np.zeros((self.free.shape[0], k), dtype=dtype)
        if r is not None:
            r2 = r[:, None] if r.ndim == 1 else r
            if r2.ndim != 2 or r2.shape != (self.n, k):
                raise InvalidInputError(
                    f"Expected `rhs` to have shape ({self.n}, {k}), got {tuple(r.shape)}.",
                    field="rhs")
            b_f = b_f + r2[self.free]
        out = np.empty((self.n, k), dtype=dtype)
        out[self.pinned] = c2
        out[self.free] = self.factor.solve(b_f)
        return cast(FloatArray, out[:, 0] if vector else out)  # complex: typed as the real case

    def __repr__(self) -> str:
        return (f"PinnedSystem(n={self.n}, pinned={self.pinned.shape[0]}, "
                f"backend={self.factor.backend!r})")


def _check_pins(lap: sp.csr_array, pinned_mask: np.ndarray, name: str) -> None:
    """Raise unless every connected component of the graph of ``lap`` holds a pin."""
    from scipy.sparse.csgraph import connected_components

    n = lap.shape[0]
    if n == 0:
        return
    graph = lap.copy()
    graph.data = (graph.data != 0).astype(np.int8)
    graph.eliminate_zeros()  # an explicit zero weight is no edge
    count, labels = connected_components(graph, directed=False)
    has_pin = np.zeros(count, dtype=bool)
    has_pin[labels[pinned_mask]] = True
    if has_pin.all():
        return
    missing = np.flatnonzero(~has_pin)
    sizes = np.bincount(labels, minlength=count)
    # report the component of the smallest vertex among those without a pin
    first_vertex = np.full(count, n, dtype=np.int64)
    np.minimum.at(first_vertex, labels, np.arange(n))
    comp = missing[np.argmin(first_vertex[missing])]
    vertex, size = int(first_vertex[comp]), int(sizes[comp])
    more = (f"; {missing.shape[0]} of the {count} components have none"
            if missing.shape[0] > 1 else "")
    if size > 1:
        what = f"a component of {size} vertices (vertex {vertex} among them)"
    elif lap[[vertex]].count_nonzero() == 0:
        what = f"a component of 1 vertex (vertex {vertex}, isolated: in no face or edge)"
    else:
        what = f"a component of 1 vertex (vertex {vertex})"
    raise DegenerateInputError(
        f"Expected every connected component to hold at least one of `{name}`, got "
        f"{what} without one{more}.", field=name)
