"""Tests for deformation.isotropic_scaling: fixed points (rest, translation, uniform
scaling), the closed-form scale step, the length ratios of the previous iterate."""

from __future__ import annotations

import numpy as np
import pytest

from algorithms.core import Cancelled, DegenerateInputError, InvalidInputError
from algorithms.deformation import IsotropicScalingResult, isotropic_scaling
from tests.algorithms.deformation.deformation_meshes import bumpy_sheet, grid


def test_rest_and_translation_are_reached_in_the_first_iteration():
    v, f = bumpy_sheet()
    idx = np.array([0, 8, 54])
    for shift in ([0.0, 0.0, 0.0], [1.0, 2.0, -3.0]):
        res = isotropic_scaling((v, f), {"indices": idx, "positions": v[idx] + shift})
        assert isinstance(res, IsotropicScalingResult)
        np.testing.assert_allclose(res.mesh.vertices, v + shift, atol=1e-12)
        np.testing.assert_allclose(res.scales, 1.0, atol=1e-12)
        # the first step reaches them; the second confirms nothing moves any more
        assert res.iterations == (1 if shift[0] == 0 else 2) and res.converged
        assert max(res.energy) < 1e-10


@pytest.mark.parametrize("factor", [0.5, 2.0, 3.0])
def test_uniform_scaling_is_the_fixed_point(factor):
    v, f = grid(6, 5, jitter=0.2)
    idx = np.array([0, 29])
    centre = np.array([1.0, 1.5])
    target = factor * (v - centre) + centre
    res = isotropic_scaling((v, f), {"indices": idx, "positions": target[idx]},
                            tolerance=1e-10, max_iterations=1000)
    assert res.converged
    np.testing.assert_allclose(res.mesh.vertices, target, atol=1e-7)
    np.testing.assert_allclose(res.scales, factor, atol=1e-7)
    assert res.energy[-1] < 1e-12 * res.energy[0]


def test_scales_are_the_closed_form_of_the_result():
    # s_c = Σ e'·e / Σ |e|² over the face's edges
    v, f = bumpy_sheet()
    idx = np.array([0, 8, 54, 62])
    pos = v[idx] * [1.5, 1.0, 1.0]
    res = isotropic_scaling((v, f), {"indices": idx, "positions": pos}, max_iterations=5,
                            tolerance=0.0)
    x = res.mesh.vertices
    num = sum(np.einsum("ij,ij->i", x[f[:, a]] - x[f[:, b]], v[f[:, a]] - v[f[:, b]])
              for a, b in ((0, 1), (1, 2), (2, 0)))
    den = sum(np.einsum("ij,ij->i", v[f[:, a]] - v[f[:, b]], v[f[:, a]] - v[f[:, b]])
              for a, b in ((0, 1), (1, 2), (2, 0)))
    np.testing.assert_allclose(res.scales, num / den, rtol=1e-12)


def test_each_step_uses_the_previous_lengths():
    # One more iteration from the result changes nothing (a fixed point of the
    # previous-iterate scheme), and the energy reported is the objective of the returned vertices.
    v, f = grid(5, 4, jitter=0.1)
    idx = np.array([0, 4, 15, 19])
    pos = v[idx] * [[1.0, 1.0]] + [[0, 0], [1, 0], [0, 0.5], [1, 0.5]]
    res = isotropic_scaling((v, f), {"indices": idx, "positions": pos}, tolerance=1e-12,
                            max_iterations=2000, regularization=0.5)
    x = res.mesh.vertices
    e = np.concatenate([v[f[:, a]] - v[f[:, b]] for a, b in ((1, 2), (2, 0), (0, 1))])
    ep = np.concatenate([x[f[:, a]] - x[f[:, b]] for a, b in ((1, 2), (2, 0), (0, 1))])
    s = np.tile(res.scales, 3)
    ratio = np.linalg.norm(ep, axis=1) / np.linalg.norm(e, axis=1)
    by_hand = np.sum((ep - s[:, None] * e) ** 2) + 0.5 * np.sum((ep - ratio[:, None] * e) ** 2)
    assert res.energy[-1] == pytest.approx(by_hand, rel=1e-9, abs=1e-15)
    again = isotropic_scaling((v, f), {"indices": idx, "positions": pos}, tolerance=1e-12,
                              max_iterations=2001, regularization=0.5)
    np.testing.assert_allclose(again.mesh.vertices, x, atol=1e-9)


def test_regularization_zero_and_progress():
    v, f = grid(4, 4)
    calls = []
    isotropic_scaling((v, f), {"indices": [0, 15], "positions": [[0, 0], [6, 3]]},
                      regularization=0.0, max_iterations=3, tolerance=0.0,
                      progress=lambda d, t, m="": calls.append((d, t)))
    assert calls == [(1, 3), (2, 3), (3, 3)]

    def stop(done, total, msg=""):
        raise Cancelled("stop")

    with pytest.raises(Cancelled):
        isotropic_scaling((v, f), {"indices": [0, 15], "positions": [[0, 0], [6, 3]]},
                          progress=stop)


def test_errors():
    v, f = grid(3, 3)
    two_v, two_f = np.vstack([v, v + 5]), np.vstack([f, f + 9])
    with pytest.raises(DegenerateInputError, match="component of 9 vertices") as info:
        isotropic_scaling((two_v, two_f), {"indices": [0], "positions": [[0, 0]]})
    assert info.value.field == "handles"
    with pytest.raises(InvalidInputError, match=">= 0") as info:
        isotropic_scaling((v, f), {"indices": [0], "positions": [[0, 0]]}, regularization=-1)
    assert info.value.field == "regularization"
    for name, bad, fragment in (("max_iterations", 0, ">= 1"), ("tolerance", -1.0, ">= 0")):
        with pytest.raises(InvalidInputError, match=fragment) as info:
            isotropic_scaling((v, f), {"indices": [0], "positions": [[0, 0]]}, **{name: bad})
        assert info.value.field == name
