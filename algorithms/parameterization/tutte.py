r"""Tutte's embedding of a disk-like mesh: boundary on a circle or square, every interior
vertex at a convex combination of its neighbours (uniform or mean value weights)."""

from __future__ import annotations

from typing import Any, Literal, get_args

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from algorithms.core.mesh import Mesh
from algorithms.core.params import MeshLike, validate_params
from algorithms.core.types import FloatArray
from algorithms.parameterization._disk import Boundary, convex_boundary, pinned_map, read_disk
from algorithms.parameterization._results import ParameterizationResult, direct_result

__all__ = ["tutte", "mean_value_weights", "TutteWeighting", "TUTTE_WEIGHTINGS"]

TutteWeighting = Literal["uniform", "mean_value"]
#: The accepted values of ``weighting``.
TUTTE_WEIGHTINGS = get_args(TutteWeighting)


def mean_value_weights(vertices: Any, faces: Any) -> sp.csr_array:
    r"""Floater's mean value weights, ``(n, n)``, not symmetric.

    .. math:: w_{ij} = \frac{\tan(\alpha_{ij}/2) + \tan(\beta_{ij}/2)}{\lVert p_j - p_i\rVert}

    with :math:`\alpha_{ij}, \beta_{ij}` the angles *at* :math:`p_i` of the two faces on
    edge :math:`(i, j)` (one on a boundary edge). Positive on every non-degenerate mesh.
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    n = v.shape[0]
    rows, cols, vals = [], [], []
    for k in range(3):
        i, j, h = f[:, k], f[:, (k + 1) % 3], f[:, (k + 2) % 3]
        a, b = v[j] - v[i], v[h] - v[i]
        la, lb = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
        cross = (np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]) if v.shape[1] == 2
                 else np.linalg.norm(np.cross(a, b), axis=1))
        half_tan = cross / (la * lb + np.einsum("ij,ij->i", a, b))   # tan(θ_i / 2)
        rows += [i, i]
        cols += [j, h]
        vals += [half_tan / la, half_tan / lb]
    w = sp.coo_array((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                     shape=(n, n)).tocsr()
    w.sum_duplicates()
    return w


def _mean_value_solve(mesh: Mesh, pinned: np.ndarray, values: FloatArray) -> FloatArray:
    w = mean_value_weights(mesh.vertices, mesh.faces)
    n = mesh.n_vertices
    lap = (sp.diags_array(np.asarray(w.sum(axis=1)).ravel()) - w).tocsr()
    free = np.setdiff1d(np.arange(n), pinned)
    rows = lap[free]
    x = np.empty((n, 2))
    x[pinned] = values
    if free.size:
        lu = sla.splu(sp.csc_matrix(rows[:, free]))
        x[free] = lu.solve(-(rows[:, pinned] @ values))
    return x


@validate_params
def tutte(mesh: MeshLike, *, boundary: Boundary = "circle",
          weighting: TutteWeighting = "uniform") -> ParameterizationResult:
    r"""Tutte embedding (circle or square boundary).

    Pins the boundary loop to a circle or square and puts every interior vertex at a convex
    combination of its neighbours (uniform or mean value weights): one sparse solve, no flipped
    faces. Reports flipped faces, angle distortion and area distortion.

    Solves, for the interior vertices :math:`u_i`,

    .. math:: \sum_j w_{ij} (u_i - u_j) = 0, \qquad u_{\text{boundary}} = c,

    with :math:`c` the boundary loop on the unit circle or the square :math:`[-1, 1]^2`,
    spaced by boundary edge length. Weights: ``"uniform"`` (:math:`w_{ij} = 1`, Tutte's
    barycentric map; symmetric, one Cholesky solve through
    :func:`algorithms.layout.laplacian`) or ``"mean_value"`` (Floater's mean value weights,
    :func:`mean_value_weights`: not symmetric, one LU solve; they reproduce a planar mesh
    whose boundary is pinned to its own convex outline).

    By Tutte's spring theorem in Floater's form (positive weights, each interior vertex a
    convex combination of its neighbours, boundary on a convex polygon), no face flips.

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or mapping
        A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
        vertex indices: connected, manifold, consistently oriented, exactly one boundary
        loop, every vertex in a face, no zero-area face.
    boundary : {"circle", "square"}, default "circle"
        The convex polygon the boundary loop is pinned to, its vertices spaced by boundary
        edge length: ``"circle"`` the unit circle; ``"square"`` the square
        :math:`[-1, 1]^2`, its corners at the four boundary vertices of smallest angle sum
        (the surface's own corners; at least 4 boundary vertices).
    weighting : {"uniform", "mean_value"}, default "uniform"
        The interior weights: ``"uniform"`` 1 per edge (Tutte's barycentric map);
        ``"mean_value"`` Floater's mean value weights (closer to conformal; a planar mesh
        pinned to its own convex outline comes back as itself). Both are positive, so no
        face flips.

    Returns
    -------
    ParameterizationResult
        ``uv``, ``mesh``, ``pinned`` (the boundary loop), ``energy`` (the spring energy
        :math:`\sum_{(i,j)} w_{ij}\lVert u_i - u_j\rVert^2`, each edge once, of the
        symmetrised weights), flips and distortion.

    Raises
    ------
    InvalidInputError
        A malformed mesh, an unknown option.
    NotADiskError
        The mesh is not a topological disk (closed, holes, several components,
        non-manifold, inconsistently oriented, unused vertices); field ``mesh``.
    DegenerateInputError
        Zero-area faces; ``boundary="square"`` with fewer than 4 boundary vertices.

    Notes
    -----
    **No flips.** With the boundary on a convex polygon and every weight positive, the
    solution is an embedding: no vertex outside the polygon, no crossing edges, no flipped
    face (Tutte 1963; Floater 2003 for any positive weights). The symmetric incentre
    (tangent) weights keep the guarantee too; they are
    :func:`algorithms.layout.laplacian` with ``weighting="tangent"``. Floater's mean value
    weights differ from them: they are per-vertex (not symmetric) and have linear
    precision.

    References
    ----------
    .. [1] W. T. Tutte, "How to draw a graph", Proc. London Math. Soc. 13 (1963).
    .. [2] M. S. Floater, "Mean value coordinates", CAGD 20(1), 19-27, 2003.

    Examples
    --------
    >>> v = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0.2]]
    >>> f = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    >>> res = tutte((v, f), boundary="square")
    >>> (res.uv.round(12) + 0.0).tolist(), res.flipped_faces
    ([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0], [0.0, 0.0]], 0)
    """
    disk = read_disk(mesh)
    m = disk.mesh
    values = convex_boundary(disk, boundary)
    if weighting == "uniform":
        uv, energy = pinned_map(disk, values, "uniform")
    else:
        uv = _mean_value_solve(m, disk.loop, values)
        w = mean_value_weights(m.vertices, m.faces)
        w = 0.5 * (w + w.T)
        lap = (sp.diags_array(np.asarray(w.sum(axis=1)).ravel()) - w).tocsr()
        energy = max(float(np.einsum("ij,ij->", uv, lap @ uv)), 0.0)
    return direct_result(m, uv, disk.loop, energy)

