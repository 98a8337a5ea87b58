"""ASAP parameterization: it converges to LSCM with the same pins, starts converged from
LSCM, and checks its options."""

from __future__ import annotations

import numpy as np
import pytest

from algorithms.core.errors import InvalidInputError
from algorithms.parameterization import asap, conformal
from algorithms.parameterization._disk import read_disk
from algorithms.parameterization.conformal import farthest_boundary_pair
from tests.algorithms.parameterization.param_meshes import bumpy, cap


def test_asap_converges_to_lscm_with_the_same_pins() -> None:
    v, f = cap(rings=5, sectors=16)
    res = asap((v, f), init="harmonic", max_iterations=3000, tolerance=1e-13)
    assert np.all(np.diff(res.energy) <= 1e-12 * res.energy[0])
    disk = read_disk((v, f))
    pins = farthest_boundary_pair(disk)
    lscm = conformal((v, f), pins={"indices": pins, "positions": res.uv[pins]})
    np.testing.assert_allclose(res.uv, lscm.uv, atol=1e-4 * np.ptp(lscm.uv))
    assert res.energy[-1] == pytest.approx(lscm.energy, rel=1e-4)


def test_asap_from_lscm_is_already_converged() -> None:
    v, f = bumpy()
    res = asap((v, f), init="lscm")
    assert res.converged and res.iterations <= 2
    assert res.energy[-1] == pytest.approx(res.energy[0], rel=1e-9)


def test_option_errors() -> None:
    v, f = bumpy()
    with pytest.raises(InvalidInputError, match="Expected `init` to be one of 'lscm', "
                       "'harmonic', got 'tutte'"):
        asap((v, f), init="tutte")
    with pytest.raises(InvalidInputError, match=r"Expected `max_iterations` to be an integer "
                       r">= 1, got 0\."):
        asap((v, f), max_iterations=0)
    with pytest.raises(InvalidInputError, match=r"Expected `tolerance` to be a number >= 0, "
                       r"got -1"):
        asap((v, f), tolerance=-1)
