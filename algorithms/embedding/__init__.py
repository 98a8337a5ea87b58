"""Embedding (n×D data → n×k): linear projections (``pca``, ``random_projection``, ``lpp``),
distance-keeping maps (``mds``, ``isomap``), graph spectral maps (``laplacian_eigenmaps``,
``lle``), the self-organising map (``som``) and stochastic neighbour embeddings (``tsne``,
``sne``); every result reports its :func:`trustworthiness`, which other families use too."""

from algorithms.embedding._quality import trustworthiness
from algorithms.embedding.isomap import IsomapResult, isomap
from algorithms.embedding.laplacian_eigenmaps import LaplacianEigenmapsResult, laplacian_eigenmaps
from algorithms.embedding.lle import LLEResult, lle
from algorithms.embedding.lpp import LPPResult, lpp
from algorithms.embedding.mds import EmbeddingMDSResult, mds
from algorithms.embedding.pca import PCAResult, pca
from algorithms.embedding.random_projection import RandomProjectionResult, random_projection
from algorithms.embedding.sne import SNEResult, sne
from algorithms.embedding.som import SOMResult, som
from algorithms.embedding.tsne import TSNEResult, tsne

__all__ = [
    "trustworthiness",
    "PCAResult", "pca",
    "EmbeddingMDSResult", "mds",
    "RandomProjectionResult", "random_projection",
    "IsomapResult", "isomap",
    "LaplacianEigenmapsResult", "laplacian_eigenmaps",
    "LPPResult", "lpp",
    "LLEResult", "lle",
    "SOMResult", "som",
    "TSNEResult", "tsne",
    "SNEResult", "sne",
]
