"""Catalog entries of the embedding family (n×D points → n×k): PCA, classical/metric MDS,
random projection, Isomap, Laplacian eigenmaps, LPP and LLE; then the iterative methods that
report progress and can be cancelled: SOM, t-SNE and SNE."""

from __future__ import annotations

from typing import Any

from algorithms.core.errors import InvalidInputError
from algorithms.core.graphs import check_neighbour_params
from algorithms.core.params import Le
from algorithms.core.validation import as_int, check_dense_size, check_min_points
from algorithms.embedding import (
    isomap,
    laplacian_eigenmaps,
    lle,
    lpp,
    mds,
    pca,
    random_projection,
    sne,
    som,
    tsne,
)
from algorithms.embedding.isomap import MAX_ISOMAP_POINTS
from algorithms.embedding.pca import check_linear_components
from algorithms.embedding.sne import MAX_SNE_POINTS, check_size
from algorithms.embedding.som import check_grid
from algorithms.embedding.tsne import check_perplexity, resolve_method
from service import scenes
from service.catalog.registry import Process, registry

# Twelve points on a closed curve that winds around the centre of a cube.
_RING = [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122],
         [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108],
         [70, 70, 122], [88, 60, 130]]
_STOCHASTIC = {"points": _RING, "perplexity": 3.0, "max_iterations": 300,
               "exaggeration_iterations": 100}
_STEPS = {"max_iterations": Le(100_000), "exaggeration_iterations": Le(100_000)}


def _components(p: Any, limit: int, reason: str) -> None:
    as_int(p.n_components, name="n_components", minimum=1, maximum=limit, reason=reason)


def _linear(p: Any) -> None:
    """At least 2 points; n_components at most their dimension and their number."""
    check_min_points(p.points, 2, name="points")
    check_linear_components(p.n_components, *p.points.shape)


def _projection(p: Any) -> None:
    """n_components at most the dimension and the number of points; density only with
    kind = 'sparse'."""
    check_linear_components(p.n_components, *p.points.shape)
    if p.density is not None and p.kind != "sparse":
        raise InvalidInputError("Expected `density` only with kind = 'sparse'.",
                                field="density")


def _dense(p: Any) -> None:
    """2 to MAX_DENSE_POINTS points (MDS keeps n×n matrices); n_components at most n."""
    check_min_points(p.points, 2, name="points")
    check_dense_size(p.points.shape[0], name="points")
    _components(p, p.points.shape[0], "the number of `points`")


def _graph(p: Any, minimum: int) -> int:
    check_min_points(p.points, minimum, name="points")
    n = int(p.points.shape[0])
    check_neighbour_params(n, p.neighbors, p.n_neighbors, p.radius)
    return n


def _isomap(p: Any) -> None:
    """A neighbour graph of 2 to 10,000 points; n_components at most their number."""
    n = _graph(p, 2)
    if n > MAX_ISOMAP_POINTS:
        raise InvalidInputError(f"Expected `points` to hold at most {MAX_ISOMAP_POINTS:,} "
                                f"points (Isomap keeps the n×n geodesic distances), got "
                                f"{n:,}.", field="points")
    _components(p, n, "the number of `points`")


def _spectral(p: Any) -> None:
    """A neighbour graph of at least 3 points; n_components at most their number minus 2."""
    n = _graph(p, 3)
    _components(p, n - 2, "the number of `points` minus two")


def _lpp(p: Any) -> None:
    """A neighbour graph of at least 3 points; n_components at most their dimension and
    their number."""
    _graph(p, 3)
    check_linear_components(p.n_components, *p.points.shape)


def _grid(p: Any) -> None:
    """At least 2 points and a grid of at least 2 nodes."""
    check_min_points(p.points, 2, name="points")
    check_grid(p.rows, p.columns)


def _tsne(p: Any) -> None:
    """At least 2 points, perplexity below their number, a gradient that takes them."""
    check_min_points(p.points, 2, name="points")
    check_perplexity(p.perplexity, p.points.shape[0])
    resolve_method(p.method, p.points.shape[0], p.n_components)


def _sne(p: Any) -> None:
    """2 to 5,000 points, perplexity below their number."""
    check_min_points(p.points, 2, name="points")
    check_perplexity(p.perplexity, p.points.shape[0])
    check_size(p.points.shape[0])


registry.add(Process(
    id="embedding.pca",
    geometry=scenes.embedding,
    title="Principal component analysis",
    description="Projects the centred data on its k principal axes (thin SVD): the "
    "orthogonal projection keeping the most variance. Reports the axes, the variance along "
    "each (eigenvalues), their share, and trustworthiness; signs fixed (each axis's largest "
    "entry positive).",
    function=pca,
    examples={"points": _RING},
    check=_linear,
    fast_path=True,
    keywords=("pca", "principal components", "svd", "dimensionality reduction"),
))

registry.add(Process(
    id="embedding.mds",
    geometry=scenes.embedding,
    title="Multidimensional scaling (classical or metric)",
    description="Classical MDS: the top eigenvectors of the double-centred squared distances "
    "−½JD⁽²⁾J (for Euclidean input the PCA scores); optionally refined by SMACOF stress "
    "majorization. Reports eigenvalues, raw and normalized stress, trustworthiness.",
    function=mds,
    examples={"points": _RING},
    limits={"max_iterations": Le(100_000)},
    check=_dense,
    keywords=("mds", "classical mds", "principal coordinates", "smacof", "stress"),
))

registry.add(Process(
    id="embedding.random_projection",
    geometry=scenes.embedding,
    title="Random projection (Johnson–Lindenstrauss)",
    description="Maps the points by a random k×D matrix, Gaussian or sparse, that keeps "
    "squared distances in expectation. Reports the matrix, the largest relative distortion "
    "of squared distances and trustworthiness.",
    function=random_projection,
    examples={"points": _RING},
    check=_projection,
    fast_path=True,
    keywords=("random projection", "johnson-lindenstrauss", "sketching"),
))

registry.add(Process(
    id="embedding.isomap",
    geometry=scenes.embedding,
    title="Isomap",
    description="Classical MDS of geodesic distances: shortest paths along the neighbourhood "
    "graph (Dijkstra), then the top eigenvectors of −½JG⁽²⁾J. A disconnected graph is an "
    "error that says into how many components it falls. Reports eigenvalues and "
    "trustworthiness.",
    function=isomap,
    examples={"points": _RING},
    check=_isomap,
    keywords=("isomap", "geodesic distances", "manifold learning", "nonlinear"),
))

registry.add(Process(
    id="embedding.laplacian_eigenmaps",
    geometry=scenes.embedding,
    title="Laplacian eigenmaps (spectral embedding)",
    description="The eigenvectors of the smallest non-trivial eigenvalues of the "
    "neighbourhood graph's Laplacian, Lv = λDv by default. A disconnected graph is an error "
    "that says into how many components it falls. Reports eigenvalues and trustworthiness.",
    function=laplacian_eigenmaps,
    examples={"points": _RING, "n_neighbors": 4},
    check=_spectral,
    keywords=("laplacian eigenmaps", "spectral embedding", "diffusion map",
              "graph laplacian"),
))

registry.add(Process(
    id="embedding.lpp",
    geometry=scenes.embedding,
    title="Locality preserving projections",
    description="The linear map closest to Laplacian eigenmaps: generalized eigenvectors of "
    "XᵀLXa = λXᵀDXa on the centred data. Reports the projection (applies to new points), "
    "eigenvalues and trustworthiness.",
    function=lpp,
    examples={"points": _RING, "n_neighbors": 4},
    check=_lpp,
    fast_path=True,
    keywords=("lpp", "locality preserving projections", "linear", "laplacianfaces"),
))

registry.add(Process(
    id="embedding.lle",
    geometry=scenes.embedding,
    title="Locally linear embedding",
    description="Sum-to-one weights reconstructing each point from its neighbours "
    "(regularised), then the bottom non-trivial eigenvectors of (I − W)ᵀ(I − W). Reports "
    "eigenvalues, the reconstruction error in the embedding and of the weights, and "
    "trustworthiness.",
    function=lle,
    examples={"points": _RING},
    check=_spectral,
    keywords=("lle", "locally linear embedding", "manifold learning", "barycentric weights"),
))

registry.add(Process(
    id="embedding.som",
    geometry=scenes.embedding,
    title="Self-organising map",
    description="A rows × columns grid of nodes pulled onto the data (Kohonen's online rule "
    "or the batch map); each point is embedded at its best-matching node's grid position. "
    "Reports the codebook, quantization and topographic errors and trustworthiness. "
    "Progress per 1 % of the steps, cancellable.",
    function=som,
    examples={"points": [[0, 0], [0.1, 0], [5, 5], [5.1, 5], [0, 5], [5, 0]], "rows": 2,
              "columns": 2},
    limits={"rows": Le(1000), "columns": Le(1000), "max_iterations": Le(10_000_000)},
    check=_grid,
    long=True,
    keywords=("som", "kohonen", "self-organizing map", "vector quantization", "embedding"),
))

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
    examples=_STOCHASTIC,
    limits=_STEPS,
    check=_tsne,
    long=True,
    keywords=("tsne", "t-sne", "stochastic neighbor embedding", "fit-sne", "visualization",
              "perplexity"),
))

registry.add(Process(
    id="embedding.sne",
    geometry=scenes.embedding,
    title="Symmetric SNE (stochastic neighbour embedding)",
    description="t-SNE's input affinities with a Gaussian kernel in the embedding too "
    "(the light tails crowd clusters together: t-SNE's motivation); exact all-pairs "
    f"gradient, at most {MAX_SNE_POINTS:,} points. Reports KL, trustworthiness and "
    "iterations. Progress every iteration, cancellable.",
    function=sne,
    examples=_STOCHASTIC,
    limits=_STEPS,
    check=_sne,
    long=True,
    keywords=("sne", "stochastic neighbor embedding", "symmetric sne", "gaussian"),
))
