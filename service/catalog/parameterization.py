"""Catalog entries of the parameterization family (a disk-like mesh in, ``uv`` out, with the
flips and the angle and area distortion of the map)."""

from __future__ import annotations

from functools import partial

from algorithms.core.params import Le
from algorithms.parameterization import (
    abf,
    arap,
    asap,
    bijective,
    check_conformal,
    check_disk,
    conformal,
    harmonic,
    stretch_minimizing,
    tutte,
)
from service import scenes
from service.catalog.registry import Process, registry

# A 3 × 3-vertex sheet bent over a ridge: the smallest useful curved disk
_SHEET = {"vertices": [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0],
                       [0, 2, 0], [1, 2, 0.3], [2, 2, 0]],
          "faces": [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6],
                    [4, 5, 8], [4, 8, 7]]}
_UV = ("uv", "texture coordinates")

# the mesh is a topological disk
_disk = partial(Process, geometry=scenes.uv_mesh, check=check_disk, examples={"mesh": _SHEET})
_iterative = partial(_disk, long=True, limits={"max_iterations": Le(100_000)})

registry.add(_disk(tutte, fast_path=True, keywords=(*_UV, "tutte", "mean value", "flattening")))
registry.add(_disk(harmonic, fast_path=True,
                   keywords=(*_UV, "harmonic", "cotangent", "flattening")))
registry.add(_disk(conformal, check=check_conformal,
                   examples={"mesh": _SHEET,
                             "pins": {"indices": [0, 2], "positions": [[0, 0], [2, 0]]}},
                   keywords=(*_UV, "lscm", "conformal", "spectral", "free boundary")))
registry.add(_iterative(arap, keywords=(*_UV, "arap", "isometric", "local/global")))
registry.add(_iterative(asap, keywords=(*_UV, "asap", "conformal", "local/global")))
registry.add(_iterative(stretch_minimizing, limits={"max_iterations": Le(10_000)},
                        keywords=(*_UV, "stretch", "texture stretch", "yoshizawa",
                                  "sander")))
registry.add(_iterative(bijective, keywords=(*_UV, "bijective", "injective",
                                             "symmetric dirichlet", "slim", "free boundary")))
registry.add(_iterative(abf, limits={"max_iterations": Le(10_000)},
                        keywords=(*_UV, "abf", "abf++", "angle based flattening",
                                  "free boundary")))
