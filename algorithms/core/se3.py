r"""Rigid motions of 3-D space, SE(3), and their Lie algebra: the exponential and logarithm,
the inverse, the adjoints and the inverse left Jacobian.

A rigid motion is the homogeneous ``(4, 4)`` matrix :math:`T = [[R, t], [0, 1]]` with
:math:`R^\mathsf{T} R = I`, :math:`\det R = 1`; it maps :math:`x \mapsto R x + t`.
A *twist* is the 6-vector :math:`\xi = (\omega, v)`, rotation first, the coordinates of the
Lie algebra element :math:`\hat\xi = [[\,[\omega]_\times, v], [0, 0]]` with
:math:`T = \exp(\hat\xi)`; :math:`[\omega]_\times` is the cross-product matrix
(:func:`hat`), :math:`\omega` the rotation vector (axis times angle).

These are the inner-loop helpers of pose-graph optimisation: they trust their inputs (a
finite rigid motion, a finite 6-vector) and check nothing.

References
----------
.. [1] J. L. Blanco-Claraco, "A tutorial on SE(3) transformation parameterizations and
   on-manifold optimization", arXiv:2103.15980, 2021.
.. [2] T. D. Barfoot, *State Estimation for Robotics*, Cambridge University Press, 2017,
   chapter 7 (the adjoints and the Jacobians of SE(3)).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

from algorithms.core.types import FloatArray

__all__ = ["hat", "inverse", "adjoint", "ad", "left_jacobian_inverse", "exp", "log"]

#: Below this rotation angle (radians) :func:`exp` uses the Taylor series of its
#: coefficients: the closed forms cancel catastrophically near zero.
EXP_SERIES_BELOW = 1e-2
#: Below this angle :func:`log` takes the rotation vector from the series of
#: :math:`\theta / \sin\theta`; within it of a half turn, from the matrix (the skew part
#: vanishes there).
LOG_ROTATION_SERIES_BELOW = 1e-2
#: Below this angle :func:`log` uses the series of the coefficient of
#: :math:`[\omega]_\times^2` in :math:`V^{-1}`.
LOG_SERIES_BELOW = 1e-1


def hat(w: FloatArray) -> FloatArray:
    r"""The cross-product matrix :math:`[w]_\times` of a 3-vector: :math:`[w]_\times x = w
    \times x`."""
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def inverse(t: FloatArray) -> FloatArray:
    r"""The inverse :math:`[[R^\mathsf{T}, -R^\mathsf{T} t], [0, 1]]` of a rigid motion
    (exact: no matrix inversion)."""
    out = np.eye(4)
    out[:3, :3] = t[:3, :3].T
    out[:3, 3] = -t[:3, :3].T @ t[:3, 3]
    return out


def adjoint(t: FloatArray) -> FloatArray:
    r"""The ``(6, 6)`` adjoint :math:`\operatorname{Ad}_T = [[R, 0], [[t]_\times R, R]]` of a
    rigid motion, acting on twists :math:`(\omega, v)`: :math:`\exp(\operatorname{Ad}_T \xi)
    = T \exp(\xi)\, T^{-1}`."""
    r = t[:3, :3]
    out = np.zeros((6, 6))
    out[:3, :3] = r
    out[3:, 3:] = r
    out[3:, :3] = hat(t[:3, 3]) @ r
    return out


def ad(xi: FloatArray) -> FloatArray:
    r"""The ``(6, 6)`` adjoint of a twist, :math:`\operatorname{ad}_\xi = [[\,[\omega]_\times,
    0], [[v]_\times, [\omega]_\times]]`: the derivative of :math:`\operatorname{Ad}` at the
    identity, :math:`\operatorname{ad}_\xi \eta` the Lie bracket :math:`[\xi, \eta]`."""
    out = np.zeros((6, 6))
    wx = hat(xi[:3])
    out[:3, :3] = wx
    out[3:, 3:] = wx
    out[3:, :3] = hat(xi[3:])
    return out


def left_jacobian_inverse(xi: FloatArray) -> FloatArray:
    r"""The inverse left Jacobian of SE(3) to second order,
    :math:`J_l^{-1}(\xi) \approx I - \tfrac12 \operatorname{ad}_\xi + \tfrac1{12}
    \operatorname{ad}_\xi^2`.

    :math:`J_l^{-1}(\xi)\,\delta` is the change of :math:`\log(\exp(\delta) \exp(\xi))` for a
    small left increment :math:`\delta`; the series' next term is of fourth order in
    :math:`\xi` (the Bernoulli numbers: :math:`B_3 = 0`), so the truncation is accurate for
    the small residual twists of an optimisation near its minimum.
    """
    a = ad(xi)
    return np.eye(6) - 0.5 * a + a @ a / 12.0


def exp(xi: FloatArray) -> FloatArray:
    r"""The rigid motion :math:`\exp(\hat\xi)` of the twist :math:`\xi = (\omega, v)`.

    With :math:`\theta = \lVert\omega\rVert` and :math:`W = [\omega]_\times`,

    .. math::

        R = I + \frac{\sin\theta}{\theta} W + \frac{1 - \cos\theta}{\theta^2} W^2, \qquad
        t = \Big(I + \frac{1 - \cos\theta}{\theta^2} W
        + \frac{\theta - \sin\theta}{\theta^3} W^2\Big) v

    (Rodrigues' formula and the left Jacobian of SO(3)); below
    :data:`EXP_SERIES_BELOW` the three coefficients come from their Taylor series.
    """
    w, v = xi[:3], xi[3:]
    theta = math.sqrt(float(w @ w))
    wx = hat(w)
    if theta < EXP_SERIES_BELOW:  # series: the closed forms cancel catastrophically near 0
        t2 = theta * theta
        sin_c = 1.0 - t2 / 6.0 + t2 * t2 / 120.0
        a = 0.5 - t2 / 24.0 + t2 * t2 / 720.0
        b = 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0
    else:
        sin_c = math.sin(theta) / theta
        a = (1.0 - math.cos(theta)) / theta ** 2
        b = (theta - math.sin(theta)) / theta ** 3
    wx2 = wx @ wx
    out = np.eye(4)
    out[:3, :3] = np.eye(3) + sin_c * wx + a * wx2
    out[:3, 3] = (np.eye(3) + a * wx + b * wx2) @ v
    return out


def log(t: FloatArray) -> FloatArray:
    r"""The twist :math:`(\omega, v)` of a rigid motion, the inverse of :func:`exp` for
    rotation angles :math:`\theta = \lVert\omega\rVert \le \pi`.

    The angle is :math:`\operatorname{atan2}(\lVert s\rVert, (\operatorname{tr} R - 1)/2)`
    with :math:`s` the axial vector of :math:`(R - R^\mathsf{T})/2` (accurate at every
    angle, unlike :math:`\arccos`), :math:`\omega = \theta\, s / \lVert s\rVert` (near a half
    turn, where :math:`s` vanishes, from the matrix itself), and

    .. math::

        v = \Big(I - \tfrac12 W + \frac{1}{\theta^2}\Big(1 - \frac{\theta\sin\theta}
        {2(1 - \cos\theta)}\Big) W^2\Big)\, t,

    the inverse of the left Jacobian of SO(3), by its Taylor series below
    :data:`LOG_SERIES_BELOW`.
    """
    r = t[:3, :3]
    skew = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]) / 2.0
    sin = math.sqrt(float(skew @ skew))
    theta = math.atan2(sin, (float(np.trace(r)) - 1.0) / 2.0)
    if theta < LOG_ROTATION_SERIES_BELOW:
        w = skew * (1.0 + theta ** 2 / 6.0 + 7.0 * theta ** 4 / 360.0)
    elif theta < math.pi - LOG_ROTATION_SERIES_BELOW:
        w = skew * (theta / sin)
    else:  # near a half turn the skew part vanishes: take the axis from the matrix
        w = Rotation.from_matrix(r).as_rotvec()
        theta = float(np.linalg.norm(w))
    wx = hat(w)
    if theta < LOG_SERIES_BELOW:  # series: the closed form cancels catastrophically near 0
        t2 = theta * theta
        c = 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0 + t2 ** 3 / 1209600.0
    else:
        c = (1.0 - theta * math.sin(theta) / (2.0 * (1.0 - math.cos(theta)))) / theta ** 2
    v = (np.eye(3) - 0.5 * wx + c * wx @ wx) @ t[:3, 3]
    return np.concatenate([w, v])
