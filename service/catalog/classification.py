"""Catalog entries of the classification family (labelled points in: a discriminating
projection and class predictions out)."""

from __future__ import annotations

from algorithms.classification import check_lda, check_nca, lda, nca
from algorithms.core.params import Le
from service import scenes
from service.catalog.registry import Process, registry

_EXAMPLES = {"points": [[0, 0], [1, 0], [0, 1], [1, 1.5], [5, 5], [6, 5], [5, 6], [6.5, 6]],
             "labels": ["a", "a", "a", "a", "b", "b", "b", "b"],
             "query": [[0.5, 0.5], [5.5, 5.0]]}

registry.add(Process(lda, geometry=scenes.embedding, examples=_EXAMPLES, check=check_lda,
                     fast_path=True,
                     keywords=("lda", "fisher discriminant", "linear discriminant analysis",
                               "supervised dimensionality reduction", "classification")))
registry.add(Process(nca, geometry=scenes.embedding, examples={**_EXAMPLES, "n_components": 1},
                     limits={"max_iterations": Le(10_000)}, check=check_nca, long=True,
                     keywords=("nca", "metric learning", "neighbourhood components analysis",
                               "supervised dimensionality reduction", "classification")))
