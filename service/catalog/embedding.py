"""Catalog entries of the embedding family (n×D points → n×k): PCA, classical/metric MDS,
random projection, Isomap, Laplacian eigenmaps, LPP and LLE; then the iterative methods that
report progress and can be cancelled: SOM, t-SNE and SNE."""

from __future__ import annotations

from functools import partial

from algorithms.core.params import Le
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
from algorithms.embedding.isomap import check_isomap
from algorithms.embedding.laplacian_eigenmaps import check_laplacian_eigenmaps
from algorithms.embedding.lle import check_lle
from algorithms.embedding.lpp import check_lpp
from algorithms.embedding.mds import check_mds
from algorithms.embedding.pca import check_pca
from algorithms.embedding.random_projection import check_random_projection
from algorithms.embedding.sne import check_sne
from algorithms.embedding.som import check_som
from algorithms.embedding.tsne import check_tsne
from service import scenes
from service.catalog.registry import Process, registry

# Twelve points on a closed curve that winds around the centre of a cube.
_RING = [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122],
         [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108],
         [70, 70, 122], [88, 60, 130]]
_STOCHASTIC = {"points": _RING, "perplexity": 3.0, "max_iterations": 300,
               "exaggeration_iterations": 100}
_STEPS = {"max_iterations": Le(100_000), "exaggeration_iterations": Le(100_000)}

_embed = partial(Process, geometry=scenes.embedding, examples={"points": _RING},
                 display=("labels",))
_neighbours = {"points": _RING, "n_neighbors": 4}

registry.add(_embed(pca, check=check_pca, fast_path=True,
                    keywords=("pca", "principal components", "svd",
                              "dimensionality reduction")))
registry.add(_embed(mds, check=check_mds, limits={"max_iterations": Le(100_000)},
                    keywords=("mds", "classical mds", "principal coordinates", "smacof",
                              "stress")))
registry.add(_embed(random_projection, check=check_random_projection, fast_path=True,
                    keywords=("random projection", "johnson-lindenstrauss", "sketching")))
registry.add(_embed(isomap, check=check_isomap,
                    keywords=("isomap", "geodesic distances", "manifold learning",
                              "nonlinear")))
registry.add(_embed(laplacian_eigenmaps, check=check_laplacian_eigenmaps, examples=_neighbours,
                    keywords=("laplacian eigenmaps", "spectral embedding", "diffusion map",
                              "graph laplacian")))
registry.add(_embed(lpp, check=check_lpp, examples=_neighbours, fast_path=True,
                    keywords=("lpp", "locality preserving projections", "linear",
                              "laplacianfaces")))
registry.add(_embed(lle, check=check_lle,
                    keywords=("lle", "locally linear embedding", "manifold learning",
                              "barycentric weights")))
registry.add(_embed(
    som, check=check_som, long=True,
    examples={"points": [[0, 0], [0.1, 0], [5, 5], [5.1, 5], [0, 5], [5, 0]], "rows": 2,
              "columns": 2},
    limits={"rows": Le(1000), "columns": Le(1000), "max_iterations": Le(10_000_000)},
    keywords=("som", "kohonen", "self-organizing map", "vector quantization", "embedding")))
registry.add(_embed(tsne, check=check_tsne, examples=_STOCHASTIC, limits=_STEPS, long=True,
                    keywords=("tsne", "t-sne", "stochastic neighbor embedding", "fit-sne",
                              "visualization", "perplexity")))
registry.add(_embed(sne, check=check_sne, examples=_STOCHASTIC, limits=_STEPS, long=True,
                    keywords=("sne", "stochastic neighbor embedding", "symmetric sne",
                              "gaussian")))
