"""Stretch-minimizing parameterization: Sander et al.'s L2 stretch by hand and against
their per-triangle formula, the reweighting lowering it below the mean value Tutte start,
no flips on convex boundaries."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from algorithms.core.errors import ConvergenceWarning, DegenerateInputError, InvalidInputError
from algorithms.parameterization import NotADiskError, stretch_minimizing, tutte
from algorithms.parameterization._quality import face_frames
from algorithms.parameterization.stretch import face_stretch, l2_stretch
from tests.algorithms.parameterization.param_meshes import bumpy, cap, grid


def _sander_l2(v: np.ndarray, f: np.ndarray, uv: np.ndarray) -> float:
    """Sander et al. 2001, section 3: the partial derivatives S_s, S_t of the map from
    texture (s, t) to the surface, a = S_s·S_s, c = S_t·S_t, L2 = sqrt((a + c)/2), and the
    surface-area-weighted norm rescaled by sqrt(texture area / surface area)."""
    q = v[f]
    s, t = uv[f][..., 0], uv[f][..., 1]
    area2 = ((s[:, 1] - s[:, 0]) * (t[:, 2] - t[:, 0])
             - (s[:, 2] - s[:, 0]) * (t[:, 1] - t[:, 0])) / 2      # signed texture area
    ss = (q[:, 0] * (t[:, 1] - t[:, 2])[:, None] + q[:, 1] * (t[:, 2] - t[:, 0])[:, None]
          + q[:, 2] * (t[:, 0] - t[:, 1])[:, None]) / (2 * area2[:, None])
    st = (q[:, 0] * (s[:, 2] - s[:, 1])[:, None] + q[:, 1] * (s[:, 0] - s[:, 2])[:, None]
          + q[:, 2] * (s[:, 1] - s[:, 0])[:, None]) / (2 * area2[:, None])
    l2sq = 0.5 * ((ss * ss).sum(1) + (st * st).sum(1))
    a3 = 0.5 * np.linalg.norm(np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]), axis=1)
    return float(np.sqrt((a3 * l2sq).sum() / a3.sum()) * np.sqrt(np.abs(area2).sum()
                                                                 / a3.sum()))


def test_stretch_by_hand() -> None:
    tri = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    f = np.array([[0, 1, 2]])
    uv = tri[:, :2] * [2.0, 1.0]           # J = diag(2, 1): Γ = 1, γ = 1/2
    l2sq, linf = face_stretch(face_frames(tri, f), f, uv)
    assert l2sq[0] == pytest.approx((1 + 0.25) / 2, rel=1e-14)
    assert linf[0] == pytest.approx(1.0, rel=1e-14)
    # normalised by sqrt(plane area / surface area) = sqrt(2)
    assert l2_stretch(tri, f, uv) == pytest.approx(np.sqrt(1.25), rel=1e-14)
    assert l2_stretch(tri, f, 3.0 * tri[:, :2]) == pytest.approx(1.0, rel=1e-14)


@pytest.mark.parametrize("seed", range(3))
def test_l2_stretch_equals_sanders_formula(seed: int) -> None:
    v, f = bumpy(seed=seed)
    uv = tutte((v, f), weighting="mean_value").uv
    assert l2_stretch(v, f, uv) == pytest.approx(_sander_l2(v, f, uv), rel=1e-12)


@pytest.mark.parametrize("mesh, boundary, gain", [
    (bumpy(seed=0), "circle", 0.01), (bumpy(seed=1), "square", 1e-5),
    (cap(), "circle", 0.01), (cap(6, 20), "square", 0.01),
])
def test_lowers_stretch_below_the_tutte_start_without_flips(mesh, boundary,  # noqa: ANN001
                                                            gain: float) -> None:
    v, f = mesh
    start = tutte((v, f), boundary=boundary, weighting="mean_value")
    res = stretch_minimizing((v, f), boundary=boundary)
    assert res.stretch[0] == pytest.approx(l2_stretch(v, f, start.uv), rel=1e-12)
    assert res.l2_stretch < res.stretch[0] * (1 - gain)
    assert res.l2_stretch == pytest.approx(l2_stretch(v, f, res.uv), rel=1e-12)
    assert res.l2_stretch == res.stretch.min()
    assert res.flipped_faces == 0 and res.degenerate_faces == 0
    np.testing.assert_allclose(res.uv[res.pinned], start.uv[start.pinned], atol=1e-12)
    assert res.max_stretch >= res.l2_stretch


@pytest.mark.parametrize("seed", range(5))
@pytest.mark.parametrize("power", [0.5, 1.0, 2.0])
def test_no_flips_on_convex_boundaries(seed: int, power: float) -> None:
    v, f = bumpy(9, 8, seed=seed)
    res = stretch_minimizing((v, f), power=power, max_iterations=8, tolerance=0)
    assert res.flipped_faces == 0 and res.degenerate_faces == 0
    assert res.l2_stretch <= res.stretch[0]


def test_planar_square_is_already_stretch_free() -> None:
    v, f = grid(6, 6, jitter=0.3, seed=2)          # its outline is the square itself
    res = stretch_minimizing((v, f), boundary="square")
    assert res.stretch[0] == pytest.approx(1.0, abs=1e-12)
    assert res.l2_stretch == pytest.approx(1.0, abs=1e-12) and res.converged
    np.testing.assert_allclose(res.uv, 2.0 * v / 5.0 - 1.0, atol=1e-10)


def test_not_converging_warns_and_progress_is_called() -> None:
    v, f = cap()
    seen = []
    with pytest.warns(ConvergenceWarning, match="Stretch minimization stopped after 1"):
        res = stretch_minimizing((v, f), max_iterations=1, tolerance=1e-12,
                                 progress=lambda d, t, msg: seen.append((d, t)))
    assert not res.converged and seen == [(1, 1)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        stretch_minimizing((v, f), max_iterations=1, tolerance=0)


def test_errors() -> None:
    v, f = bumpy(6, 5)
    with pytest.raises(InvalidInputError, match="Expected `boundary` to be one of 'circle', "
                       "'square', got 'hexagon'"):
        stretch_minimizing((v, f), boundary="hexagon")
    for power in (0, -1.0, 4.5):
        with pytest.raises(InvalidInputError, match=r"Expected `power` to be a number > 0 and "
                           r"<= 4, got"):
            stretch_minimizing((v, f), power=power)
    with pytest.raises(InvalidInputError,
                       match=r"Expected `max_iterations` to be an integer >= 1, got 0\."):
        stretch_minimizing((v, f), max_iterations=0)
    with pytest.raises(InvalidInputError,
                       match=r"Expected `tolerance` to be a number >= 0, got -1"):
        stretch_minimizing((v, f), tolerance=-1)
    tetra = ([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
             [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
    with pytest.raises(NotADiskError, match="closed mesh"):
        stretch_minimizing(tetra)
    flat = ([[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0]], [[0, 1, 3], [1, 2, 3], [0, 2, 1]])
    with pytest.raises(DegenerateInputError, match="zero-area"):
        stretch_minimizing(flat)
    with pytest.raises(NotADiskError, match="vertex 30 in no face"):
        stretch_minimizing((np.vstack([v, [[9, 9, 9]]]), f))
