"""Parameterization: maps of a disk-like triangle mesh to the plane (``uv``), with the
flips and the angle and area distortion of each."""

from algorithms.parameterization._disk import NotADiskError, check_disk
from algorithms.parameterization._results import LocalGlobalResult, ParameterizationResult
from algorithms.parameterization.abf import AbfResult, abf
from algorithms.parameterization.arap import arap
from algorithms.parameterization.asap import asap
from algorithms.parameterization.bijective import BijectiveResult, bijective
from algorithms.parameterization.conformal import check_conformal, check_pins, conformal
from algorithms.parameterization.harmonic import harmonic
from algorithms.parameterization.stretch import StretchResult, stretch_minimizing
from algorithms.parameterization.tutte import tutte

__all__ = [
    "NotADiskError",
    "check_disk",
    "check_pins",
    "check_conformal",
    "ParameterizationResult",
    "LocalGlobalResult",
    "tutte",
    "harmonic",
    "conformal",
    "arap",
    "asap",
    "StretchResult",
    "stretch_minimizing",
    "BijectiveResult",
    "bijective",
    "AbfResult",
    "abf",
]
