"""Catalog entries of the classification family (labelled points in: a discriminating
projection and class predictions out)."""

from __future__ import annotations

from typing import Any

from algorithms.classification import as_labels, lda, nca
from algorithms.core.errors import InvalidInputError
from algorithms.core.params import Le
from service import scenes
from service.catalog.registry import Process, registry

_EXAMPLES = {"points": [[0, 0], [1, 0], [0, 1], [1, 1.5], [5, 5], [6, 5], [5, 6], [6.5, 6]],
             "labels": ["a", "a", "a", "a", "b", "b", "b", "b"],
             "query": [[0.5, 0.5], [5.5, 5.0]]}


def _supervised(p: Any) -> tuple[int, int]:
    """One label per point, at least 2 classes; query points of the points' dimension."""
    n, d = p.points.shape
    classes, _ = as_labels(p.labels, n)
    if p.query is not None and p.query.shape[1] != d:
        raise InvalidInputError(f"Expected `query` to have the dimension of `points` "
                                f"({d}), got shape {p.query.shape}.", field="query")
    return d, classes.shape[0]


def _at_most(p: Any, limit: int, what: str) -> None:
    if p.n_components is not None and p.n_components > limit:
        raise InvalidInputError(f"Expected `n_components` to be at most {what}, got "
                                f"{p.n_components}.", field="n_components")


def _lda(p: Any) -> None:
    """Labels and query that fit the points; n_components at most min(classes − 1, d)."""
    d, c = _supervised(p)
    _at_most(p, min(c - 1, d), f"min(classes − 1, d) = min({c - 1}, {d})")


def _nca(p: Any) -> None:
    """Labels and query that fit the points; n_components at most their dimension."""
    d, _ = _supervised(p)
    _at_most(p, d, f"the dimension of `points` ({d})")


registry.add(Process(
    id="classification.lda",
    geometry=scenes.embedding,
    title="Fisher linear discriminant analysis",
    description="The directions maximising between-class over within-class variance "
    "(S_B a = λ S_W a, by two SVDs as scikit-learn's svd solver), the points projected on "
    "them, and the Gaussian shared-covariance classifier's predictions for the points and "
    "optional query points. Reports accuracy, explained variance and trustworthiness.",
    function=lda,
    examples=_EXAMPLES,
    check=_lda,
    fast_path=True,
    keywords=("lda", "fisher discriminant", "linear discriminant analysis",
              "supervised dimensionality reduction", "classification"),
))

registry.add(Process(
    id="classification.nca",
    geometry=scenes.embedding,
    title="Neighbourhood components analysis",
    description="The linear map maximising the expected number of points whose stochastic "
    "nearest neighbour (softmax over squared distances) has their class, by L-BFGS as "
    "scikit-learn. Reports the map, the embedding, leave-one-out 1-NN accuracy, query "
    "predictions and trustworthiness. Progress per iteration, cancellable.",
    function=nca,
    examples={**_EXAMPLES, "n_components": 1},
    limits={"max_iterations": Le(10_000)},
    check=_nca,
    long=True,
    keywords=("nca", "metric learning", "neighbourhood components analysis",
              "supervised dimensionality reduction", "classification"),
))
