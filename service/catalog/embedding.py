"""Catalog entries of the embedding family (n×D points → n×k): PCA, classical/metric MDS,
random projection, Isomap, Laplacian eigenmaps, LPP and LLE; then the iterative methods that
report progress and can be cancelled: SOM, t-SNE and SNE."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from algorithms.core.errors import InvalidInputError
from algorithms.embedding import (
    EmbeddingMDSResult,
    IsomapResult,
    LaplacianEigenmapsResult,
    LLEResult,
    LPPResult,
    PCAResult,
    RandomProjectionResult,
    isomap,
    laplacian_eigenmaps,
    lle,
    lpp,
    mds,
    pca,
    random_projection,
)
from algorithms.embedding.isomap import MAX_ISOMAP_POINTS
from algorithms.embedding.som import SOMResult, som
from algorithms.embedding.sne import MAX_SNE_POINTS, SNEResult, sne
from algorithms.embedding.tsne import MAX_EXACT_POINTS, TSNEResult, tsne
from algorithms.core.validation import MAX_DENSE_POINTS
from service.catalog.base import Params
from service.catalog.inputs import Points
from service import scenes
from service.catalog.registry import Process, registry

# The seed document's example: twelve points on a closed curve around a cube's centre.
_RING = [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122],
         [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108],
         [70, 70, 122], [88, 60, 130]]

_POINTS = "The data: an (n, D) array, one row per point."
_N_COMPONENTS = "The dimension k of the embedding."
_QUALITY = ("The neighbourhood size of the reported trustworthiness (clipped below n / 2).")
_NEIGHBORS = ("The neighbourhood graph: knn joins each point to its n_neighbors nearest "
              "(either way round), radius every pair closer than radius, all every pair.")
_RADIUS = "The radius for neighbors = radius."
_SIGMA = "The heat kernel's width σ; default the mean edge length."
_LAPLACIAN = ("The normalisation: random_walk solves Lv = λDv (the paper, scikit-learn), "
              "symmetric D^−½LD^−½y = λy (the seed document), unnormalized Ly = λy.")


def _count(points: object) -> tuple[int, int]:
    return points.shape  # type: ignore[attr-defined, no-any-return]


def _check_components(k: int, limit: int, what: str) -> None:
    if k > limit:
        raise InvalidInputError(f"Expected `n_components` to be at most {what} ({limit}), "
                                f"got {k}.", field="n_components")


def _check_graph(neighbors: str, n_neighbors: int | None, radius: float | None,
                 n: int) -> None:
    if neighbors == "knn" and n_neighbors is not None and n_neighbors > n - 1:
        raise InvalidInputError(
            f"Expected `n_neighbors` to be below the number of `points` ({n}), got "
            f"{n_neighbors}: there are fewer points than neighbours.", field="n_neighbors")
    if neighbors == "radius" and radius is None:
        raise InvalidInputError("Expected `radius` with neighbors = 'radius', got none.",
                                field="radius")


class _EmbeddingParams(Params):
    points: Points = Field(description=_POINTS, examples=[_RING])
    n_components: int = Field(2, ge=1, description=_N_COMPONENTS)
    quality_neighbors: int = Field(5, ge=1, description=_QUALITY)


# -- embedding.pca ---------------------------------------------------------------------------
class PCAParams(_EmbeddingParams):
    @model_validator(mode="after")
    def _fits(self) -> PCAParams:
        n, d = _count(self.points)
        _check_components(self.n_components, d, "the dimension of `points`")
        _check_components(self.n_components, n, "the number of `points`")
        if n < 2:
            raise InvalidInputError(f"Expected `points` to hold at least 2 points, got {n}.",
                                    field="points")
        return self


registry.add(Process(
    id="embedding.pca",
    geometry=scenes.embedding,
    title="Principal component analysis",
    description="Projects the centred data on its k principal axes (thin SVD): the "
    "orthogonal projection keeping the most variance. Reports the axes, the variance along "
    "each (eigenvalues), their share, and trustworthiness; signs fixed (each axis's largest "
    "entry positive).",
    function=pca,
    params=PCAParams,
    result=PCAResult,
    reference="Pearson, K. (1901). On lines and planes of closest fit to systems of points "
    "in space. Philosophical Magazine 2(11), 559–572.",
    fast_path=True,
    keywords=("pca", "principal components", "svd", "dimensionality reduction"),
))


# -- embedding.mds ---------------------------------------------------------------------------
class EmbeddingMDSParams(_EmbeddingParams):
    metric: bool = Field(False, description="Refine the classical embedding by SMACOF "
                         "(minimise the raw stress, scikit-learn's MDS).")
    max_iterations: int = Field(300, ge=0, le=100_000, description="Most SMACOF iterations "
                                "(metric = true).")
    tolerance: float = Field(1e-6, ge=0, description="SMACOF stops when an iteration lowers "
                             "the stress by less than this fraction.")

    @model_validator(mode="after")
    def _fits(self) -> EmbeddingMDSParams:
        n, _ = _count(self.points)
        if n > MAX_DENSE_POINTS:
            raise InvalidInputError(f"Expected `points` to hold at most {MAX_DENSE_POINTS:,} "
                                    f"points (MDS keeps n×n matrices), got {n:,}.",
                                    field="points")
        _check_components(self.n_components, n, "the number of `points`")
        return self


registry.add(Process(
    id="embedding.mds",
    geometry=scenes.embedding,
    title="Multidimensional scaling (classical or metric)",
    description="Classical MDS: the top eigenvectors of the double-centred squared distances "
    "−½JD⁽²⁾J (for Euclidean input the PCA scores); optionally refined by SMACOF stress "
    "majorization. Reports eigenvalues, raw and normalized stress, trustworthiness.",
    function=mds,
    params=EmbeddingMDSParams,
    result=EmbeddingMDSResult,
    reference="Torgerson, W. S. (1952). Multidimensional scaling: I. Theory and method. "
    "Psychometrika 17, 401–419.",
    keywords=("mds", "classical mds", "principal coordinates", "smacof", "stress"),
))


# -- embedding.random_projection -------------------------------------------------------------
class RandomProjectionParams(_EmbeddingParams):
    kind: Literal["gaussian", "sparse"] = Field(
        "gaussian", description="Gaussian entries N(0, 1/k), or sparse ±√(s/k) with "
        "s = 1/density (Achlioptas; Li, Hastie and Church).")
    density: float | None = Field(None, gt=0, le=1, description="Fraction of non-zero "
                                  "entries for kind = sparse; default 1/√D.")
    seed: int = Field(0, ge=0, description="The same seed gives the same matrix.")

    @model_validator(mode="after")
    def _fits(self) -> RandomProjectionParams:
        n, d = _count(self.points)
        _check_components(self.n_components, d, "the dimension of `points`")
        _check_components(self.n_components, n, "the number of `points`")
        if self.density is not None and self.kind != "sparse":
            raise InvalidInputError("Expected `density` only with kind = 'sparse'.",
                                    field="density")
        return self


registry.add(Process(
    id="embedding.random_projection",
    geometry=scenes.embedding,
    title="Random projection (Johnson–Lindenstrauss)",
    description="Maps the points by a random k×D matrix, Gaussian or sparse, that keeps "
    "squared distances in expectation. Reports the matrix, the largest relative distortion "
    "of squared distances and trustworthiness.",
    function=random_projection,
    params=RandomProjectionParams,
    result=RandomProjectionResult,
    reference="Achlioptas, D. (2003). Database-friendly random projections: "
    "Johnson–Lindenstrauss with binary coins. J. Comput. Syst. Sci. 66(4), 671–687.",
    fast_path=True,
    keywords=("random projection", "johnson-lindenstrauss", "sketching"),
))


# -- graph methods ---------------------------------------------------------------------------
class _GraphParams(_EmbeddingParams):
    neighbors: Literal["knn", "radius", "all"] = Field("knn", description=_NEIGHBORS)
    radius: float | None = Field(None, gt=0, description=_RADIUS)

    def _graph_checks(self, n_neighbors: int | None, minimum_points: int) -> int:
        n, _ = _count(self.points)
        if n < minimum_points:
            raise InvalidInputError(f"Expected `points` to hold at least {minimum_points} "
                                    f"points, got {n}.", field="points")
        _check_graph(self.neighbors, n_neighbors, self.radius, n)
        return n


class IsomapParams(_GraphParams):
    n_neighbors: int = Field(5, ge=1, description="Neighbours per point (neighbors = knn).")
    weighting: Literal["distance", "uniform"] = Field(
        "distance", description="Edge lengths of the shortest paths: the Euclidean distance, "
        "or 1 per edge (hop counts).")

    @model_validator(mode="after")
    def _fits(self) -> IsomapParams:
        n = self._graph_checks(self.n_neighbors, 2)
        if n > MAX_ISOMAP_POINTS:
            raise InvalidInputError(f"Expected `points` to hold at most {MAX_ISOMAP_POINTS:,} "
                                    f"points (Isomap keeps the n×n geodesic distances), got "
                                    f"{n:,}.", field="points")
        _check_components(self.n_components, n, "the number of `points`")
        return self


registry.add(Process(
    id="embedding.isomap",
    geometry=scenes.embedding,
    title="Isomap",
    description="Classical MDS of geodesic distances: shortest paths along the neighbourhood "
    "graph (Dijkstra), then the top eigenvectors of −½JG⁽²⁾J. A disconnected graph is an "
    "error that says into how many components it falls. Reports eigenvalues and "
    "trustworthiness.",
    function=isomap,
    params=IsomapParams,
    result=IsomapResult,
    reference="Tenenbaum, J. B., de Silva, V., Langford, J. C. (2000). A global geometric "
    "framework for nonlinear dimensionality reduction. Science 290, 2319–2323.",
    keywords=("isomap", "geodesic distances", "manifold learning", "nonlinear"),
))


class _SpectralParams(_GraphParams):
    n_neighbors: int | None = Field(None, ge=1, description="Neighbours per point "
                                    "(neighbors = knn); default max(n / 10, 1).",
                                    examples=[4])
    weighting: Literal["uniform", "distance", "heat"] = Field(
        "uniform", description="Edge weights: 1, 1/d, or the heat kernel exp(−d²/2σ²).")
    sigma: float | None = Field(None, gt=0, description=_SIGMA)
    laplacian: Literal["random_walk", "symmetric", "unnormalized"] = Field(
        "random_walk", description=_LAPLACIAN)


class LaplacianEigenmapsParams(_SpectralParams):
    @model_validator(mode="after")
    def _fits(self) -> LaplacianEigenmapsParams:
        n = self._graph_checks(self.n_neighbors, 3)
        _check_components(self.n_components, n - 2, "the number of `points` minus two")
        return self


registry.add(Process(
    id="embedding.laplacian_eigenmaps",
    geometry=scenes.embedding,
    title="Laplacian eigenmaps (spectral embedding)",
    description="The eigenvectors of the smallest non-trivial eigenvalues of the "
    "neighbourhood graph's Laplacian, Lv = λDv by default. A disconnected graph is an error "
    "that says into how many components it falls. Reports eigenvalues and trustworthiness.",
    function=laplacian_eigenmaps,
    params=LaplacianEigenmapsParams,
    result=LaplacianEigenmapsResult,
    reference="Belkin, M., Niyogi, P. (2003). Laplacian eigenmaps for dimensionality "
    "reduction and data representation. Neural Computation 15(6), 1373–1396.",
    keywords=("laplacian eigenmaps", "spectral embedding", "diffusion map",
              "graph laplacian"),
))


class LPPParams(_SpectralParams):
    @model_validator(mode="after")
    def _fits(self) -> LPPParams:
        n = self._graph_checks(self.n_neighbors, 3)
        _, d = _count(self.points)
        _check_components(self.n_components, d, "the dimension of `points`")
        _check_components(self.n_components, n, "the number of `points`")
        return self


registry.add(Process(
    id="embedding.lpp",
    geometry=scenes.embedding,
    title="Locality preserving projections",
    description="The linear map closest to Laplacian eigenmaps: generalized eigenvectors of "
    "XᵀLXa = λXᵀDXa on the centred data. Reports the projection (applies to new points), "
    "eigenvalues and trustworthiness.",
    function=lpp,
    params=LPPParams,
    result=LPPResult,
    reference="He, X., Niyogi, P. (2003). Locality preserving projections. NIPS 16.",
    fast_path=True,
    keywords=("lpp", "locality preserving projections", "linear", "laplacianfaces"),
))


class LLEParams(_EmbeddingParams):
    neighbors: Literal["knn", "radius"] = Field(
        "knn", description="Each point's own n_neighbors nearest, or all within radius.")
    n_neighbors: int = Field(5, ge=1, description="Neighbours per point (neighbors = knn).")
    radius: float | None = Field(None, gt=0, description=_RADIUS)
    regularization: float = Field(1e-3, ge=0, description="r: the local Gram matrix C gets "
                                  "r·trace(C) on its diagonal; needed when n_neighbors > D.")

    @model_validator(mode="after")
    def _fits(self) -> LLEParams:
        n, _ = _count(self.points)
        if n < 3:
            raise InvalidInputError(f"Expected `points` to hold at least 3 points, got {n}.",
                                    field="points")
        _check_graph(self.neighbors, self.n_neighbors, self.radius, n)
        _check_components(self.n_components, n - 2, "the number of `points` minus two")
        return self


registry.add(Process(
    id="embedding.lle",
    geometry=scenes.embedding,
    title="Locally linear embedding",
    description="Sum-to-one weights reconstructing each point from its neighbours "
    "(regularised), then the bottom non-trivial eigenvectors of (I − W)ᵀ(I − W). Reports "
    "eigenvalues, the reconstruction error in the embedding and of the weights, and "
    "trustworthiness.",
    function=lle,
    params=LLEParams,
    result=LLEResult,
    reference="Roweis, S. T., Saul, L. K. (2000). Nonlinear dimensionality reduction by "
    "locally linear embedding. Science 290, 2323–2326.",
    keywords=("lle", "locally linear embedding", "manifold learning", "barycentric weights"),
))


class SOMParams(Params):
    points: Points = Field(description="The points to map, (n, d), n ≥ 2.",
                           examples=[[[0, 0], [0.1, 0], [5, 5], [5.1, 5], [0, 5], [5, 0]]])
    rows: int = Field(10, ge=1, le=1000, description="Grid rows.", examples=[2])
    columns: int = Field(10, ge=1, le=1000, description="Grid columns.", examples=[2])
    method: Literal["online", "batch"] = Field(
        "online", description="online: Kohonen's rule, one random point per step (the seed "
        "document's gradient descent); batch: each epoch's fixed point.")
    max_iterations: int | None = Field(None, ge=1, le=10_000_000, description="Samples "
                                       "presented (online; default max(1000, 10n) up to "
                                       "100,000) or epochs (batch; default 30).")
    learning_rate: float = Field(0.5, gt=0, le=1, description="Starting step η₀ (online).")
    sigma: float | None = Field(None, gt=0, description="Starting neighbourhood width in "
                                "grid units; half the larger grid side by default.")
    init: Literal["pca", "random"] = Field("pca", description="Start on the plane of the two "
                                           "principal axes, or at random points (seed).")
    seed: int = Field(0, ge=0, description="Seeds the sample order and the random start.")

    @model_validator(mode="after")
    def _grid(self) -> SOMParams:
        if self.points.shape[0] < 2:
            raise InvalidInputError(f"Expected `points` to hold at least 2 points, got "
                                    f"{self.points.shape[0]}.", field="points")
        if self.rows * self.columns < 2:
            raise InvalidInputError(f"Expected a grid of at least 2 nodes, got rows="
                                    f"{self.rows} and columns={self.columns}.", field="rows")
        return self


registry.add(Process(
    id="embedding.som",
    geometry=scenes.embedding,
    title="Self-organising map",
    description="A rows × columns grid of nodes pulled onto the data (Kohonen's online rule "
    "or the batch map); each point is embedded at its best-matching node's grid position. "
    "Reports the codebook, quantization and topographic errors and trustworthiness. "
    "Progress per 1 % of the steps, cancellable.",
    function=som,
    params=SOMParams,
    result=SOMResult,
    reference="Kohonen, T. (1982). Self-organized formation of topologically correct feature "
    "maps. Biological Cybernetics 43, 59–69.",
    long=True,
    keywords=("som", "kohonen", "self-organizing map", "vector quantization", "embedding"),
))


# -- embedding.tsne, embedding.sne -----------------------------------------------------------
_PERPLEXITY = ("The effective number of neighbours of each point's Gaussian (its entropy is "
               "log perplexity, by binary search); below the number of points.")


class _StochasticParams(_EmbeddingParams):
    perplexity: float = Field(30.0, gt=0, description=_PERPLEXITY, examples=[3.0])
    init: Literal["pca", "random"] = Field(
        "pca", description="Start from the PCA scores (first column's standard deviation "
        "1e-4, as openTSNE and scikit-learn) or from Gaussian draws of that size (seed).")
    learning_rate: float | None = Field(
        None, gt=0, description="The step; by default (null) max(n / 4α, 50) with α the "
        "exaggeration in force (openTSNE's auto, n / α, in scikit-learn's gradient units).")
    max_iterations: int = Field(750, ge=1, le=100_000, description="Gradient steps in all, "
                                "the early exaggeration included.", examples=[300])
    exaggeration_iterations: int = Field(250, ge=0, le=100_000, description="Steps with P "
                                         "multiplied by early_exaggeration.", examples=[100])
    min_grad_norm: float = Field(1e-7, ge=0, description="After the exaggeration, stop once "
                                 "the gradient's norm is below this.")
    seed: int = Field(0, ge=0, description="Seeds the random start; the same seed gives the "
                      "same embedding.")

    def _stochastic_checks(self) -> int:
        n, _ = _count(self.points)
        if n < 2:
            raise InvalidInputError(f"Expected `points` to hold at least 2 points, got {n}.",
                                    field="points")
        if self.perplexity >= n:
            raise InvalidInputError(f"Expected `perplexity` to be below the number of "
                                    f"`points` ({n}), got {self.perplexity:g}.",
                                    field="perplexity")
        return n


class TSNEParams(_StochasticParams):
    method: Literal["auto", "exact", "fft"] = Field(
        "auto", description="exact: all pairs each step, affinities over all pairs (at most "
        f"{MAX_EXACT_POINTS:,} points); fft: affinities over the 3·perplexity nearest "
        "neighbours, repulsion by FFT-accelerated interpolation (FIt-SNE; n_components ≤ 2); "
        "auto: exact below 500 points or for n_components > 2, else fft.")
    early_exaggeration: float = Field(12.0, ge=1, description="The factor on P during the "
                                      "first exaggeration_iterations steps.")

    @model_validator(mode="after")
    def _fits(self) -> TSNEParams:
        n = self._stochastic_checks()
        exact = self.method == "exact" or (self.method == "auto" and
                                           (n < 500 or self.n_components > 2))
        if exact and n > MAX_EXACT_POINTS:
            field = "method" if self.method == "exact" else "n_components"
            raise InvalidInputError(f"Expected at most {MAX_EXACT_POINTS:,} `points` for the "
                                    f"exact gradient (method = 'exact' or n_components > 2), "
                                    f"got {n:,}.", field=field)
        if self.method == "fft" and self.n_components > 2:
            raise InvalidInputError(f"Expected `n_components` <= 2 for method = 'fft', got "
                                    f"{self.n_components}.", field="n_components")
        return self


registry.add(Process(
    id="embedding.tsne",
    geometry=scenes.embedding,
    title="t-SNE (t-distributed stochastic neighbour embedding)",
    description="Perplexity-calibrated Gaussian affinities (binary search per point), "
    "Cauchy affinities in the embedding, KL(P‖Q) minimised by gradient descent with "
    "momentum, gains and early exaggeration; exact all-pairs gradient for small inputs, "
    "FFT-interpolated repulsion (FIt-SNE) for up to 100,000s of points. Reports KL, "
    "trustworthiness and iterations. Progress every iteration, cancellable.",
    function=tsne,
    params=TSNEParams,
    result=TSNEResult,
    reference="van der Maaten, L., Hinton, G. (2008). Visualizing data using t-SNE. JMLR 9, "
    "2579–2605; Linderman, G. C. et al. (2019). Fast interpolation-based t-SNE for improved "
    "visualization of single-cell RNA-seq data. Nature Methods 16, 243–245.",
    long=True,
    keywords=("tsne", "t-sne", "stochastic neighbor embedding", "fit-sne", "visualization",
              "perplexity"),
))


class SNEParams(_StochasticParams):
    early_exaggeration: float = Field(4.0, ge=1, description="The factor on P during the "
                                      "first exaggeration_iterations steps.")

    @model_validator(mode="after")
    def _fits(self) -> SNEParams:
        n = self._stochastic_checks()
        if n > MAX_SNE_POINTS:
            raise InvalidInputError(f"Expected `points` to hold at most {MAX_SNE_POINTS:,} "
                                    f"points for SNE (an exact O(n²) gradient), got {n:,}; "
                                    f"use embedding.tsne.", field="points")
        return self


registry.add(Process(
    id="embedding.sne",
    geometry=scenes.embedding,
    title="Symmetric SNE (stochastic neighbour embedding)",
    description="t-SNE's input affinities with a Gaussian kernel in the embedding too "
    "(the light tails crowd clusters together: t-SNE's motivation); exact all-pairs "
    f"gradient, at most {MAX_SNE_POINTS:,} points. Reports KL, trustworthiness and "
    "iterations. Progress every iteration, cancellable.",
    function=sne,
    params=SNEParams,
    result=SNEResult,
    reference="Hinton, G., Roweis, S. (2002). Stochastic neighbor embedding. NIPS 15; van der "
    "Maaten, L., Hinton, G. (2008). Visualizing data using t-SNE. JMLR 9 (symmetric SNE).",
    long=True,
    keywords=("sne", "stochastic neighbor embedding", "symmetric sne", "gaussian"),
))
