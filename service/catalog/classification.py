"""Catalog entries of the classification family (labelled points in: a discriminating
projection and class predictions out). Imported by :mod:`service.catalog.clustering`."""

from __future__ import annotations

from typing import Annotated, Any, Literal

import numpy as np
from pydantic import Field, PlainSerializer, PlainValidator, WithJsonSchema, model_validator

from algorithms.classification import LDAResult, NCAResult, lda, nca
from algorithms.classification._common import as_labels
from algorithms.core.errors import InvalidInputError
from service.catalog.base import Params
from service.catalog.inputs import Labels, Points
from service import scenes
from service.catalog.registry import Process, registry



_POINTS = [[0, 0], [1, 0], [0, 1], [1, 1.5], [5, 5], [6, 5], [5, 6], [6.5, 6]]
_LABELS = ["a", "a", "a", "a", "b", "b", "b", "b"]
_QUERY = [[0.5, 0.5], [5.5, 5.0]]


class _Supervised(Params):
    points: Points = Field(description="The training points, (n, d).", examples=[_POINTS])
    labels: Labels = Field(description="The class of each point (integers or strings), at "
                           "least 2 classes.", examples=[_LABELS])
    query: Points | None = Field(None, description="Points to embed and classify with the "
                                 "fitted model, (m, d).", examples=[_QUERY])

    def _check(self) -> tuple[int, int, int]:
        n, d = self.points.shape
        classes, _ = as_labels(self.labels, n)
        if self.query is not None and self.query.shape[1] != d:
            raise InvalidInputError(f"Expected `query` to have the dimension of `points` "
                                    f"({d}), got shape {self.query.shape}.", field="query")
        return n, d, classes.shape[0]


class LDAParams(_Supervised):
    n_components: int | None = Field(None, ge=1, description="The number of discriminant "
                                     "directions, at most min(classes − 1, d); that maximum "
                                     "by default.")

    @model_validator(mode="after")
    def _sizes(self) -> LDAParams:
        _, d, c = self._check()
        if self.n_components is not None and self.n_components > min(c - 1, d):
            raise InvalidInputError(
                f"Expected `n_components` to be at most min(classes − 1, d) = "
                f"min({c - 1}, {d}), got {self.n_components}.", field="n_components")
        return self


registry.add(Process(
    id="classification.lda",
    geometry=scenes.embedding,
    title="Fisher linear discriminant analysis",
    description="The directions maximising between-class over within-class variance "
    "(S_B a = λ S_W a, by two SVDs as scikit-learn's svd solver), the points projected on "
    "them, and the Gaussian shared-covariance classifier's predictions for the points and "
    "optional query points. Reports accuracy, explained variance and trustworthiness.",
    function=lda,
    params=LDAParams,
    result=LDAResult,
    reference="Fisher, R. A. (1936). The use of multiple measurements in taxonomic problems. "
    "Annals of Eugenics 7(2), 179–188.",
    fast_path=True,
    keywords=("lda", "fisher discriminant", "linear discriminant analysis",
              "supervised dimensionality reduction", "classification"),
))


class NCAParams(_Supervised):
    n_components: int | None = Field(None, ge=1, description="The output dimension k, at "
                                     "most d; d by default.", examples=[1])
    init: Literal["auto", "pca", "lda", "identity", "random"] = Field(
        "auto", description="The starting map: auto (LDA when k ≤ min(d, classes − 1), else "
        "PCA when k < d, else the identity), pca, lda, identity or random (drawn with seed).")
    max_iterations: int = Field(50, ge=1, le=10_000, description="Most L-BFGS iterations.")
    tolerance: float = Field(1e-5, ge=0, description="L-BFGS stops when the relative "
                             "decrease of the objective or the gradient falls below this.")
    seed: int = Field(0, ge=0, description="Seed of the random start.")

    @model_validator(mode="after")
    def _sizes(self) -> NCAParams:
        _, d, _ = self._check()
        if self.n_components is not None and self.n_components > d:
            raise InvalidInputError(f"Expected `n_components` to be at most the dimension of "
                                    f"`points` ({d}), got {self.n_components}.",
                                    field="n_components")
        return self


registry.add(Process(
    id="classification.nca",
    geometry=scenes.embedding,
    title="Neighbourhood components analysis",
    description="The linear map maximising the expected number of points whose stochastic "
    "nearest neighbour (softmax over squared distances) has their class, by L-BFGS as "
    "scikit-learn. Reports the map, the embedding, leave-one-out 1-NN accuracy, query "
    "predictions and trustworthiness. Progress per iteration, cancellable.",
    function=nca,
    params=NCAParams,
    result=NCAResult,
    reference="Goldberger, J., Roweis, S., Hinton, G., Salakhutdinov, R. (2004). "
    "Neighbourhood components analysis. NIPS 17.",
    long=True,
    keywords=("nca", "metric learning", "neighbourhood components analysis",
              "supervised dimensionality reduction", "classification"),
))
