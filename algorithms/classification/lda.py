r"""Fisher's linear discriminant analysis: the projection that spreads the class means
apart relative to the spread within classes, and the Gaussian classifier that goes with it."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Any

import numpy as np
import scipy.linalg as la

from algorithms.classification._common import check_labelled
from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.params import Ge, LabelsLike, PointsLike, validate_params
from algorithms.core.types import FloatArray, IntArray, IntpArray
from algorithms.core.validation import as_int
from algorithms.embedding import trustworthiness

__all__ = ["LDAResult", "lda", "check_lda"]

#: Relative threshold below which a singular value counts as zero (scikit-learn's ``tol``).
RANK_TOLERANCE = 1e-4


@dataclass(frozen=True, eq=False)
class LDAResult:
    """The discriminant projection of the points, and class predictions.

    Attributes
    ----------
    embedding : (n, k) float array
        The points projected on the ``k`` discriminant directions (``k`` at most the rank
        of the class means, see ``lda``'s Notes), centred on the
        prior-weighted mean of the class means; within-class covariance is the identity
        there. Each column's largest entry (in absolute value) is positive.
    scalings : (d, k) float array
        The projection: ``embedding = (points - mean) @ scalings``.
    mean : (d,) float array
        The centre subtracted before projecting (the prior-weighted mean of the class means).
    classes : (c,) list
        The distinct labels (integers or strings), sorted; class ``i`` of ``predictions``
        is ``classes[i]``.
    class_means : (c, d) float array
        The mean of each class, in the order of ``classes``.
    predictions : (n,) list
        The most probable class of each point (from ``classes``).
    accuracy : float
        The fraction of points whose prediction is their label (training accuracy).
    explained_variance_ratio : (k,) float array
        The share of the between-class variance along each direction (one per column of
        ``embedding``).
    query_embedding : (m, k) float array
        ``query`` projected likewise; ``(0, k)`` without a query.
    query_predictions : (m,) list
        The most probable class of each query point; empty without a query.
    trustworthiness : float
        How well the embedding keeps each point's 5 nearest neighbours (1 is perfect;
        ``sklearn.manifold.trustworthiness``).
    """

    embedding: FloatArray
    scalings: FloatArray
    mean: FloatArray
    classes: list[Any]
    class_means: FloatArray
    predictions: list[Any]
    accuracy: float
    explained_variance_ratio: FloatArray
    query_embedding: FloatArray
    query_predictions: list[Any]
    trustworthiness: float


def check_lda(points: Any, labels: Any, n_components: Any = None, query: Any = None
              ) -> tuple[FloatArray, np.ndarray, IntArray, int, FloatArray | None]:
    """Check the inputs of :func:`lda`: labelled points (:func:`check_labelled`), more of
    them than classes, and ``n_components`` at most ``min(classes - 1, d)``. Returns the
    points, classes, class indices, the number of components and the query."""
    x, classes, y, q = check_labelled(points, labels, query)
    n, d = x.shape
    c = classes.shape[0]
    if n <= c:
        raise InvalidInputError(
            f"Expected `points` to hold more points than classes ({c}), got {n}.",
            field="points")
    most = min(c - 1, d)
    k = most if n_components is None else as_int(
        n_components, name="n_components", minimum=1, maximum=most,
        reason=f"min(classes - 1, dimension) = min({c - 1}, {d})")
    return x, classes, y, k, q


@validate_params
def lda(
    points: PointsLike,
    labels: LabelsLike,
    *,
    n_components: Annotated[int, Ge(1)] | None = None,
    query: PointsLike | None = None,
) -> LDAResult:
    r"""Fisher linear discriminant analysis.

    The directions maximising between-class over within-class variance (S_B a = λ S_W a, by two SVDs
    as scikit-learn's svd solver), the points projected on them, and the Gaussian shared-covariance
    classifier's predictions for the points and optional query points. Reports accuracy, explained
    variance and trustworthiness.

    The discriminant directions :math:`a` maximise the ratio of between-class to
    within-class variance of the projected points

    .. math::

        \max_a \frac{a^\mathsf{T} S_B a}{a^\mathsf{T} S_W a}, \qquad
        S_B = \sum_c \pi_c (\mu_c - \bar\mu)(\mu_c - \bar\mu)^\mathsf{T}, \quad
        S_W = \frac1n \sum_c \sum_{i \in c} (x_i - \mu_c)(x_i - \mu_c)^\mathsf{T},

    solved as the generalised eigenproblem :math:`S_B a = \lambda S_W a`; at most
    :math:`c - 1` directions carry between-class variance. As scikit-learn's ``svd``
    solver, it is computed without forming :math:`S_W`: an SVD of the within-class
    residuals (coordinates scaled to unit standard deviation) whitens :math:`S_W` on its
    range, dropping directions with singular values below ``1e-4`` (constant coordinates,
    ``d > n - c``), then an SVD of the whitened, prior-weighted class means gives the
    directions. Priors :math:`\pi_c` are the class proportions.

    Predictions: the class maximising :math:`-\tfrac12 \lVert z - \nu_c \rVert^2 + \log
    \pi_c` with :math:`z` the whitened point and :math:`\nu_c` the whitened class mean
    (the Bayes rule for Gaussian classes with a shared covariance).

    Parameters
    ----------
    points : (n, d) float array
        The training points, one row per point; more points than classes, at least 3.
    labels : (n,) int or str array
        The class of each point (integers or strings); at least 2 classes.
    n_components : int, optional
        The number ``k`` of discriminant directions, ``1 <= k <= min(c - 1, d)`` for
        ``c`` classes; that maximum when omitted. Fewer directions are returned when the
        class means span fewer dimensions (see Notes).
    query : (m, d) float array, optional
        Points to project and classify with the fitted model; none when omitted (the
        query outputs are then empty).

    Returns
    -------
    LDAResult
        ``embedding``, ``scalings``, ``mean``, ``classes``, ``class_means``,
        ``predictions``, ``accuracy``, ``explained_variance_ratio``, ``query_embedding``,
        ``query_predictions``, ``trustworthiness``.

    Raises
    ------
    InvalidInputError
        Bad ``points``; ``labels`` not one per point or fewer than 2 classes;
        ``n_components`` above ``min(c - 1, d)``; ``query`` of another dimension.
    DegenerateInputError
        No within-class spread at all (every point equal to its class mean), or class
        means that coincide in every direction where the classes spread.

    Notes
    -----
    LDA is principal component analysis's idea applied to classes: find a line on which
    the variance of the class means is as large as possible (classes spread apart) and
    each class's own variance as small as possible (classes gather). The ratio above is
    that criterion.

    When the class means span fewer dimensions than ``n_components`` (4 classes whose means
    lie in a plane of 3-D data: rank 2 although ``min(c - 1, d) = 3``), only the directions
    that carry between-class variance are returned (singular values of the whitened class
    means above ``1e-4`` of the largest), as scikit-learn's ``transform`` does: a further
    direction would be arbitrary and its embedding column constant. ``embedding``,
    ``scalings``, ``query_embedding`` and ``explained_variance_ratio`` then have that many
    columns. (scikit-learn's ``explained_variance_ratio_`` keeps ``n_components`` entries,
    the trailing ones below ``1e-8``.)

    References
    ----------
    .. [1] R. A. Fisher, "The use of multiple measurements in taxonomic problems", Annals
       of Eugenics 7(2), 1936.
    .. [2] T. Hastie, R. Tibshirani, J. Friedman, *The Elements of Statistical Learning*,
       2nd ed., Springer 2009, §4.3.

    Examples
    --------
    >>> pts = [[0, 0], [1, 0], [0, 1], [5, 5], [6, 5], [5, 6]]
    >>> res = lda(pts, [0, 0, 0, 1, 1, 1], query=[[0.5, 0.5], [5.5, 5.0]])
    >>> res.predictions, res.query_predictions, res.embedding.shape
    ([0, 0, 0, 1, 1, 1], [0, 1], (6, 1))
    """
    x, classes, y, k, q = check_lda(points, labels, n_components, query)
    n, d = x.shape
    c = classes.shape[0]

    counts = np.bincount(y, minlength=c).astype(np.float64)
    priors = counts / n
    means = np.zeros((c, d))
    np.add.at(means, y, x)
    means /= counts[:, None]
    xbar = priors @ means
    resid = x - means[y]
    std = resid.std(axis=0)
    std[std == 0] = 1.0
    _, s, vt = la.svd(resid / std / np.sqrt(n), full_matrices=False, check_finite=False)
    rank = int(np.sum(s > RANK_TOLERANCE))
    if rank == 0:
        raise DegenerateInputError(
            "Expected some spread of `points` within their classes, got every point equal "
            "to its class mean (the within-class covariance is zero).", field="points")
    whiten = (vt[:rank] / std).T / s[:rank]               # (d, rank): S_W^(-1/2) on its range
    between = (np.sqrt(n * priors / max(c - 1, 1))[:, None] * (means - xbar)) @ whiten
    _, s2, vt2 = la.svd(between, full_matrices=False, check_finite=False)
    if s2.size == 0 or s2[0] <= 0:
        raise DegenerateInputError(
            "Expected the class means of `points` to differ along directions in which the "
            "classes spread, got means that are equal there (they differ, if at all, only "
            "where every class is flat).", field="points")
    rank2 = int(np.sum(s2 > RANK_TOLERANCE * s2[0]))
    full = whiten @ vt2[:rank2].T                          # (d, rank2)
    full = _fix_signs_by_data(x - xbar, full)
    k = min(k, rank2)  # as scikit-learn: only the directions that carry between-class rank
    ratio = (s2 ** 2 / np.sum(s2 ** 2))[:k]
    scalings = full[:, :k]
    emb = (x - xbar) @ scalings
    nu = (means - xbar) @ full                             # whitened class means
    log_priors = np.log(priors)

    def classify(z: FloatArray) -> IntpArray:
        score = z @ nu.T - 0.5 * np.einsum("ij,ij->i", nu, nu)[None, :] + log_priors
        best: IntpArray = np.argmax(score, axis=1)
        return best

    pred = classify((x - xbar) @ full)
    if q is not None:
        q_emb = (q - xbar) @ scalings
        q_pred = classes[classify((q - xbar) @ full)].tolist()
    else:
        q_emb = np.zeros((0, k))
        q_pred = []
    return LDAResult(
        embedding=np.ascontiguousarray(emb),
        scalings=np.ascontiguousarray(scalings),
        mean=xbar,
        classes=classes.tolist(),
        class_means=means,
        predictions=classes[pred].tolist(),
        accuracy=float(np.mean(pred == y)),
        explained_variance_ratio=np.ascontiguousarray(ratio),
        query_embedding=np.ascontiguousarray(q_emb),
        query_predictions=q_pred,
        trustworthiness=trustworthiness(x, emb),
    )


def _fix_signs_by_data(centred: FloatArray, directions: FloatArray) -> FloatArray:
    """Flip each direction so that the largest projection (in absolute value) is positive."""
    proj = centred @ directions
    big = np.argmax(np.abs(proj), axis=0)
    return directions * np.where(proj[big, np.arange(proj.shape[1])] < 0, -1.0, 1.0)
