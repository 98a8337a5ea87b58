"""ARAP parameterization: monotone energy, lower area distortion than LSCM, planar meshes
kept, convergence warnings and progress, option errors."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from algorithms.core.errors import ConvergenceWarning, InvalidInputError
from algorithms.parameterization import arap, conformal
from tests.algorithms.parameterization.param_meshes import bumpy, grid


def _pairwise(x: np.ndarray) -> np.ndarray:
    return np.linalg.norm(x[:, None] - x[None], axis=-1)


@pytest.mark.parametrize("seed", range(3))
def test_arap_energy_never_increases_and_lowers_area_distortion(seed: int) -> None:
    v, f = bumpy(seed=seed)
    res = arap((v, f), init="harmonic", max_iterations=40, tolerance=0)
    assert np.all(np.diff(res.energy) <= 1e-12 * res.energy[0])
    assert res.energy[-1] < 0.5 * res.energy[0]
    assert res.flipped_faces == 0
    lscm = conformal((v, f))
    assert res.area_distortion < lscm.area_distortion
    assert res.iterations == 40  # tolerance 0: every iteration, as libigl runs them


def test_tolerance_zero_runs_past_the_energy_s_plateau() -> None:
    # 1000 iterations on a bumpy disk: the energy stops falling long before (the run with a
    # tolerance stops there), tolerance 0 still runs them all (libigl's arap_solve)
    v, f = bumpy(seed=0)
    stopped = arap((v, f), max_iterations=1000, tolerance=1e-12)
    everything = arap((v, f), max_iterations=1000, tolerance=0)
    assert stopped.converged and stopped.iterations < 1000
    assert everything.iterations == 1000
    np.testing.assert_allclose(everything.energy[:len(stopped.energy)], stopped.energy,
                               rtol=1e-12)


def test_arap_keeps_a_planar_mesh() -> None:
    v, f = grid(7, 6, jitter=0.3, seed=1)
    res = arap((v, f), max_iterations=500, tolerance=1e-14)
    np.testing.assert_allclose(_pairwise(res.uv), _pairwise(v), atol=1e-7)
    assert res.converged and res.energy[-1] < 1e-12


def test_not_converging_warns_and_progress_is_called() -> None:
    v, f = bumpy()
    seen = []
    with pytest.warns(ConvergenceWarning, match="ARAP parameterization stopped after 2"):
        res = arap((v, f), init="harmonic", max_iterations=2, tolerance=1e-12,
                   progress=lambda d, t, msg: seen.append((d, t)))
    assert not res.converged and seen == [(1, 2), (2, 2)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        arap((v, f), max_iterations=2, tolerance=0)          # tolerance 0: no warning


def test_option_errors() -> None:
    v, f = bumpy()
    with pytest.raises(InvalidInputError, match="Expected `init` to be one of 'lscm', "
                       "'harmonic', got 'tutte'"):
        arap((v, f), init="tutte")
    with pytest.raises(InvalidInputError, match=r"Expected `max_iterations` to be an integer "
                       r">= 1, got 0\."):
        arap((v, f), max_iterations=0)
    with pytest.raises(InvalidInputError, match=r"Expected `tolerance` to be a number >= 0, "
                       r"got -1"):
        arap((v, f), tolerance=-1)
