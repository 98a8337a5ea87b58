"""Catalog entries of the deformation family (a mesh and handles in, the deformed mesh out)."""

from __future__ import annotations

from functools import partial

from algorithms.core.params import Le
from algorithms.deformation import (
    arap,
    biharmonic,
    check_deformation_transfer,
    check_handles,
    deformation_transfer,
    harmonic,
    isotropic_scaling,
    laplacian,
    laplacian_editing,
)
from service import scenes
from service.catalog.registry import Process, registry

# A 2 × 1 strip of unit squares in the plane z = 0 (six vertices, four triangles) ...
_STRIP_VERTICES = [[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]]
_STRIP = {"vertices": _STRIP_VERTICES, "faces": [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]]}
# ... its left end held, its right end lifted by 1
_LIFT = {"indices": [0, 3, 2, 5], "positions": [[0, 0, 0], [0, 1, 0], [2, 0, 1], [2, 1, 1]]}
# the strip folded up along x = 1 (a quarter turn of its right half)
_FOLDED = [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 1, 0], [1, 1, 0], [1, 1, 1]]
_TARGET_MESH = {"vertices": [[0, 0, 0], [2, 0, 0], [4, 0, 0], [0, 1, 0], [2, 1, 0],
                             [4, 1, 0]],
                "faces": _STRIP["faces"]}

# the handles index distinct vertices of the mesh, one at least in every component
_handled = partial(Process, geometry=scenes.deformed_mesh, check=check_handles,
                   examples={"mesh": _STRIP, "handles": _LIFT})

registry.add(_handled(laplacian,
                      keywords=("laplacian coordinates", "mesh editing", "handles", "linear")))
registry.add(_handled(laplacian_editing, fast_path=True,
                      keywords=("laplacian coordinates", "mesh editing", "handles",
                                "similarity")))
registry.add(_handled(arap, limits={"max_iterations": Le(10_000)}, long=True,
                      keywords=("arap", "rigid", "mesh editing", "handles", "local/global")))
registry.add(_handled(harmonic, fast_path=True,
                      keywords=("harmonic", "membrane", "handles", "linear")))
registry.add(_handled(biharmonic, fast_path=True,
                      keywords=("biharmonic", "thin plate", "handles", "linear")))
registry.add(_handled(isotropic_scaling, limits={"max_iterations": Le(100_000)}, long=True,
                      keywords=("scale", "stretch", "resizing", "handles", "local/global")))
registry.add(_handled(
    deformation_transfer, check=check_deformation_transfer, fast_path=True,
    examples={"mesh": _TARGET_MESH, "handles": {"indices": [0], "positions": [[0, 0, 0]]},
              "source": _STRIP_VERTICES, "source_deformed": _FOLDED},
    keywords=("deformation transfer", "deformation gradient", "retargeting", "handles")))
