"""Cases ported from pycpd's own tests (testing/rigid_test.py, affine_test.py,
deformable_test.py), each naming the original. pycpd's tests load its fish outline
(data/fish_*.txt, not shipped in its wheel); here a fish-like closed outline of 91 points
stands in, with pycpd's transforms and tolerances.

Convention: pycpd moves row vectors as ``Y @ R + t`` and reports that ``R``; ours moves
``source @ rotation.T + translation`` (column vectors, scipy's and Open3D's convention), so
our ``rotation`` is pycpd's ``R`` transposed, and likewise ``linear`` for pycpd's ``B``."""

from __future__ import annotations

import numpy as np
from numpy.testing import assert_almost_equal, assert_array_almost_equal
from pycpd import AffineRegistration, DeformableRegistration, RigidRegistration

from algorithms.registration import cpd


def _fish(n: int = 91) -> np.ndarray:
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    body = np.c_[np.cos(t) * (1 + 0.3 * np.cos(2 * t)), 0.5 * np.sin(t) * (1 + 0.4 * np.cos(t))]
    tail = np.c_[-1.2 - 0.4 * np.abs(np.sin(3 * t)), 0.6 * np.sin(t)]
    return np.where((np.cos(t) < -0.85)[:, None], tail, body)


def _bent(y: np.ndarray) -> np.ndarray:
    # a smooth non-rigid bend of the outline (pycpd's fish_source is a warped fish_target)
    return y + np.c_[0.1 * np.sin(2 * y[:, 1]), 0.15 * y[:, 0] ** 2 - 0.1]


THETA = np.pi / 6.0


# pycpd: testing/rigid_test.py::test_2D
def test_rigid_2d() -> None:
    r = np.array([[np.cos(THETA), -np.sin(THETA)], [np.sin(THETA), np.cos(THETA)]])
    t = np.array([0.5, 1.0])
    y = _fish()
    x = y @ r + t
    res = cpd(y, x)
    assert_almost_equal(1.0, res.scale)
    assert_array_almost_equal(r.T, res.rotation)
    assert_array_almost_equal(t, res.translation)
    assert_array_almost_equal(x, res.moved)
    _, (s_ref, r_ref, t_ref) = RigidRegistration(X=x, Y=y).register()
    assert_array_almost_equal(r_ref.T, res.rotation)


# pycpd: testing/rigid_test.py::test_3D
def test_rigid_3d() -> None:
    r = np.array([[np.cos(THETA), -np.sin(THETA), 0], [np.sin(THETA), np.cos(THETA), 0],
                  [0, 0, 1]])
    t = np.array([0.5, 1.0, -2.0])
    y = np.c_[_fish(), np.zeros(91)]
    x = y @ r + t
    res = cpd(y, x)
    assert_almost_equal(1.0, res.scale)
    assert_array_almost_equal(r.T, res.rotation)
    assert_array_almost_equal(t, res.translation)
    assert_array_almost_equal(x, res.moved)


# pycpd: testing/affine_test.py::test_2D
def test_affine_2d() -> None:
    b = np.array([[1.0, 0.5], [0, 1.0]])
    t = np.array([0.5, 1.0])
    y = _fish()
    x = y @ b + t
    res = cpd(y, x, model="affine")
    assert_array_almost_equal(b.T, res.linear)
    assert_array_almost_equal(t, res.translation)
    assert_array_almost_equal(x, res.moved)
    _, (b_ref, t_ref) = AffineRegistration(X=x, Y=y).register()
    assert_array_almost_equal(b_ref.T, res.linear)


# pycpd: testing/affine_test.py::test_3D (two parallel copies of the outline)
def test_affine_3d() -> None:
    b = np.array([[1.0, 0.5, 0.0], [0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    t = np.array([0.5, 1.0, -2.0])
    f = _fish()
    y = np.vstack([np.c_[f, np.zeros(91)], np.c_[f, np.ones(91)]])
    x = y @ b + t
    res = cpd(y, x, model="affine")
    assert_array_almost_equal(b.T, res.linear)
    assert_array_almost_equal(t, res.translation)
    assert_array_almost_equal(x, res.moved)


# pycpd: testing/deformable_test.py::test_2D (pycpd's tolerance: 1 decimal)
def test_deformable_2d() -> None:
    x = _fish()
    y = _bent(x)
    res = cpd(y, x, model="nonrigid")
    assert_array_almost_equal(x, res.moved, decimal=1)
    ty, _ = DeformableRegistration(X=x, Y=y).register()
    assert_array_almost_equal(ty, res.moved, decimal=1)


# pycpd: testing/deformable_test.py::test_3D and test_3D_low_rank (0 decimals)
def test_deformable_3d_and_low_rank() -> None:
    f = _fish()
    x = np.vstack([np.c_[f, np.zeros(91)], np.c_[f, np.ones(91)]])
    y = np.vstack([np.c_[_bent(f), np.zeros(91)], np.c_[_bent(f), np.ones(91)]])
    assert_array_almost_equal(cpd(y, x, model="nonrigid").moved, x, decimal=0)
    assert_array_almost_equal(cpd(y, x, model="nonrigid", low_rank=40).moved, x, decimal=0)
