r"""Bijective parameterization with a free boundary: symmetric Dirichlet energy plus a
boundary barrier, minimised by SLIM steps with flip-free, crossing-free line search."""

from __future__ import annotations

import importlib.util
from dataclasses import dataclass
from typing import Annotated, Any, cast

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from algorithms.core.errors import ConvergenceWarning, DegenerateInputError, warn
from algorithms.core.linsolve import Factor
from algorithms.core.mesh import Mesh, face_areas, signed_areas
from algorithms.core.params import Ge, MeshLike, validate_params
from algorithms.core.progress import Progress, as_progress
from algorithms.core.types import FloatArray, IntArray
from algorithms.parameterization._disk import Disk, convex_boundary, pinned_map, read_disk
from algorithms.parameterization._quality import face_frames, jacobians, quality
from algorithms.parameterization.tutte import _mean_value_solve

__all__ = ["BijectiveResult", "bijective", "symmetric_dirichlet", "max_flip_free_step",
           "boundary_crossings", "BijectiveSolver"]

#: The barrier acts on a boundary vertex closer than ``BARRIER_WIDTH`` times the mean
#: boundary edge length (of the surface, or of the start if shorter) to a boundary edge.
BARRIER_WIDTH = 0.25
#: The weight of the barrier against the (area-normalised) symmetric Dirichlet energy.
BARRIER_WEIGHT = 1e-2
#: The first trial step is this fraction of the largest step that keeps every triangle
#: positive (as libigl's SLIM).
STEP_FRACTION = 0.8
#: The weight of the proximal term ‖x − x_k‖² that makes the SLIM system definite (the
#: energy does not see translations), against the un-normalised energy (as libigl).
PROXIMAL = 1e-4
#: Sufficient decrease (Armijo) constant of the line search.
ARMIJO = 1e-4

_HAVE_CVXOPT = importlib.util.find_spec("cvxopt") is not None


@dataclass(frozen=True, eq=False)
class BijectiveResult:
    """A bijective (flip-free, boundary not self-intersecting) map of a disk to the plane.

    Attributes
    ----------
    uv : (n, 2) float array
        The position of every vertex in the plane, row ``i`` for vertex ``i``.
    mesh : Mesh
        The input mesh (its faces index ``uv`` too).
    energy : (k + 1,) float array
        The objective (area-weighted mean symmetric Dirichlet energy plus the boundary
        barrier) of the Tutte start and after each iteration; decreasing.
    symmetric_dirichlet : float
        The area-weighted mean of σ₁² + σ₂² + σ₁⁻² + σ₂⁻² over the faces of ``uv``: 4 for
        an isometry, larger otherwise.
    iterations : int
        The number of iterations run.
    converged : bool
        True when the last iteration lowered the objective by at most ``tolerance`` times
        its value (or could not lower it); False when ``max_iterations`` stopped the run.
    boundary_crossings : int
        Pairs of boundary edges that cross in the plane: 0 (the map is bijective).
    flipped_faces : int
        Faces whose orientation in the plane is opposite to that of the map as a whole: 0.
    degenerate_faces : int
        Faces collapsed to (near) zero area in the plane.
    angle_distortion : float
        Area-weighted mean of σ₁/σ₂ − 1 over the faces: 0 for a conformal map.
    area_distortion : float
        Area-weighted mean of |log(σ₁σ₂ / s)|, s the ratio of total plane area to total
        surface area: 0 when every face's area is scaled alike.
    """

    uv: FloatArray
    mesh: Mesh
    energy: FloatArray
    symmetric_dirichlet: float
    iterations: int
    converged: bool
    boundary_crossings: int
    flipped_faces: int
    degenerate_faces: int
    angle_distortion: float
    area_distortion: float


# ----------------------------------------------------------------------------- helpers


def _cross(a: FloatArray, b: FloatArray) -> FloatArray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _smallest_positive_root(c0: FloatArray, c1: FloatArray, c2: FloatArray
                            ) -> tuple[FloatArray, FloatArray]:
    """Both real roots of c0 + c1 t + c2 t² (``inf`` where none or not positive),
    computed stably; a vanishing c2 leaves the linear root."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        disc = c1 * c1 - 4.0 * c2 * c0
        sq = np.sqrt(np.maximum(disc, 0.0))
        q = -0.5 * (c1 + np.where(c1 >= 0, sq, -sq))
        quad = np.abs(c2) > 1e-14 * (np.abs(c1) + np.abs(c0) + np.finfo(float).tiny)
        r1 = np.where(quad, q / c2, -c0 / c1)
        r2 = np.where(quad, c0 / q, np.inf)
        real = ~quad | (disc >= 0)
        r1 = np.where(real & (r1 > 0) & np.isfinite(r1), r1, np.inf)
        r2 = np.where(real & (r2 > 0) & np.isfinite(r2), r2, np.inf)
    return np.minimum(r1, r2), np.maximum(r1, r2)


def max_flip_free_step(uv: FloatArray, faces: IntArray, direction: FloatArray) -> float:
    r"""The largest :math:`t > 0` up to which no triangle of ``uv + s·direction``,
    :math:`0 \le s < t`, changes orientation: the smallest positive root over the faces
    of :math:`\det(t) = c_0 + c_1 t + c_2 t^2` (each face's doubled signed area, a
    quadratic in the step), ``inf`` if none."""
    p, d = uv[faces], direction[faces]
    a0, b0 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    a1, b1 = d[:, 1] - d[:, 0], d[:, 2] - d[:, 0]
    c0 = _cross(a0, b0)
    c1 = _cross(a0, b1) + _cross(a1, b0)
    c2 = _cross(a1, b1)
    r, _ = _smallest_positive_root(c0, c1, c2)
    return float(r.min()) if r.size else float("inf")


def symmetric_dirichlet(vertices: Any, faces: Any, uv: Any) -> float:
    r"""The area-weighted mean symmetric Dirichlet energy of the map ``uv``,

    .. math:: E = \frac{\sum_t A_t \left(\lVert J_t\rVert_F^2 + \lVert J_t^{-1}\rVert_F^2
       \right)}{\sum_t A_t} = \frac{\sum_t A_t (\sigma_1^2 + \sigma_2^2 + \sigma_1^{-2}
       + \sigma_2^{-2})}{\sum_t A_t},

    4 for an isometry; ``inf`` if a face is collapsed or flipped (relative to the map's
    orientation: the energy is defined on orientation-preserving maps)."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    x = np.asarray(uv, dtype=np.float64)
    fr = face_frames(v, f)
    area = 0.5 * fr[:, 1, 0] * fr[:, 2, 1]
    sign = 1.0 if signed_areas(x, f).sum() >= 0 else -1.0
    return _sd(area / area.sum(), jacobians(fr, f, x), sign)


def _sd(weight: FloatArray, J: FloatArray, sign: float = 1.0) -> float:
    det = sign * (J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0])
    if not (det > 0).all():
        return float("inf")
    fro = np.square(J).reshape(-1, 4).sum(axis=1)
    return float(np.dot(weight, fro * (1.0 + 1.0 / (det * det))))


def _segment_distance(p: FloatArray, a: FloatArray, b: FloatArray
                      ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Distance from points ``p`` to segments ``ab``, the segment parameter of the nearest
    point and the unit direction from it to ``p``."""
    e = b - a
    ll = np.einsum("ij,ij->i", e, e)
    s = np.clip(np.einsum("ij,ij->i", p - a, e) / ll, 0.0, 1.0)
    r = p - (a + s[:, None] * e)
    d = np.sqrt(np.einsum("ij,ij->i", r, r))
    return d, s, r / np.maximum(d, np.finfo(float).tiny)[:, None]


def _near_pairs(points: FloatArray, a: FloatArray, b: FloatArray, reach: FloatArray
                ) -> tuple[IntArray, IntArray]:
    """Pairs (segment e, point k) with point k within ``reach[e]`` of segment e's
    midpoint, found with a k-d tree."""
    tree = cKDTree(points)
    mid = 0.5 * (a + b)
    hits = tree.query_ball_point(mid, reach)
    counts = np.fromiter((len(h) for h in hits), dtype=np.int64, count=len(hits))
    if counts.sum() == 0:
        return np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int64)
    seg = np.repeat(np.arange(len(hits)), counts)
    pts = np.concatenate([np.asarray(h, dtype=np.int64) for h in hits if h])
    return seg, pts


def boundary_crossings(uv: Any, loop: Any) -> int:
    """The number of pairs of non-adjacent edges of the closed polygon ``uv[loop]`` that
    intersect (touching counts)."""
    x = np.asarray(uv, dtype=np.float64)[np.asarray(loop)]
    b = x.shape[0]
    if b < 4:
        return 0
    a, c = x, np.roll(x, -1, axis=0)
    length = np.linalg.norm(c - a, axis=1)
    tree = cKDTree(0.5 * (a + c))
    pairs = tree.query_pairs(float(length.max()) * (1 + 1e-9), output_type="ndarray")
    if pairs.size == 0:
        return 0
    i, j = pairs[:, 0], pairs[:, 1]
    adjacent = ((j - i) % b == 1) | ((i - j) % b == 1)
    i, j = i[~adjacent], j[~adjacent]
    p1, p2, q1, q2 = a[i], c[i], a[j], c[j]
    d1 = _cross(p2 - p1, q1 - p1)
    d2 = _cross(p2 - p1, q2 - p1)
    d3 = _cross(q2 - q1, p1 - q1)
    d4 = _cross(q2 - q1, p2 - q1)
    return int(np.count_nonzero((d1 * d2 <= 0) & (d3 * d4 <= 0)))


# ----------------------------------------------------------------------------- solver


class BijectiveSolver:
    """Symmetric Dirichlet energy with a boundary barrier on one disk, minimised from a
    flip-free start by SLIM steps (Rabinovich et al. 2017) and a line search that never
    lets a triangle flip or the boundary cross itself.

    Parameters
    ----------
    disk : Disk
        A checked disk (see :func:`~algorithms.parameterization._disk.read_disk`).
    initial : (n, 2) float array, optional
        The start; the barrier's width is a quarter of the mean boundary edge length of
        the surface or of the start, whichever is smaller.
    """

    def __init__(self, disk: Disk, initial: FloatArray | None = None) -> None:
        m = disk.mesh
        self.mesh, self.loop = m, disk.loop
        f = m.faces
        self.n = m.n_vertices
        fr = face_frames(m.vertices, f)
        self.frames = fr
        area = 0.5 * fr[:, 1, 0] * fr[:, 2, 1]
        self.weight = area / area.sum()
        # libigl's proximal term against the un-normalised energy (with it, the first step
        # from a common start equals libigl's SLIM step to rounding)
        self.proximal = PROXIMAL / float(area.sum())
        l1, x2, y2 = fr[:, 1, 0], fr[:, 2, 0], fr[:, 2, 1]
        g = np.zeros((f.shape[0], 3, 2))             # ∂J[a, c] / ∂x_a[f_k] = g[t, k, c]
        g[:, 0, 0], g[:, 1, 0] = -1.0 / l1, 1.0 / l1
        g[:, 0, 1] = (x2 - l1) / (l1 * y2)
        g[:, 1, 1] = -x2 / (l1 * y2)
        g[:, 2, 1] = 1.0 / y2
        self.g = g
        # the fixed sparsity of the proxy Hessian over x = [u; v]: entry (b, k), (b', l)
        # of every face, and the diagonal; scattered by `_slot_of` into CSC order
        n2 = 2 * self.n
        var = np.arange(2)[None, :, None] * self.n + f[:, None, :]          # (m, b, k)
        shape = (f.shape[0], 2, 2, 3, 3)
        rows = np.broadcast_to(var[:, :, None, :, None], shape).ravel()
        cols = np.broadcast_to(var[:, None, :, None, :], shape).ravel()
        diag = np.arange(n2)
        keys = np.concatenate([cols, diag]) * n2 + np.concatenate([rows, diag])
        uniq, self._slot_of = np.unique(keys, return_inverse=True)
        self._indices = (uniq % n2).astype(np.int32)
        self._indptr = np.concatenate([[0], np.cumsum(np.bincount(uniq // n2,
                                                                  minlength=n2))])
        self._var = var
        self._fixed_nnz = self._indices.size
        self._symbolic: Any = None
        loop = disk.loop
        self.edge_a, self.edge_b = loop, np.roll(loop, -1)
        pos = m.vertices[loop]
        lengths = np.linalg.norm(np.roll(pos, -1, axis=0) - pos, axis=1)
        mean = float(lengths.mean())
        if initial is not None:                  # the start's boundary may be shorter
            start = np.asarray(initial, dtype=np.float64)[loop]
            mean = min(mean, float(np.linalg.norm(np.roll(start, -1, axis=0) - start,
                                                  axis=1).mean()))
        self.eps = BARRIER_WIDTH * mean
        self.lam = BARRIER_WEIGHT

    # -- energy ------------------------------------------------------------------------

    def _barrier_pairs(self, uv: FloatArray, reach_extra: float = 0.0
                       ) -> tuple[IntArray, IntArray]:
        """(edge slot, vertex slot) pairs with the vertex not on the edge nor next to it,
        and within ``eps + reach_extra`` of the edge's midpoint disk."""
        loop = self.loop
        b = loop.shape[0]
        if b < 4:
            return np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int64)
        pa, pb = uv[self.edge_a], uv[self.edge_b]
        length = np.linalg.norm(pb - pa, axis=1)
        e, k = _near_pairs(uv[loop], pa, pb, 0.5 * length + self.eps + reach_extra)
        off = (k - e) % b                  # edge e runs from slot e to slot e + 1
        keep = (off != 0) & (off != 1) & (off != 2) & (off != b - 1)
        return e[keep], k[keep]

    def _barrier(self, uv: FloatArray) -> tuple[float, IntArray, IntArray, FloatArray,
                                                 FloatArray, FloatArray]:
        e, k = self._barrier_pairs(uv)
        loop = self.loop
        d, s, nrm = _segment_distance(uv[loop[k]], uv[self.edge_a[e]], uv[self.edge_b[e]])
        act = d < self.eps
        e, k, d, s, nrm = e[act], k[act], d[act], s[act], nrm[act]
        with np.errstate(divide="ignore"):
            r = self.eps / d - 1.0
        return float(self.lam * np.dot(r, r)), e, k, d, s, nrm

    def energy(self, uv: FloatArray) -> float:
        """Objective at ``uv``: mean symmetric Dirichlet plus the barrier; ``inf`` when a
        face is flipped or collapsed."""
        sd = _sd(self.weight, jacobians(self.frames, self.mesh.faces, uv))
        if not np.isfinite(sd):
            return sd
        return sd + self._barrier(uv)[0]

    # -- one step ----------------------------------------------------------------------

    def _system(self, uv: FloatArray) -> tuple[sp.csc_array, FloatArray]:
        """The SLIM proxy Hessian (plus the barrier's Gauss-Newton term) and the gradient
        of the objective, both over ``x = [u; v]``."""
        f, n, g = self.mesh.faces, self.n, self.g
        J = jacobians(self.frames, f, uv)
        # closed-form 2×2 SVD J = Rot(φ) diag(s₁, s₂) Rot(θ) from the similarity part
        # (e, h) and the anti-similarity part (p, g); R = Rot(φ + θ) the nearest rotation
        a, b, c, d = J[:, 0, 0], J[:, 0, 1], J[:, 1, 0], J[:, 1, 1]
        e, p, gg, h = 0.5 * (a + d), 0.5 * (a - d), 0.5 * (c + b), 0.5 * (c - b)
        q, r = np.hypot(e, h), np.hypot(p, gg)
        s = np.maximum(np.stack([q + r, q - r], axis=1), 1e-12)
        rot, anti = np.arctan2(h, e), np.arctan2(gg, p)
        phi = 0.5 * (rot + anti)
        w2 = (s + 1.0) * (s * s + 1.0) / s ** 3          # squared SLIM weights, SD energy
        co, si = np.cos(phi), np.sin(phi)
        M = np.empty_like(J)                             # WᵀW = Rot(φ) diag(w²) Rot(φ)ᵀ
        M[:, 0, 0] = w2[:, 0] * co * co + w2[:, 1] * si * si
        M[:, 1, 1] = w2[:, 0] * si * si + w2[:, 1] * co * co
        M[:, 0, 1] = M[:, 1, 0] = (w2[:, 0] - w2[:, 1]) * co * si
        R = np.empty_like(J)
        R[:, 0, 0] = R[:, 1, 1] = np.cos(rot)
        R[:, 1, 0] = np.sin(rot)
        R[:, 0, 1] = -R[:, 1, 0]
        # proxy Σ_t A_t ‖W_t (J_t − R_t)‖²: J_t[b, c] = Σ_k g[t, k, c] x_b[f_tk], so its
        # Hessian block (b, k), (b', l) is 2 A_t (WᵀW)[b, b'] (g gᵀ)[k, l] and its gradient
        # (the energy's) Σ_c 2 A_t (WᵀW (J − R))[b, c] g[t, k, c]
        wt = 2.0 * self.weight
        gt = g.transpose(0, 2, 1)
        K = g @ gt
        hv = (wt[:, None, None, None, None] * M[:, :, :, None, None]
              * K[:, None, None, :, :])                                  # (m, b, b', k, l)
        var = self._var                                                  # (m, b, k)
        # np.bincount with weights sums float64 (its stub says intp)
        data = cast(FloatArray, np.bincount(
            self._slot_of, minlength=self._indices.size,
            weights=np.concatenate([hv.ravel(), np.full(2 * n, self.proximal)])))
        H = sp.csc_array((data, self._indices, self._indptr), shape=(2 * n, 2 * n))
        G = wt[:, None, None] * (M @ (J - R))
        grad = cast(FloatArray, np.bincount(var.ravel(), weights=(G @ gt).ravel(),
                                            minlength=2 * n))
        _, edge, slot, dist, s_, nrm = self._barrier(uv)
        if edge.size:
            loop = self.loop
            verts = np.stack([loop[slot], self.edge_a[edge], self.edge_b[edge]],
                             axis=1)                                                # (q, 3)
            coef = np.stack([np.ones_like(s_), s_ - 1.0, -s_], axis=1)             # ∂d/∂p
            dd = (coef[:, :, None] * nrm[:, None, :]).reshape(-1, 6)              # (q, 6)
            idx = (np.arange(2)[None, None, :] * n + verts[:, :, None]).reshape(-1, 6)
            r = self.eps / dist - 1.0
            dphi = -2.0 * self.lam * r * self.eps / dist ** 2
            hgn = 2.0 * self.lam * (self.eps / dist ** 2) ** 2
            grad += np.bincount(idx.ravel(), weights=(dphi[:, None] * dd).ravel(),
                                minlength=2 * n)
            bv = hgn[:, None, None] * dd[:, :, None] * dd[:, None, :]
            hr = np.broadcast_to(idx[:, :, None], bv.shape).ravel()
            hc = np.broadcast_to(idx[:, None, :], bv.shape).ravel()
            H = (H + sp.coo_array((bv.ravel(), (hr, hc)), shape=H.shape).tocsc()).tocsc()
        return H, grad

    def _max_crossing_free_step(self, uv: FloatArray, d: FloatArray, limit: float) -> float:
        """The first ``t`` in (0, limit] at which a boundary vertex meets a boundary edge
        it is not an end of, moving along ``d``; ``inf`` if none."""
        loop = self.loop
        b = loop.shape[0]
        if b < 4:
            return float("inf")
        pa, pb = uv[self.edge_a], uv[self.edge_b]
        move = float(np.linalg.norm(d[loop], axis=1).max()) * limit
        length = np.linalg.norm(pb - pa, axis=1)
        e, k = _near_pairs(uv[loop], pa, pb, 0.5 * length + 3.0 * move + 1e-12)
        off = (k - e) % b
        keep = (off != 0) & (off != 1)
        e, k = e[keep], k[keep]
        if e.size == 0:
            return float("inf")
        i, j, v = self.edge_a[e], self.edge_b[e], loop[k]
        a0, a1 = uv[j] - uv[i], d[j] - d[i]
        b0, b1 = uv[v] - uv[i], d[v] - d[i]
        c0 = _cross(a0, b0)
        c1 = _cross(a0, b1) + _cross(a1, b0)
        c2 = _cross(a1, b1)
        best = np.full(e.size, np.inf)
        for r in _smallest_positive_root(c0, c1, c2):
            ok = np.isfinite(r) & (r <= limit)
            rr = np.where(ok, r, 0.0)[:, None]
            at, bt = a0 + rr * a1, b0 + rr * b1
            s = np.einsum("ij,ij->i", bt, at) / np.maximum(np.einsum("ij,ij->i", at, at),
                                                           np.finfo(float).tiny)
            hit = ok & (s >= 0) & (s <= 1)
            best = np.where(hit, np.minimum(best, r), best)
        return float(best.min())

    def _solve(self, H: sp.csc_array, rhs: FloatArray) -> FloatArray:
        """Solve ``H x = rhs``. While ``H`` has the fixed sparsity (no barrier terms), CHOLMOD
        (through cvxopt, when installed) reuses one symbolic factorization (the
        fill-reducing ordering) across iterations; otherwise :class:`Factor`."""
        if H.nnz != self._fixed_nnz or not _HAVE_CVXOPT:
            return Factor(H, name="mesh").solve(rhs)
        import cvxopt
        import cvxopt.cholmod as cholmod

        if self._symbolic is None:
            col = np.repeat(np.arange(H.shape[1], dtype=np.int64), np.diff(H.indptr))
            low = H.indices >= col
            self._low = low
            self._ij = (cvxopt.matrix(H.indices[low].astype(np.int64)),
                        cvxopt.matrix(col[low]))
        m = cvxopt.spmatrix(cvxopt.matrix(H.data[self._low]), *self._ij, H.shape)
        try:
            if self._symbolic is None:
                self._symbolic = cholmod.symbolic(m, uplo="L")
            cholmod.numeric(m, self._symbolic)
        except ArithmeticError:                       # pragma: no cover - H is definite
            return Factor(H, name="mesh").solve(rhs)
        x = cvxopt.matrix(np.asfortranarray(rhs))
        cholmod.solve(self._symbolic, x)
        return np.array(x).reshape(rhs.shape)

    def step(self, uv: FloatArray, e0: float) -> tuple[FloatArray, float]:
        """One SLIM step with the line search; returns the new map and objective (the
        old ones when no step lowers the objective)."""
        n = self.n
        H, grad = self._system(uv)
        dx = -self._solve(H, grad)
        d = np.stack([dx[:n], dx[n:]], axis=1)
        t = min(1.0, STEP_FRACTION * max_flip_free_step(uv, self.mesh.faces, d))
        # a trial at or beyond the first contact of the boundary with itself is skipped,
        # not shortened, so that the halving sequence is libigl's whenever that is bijective
        contact = self._max_crossing_free_step(uv, d, t)
        slope = float(np.dot(grad, dx))
        if not slope < 0:
            return uv, e0
        for _ in range(60):
            if t < contact:
                cand = uv + t * d
                e = self.energy(cand)
                if e <= e0 + ARMIJO * t * slope:
                    return cand, e
            t *= 0.5
        return uv, e0

    def solve(self, initial: FloatArray, *, max_iterations: int, tolerance: float,
              progress: Progress | None = None) -> BijectiveResult:
        """Iterate from ``initial`` (``(n, 2)``, flip-free, positively oriented, boundary
        simple)."""
        report = as_progress(progress)
        uv = np.array(initial, dtype=np.float64)
        energies = [self.energy(uv)]
        converged = False
        for it in range(max_iterations):
            uv, e = self.step(uv, energies[-1])
            stalled = e >= energies[-1]
            energies.append(e)
            report(it + 1, max_iterations, f"iteration {it + 1}: energy {e:.6g}")
            if stalled or energies[-2] - e <= tolerance * e:
                converged = True
                break
        if not converged and tolerance > 0:
            warn(f"Bijective parameterization stopped after {max_iterations} "
                 f"iterations with the energy still falling faster than "
                 f"tolerance={tolerance}.", ConvergenceWarning)
        m = self.mesh
        q = quality(m.vertices, m.faces, uv, self.frames)
        sd = _sd(self.weight, jacobians(self.frames, m.faces, uv))
        return BijectiveResult(uv=uv, mesh=m, energy=np.array(energies),
                               symmetric_dirichlet=sd, iterations=len(energies) - 1,
                               converged=converged,
                               boundary_crossings=boundary_crossings(uv, self.loop),
                               **q.fields())


def tutte_start(disk: Disk) -> FloatArray:
    """A flip-free start: the mean value Tutte map onto the circle (uniform weights if
    rounding flipped a face), scaled so its area equals the surface's.

    Raises
    ------
    DegenerateInputError
        Both Tutte maps have a collapsed or flipped face: in exact arithmetic neither can
        (Tutte's theorem), so only faces thin or small enough for rounding to fold do.
    """
    m = disk.mesh
    circle = convex_boundary(disk, "circle")
    uv = _mean_value_solve(m, disk.loop, circle)
    if not (signed_areas(uv, m.faces) > 0).all():
        uv = pinned_map(disk, circle, "uniform")[0]
    sa = signed_areas(uv, m.faces)
    if not (sa > 0).all():
        t = int(np.argmin(sa))
        raise DegenerateInputError(
            f"Expected `mesh` to have a flip-free Tutte map to start from, got face {t} "
            f"collapsed in it by rounding (signed area {sa[t]:.3g}); remesh the thinnest or "
            f"smallest faces.", field="mesh")
    scale: float = np.sqrt(face_areas(m.vertices, m.faces).sum() / sa.sum())
    return uv * scale


@validate_params
def bijective(mesh: MeshLike, *, max_iterations: Annotated[int, Ge(1)] = 100,
              tolerance: Annotated[float, Ge(0)] = 1e-6,
              progress: Progress | None = None) -> BijectiveResult:
    r"""Bijective parameterization (symmetric Dirichlet, free boundary).

    Minimises the symmetric Dirichlet energy plus a boundary barrier from a flip-free Tutte start by
    SLIM steps; the line search never lets a face flip or the boundary cross itself (quadratic step
    bounds), so the map is bijective by construction. Reports flipped faces, angle distortion and
    area distortion.

    Minimises, over the UV positions :math:`u`,

    .. math::

        E(u) = \frac{\sum_t A_t \left(\lVert J_t\rVert_F^2 + \lVert J_t^{-1}\rVert_F^2
        \right)}{\sum_t A_t} + \lambda \sum_{e} \sum_{k}
        \max\!\left(0, \frac{\varepsilon}{d(u_k, e)} - 1\right)^2,

    the area-weighted symmetric Dirichlet energy (infinite on a collapsed face, so it
    keeps every face's orientation) plus Smith and Schaefer's boundary barrier
    (:math:`e` a boundary edge, :math:`k` a boundary vertex not on it or next to it,
    :math:`d` the distance from the vertex to the edge segment, :math:`\varepsilon` a
    quarter of the mean boundary edge length, :math:`\lambda = 10^{-2}`).

    * Start: the mean value Tutte map onto the circle, scaled to the surface's area:
      flip-free with a simple boundary (Tutte's theorem).
    * Direction: the SLIM step (Rabinovich et al. 2017): the minimiser of the reweighted
      quadratic proxy :math:`\sum_t A_t \lVert W_t (J_t - R_t)\rVert_F^2` whose gradient
      equals the energy's at the current map, plus the barrier's Gauss-Newton term; one
      sparse Cholesky solve over :math:`(u, v)`.
    * Line search: the first trial is 0.8 of the largest step at which no triangle's
      signed area reaches zero (per triangle, the smallest positive root of a quadratic in
      the step), capped at 1, then halved until the objective falls enough (Armijo).
      Trials at or beyond the first contact of a boundary vertex with a boundary edge (a
      quadratic in the step too, for the pairs a k-d tree finds within reach) are skipped.

    Every accepted step is therefore flip-free and keeps the boundary from touching itself
    all along the way: the map is bijective by construction, not by luck. While the
    barrier and the contact bound are idle, every step is libigl's SLIM step (the same
    proxy, proximal term and halving), so the two agree to rounding; where SLIM's
    free boundary overlaps itself (a strip wound more than once around an axis), this
    map stops at contact.

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or mapping
        A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
        vertex indices: connected, manifold, consistently oriented, exactly one boundary
        loop, every vertex in a face, no zero-area face.
    max_iterations : int, default 100
        Upper bound on SLIM iterations.
    tolerance : float, default 1e-6
        Stop when an iteration lowers the objective by at most this fraction; ``0`` runs
        all ``max_iterations`` (unless no step lowers it any more).
    progress : callable, optional
        ``progress(done, max_iterations, message)`` after every iteration; it may raise
        :class:`~algorithms.core.errors.Cancelled`.

    Returns
    -------
    BijectiveResult
        ``uv``, ``mesh``, ``energy`` (start, then per iteration), ``symmetric_dirichlet``,
        ``iterations``, ``converged``, ``boundary_crossings`` (0), flips (0) and
        distortion.

    Raises
    ------
    InvalidInputError
        A malformed mesh, a bad ``max_iterations`` or ``tolerance``.
    NotADiskError
        The mesh is not a topological disk; field ``mesh``.
    DegenerateInputError
        Zero-area faces, or faces so thin that rounding folds them in the Tutte start.
    Cancelled
        Raised by ``progress``.

    Notes
    -----
    **The barrier measures the distance to the segment**, as Smith and Schaefer's paper
    does. The triangle-inequality slack :math:`d_{ijk} = \lVert p_i - p_k\rVert +
    \lVert p_j - p_k\rVert - \lVert p_i - p_j\rVert`, sometimes used in its place, is
    zero on the segment too, but it measures how far the three points are from
    collinear, not how close :math:`p_k` is to the edge: at height :math:`h` over the
    middle of an edge of length :math:`\ell` it is about :math:`2h^2/\ell`, so its reach
    would depend on the edge's length. The two vertices next to an edge are left out
    (they cannot reach it without a face of theirs collapsing first, which the energy
    forbids; the line search still checks them). A scaffold mesh around the boundary
    (Jiang et al. 2017) is the other way to keep a free boundary from crossing itself;
    this keeps the paper's barrier.

    **Area weights.** The symmetric Dirichlet energy is weighted by face area, so that it
    does not depend on how finely a region is meshed.

    Smith and Schaefer minimise with a quasi-Newton method; SLIM's proxy converges in
    fewer iterations on the same energy, and the flip-free and contact-free step bounds
    are theirs. The proxy system is solved by CHOLMOD with one symbolic factorization
    reused across iterations while the barrier is idle.

    References
    ----------
    .. [1] J. Smith and S. Schaefer, "Bijective parameterization with free boundaries",
       ACM Trans. Graph. 34(4) (SIGGRAPH), 2015.
    .. [2] M. Rabinovich, R. Poranne, D. Panozzo and O. Sorkine-Hornung, "Scalable locally
       injective mappings", ACM Trans. Graph. 36(2), 2017.

    Examples
    --------
    A flat mesh is already an isometry: the result keeps its shape (energy 4).

    >>> import numpy as np
    >>> v = np.array([[0, 0], [2, 0], [2, 1], [0, 1], [1, 0.5]])
    >>> f = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    >>> res = bijective((v, f), max_iterations=200, tolerance=1e-12)
    >>> round(res.symmetric_dirichlet, 6), res.flipped_faces, res.boundary_crossings
    (4.0, 0, 0)
    """
    disk = read_disk(mesh)
    uv0 = tutte_start(disk)
    return BijectiveSolver(disk, uv0).solve(uv0, max_iterations=max_iterations,
                                       tolerance=tolerance, progress=progress)
