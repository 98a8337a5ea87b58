"""Typed calls: one method per process, ``client.<family>.<method>(...)``.

Generated from the service's catalog by ``python -m service.sdkgen morphserve/_typed.py``
(``make sdk``); do not edit it by hand. Each method has the signature of its algorithm:
the same inputs, defaults and choices, so that a mistyped keyword is a ``TypeError`` before
any request is sent (naming the closest keyword there is: "did you mean `max_iterations`?"),
and the editor shows the documentation. A method starts a job as
:meth:`Client.execute` does (inputs left at their defaults are not sent) and returns the
:class:`Job` (with :class:`AsyncClient`: an awaitable of the :class:`AsyncJob`).
"""

# ruff: noqa: E501  (the docstrings are the algorithms', indented one level deeper)

from __future__ import annotations

import difflib
import functools
import inspect
from collections.abc import Callable, Iterable, Mapping
from typing import TYPE_CHECKING, Any, Literal, TypeAlias, cast

if TYPE_CHECKING:
    from ._client import AsyncClient, AsyncJob, Client, Job

__all__ = ["AsyncTypedCalls", "TypedCalls"]


ArrayLike: TypeAlias = Any
"""A numeric array: a numpy array, nested lists, or a ``.npy`` file path."""


PointsLike: TypeAlias = Any
"""An ``(n, d)`` point set: an array or nested lists, a point cloud or mesh object (trimesh, Open3D, PyVista: its points), or the path of a geometry file (.ply, .obj, .stl, .off, .glb, .npy)."""


MeshLike: TypeAlias = Any
"""A triangle mesh: ``{"vertices": ..., "faces": ...}``, a mesh object (trimesh, Open3D, PyVista) or the path of a mesh file (.ply, .obj, .stl, .off, .glb)."""


HandlesLike: TypeAlias = Any
"""Vertex indices and their positions: ``{"indices": ..., "positions": ...}``."""


GraphLike: TypeAlias = Any
"""A graph: ``{"n_nodes": ..., "edges": ..., "weights": ...}``."""


ShapeLike: TypeAlias = Any
"""A point set or a mesh (see ``PointsLike`` and ``MeshLike``)."""


def _changed(inputs: dict[str, Any], defaults: dict[str, Any]) -> dict[str, Any]:
    """The inputs to send: all but those left at their defaults (the service has the same)."""
    return {
        name: value
        for name, value in inputs.items()
        if name not in defaults
        or not (value is None and defaults[name] is None
                or type(value) is type(defaults[name]) and value == defaults[name])
    }


#: The options of every execution, after a method's inputs.
_OPTIONS = ("wait", "outputs", "idempotency_key", "time_limit")


def _unknown_keyword_message(method: str, name: str, valid: list[str]) -> str:
    """Python's refusal of a keyword a method does not take, with the closest it does take
    and the inputs there are (as the service's 422 tells an unknown input)."""
    guess = difflib.get_close_matches(name, valid, n=1, cutoff=0.6)
    hint = f"; did you mean `{guess[0]}`?" if guess else "."
    inputs = ", ".join(f"`{v}`" for v in valid if v not in _OPTIONS)
    return (f"{method}() got an unexpected keyword argument {name!r}{hint} "
            f"The inputs are {inputs}.")


def _refusing_unknown_keywords(method: Callable[..., Any]) -> Callable[..., Any]:
    """``method`` (a sync or async one), refusing a keyword it does not take with
    :func:`_unknown_keyword_message`: a ``TypeError`` before any request. The signature and
    docstring stay the method's (``functools.wraps``)."""
    keywords = [name for name, p in inspect.signature(method).parameters.items()
                if name != "self" and p.kind in (inspect.Parameter.POSITIONAL_OR_KEYWORD,
                                                 inspect.Parameter.KEYWORD_ONLY)]
    known = frozenset(keywords)

    def check(given: Mapping[str, Any]) -> None:
        for name in given:
            if name not in known:
                raise TypeError(_unknown_keyword_message(method.__qualname__, name, keywords))

    if inspect.iscoroutinefunction(method):
        @functools.wraps(method)
        async def refusing_async(self: Any, *args: Any, **kwargs: Any) -> Any:
            check(kwargs)
            return await method(self, *args, **kwargs)

        return refusing_async

    @functools.wraps(method)
    def refusing(self: Any, *args: Any, **kwargs: Any) -> Any:
        check(kwargs)
        return method(self, *args, **kwargs)

    return refusing


class _Family:
    """The processes of one family, called through a :class:`Client`."""

    def __init__(self, client: Client) -> None:
        self._client = client

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        for name, value in list(vars(cls).items()):
            if not name.startswith("_") and inspect.isfunction(value):
                setattr(cls, name, _refusing_unknown_keywords(value))

    def __repr__(self) -> str:
        return f"<{type(self).__name__} of {self._client!r}>"


class _AsyncFamily:
    """The processes of one family, called through an :class:`AsyncClient`."""

    def __init__(self, client: AsyncClient) -> None:
        self._client = client

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        for name, value in list(vars(cls).items()):
            if not name.startswith("_") and inspect.isfunction(value):
                setattr(cls, name, _refusing_unknown_keywords(value))

    def __repr__(self) -> str:
        return f"<{type(self).__name__} of {self._client!r}>"


_DEFAULTS_ALIGNMENT_AFFINE: dict[str, Any] = {"weights": None, "symmetric": False}
_DEFAULTS_ALIGNMENT_HOMOGRAPHY: dict[str, Any] = {"weights": None, "symmetric": False}
_DEFAULTS_ALIGNMENT_PCA: dict[str, Any] = {"mode": "unoriented", "choose": "residual", "scale": "anisotropic", "allow_reflection": False, "symmetric": False}
_DEFAULTS_ALIGNMENT_PRINCIPAL_SCALING: dict[str, Any] = {"weights": None, "allow_reflection": False, "symmetric": False}
_DEFAULTS_ALIGNMENT_RIGID: dict[str, Any] = {"weights": None, "allow_reflection": False}
_DEFAULTS_ALIGNMENT_SIMILARITY: dict[str, Any] = {"weights": None, "allow_reflection": False, "symmetric": False}
_DEFAULTS_ASSIGNMENT_BIPARTITE: dict[str, Any] = {"metric": "euclidean", "max_cost": None}
_DEFAULTS_ASSIGNMENT_CLOSEST_PAIR: dict[str, Any] = {}
_DEFAULTS_ASSIGNMENT_DISTANCE: dict[str, Any] = {}
_DEFAULTS_ASSIGNMENT_NEAREST: dict[str, Any] = {"k": 1, "direction": "forward", "max_distance": None}
_DEFAULTS_ASSIGNMENT_OPTIMAL_TRANSPORT: dict[str, Any] = {"source_weights": None, "target_weights": None, "method": "exact", "reg": 0.05, "max_iterations": 1000, "tolerance": 1e-09, "metric": "sqeuclidean"}
_DEFAULTS_CLASSIFICATION_LDA: dict[str, Any] = {"n_components": None, "query": None}
_DEFAULTS_CLASSIFICATION_NCA: dict[str, Any] = {"n_components": None, "init": "auto", "max_iterations": 50, "tolerance": 1e-05, "query": None, "seed": 0}
_DEFAULTS_LAYOUT_LAPLACIAN: dict[str, Any] = {"mesh": None, "graph": None, "pins": None, "weighting": "uniform", "boundary_spacing": "arc_length"}
_DEFAULTS_LAYOUT_MDS: dict[str, Any] = {"distances": None, "distance_pairs": None, "n_points": None, "graph": None, "n_components": 2, "rank": None, "max_iterations": 500, "tolerance": 1e-07}
_DEFAULTS_LAYOUT_POISSON: dict[str, Any] = {"mesh": None, "graph": None, "anchors": None, "anchor_weights": None, "pins": None, "weighting": "uniform"}
_DEFAULTS_LAYOUT_STRESS: dict[str, Any] = {"distances": None, "distance_pairs": None, "n_points": None, "graph": None, "n_components": 2, "weighting": "inverse_square", "init": "classical", "initial_positions": None, "max_iterations": 300, "tolerance": 1e-06, "relaxation": 1.0, "seed": 0}
_DEFAULTS_CLUSTERING_MARKOV: dict[str, Any] = {"points": None, "graph": None, "neighbors": "knn", "n_neighbors": 10, "radius": None, "weighting": "uniform", "sigma": None, "expansion": 2, "inflation": 2.0, "self_loops": 1.0, "pruning_threshold": 0.0001, "max_iterations": 100, "tolerance": 1e-06, "labels": None}
_DEFAULTS_CLUSTERING_SPECTRAL: dict[str, Any] = {"n_clusters": 8, "neighbors": "knn", "n_neighbors": 10, "radius": None, "weighting": "uniform", "sigma": None, "n_init": 10, "seed": 0, "labels": None}
_DEFAULTS_DEFORMATION_ARAP: dict[str, Any] = {"energy": "spokes_and_rims", "similarity": False, "max_iterations": 30, "tolerance": 1e-05}
_DEFAULTS_DEFORMATION_BIHARMONIC: dict[str, Any] = {"order": 2}
_DEFAULTS_DEFORMATION_DEFORMATION_TRANSFER: dict[str, Any] = {}
_DEFAULTS_DEFORMATION_HARMONIC: dict[str, Any] = {}
_DEFAULTS_DEFORMATION_ISOTROPIC_SCALING: dict[str, Any] = {"regularization": 1.0, "max_iterations": 200, "tolerance": 1e-06}
_DEFAULTS_DEFORMATION_LAPLACIAN: dict[str, Any] = {"weights": "cotangent"}
_DEFAULTS_DEFORMATION_LAPLACIAN_EDITING: dict[str, Any] = {"weights": "uniform"}
_DEFAULTS_EMBEDDING_ISOMAP: dict[str, Any] = {"n_components": 2, "neighbors": "knn", "n_neighbors": 5, "radius": None, "weighting": "distance", "quality_neighbors": 5, "labels": None}
_DEFAULTS_EMBEDDING_LAPLACIAN_EIGENMAPS: dict[str, Any] = {"n_components": 2, "neighbors": "knn", "n_neighbors": None, "radius": None, "weighting": "uniform", "sigma": None, "laplacian": "random_walk", "quality_neighbors": 5, "labels": None}
_DEFAULTS_EMBEDDING_LLE: dict[str, Any] = {"n_components": 2, "neighbors": "knn", "n_neighbors": 5, "radius": None, "regularization": 0.001, "quality_neighbors": 5, "labels": None}
_DEFAULTS_EMBEDDING_LPP: dict[str, Any] = {"n_components": 2, "neighbors": "knn", "n_neighbors": None, "radius": None, "weighting": "uniform", "sigma": None, "laplacian": "random_walk", "quality_neighbors": 5, "labels": None}
_DEFAULTS_EMBEDDING_MDS: dict[str, Any] = {"n_components": 2, "metric": False, "max_iterations": 300, "tolerance": 1e-06, "quality_neighbors": 5, "labels": None}
_DEFAULTS_EMBEDDING_PCA: dict[str, Any] = {"n_components": 2, "quality_neighbors": 5, "labels": None}
_DEFAULTS_EMBEDDING_RANDOM_PROJECTION: dict[str, Any] = {"n_components": 2, "kind": "gaussian", "density": None, "seed": 0, "quality_neighbors": 5, "labels": None}
_DEFAULTS_EMBEDDING_SNE: dict[str, Any] = {"n_components": 2, "perplexity": 30.0, "init": "pca", "learning_rate": "auto", "max_iterations": 750, "early_exaggeration": 4.0, "exaggeration_iterations": 250, "min_grad_norm": 1e-07, "seed": 0, "quality_neighbors": 5, "labels": None}
_DEFAULTS_EMBEDDING_SOM: dict[str, Any] = {"rows": 10, "columns": 10, "method": "online", "max_iterations": None, "learning_rate": 0.5, "sigma": None, "init": "pca", "seed": 0, "labels": None}
_DEFAULTS_EMBEDDING_TSNE: dict[str, Any] = {"n_components": 2, "perplexity": 30.0, "method": "auto", "init": "pca", "learning_rate": "auto", "max_iterations": 750, "early_exaggeration": 12.0, "exaggeration_iterations": 250, "min_grad_norm": 1e-07, "seed": 0, "quality_neighbors": 5, "labels": None}
_DEFAULTS_INTERPOLATION_AFFINE: dict[str, Any] = {"target": None, "transform": None, "times": None, "reflection": "refuse", "pivot": "centroid"}
_DEFAULTS_INTERPOLATION_ARAP: dict[str, Any] = {"target": None, "transform": None, "times": None, "anchor": 0}
_DEFAULTS_INTERPOLATION_POISSON: dict[str, Any] = {"target": None, "transform": None, "times": None, "anchor": 0}
_DEFAULTS_INTERPOLATION_RIGID: dict[str, Any] = {"target": None, "transform": None, "times": None, "scale": False, "pivot": "centroid"}
_DEFAULTS_PARAMETERIZATION_ABF: dict[str, Any] = {"max_iterations": 20, "tolerance": 1e-08}
_DEFAULTS_PARAMETERIZATION_ARAP: dict[str, Any] = {"init": "lscm", "max_iterations": 100, "tolerance": 1e-06}
_DEFAULTS_PARAMETERIZATION_ASAP: dict[str, Any] = {"init": "harmonic", "max_iterations": 100, "tolerance": 1e-06}
_DEFAULTS_PARAMETERIZATION_BIJECTIVE: dict[str, Any] = {"max_iterations": 100, "tolerance": 1e-06}
_DEFAULTS_PARAMETERIZATION_CONFORMAL: dict[str, Any] = {"method": "lscm", "pins": None}
_DEFAULTS_PARAMETERIZATION_HARMONIC: dict[str, Any] = {"boundary": "circle"}
_DEFAULTS_PARAMETERIZATION_STRETCH_MINIMIZING: dict[str, Any] = {"boundary": "circle", "power": 1.0, "max_iterations": 20, "tolerance": 0.0001}
_DEFAULTS_PARAMETERIZATION_TUTTE: dict[str, Any] = {"boundary": "circle", "weighting": "uniform"}
_DEFAULTS_REGISTRATION_CPD: dict[str, Any] = {"model": "rigid", "scale": True, "w": 0.0, "beta": 2.0, "alpha": 2.0, "low_rank": None, "normalize": True, "sigma2": None, "max_iterations": 100, "tolerance": 1e-05}
_DEFAULTS_REGISTRATION_ICP: dict[str, Any] = {"model": "rigid", "metric": "point_to_point", "init": "identity", "max_iterations": 30, "tolerance": 1e-06, "max_correspondence_distance": None, "overlap": 1.0, "kernel": "none", "kernel_scale": None, "target_normals": None, "source_normals": None, "normal_neighbors": 10}
_DEFAULTS_REGISTRATION_MULTIWAY: dict[str, Any] = {"correspondences": True, "model": "rigid", "init": None, "max_iterations": 100, "tolerance": 1e-09, "max_correspondence_distance": None, "metric": "symmetric", "neighbors": None, "min_fitness": 0.3, "edge_prune_threshold": 0.25, "preference_loop_closure": 1.0, "icp_max_iterations": 30}
_DEFAULTS_REGISTRATION_RANSAC: dict[str, Any] = {"features": "fpfh", "voxel_size": None, "feature_radius": None, "max_correspondence_distance": None, "max_iterations": 100000, "confidence": 0.999, "mutual_filter": True, "refine": True, "seed": 0}


class Alignment(_Family):
    """The alignment processes, through a :class:`Client`: ``affine``, ``homography``, ``pca``, ``principal_scaling``, ``rigid``, ``similarity``."""

    def affine(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        weights: ArrayLike | None = None,
        symmetric: bool = False,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Affine alignment (linear least squares).

        The matrix A and translation b minimising Σ wᵢ‖A xᵢ + b − yᵢ‖² for paired points in any
        dimension: A = Ỹ X̃⁺ by least squares, b through the centroids.

        Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The model is
        ``y = A x + b`` with any ``d×d`` matrix ``A``:

        .. math::

            \min_{A,\ b}\ \sum_{i=1}^{n} w_i \lVert A x_i + b - y_i \rVert^2 .

        With weighted centroids :math:`\bar x, \bar y` and centred points stacked as the columns
        of :math:`\tilde X, \tilde Y` (each scaled by :math:`\sqrt{w_i}`), the solution is

        .. math::

            A = \tilde Y \tilde X^{+} = \tilde Y \tilde X^\mathsf{T}
                (\tilde X \tilde X^\mathsf{T})^{-1}, \qquad b = \bar y - A \bar x,

        computed by :func:`numpy.linalg.lstsq` on :math:`\tilde X^\mathsf{T} A^\mathsf{T} =
        \tilde Y^\mathsf{T}` (an SVD of the ``n×d`` data), never by forming the inverse.

        Parameters
        ----------
        source : (n, d) float array
            The points to move, any ``d >= 1``, at least ``d + 1`` of them affinely independent.
        target : (n, d) float array
            Where they should land, paired row by row with ``source``.
        weights : (n,) float array, optional
            Non-negative per-pair weights with a positive sum; all equal when omitted. Pairs of
            weight zero are ignored, but the pairs left must still span ``d`` dimensions.
        symmetric : bool, default False
            Minimise the forward and the inverse residuals together,
            :math:`\sum_i w_i (\lVert A x_i + b - y_i \rVert^2
            + \lVert A^{-1}(y_i - b) - x_i \rVert^2)`; iterative, see Notes.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``alignment.affine``; its results hold ``transform``, ``linear``, ``translation``, ``rmse``, ``iterations``, ``converged``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] S. Schaefer, T. McPhail and J. Warren, "Image deformation using moving least
           squares", ACM Transactions on Graphics 25(3), 533-540, 2006 (the affine case).
        .. [2] G. H. Golub and C. F. Van Loan, Matrix Computations, 4th ed., §5.5 (least squares
           by the SVD), 2013.

        Examples
        --------
        >>> job = client.alignment.affine(  # doctest: +SKIP
        ...     [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
        ...     [[1, 0, 0], [3, 0, 0], [2, 1, 0], [1, 0, 3]],
        ...     wait=30)
        >>> job.results()["transform"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "weights": weights, "symmetric": symmetric}
        return self._client.execute(
            "alignment.affine",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ALIGNMENT_AFFINE),
        )

    def homography(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        weights: ArrayLike | None = None,
        symmetric: bool = False,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Projective alignment (normalised DLT).

        The (d+1)×(d+1) projective matrix P (P[d, d] = 1 when possible) with y ≈ dehomogenize(P [x; 1]),
        by the direct linear transformation on Hartley-normalised points, in any dimension; at least d +
        2 pairs in general position.

        Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The model is
        :math:`y = \operatorname{dehom}(P\,[x; 1])` with a ``(d+1)×(d+1)`` matrix ``P``
        defined up to scale, where :math:`\operatorname{dehom}(h) = h_{1..d} / h_{d+1}`.
        Writing :math:`p_j` for the rows of ``P`` and :math:`h_i = [x_i; 1]`, each pair gives
        ``d`` equations linear in ``P`` once the scale is multiplied out,

        .. math::

            p_j^\mathsf{T} h_i - y_{ij}\, p_{d+1}^\mathsf{T} h_i = 0, \qquad j = 1, \dots, d,

        stacked into :math:`A\,\operatorname{vec}(P) = 0`. The estimate minimises the
        algebraic error :math:`\sum_i w_i \lVert A_i \operatorname{vec}(P)\rVert^2` subject to
        :math:`\lVert P \rVert_F = 1`: ``vec(P)`` is the right singular vector of the smallest
        singular value of ``A``. Points are first normalised (Hartley): each set is centred at
        its weighted centroid and scaled so that its root-mean-square distance from it is
        :math:`\sqrt d`; the matrix found for the normalised points is mapped back,
        :math:`P = T_y^{-1} \hat P T_x`.

        Parameters
        ----------
        source : (n, d) float array
            The points to move, any ``d >= 1``, at least ``d + 2`` of them in general position.
        target : (n, d) float array
            Where they should land, paired row by row with ``source``.
        weights : (n,) float array, optional
            Non-negative per-pair weights with a positive sum; all equal when omitted. The
            ``d`` DLT rows of pair ``i`` are multiplied by :math:`\sqrt{w_i}` (so they weight the
            algebraic error), and the normalisation uses the weighted centroid and spread.
        symmetric : bool, default False
            Report the forward and backward transfer errors together in ``rmse``. The DLT
            equations of the inverse map are the same equations, so the estimate is unchanged.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``alignment.homography``; its results hold ``transform``, ``linear``, ``translation``, ``perspective``, ``rmse``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] R. Hartley and A. Zisserman, Multiple View Geometry in Computer Vision, 2nd ed.,
           §4.1-4.4 (DLT and normalisation), Cambridge University Press, 2004.
        .. [2] R. Hartley, "In defense of the eight-point algorithm", IEEE TPAMI 19(6),
           580-593, 1997.
        .. [3] J. Zaragoza, T.-J. Chin, M. S. Brown and D. Suter, "As-projective-as-possible
           image stitching with moving DLT", CVPR 2013 (the weighted DLT).

        Examples
        --------
        >>> job = client.alignment.homography(  # doctest: +SKIP
        ...     [[0, 0], [1, 0], [1, 1], [0, 1]],
        ...     [[0, 0], [0.5, 0], [0.5, 0.5], [0, 1]],
        ...     wait=30)
        >>> job.results()["transform"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "weights": weights, "symmetric": symmetric}
        return self._client.execute(
            "alignment.homography",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ALIGNMENT_HOMOGRAPHY),
        )

    def pca(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        mode: Literal["unoriented", "oriented"] = "unoriented",
        choose: Literal["residual", "rotation"] = "residual",
        scale: Literal["anisotropic", "isotropic", "none"] = "anisotropic",
        allow_reflection: bool = False,
        symmetric: bool = False,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Principal-axis alignment (no correspondences).

        Lays the principal axes of the source onto those of the target (sets of any sizes): A = E′ S K
        Eᵀ with signs S from skewness (oriented) or the best of the proper sign choices (unoriented),
        scale K none, isotropic or anisotropic √(D′D⁻¹).

        Each set is centred and its covariance diagonalised,
        :math:`\frac1n \tilde X^\mathsf{T} \tilde X = E D E^\mathsf{T}` and
        :math:`\frac1m \tilde Y^\mathsf{T} \tilde Y = E' D' E'^\mathsf{T}`, eigenvalues in
        decreasing order. The axes are paired by that order and the map is

        .. math::

            A = E' S K E^\mathsf{T}, \qquad t = \bar y - A \bar x,

        with :math:`S = \operatorname{diag}(\pm 1)` the chosen signs and ``K`` the scale:
        ``"anisotropic"`` :math:`K = \sqrt{D' D^{-1}}`, ``"isotropic"``
        :math:`K = \sqrt{\operatorname{tr} D' / \operatorname{tr} D}\, I`, ``"none"``
        :math:`K = I`. ``rotation`` is :math:`R = E' S E^\mathsf{T}`.

        The signs of eigenvectors are arbitrary; ``mode`` fixes them:

        - ``"oriented"``: each axis points where the set's third moment along it is positive
          (towards its long tail: the skewness), in both sets; then, if :math:`\det R = -1` and
          reflections are not allowed, the axis of the smallest eigenvalue is flipped (of all
          single flips, it increases the residual least).
        - ``"unoriented"``: every sign choice is tried, the :math:`2^{d-1}` proper ones
          (:math:`2^d` with ``allow_reflection``), and ``choose`` picks one: ``"residual"``
          (default) the one of smallest Chamfer distance between the moved source and the
          target (kd-tree), ``"rotation"`` the one of smallest rotation angle, i.e. largest
          :math:`\operatorname{tr} R`.

        Parameters
        ----------
        source : (n, d) float array
            The points to move, ``d >= 2``, ``n >= 2``.
        target : (m, d) float array
            The points to align to; same ``d``, any ``m >= 2``.
        mode : {"unoriented", "oriented"}, default "unoriented"
            How the signs of the axes are fixed: ``"unoriented"`` tries every proper sign
            choice of the principal axes and keeps the one ``choose`` prefers; ``"oriented"``
            points each axis towards its set's skew (third moment) and pairs the axes in order
            of variance.
        choose : {"residual", "rotation"}, default "residual"
            With ``mode="unoriented"``, which sign choice is kept: ``"residual"`` the one of
            least Chamfer distance, ``"rotation"`` the one of smallest rotation angle (largest
            trace). Ignored when oriented.
        scale : {"anisotropic", "isotropic", "none"}, default "anisotropic"
            How the source is stretched: ``"anisotropic"`` each principal axis by the ratio of
            the two sets' standard deviations along it, ``"isotropic"`` by one factor, the ratio
            of RMS radii, ``"none"`` not at all (rotate only).
        allow_reflection : bool, default False
            Let ``rotation`` be a reflection when that pairs the axes better.
        symmetric : bool, default False
            Count the inverse residuals in ``rmse`` too (target moved back onto the source).
            The Chamfer distance that ``choose="residual"`` minimises already counts both ways.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``alignment.pca``; its results hold ``transform``, ``linear``, ``rotation``, ``scale``, ``axes``, ``translation``, ``rmse``, ``chamfer``, ``reflection``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] T. Ju, "CSE 554 Lecture 7: Alignment", Washington University in St. Louis
           (principal-axis alignment and the sign ambiguity).

        Examples
        --------
        >>> job = client.alignment.pca(  # doctest: +SKIP
        ...     [[-1, 0], [-1, 0], [2, 0], [0, 0.5], [0, 0.5], [0, -1]],
        ...     [[4, 2], [-0.5, 2], [-0.5, 2], [1, 8], [1, -1], [1, -1]],
        ...     wait=30)
        >>> job.results()["transform"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "mode": mode, "choose": choose, "scale": scale, "allow_reflection": allow_reflection, "symmetric": symmetric}
        return self._client.execute(
            "alignment.pca",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ALIGNMENT_PCA),
        )

    def principal_scaling(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        weights: ArrayLike | None = None,
        allow_reflection: bool = False,
        symmetric: bool = False,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Principal scaling alignment (the cross-covariance map M = Ỹ X̃ᵀ).

        Scale along perpendicular axes, then rotate: y = UΣVᵀx + t with UΣVᵀ = Σ wᵢ ỹᵢ x̃ᵢᵀ. Equals the
        least-squares affine map exactly when the source is whitened (Σ wᵢ x̃ᵢ x̃ᵢᵀ = I); otherwise a
        worse fit.

        Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The map
        :math:`y = U \Sigma V^\mathsf{T} x + t` (``U``, ``V`` orthonormal, :math:`\Sigma \ge 0`
        diagonal) is taken from the cross-covariance itself,

        .. math::

            M = \sum_{i=1}^{n} w_i \tilde y_i \tilde x_i^\mathsf{T} = \tilde Y \tilde X^\mathsf{T}
              = U \Sigma V^\mathsf{T}, \qquad t = \bar y - M \bar x,

        with weighted centroids :math:`\bar x, \bar y` and centred points :math:`\tilde x_i,
        \tilde y_i`. This function computes exactly that (the weights enter unnormalised, so
        that all-ones weights give :math:`\tilde Y \tilde X^\mathsf{T}`), with the reflection
        fix of :func:`~algorithms.alignment.rigid`. It is **not** a least-squares fit in general;
        see Notes.

        Parameters
        ----------
        source : (n, d) float array
            The points to move, ``d >= 2`` and ``n >= d``.
        target : (n, d) float array
            Where they should land, paired row by row with ``source``.
        weights : (n,) float array, optional
            Non-negative per-pair weights with a positive sum; all ones when omitted. Unlike in
            the other alignment methods their overall size matters: doubling every weight
            doubles ``M``.
        allow_reflection : bool, default False
            Keep :math:`U \Sigma V^\mathsf{T}` when :math:`\det(U V^\mathsf{T}) = -1`. Off: the
            left singular vector of the smallest singular value is negated, so the map never
            mirrors.
        symmetric : bool, default False
            Report the forward and inverse residuals together in ``rmse``. ``M`` is a formula,
            not a minimiser, so the flag changes only the figure (and requires ``M``
            invertible).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``alignment.principal_scaling``; its results hold ``transform``, ``linear``, ``rotation``, ``scale``, ``axes``, ``translation``, ``rmse``, ``reflection``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] S. Umeyama, "Least-squares estimation of transformation parameters between two
           point patterns", IEEE TPAMI 13(4), 376-380, 1991: the same cross-covariance, whose
           rotation factor is the rigid fit.

        Examples
        --------
        >>> job = client.alignment.principal_scaling(  # doctest: +SKIP
        ...     [[0.5, 0.5], [-0.5, 0.5], [-0.5, -0.5], [0.5, -0.5]],
        ...     [[2.5, 1.25], [-0.5, 1.25], [-0.5, 0.75], [2.5, 0.75]],
        ...     wait=30)
        >>> job.results()["transform"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "weights": weights, "allow_reflection": allow_reflection, "symmetric": symmetric}
        return self._client.execute(
            "alignment.principal_scaling",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ALIGNMENT_PRINCIPAL_SCALING),
        )

    def rigid(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        weights: ArrayLike | None = None,
        allow_reflection: bool = False,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Rigid alignment (Kabsch / Umeyama without scale).

        The rotation R (det +1 unless reflections are allowed) and translation t minimising Σ wᵢ‖R xᵢ +
        t − yᵢ‖² for paired points in any dimension d ≥ 2.

        Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The model is
        ``y = R x + t`` with ``R`` orthogonal, solved in closed form (Kabsch 1976; Umeyama 1991
        without the scale):

        .. math::

            \min_{R^\mathsf{T} R = I,\ \det R = 1,\ t}\ \sum_{i=1}^{n} w_i
            \lVert R x_i + t - y_i \rVert^2

        With :math:`\bar x = \sum_i w_i x_i / \sum_i w_i` and :math:`\bar y` likewise, the
        weighted cross-covariance :math:`C = \sum_i w_i (y_i - \bar y)(x_i - \bar x)^\mathsf{T}
        = U \Sigma V^\mathsf{T}` gives :math:`R = U D V^\mathsf{T}` with
        :math:`D = \operatorname{diag}(1, \dots, 1, \operatorname{sign}\det(U V^\mathsf{T}))`
        and :math:`t = \bar y - R \bar x`.

        Parameters
        ----------
        source : (n, d) float array
            The points to move, ``d >= 2`` and ``n >= d``.
        target : (n, d) float array
            Where they should land, paired row by row with ``source``.
        weights : (n,) float array, optional
            Non-negative per-pair weights with a positive sum; all equal when omitted. Pairs of
            weight zero are ignored, but the pairs left must still determine the rotation.
        allow_reflection : bool, default False
            Also consider improper orthogonal matrices (determinant -1), i.e. solve the plain
            orthogonal Procrustes problem without the constraint :math:`\det R = 1`.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``alignment.rigid``; its results hold ``transform``, ``linear``, ``rotation``, ``translation``, ``scale``, ``rmse``, ``reflection``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] W. Kabsch, "A solution for the best rotation to relate two sets of vectors",
           Acta Crystallographica A 32(5), 922-923, 1976; and "A discussion of the solution for
           the best rotation to relate two sets of vectors", Acta Cryst. A 34(5), 827-828, 1978.
        .. [2] S. Umeyama, "Least-squares estimation of transformation parameters between two
           point patterns", IEEE Transactions on Pattern Analysis and Machine Intelligence
           13(4), 376-380, 1991.

        Examples
        --------
        >>> job = client.alignment.rigid(  # doctest: +SKIP
        ...     [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
        ...     [[1, 2, 3], [1, 3, 3], [0, 2, 3], [1, 2, 4]],
        ...     wait=30)
        >>> job.results()["transform"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "weights": weights, "allow_reflection": allow_reflection}
        return self._client.execute(
            "alignment.rigid",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ALIGNMENT_RIGID),
        )

    def similarity(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        weights: ArrayLike | None = None,
        allow_reflection: bool = False,
        symmetric: bool = False,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Similarity alignment (Umeyama).

        The rotation R (det +1 unless reflections are allowed), uniform scale s and translation t
        minimising Σ wᵢ‖s R xᵢ + t − yᵢ‖² for paired points, d ≥ 2; s = tr(DΣ)/σx² with Umeyama's
        reflection-corrected trace.

        Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The model is
        ``y = s R x + t`` with ``R`` orthogonal and ``s > 0``, solved in closed form (Umeyama
        1991):

        .. math::

            \min_{R^\mathsf{T} R = I,\ \det R = 1,\ s > 0,\ t}\ \sum_{i=1}^{n} w_i
            \lVert s R x_i + t - y_i \rVert^2 .

        With weighted centroids :math:`\bar x, \bar y`, centred points :math:`\tilde x_i,
        \tilde y_i`, normalised weights :math:`p_i = w_i / \sum_j w_j`, the cross-covariance
        :math:`C = \sum_i p_i \tilde y_i \tilde x_i^\mathsf{T} = U \Sigma V^\mathsf{T}` and
        :math:`\sigma_x^2 = \sum_i p_i \lVert \tilde x_i \rVert^2`:

        .. math::

            R = U D V^\mathsf{T}, \qquad
            s = \frac{\operatorname{tr}(D \Sigma)}{\sigma_x^2}, \qquad
            t = \bar y - s R \bar x,

        where :math:`D = \operatorname{diag}(1, \dots, 1, \operatorname{sign}\det(U V^\mathsf{T}))`
        (the identity with ``allow_reflection=True``).

        Parameters
        ----------
        source : (n, d) float array
            The points to move, ``d >= 2`` and ``n >= d``.
        target : (n, d) float array
            Where they should land, paired row by row with ``source``.
        weights : (n,) float array, optional
            Non-negative per-pair weights with a positive sum; all equal when omitted. Pairs of
            weight zero are ignored, but the pairs left must still determine the rotation.
        allow_reflection : bool, default False
            Also consider improper orthogonal matrices (determinant -1).
        symmetric : bool, default False
            Minimise the forward and the inverse residuals together,
            :math:`\sum_i w_i (\lVert s R x_i + t - y_i \rVert^2
            + \lVert s^{-1} R^\mathsf{T}(y_i - t) - x_i \rVert^2)`; see Notes.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``alignment.similarity``; its results hold ``transform``, ``linear``, ``rotation``, ``translation``, ``scale``, ``rmse``, ``reflection``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] S. Umeyama, "Least-squares estimation of transformation parameters between two
           point patterns", IEEE Transactions on Pattern Analysis and Machine Intelligence
           13(4), 376-380, 1991.
        .. [2] B. K. P. Horn, "Closed-form solution of absolute orientation using unit
           quaternions", Journal of the Optical Society of America A 4(4), 629-642, 1987.

        Examples
        --------
        >>> job = client.alignment.similarity(  # doctest: +SKIP
        ...     [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
        ...     [[1, 2, 3], [1, 4, 3], [-1, 2, 3], [1, 2, 5]],
        ...     wait=30)
        >>> job.results()["transform"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "weights": weights, "allow_reflection": allow_reflection, "symmetric": symmetric}
        return self._client.execute(
            "alignment.similarity",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ALIGNMENT_SIMILARITY),
        )


class Assignment(_Family):
    """The assignment processes, through a :class:`Client`: ``bipartite``, ``closest_pair``, ``distance``, ``nearest``, ``optimal_transport``."""

    def bipartite(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        metric: Literal["euclidean", "sqeuclidean"] = "euclidean",
        max_cost: float | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Optimal one-to-one matching (linear assignment).

        Matches the points of two sets one to one at the least total cost; sets may differ in size (the
        surplus stays unmatched), and max_cost leaves far points single. At most 16 million pairs n·m.

        With :math:`c_{ij}` the ``metric`` cost between :math:`x_i` and :math:`y_j`, this solves
        the (rectangular) linear assignment problem

        .. math::

            \min_{\pi}\ \sum_{(i, j) \in \pi} c_{ij}

        over matchings :math:`\pi` (sets of pairs in which no point appears twice) of size
        :math:`\min(n, m)`: when the sets differ in size, the surplus points of the larger set
        stay unmatched. With ``max_cost`` = :math:`\tau` every point may stay unmatched at a
        price of :math:`\tau / 2`, so a pair is worth making only when it costs less than
        :math:`\tau`:

        .. math::

            \min_{\pi}\ \sum_{(i, j) \in \pi} c_{ij}
            + \frac{\tau}{2}\,\bigl(n + m - 2\lvert\pi\rvert\bigr),
            \qquad c_{ij} \le \tau \ \text{for every}\ (i, j) \in \pi,

        that is, the matching maximises the total saving :math:`\sum_\pi (\tau - c_{ij})`.
        No returned pair costs more than :math:`\tau`.

        Parameters
        ----------
        source : (n, d) float array
            The first point set, any ``d >= 1``, at least one point.
        target : (m, d) float array
            The second point set, same ``d``; its size may differ from ``source`` (the surplus
            of the larger set stays unmatched). At most 16 million pairs ``n·m``
            (``MAX_COST_ENTRIES``).
        metric : {"euclidean", "sqeuclidean"}, default "euclidean"
            The cost of a pair: the distance :math:`\lVert x_i - y_j \rVert`, or its square.
            The squared distance favours many small displacements over a few large ones.
        max_cost : float, optional
            The largest cost of a pair (``> 0``, in the units of ``metric``): leaving a point
            unmatched costs half of it, so points whose every partner costs more stay
            unmatched. Omitted: every point of the smaller set is matched.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``assignment.bipartite``; its results hold ``pairs``, ``distances``, ``cost``, ``rmse``, ``n_pairs``, ``unmatched_source``, ``unmatched_target``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] H. W. Kuhn, "The Hungarian method for the assignment problem", Naval Research
           Logistics Quarterly 2, 83-97, 1955.
        .. [2] R. Jonker and A. Volgenant, "A shortest augmenting path algorithm for dense and
           sparse linear assignment problems", Computing 38, 325-340, 1987.
        .. [3] D. F. Crouse, "On implementing 2D rectangular assignment algorithms", IEEE
           Transactions on Aerospace and Electronic Systems 52(4), 1679-1696, 2016.

        Examples
        --------
        >>> job = client.assignment.bipartite(  # doctest: +SKIP
        ...     [[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]],
        ...     [[0.1, 0.0], [2.0, 0.0]],
        ...     wait=30)
        >>> job.results()["pairs"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "metric": metric, "max_cost": max_cost}
        return self._client.execute(
            "assignment.bipartite",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ASSIGNMENT_BIPARTITE),
        )

    def closest_pair(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Closest pair between two point sets (kd-tree).

        The single pair of points, one from each set, at the smallest distance.

        .. math::

            (i^\ast, j^\ast) = \operatorname*{arg\,min}_{i, j}\ \lVert x_i - y_j \rVert

        Parameters
        ----------
        source : (n, d) float array
            The first point set, any ``d >= 1``, at least one point.
        target : (m, d) float array
            The second point set, same ``d``; its size may differ from ``source``.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``assignment.closest_pair``; its results hold ``source_index``, ``target_index``, ``distance``, ``pairs``, ``distances``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] J. L. Bentley, "Multidimensional binary search trees used for associative
           searching", Communications of the ACM 18(9), 509-517, 1975.

        Examples
        --------
        >>> job = client.assignment.closest_pair(  # doctest: +SKIP
        ...     [[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]],
        ...     [[0.1, 0.0], [2.0, 0.0]],
        ...     wait=30)
        >>> job.results()["source_index"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target}
        return self._client.execute(
            "assignment.closest_pair",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ASSIGNMENT_CLOSEST_PAIR),
        )

    def distance(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Chamfer, Hausdorff and RMSE distances between point sets.

        How far apart two point sets are, from their nearest-neighbour assignment in both directions:
        Chamfer (sum and mean), Hausdorff (and both directed halves), RMSE, and every point's distance
        to the other set.

        With the nearest-neighbour distances :math:`d_i = \min_j \lVert x_i - y_j \rVert`
        (forward, one per source point) and :math:`e_j = \min_i \lVert x_i - y_j \rVert`
        (backward, one per target point):

        .. math::

            \text{chamfer} &= \sum_i d_i + \sum_j e_j, \qquad
            \text{chamfer\_mean} = \tfrac{1}{n}\sum_i d_i + \tfrac{1}{m}\sum_j e_j, \\
            \text{hausdorff} &= \max\bigl(\max_i d_i,\ \max_j e_j\bigr), \qquad
            \text{rmse} = \sqrt{\frac{\sum_i d_i^2 + \sum_j e_j^2}{n + m}} .

        ``chamfer`` measures the difference of two sets by a sum of distances (Barrow et al.
        1977 [1]_); it equals the sum of the distances of :func:`nearest` with
        ``direction="both"``.

        Parameters
        ----------
        source : (n, d) float array
            The first point set, any ``d >= 1``, at least one point.
        target : (m, d) float array
            The second point set, same ``d``; its size may differ from ``source``.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``assignment.distance``; its results hold ``chamfer``, ``chamfer_mean``, ``hausdorff``, ``hausdorff_forward``, ``hausdorff_backward``, ``rmse``, ``rmse_forward``, ``rmse_backward``, ``forward_distances``, ``backward_distances``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] H. G. Barrow, J. M. Tenenbaum, R. C. Bolles and H. C. Wolf, "Parametric
           correspondence and chamfer matching: two new techniques for image matching",
           IJCAI 1977, 659-663.
        .. [2] D. P. Huttenlocher, G. A. Klanderman and W. J. Rucklidge, "Comparing images
           using the Hausdorff distance", IEEE TPAMI 15(9), 850-863, 1993.

        Examples
        --------
        >>> job = client.assignment.distance(  # doctest: +SKIP
        ...     [[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]],
        ...     [[0.1, 0.0], [2.0, 0.0]],
        ...     wait=30)
        >>> job.results()["chamfer"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target}
        return self._client.execute(
            "assignment.distance",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ASSIGNMENT_DISTANCE),
        )

    def nearest(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        k: int = 1,
        direction: Literal["forward", "backward", "union", "intersection", "both"] = "forward",
        max_distance: float | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Nearest-neighbour assignment (kd-tree).

        Pairs each point with its k nearest neighbours in the other set, in one or both directions,
        optionally within a distance.

        For ``direction="forward"`` every source point :math:`x_i` is paired with the ``k``
        target points closest to it,

        .. math::

            \mathcal{P}_\to = \{(i, j) : y_j \in \operatorname{kNN}_k(x_i; Y)\},

        and ``"backward"`` does the same from the target side,
        :math:`\mathcal{P}_\leftarrow = \{(i, j) : x_i \in \operatorname{kNN}_k(y_j; X)\}`.
        ``"union"`` is :math:`\mathcal{P}_\to \cup \mathcal{P}_\leftarrow`, ``"intersection"``
        is :math:`\mathcal{P}_\to \cap \mathcal{P}_\leftarrow` (mutual nearest neighbours), and
        ``"both"`` is the forward list followed by the backward list without removing
        duplicates, so that with ``k=1`` the sum of ``distances`` is the Chamfer distance

        .. math::

            \sum_i \min_j \lVert x_i - y_j \rVert + \sum_j \min_i \lVert x_i - y_j \rVert .

        Parameters
        ----------
        source : (n, d) float array
            The first point set, any ``d >= 1``.
        target : (m, d) float array
            The second point set, same ``d``; its size may differ from ``source``.
        k : int, default 1
            Neighbours per query point, ``1 <= k <=`` the size of the set searched: ``target``
            for forward, ``source`` for backward, the smaller of the two otherwise.
        direction : {"forward", "backward", "union", "intersection", "both"}, default "forward"
            Which pairs to return: ``"forward"`` each source point with its ``k`` nearest
            target points; ``"backward"`` each target point with its ``k`` nearest source
            points; ``"union"`` the pairs found in either direction, ``"intersection"`` those
            found in both (mutual nearest neighbours), each pair once; ``"both"`` the forward
            list followed by the backward one, duplicates kept (with ``k=1`` its distances sum
            to the Chamfer distance).
        max_distance : float, optional
            Drop pairs farther apart than this (``> 0``, in the points' units); pairs at exactly
            this distance are kept. Applied in each direction before union or intersection.
            Omitted: no pair is dropped.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``assignment.nearest``; its results hold ``pairs``, ``distances``, ``rmse``, ``n_pairs``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] J. L. Bentley, "Multidimensional binary search trees used for associative
           searching", Communications of the ACM 18(9), 509-517, 1975.
        .. [2] S. Maneewongvatana and D. M. Mount, "Analysis of approximate nearest neighbor
           searching with clustered point sets", arXiv:cs/9901013, 1999 (the sliding-midpoint
           kd-tree of scipy's ``cKDTree``).

        Examples
        --------
        >>> job = client.assignment.nearest(  # doctest: +SKIP
        ...     [[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]],
        ...     [[0.1, 0.0], [2.0, 0.0]],
        ...     wait=30)
        >>> job.results()["pairs"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "k": k, "direction": direction, "max_distance": max_distance}
        return self._client.execute(
            "assignment.nearest",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ASSIGNMENT_NEAREST),
        )

    def optimal_transport(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        source_weights: ArrayLike | None = None,
        target_weights: ArrayLike | None = None,
        method: Literal["exact", "sinkhorn"] = "exact",
        reg: float = 0.05,
        max_iterations: int = 1000,
        tolerance: float = 1e-09,
        metric: Literal["euclidean", "sqeuclidean"] = "sqeuclidean",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Optimal transport between weighted point sets (exact or Sinkhorn).

        The transport plan moving the mass of one weighted point set onto another at the least cost,
        returned sparse as (source, target, mass) pairs, with its cost (Wasserstein distance). Exact
        linear program, or entropic Sinkhorn in the log domain. At most 16 million pairs n·m.

        With masses :math:`a \in \mathbb{R}^n_{\ge 0}`, :math:`b \in \mathbb{R}^m_{\ge 0}`
        (each summing to 1) and the ``metric`` cost :math:`C_{ij}` between :math:`x_i` and
        :math:`y_j`, the exact method solves the Kantorovich problem

        .. math::

            \min_{P \ge 0}\ \langle C, P \rangle = \sum_{ij} C_{ij} P_{ij}
            \quad\text{subject to}\quad P \mathbf{1} = a,\ \ P^\mathsf{T} \mathbf{1} = b,

        and ``method="sinkhorn"`` its entropic regularisation (Cuturi 2013)

        .. math::

            \min_{P \ge 0,\ P \mathbf{1} = a,\ P^\mathsf{T} \mathbf{1} = b}\
            \langle C, P \rangle - \varepsilon H(P), \qquad
            H(P) = -\sum_{ij} P_{ij} (\log P_{ij} - 1),

        whose solution :math:`P_{ij} = \exp((f_i + g_j - C_{ij})/\varepsilon)` is found by
        alternating the dual updates, in the log domain,

        .. math::

            f_i \leftarrow \varepsilon \log a_i
                - \varepsilon \operatorname{LSE}_j \bigl((g_j - C_{ij})/\varepsilon\bigr), \qquad
            g_j \leftarrow \varepsilon \log b_j
                - \varepsilon \operatorname{LSE}_i \bigl((f_i - C_{ij})/\varepsilon\bigr).

        Parameters
        ----------
        source : (n, d) float array
            The points mass leaves from, any ``d >= 1``, at least one point.
        target : (m, d) float array
            The points mass arrives at, same ``d``; its size may differ from ``source``. At
            most 16 million pairs ``n·m`` (``MAX_COST_ENTRIES``).
        source_weights : (n,) float array, optional
            Non-negative masses of the source points with a positive sum; uniform when omitted.
            They are relative: normalised to sum to 1 (so the totals of the two sets never
            disagree). Points of mass 0 take no part.
        target_weights : (m,) float array, optional
            Non-negative masses of the target points with a positive sum, normalised to sum
            to 1; uniform when omitted. Points of mass 0 take no part.
        method : {"exact", "sinkhorn"}, default "exact"
            ``"exact"``: the transport linear program (an assignment when the masses are
            uniform on sets of equal size, else the network simplex); ``"sinkhorn"``: its
            entropic regularisation, solved by log-domain Sinkhorn iterations (faster on
            large sets, a blurred plan).
        reg : float, default 0.05
            Sinkhorn's :math:`\varepsilon` (``> 0``), in the units of the cost (absolute, as in
            POT): smaller is closer to the exact plan but needs more iterations. Checked but
            unused by the exact method.
        max_iterations : int, default 1000
            Sinkhorn's iteration limit (``>= 1``); one iteration updates both potentials.
        tolerance : float, default 1e-9
            Sinkhorn stops when the L1 error of the plan's marginals is at most this (``> 0``),
            checked every iteration. POT's ``sinkhorn`` has the same default (``stopThr=1e-9``)
            but checks the L2 norm of the column marginals' error every 10 iterations, so it
            may run a few iterations more; the L1 rule bounds the mass misplaced, which is what
            the plan's users read.
        metric : {"sqeuclidean", "euclidean"}, default "sqeuclidean"
            The cost of moving unit mass from :math:`x_i` to :math:`y_j`:
            :math:`\lVert x_i - y_j \rVert^2` (2-Wasserstein) or :math:`\lVert x_i - y_j \rVert`
            (1-Wasserstein, earth mover's distance).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``assignment.optimal_transport``; its results hold ``pairs``, ``masses``, ``distances``, ``cost``, ``rmse``, ``marginal_error``, ``n_pairs``, ``iterations``, ``converged``, ``solver``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] L. Kantorovich, "On the translocation of masses", Doklady Akademii Nauk SSSR 37,
           199-201, 1942.
        .. [2] M. Cuturi, "Sinkhorn distances: lightspeed computation of optimal transport",
           NeurIPS 26, 2013.
        .. [3] G. Peyré and M. Cuturi, "Computational optimal transport", Foundations and
           Trends in Machine Learning 11(5-6), 355-607, 2019 (sections 3 and 4.4, the
           log-domain Sinkhorn).
        .. [4] N. Bonneel, M. van de Panne, S. Paris and W. Heidrich, "Displacement
           interpolation using Lagrangian mass transport", ACM Transactions on Graphics 30(6),
           158, 2011 (the network simplex POT implements).
        .. [5] A. Thibault, L. Chizat, C. Dossal and N. Papadakis, "Overrelaxed Sinkhorn-Knopp
           algorithm for regularized optimal transport", Algorithms 14(5), 143, 2021.
        .. [6] G. Birkhoff, "Tres observaciones sobre el algebra lineal", Universidad Nacional
           de Tucumán Revista, Serie A 5, 147-151, 1946.

        Examples
        --------
        >>> job = client.assignment.optimal_transport(  # doctest: +SKIP
        ...     [[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]],
        ...     [[0.1, 0.0], [2.0, 0.0]],
        ...     wait=30)
        >>> job.results()["pairs"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "source_weights": source_weights, "target_weights": target_weights, "method": method, "reg": reg, "max_iterations": max_iterations, "tolerance": tolerance, "metric": metric}
        return self._client.execute(
            "assignment.optimal_transport",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ASSIGNMENT_OPTIMAL_TRANSPORT),
        )


class Classification(_Family):
    """The classification processes, through a :class:`Client`: ``lda``, ``nca``."""

    def lda(
        self,
        points: PointsLike,
        labels: ArrayLike,
        *,
        n_components: int | None = None,
        query: PointsLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
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
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``classification.lda``; its results hold ``embedding``, ``scalings``, ``mean``, ``classes``, ``class_means``, ``predictions``, ``accuracy``, ``explained_variance_ratio``, ``query_embedding``, ``query_predictions``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] R. A. Fisher, "The use of multiple measurements in taxonomic problems", Annals
           of Eugenics 7(2), 1936.
        .. [2] T. Hastie, R. Tibshirani, J. Friedman, *The Elements of Statistical Learning*,
           2nd ed., Springer 2009, §4.3.

        Examples
        --------
        >>> job = client.classification.lda(  # doctest: +SKIP
        ...     [[0, 0], [1, 0], [0, 1], [1, 1.5], [5, 5], [6, 5], [5, 6], [6.5, 6]],
        ...     ['a', 'a', 'a', 'a', 'b', 'b', 'b', 'b'],
        ...     query=[[0.5, 0.5], [5.5, 5.0]],
        ...     wait=30)
        >>> job.results()["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "labels": labels, "n_components": n_components, "query": query}
        return self._client.execute(
            "classification.lda",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_CLASSIFICATION_LDA),
        )

    def nca(
        self,
        points: PointsLike,
        labels: ArrayLike,
        *,
        n_components: int | None = None,
        init: Literal["auto", "pca", "lda", "identity", "random"] = "auto",
        max_iterations: int = 50,
        tolerance: float = 1e-05,
        query: PointsLike | None = None,
        seed: int = 0,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Neighbourhood components analysis.

        The linear map maximising the expected number of points whose stochastic nearest neighbour
        (softmax over squared distances) has their class, by L-BFGS as scikit-learn. Reports the map,
        the embedding, leave-one-out 1-NN accuracy, query predictions and trustworthiness. Progress per
        iteration, cancellable.

        With :math:`z_i = A x_i`, each point picks a neighbour at random with probability

        .. math:: p_{ij} = \frac{e^{-\lVert z_i - z_j \rVert^2}}
                  {\sum_{l \ne i} e^{-\lVert z_i - z_l \rVert^2}}, \qquad p_{ii} = 0,

        and NCA maximises the expected number of points that pick one of their own class,
        :math:`f(A) = \sum_i \sum_{j \in C_i} p_{ij}`, with gradient

        .. math:: \frac{\partial f}{\partial A} = 2A \sum_i \Big(p_i \sum_k p_{ik}
                  x_{ik} x_{ik}^\mathsf{T} - \sum_{j \in C_i} p_{ij} x_{ij} x_{ij}^\mathsf{T}\Big),
                  \quad x_{ij} = x_i - x_j,

        by L-BFGS (scipy), as scikit-learn's ``NeighborhoodComponentsAnalysis`` does (same
        defaults, same initialisations, the same objective). Each gradient costs
        :math:`O(n^2 (d + k))` with dense ``n×n`` matrices.

        Parameters
        ----------
        points : (n, d) float array
            The training points, one row per point; at least 3 and at most 20,000 points (the
            method holds dense ``n×n`` matrices).
        labels : (n,) int or str array
            The class of each point (integers or strings); at least 2 classes.
        n_components : int, optional
            The output dimension ``k``, ``1 <= k <= d``; ``d`` when omitted.
        init : {"auto", "pca", "lda", "identity", "random"}, default "auto"
            The starting map: ``"pca"`` the ``k`` principal axes, ``"lda"`` the discriminant
            directions (needs ``k <= min(d, c - 1)`` for ``c`` classes; when the classes
            differ only along directions in which they are flat, PCA starts instead),
            ``"identity"`` the first ``k`` coordinates, ``"random"`` a standard normal
            ``k×d`` matrix drawn with ``seed``; ``"auto"`` is LDA when ``k <= min(d, c - 1)``,
            else PCA when ``k < d``, else the identity (scikit-learn's rule).
        max_iterations : int, default 50
            Most L-BFGS iterations (``converged`` is False when they run out).
        tolerance : float, default 1e-5
            L-BFGS stops when the relative decrease of the objective, or the largest gradient
            entry, falls below this (scipy's ``tol``, as scikit-learn passes it).
        query : (m, d) float array, optional
            Points to embed and classify (1-nearest neighbour in the embedding); none when
            omitted (the query outputs are then empty).
        seed : int or numpy Generator, default 0
            Draws the start of ``init="random"`` (unused otherwise); the same seed gives the
            same map.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``classification.nca``; its results hold ``embedding``, ``transform``, ``objective``, ``accuracy``, ``query_embedding``, ``query_predictions``, ``trustworthiness``, ``iterations``, ``converged``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] J. Goldberger, S. Roweis, G. Hinton, R. Salakhutdinov, "Neighbourhood
           components analysis", NIPS 2004.

        Examples
        --------
        >>> job = client.classification.nca(  # doctest: +SKIP
        ...     [[0, 0], [1, 0], [0, 1], [1, 1.5], [5, 5], [6, 5], [5, 6], [6.5, 6]],
        ...     ['a', 'a', 'a', 'a', 'b', 'b', 'b', 'b'],
        ...     n_components=1,
        ...     query=[[0.5, 0.5], [5.5, 5.0]],
        ...     wait=30)
        >>> job.results()["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "labels": labels, "n_components": n_components, "init": init, "max_iterations": max_iterations, "tolerance": tolerance, "query": query, "seed": seed}
        return self._client.execute(
            "classification.nca",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_CLASSIFICATION_NCA),
        )


class Layout(_Family):
    """The layout processes, through a :class:`Client`: ``laplacian``, ``mds``, ``poisson``, ``stress``."""

    def laplacian(
        self,
        mesh: MeshLike | None = None,
        *,
        graph: GraphLike | None = None,
        pins: HandlesLike | None = None,
        weighting: Literal["uniform", "cotangent", "tangent"] = "uniform",
        boundary_spacing: Literal["arc_length", "uniform"] = "arc_length",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Laplacian (spring) layout; Tutte embedding.

        Places every free vertex at the weighted average of its neighbours, some vertices pinned: L₀₀x =
        −L₀₁c, one factored solve for all coordinates. A mesh's boundary pinned to the unit circle by
        default (Tutte's embedding: with uniform or tangent weights no face flips). Reports the spring
        energy and flipped faces.

        Minimises the spring energy with the pinned positions :math:`c` fixed,

        .. math::

            \min_{p} \sum_{(i,j) \in E} w_{ij} \lVert p_i - p_j \rVert^2
            \quad\text{s.t.}\quad p_P = c
            \qquad\Longleftrightarrow\qquad L_{00}\, x = -L_{01}\, c,

        one solve of the free block of :math:`L = D - W` per coordinate (one factorization):
        every free vertex lands at the weighted average of its neighbours.

        Without ``pins``, a mesh's longest boundary loop is pinned to the unit circle in its
        order (counter-clockwise for counter-clockwise faces), its vertices spaced by the
        lengths of the boundary edges (``boundary_spacing="arc_length"``, as
        ``igl.map_vertices_to_circle``) or evenly (``"uniform"``); this is Tutte's embedding,
        a parameterization of a disk-like surface. By Tutte's spring theorem (Floater's
        generalisation to positive weights), non-negative weights and a boundary on a convex
        polygon give a layout in which no face flips.

        Parameters
        ----------
        mesh : Mesh or mapping, optional
            A triangle mesh, ``{"vertices": (n, 2|3), "faces": (m, 3)}``, whose edges are the
            springs; without ``pins`` its longest boundary loop is pinned to the unit circle
            (Tutte's embedding). Exactly one of ``mesh`` and ``graph``.
        graph : Graph or mapping, optional
            Instead of ``mesh``: a graph ``{"nodes": n, "edges": (e, 2), "weights": (e,)?}``;
            its weights (default 1, non-negative) are the spring stiffnesses. A repeated edge
            counts once (its first weight). Needs ``pins``.
        pins : Handles or mapping, optional
            ``{"indices": (p,), "positions": (p, k)}``: the pinned vertices (nodes) and their
            positions, in any dimension ``k >= 2``, the dimension of the layout; at least one
            in every connected component. Default for a mesh: its boundary on the unit circle
            (then ``k = 2``).
        weighting : {"uniform", "cotangent", "tangent"}, default "uniform"
            Mesh edge weights: ``"uniform"`` 1 (Tutte's barycentric map), ``"cotangent"``
            :math:`(\cot\alpha + \cot\beta)/2` (the harmonic map; negative across edges
            opposite obtuse angles, so faces may flip) or ``"tangent"`` :math:`\sum
            \tan(\theta/2) / \lVert p_i - p_j \rVert` (Floater's mean value weights, never
            negative: no flips). A graph takes only ``"uniform"`` (its own weights).
        boundary_spacing : {"arc_length", "uniform"}, default "arc_length"
            Where the default boundary's vertices go on the circle: ``"arc_length"`` spaced by
            the lengths of the boundary edges, ``"uniform"`` evenly. Unused with ``pins``.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``layout.laplacian``; its results hold ``positions``, ``pinned``, ``energy``, ``flipped_faces``, ``degenerate_faces``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] W. T. Tutte, "How to draw a graph", Proc. London Math. Soc. 13 (1963).
        .. [2] M. S. Floater, "Parametrization and smooth approximation of surface
           triangulations", CAGD 14 (1997); "Mean value coordinates", CAGD 20 (2003).

        Examples
        --------
        >>> job = client.layout.laplacian(  # doctest: +SKIP
        ...     mesh={'vertices': [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]], 'faces': [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]},
        ...     wait=30)
        >>> job.results()["positions"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "graph": graph, "pins": pins, "weighting": weighting, "boundary_spacing": boundary_spacing}
        return self._client.execute(
            "layout.laplacian",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_LAYOUT_LAPLACIAN),
        )

    def mds(
        self,
        distances: ArrayLike | None = None,
        *,
        distance_pairs: ArrayLike | None = None,
        n_points: int | None = None,
        graph: GraphLike | None = None,
        n_components: int = 2,
        rank: int | None = None,
        max_iterations: int = 500,
        tolerance: float = 1e-07,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Classical multidimensional scaling (with completion of missing distances).

        Coordinates from the top eigenvectors of the double-centred squared distances −½JD⁽²⁾J. Missing
        distances are completed first: rank-(k+2) truncation of the squared distances (Drineas et al.'s
        one-shot estimate), refined by alternating projections. Reports the stress over the known pairs.

        With the squared distances :math:`D^{(2)} = D \odot D` and the centring matrix
        :math:`J = I - \tfrac1n \mathbf 1 \mathbf 1^\mathsf{T}`, points :math:`X` with those
        distances satisfy :math:`X X^\mathsf{T} = -\tfrac12 J D^{(2)} J`. Its ``k`` largest
        eigenpairs :math:`(\lambda_c, e_c)` give :math:`X = [\sqrt{\lambda_1} e_1, \dots,
        \sqrt{\lambda_k} e_k]`, the best rank-``k`` fit of the centred Gram matrix.

        **Completion** (Drineas, Javed, Magdon-Ismail, Pandurangan, Virrankoski and Savvides
        2006). Squared Euclidean distances of points in :math:`\mathbb R^k` form a matrix of
        rank at most :math:`k + 2`. Missing entries are set to zero and the known
        off-diagonal ones divided by the fraction ``p`` of known pairs (an unbiased estimate
        of the full matrix), and the result is truncated to rank ``r = rank`` (default
        ``k + 2``): that is the paper's one-shot estimate. It is then refined by alternating
        projections: the missing entries are replaced by the current estimate, the known ones
        (and the zero diagonal) restored, and the matrix truncated to rank ``r`` again, until
        the missing entries change by less than ``tolerance`` (relative) or
        ``max_iterations`` is reached; ``max_iterations=0`` keeps the one-shot estimate.
        Completed squared distances are clipped at zero.

        The truncation keeps the eigenpairs a squared-distance matrix has: its largest
        (positive) eigenvalue and its ``r - 1`` most negative ones (Schoenberg: a Euclidean
        squared-distance matrix is negative semidefinite on the vectors summing to zero, so it
        has exactly one positive eigenvalue).

        Parameters
        ----------
        distances : (n, n) array_like, optional
            Pairwise distances, non-negative, the diagonal zero; NaN (``null`` in JSON) marks
            a missing entry. Symmetric where ``d_ij`` and ``d_ji`` are both known (to a
            relative 1e-5, as scikit-learn's MDS checks; an asymmetric matrix is refused);
            where one is known it stands for both. Exactly one of ``distances``,
            ``distance_pairs`` and ``graph``.
        distance_pairs : (m, 3) array_like, optional
            Instead of ``distances``: the known distances as rows ``(i, j, d)``, points ``i``
            and ``j`` (0-based) ``d`` apart; every other pair is missing. A pair listed twice
            (either order) must give one distance.
        n_points : int, optional
            With ``distance_pairs``: the number of points (default: the largest index + 1).
        graph : Graph or mapping, optional
            Instead of ``distances``: a connected graph whose shortest-path lengths are the
            distances (``graph.weights`` are edge lengths, default 1).
        n_components : int, default 2
            The dimension ``k`` of the layout, at most the number of points.
        rank : int, optional
            The rank of the completed squared-distance matrix, from ``n_components`` to the
            number of points; default ``n_components + 2``. Only used when entries are
            missing.
        max_iterations : int, default 500
            Refinement iterations of the completion after its one-shot estimate; 0 keeps the
            one-shot estimate of Drineas et al.
        tolerance : float, default 1e-7
            The completion stops when the missing squared distances change by less than this,
            relative to their size.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``layout.mds``; its results hold ``positions``, ``eigenvalues``, ``stress``, ``normalized_stress``, ``missing_pairs``, ``completion_iterations``, ``converged``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] W. S. Torgerson, "Multidimensional scaling: I. Theory and method",
           Psychometrika 17 (1952).
        .. [2] P. Drineas, A. Javed, M. Magdon-Ismail, G. Pandurangan, R. Virrankoski,
           A. Savvides, "Distance matrix reconstruction from incomplete distance information
           for sensor network localization", IEEE SECON (2006).

        Examples
        --------
        >>> job = client.layout.mds(  # doctest: +SKIP
        ...     distances=[[0, 3, 4], [3, 0, 5], [4, 5, 0]],
        ...     wait=30)
        >>> job.results()["positions"]  # doctest: +SKIP
        """
        inputs = {"distances": distances, "distance_pairs": distance_pairs, "n_points": n_points, "graph": graph, "n_components": n_components, "rank": rank, "max_iterations": max_iterations, "tolerance": tolerance}
        return self._client.execute(
            "layout.mds",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_LAYOUT_MDS),
        )

    def poisson(
        self,
        mesh: MeshLike | None = None,
        *,
        graph: GraphLike | None = None,
        vectors: ArrayLike,
        anchors: HandlesLike | None = None,
        anchor_weights: ArrayLike | None = None,
        pins: HandlesLike | None = None,
        weighting: Literal["uniform", "cotangent", "tangent"] = "uniform",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Poisson layout (edge vectors to match, soft anchors).

        Positions whose edge differences best match given vectors, pulled towards anchors and held at
        pins: min Σ wᵢⱼ‖(pᵢ − pⱼ) − vᵢⱼ‖² + Σ uᵢ‖pᵢ − zᵢ‖², solved as (DᵀWD + U)x = DᵀWv + Uz with one
        sparse factorization.

        .. math::

            \min_x \sum_{(i,j)} w_{ij} \lVert (p_i - p_j) - v_{ij} \rVert^2
                + \sum_i u_i \lVert p_i - z_i \rVert^2
            \;=\; \min_x (Dx - v)^\mathsf{T} W (Dx - v) + (x - z)^\mathsf{T} U (x - z)

        with :math:`D` the ``e×n`` difference matrix (row ``(i, j)``: +1 at ``i``, −1 at
        ``j``), so that

        .. math:: (D^\mathsf{T} W D + U)\, x = D^\mathsf{T} W v + U z ,

        solved once for all ``k`` coordinates (one sparse Cholesky factorization). With
        ``pins`` the pinned rows are fixed and the system is split as in
        :func:`~algorithms.layout.laplacian`.

        Parameters
        ----------
        mesh : Mesh or mapping, optional
            A triangle mesh ``{"vertices": (n, 2|3), "faces": (m, 3)}``; its edges, in the
            order of ``vectors``, are its unique edges ``(i, j)``, ``i < j``, sorted
            lexicographically. Exactly one of ``mesh`` and ``graph``.
        graph : Graph or mapping, optional
            Instead of ``mesh``: a graph ``{"nodes": n, "edges": (e, 2), "weights": (e,)?}``;
            edges in their given order and orientation, weights ``w`` (default 1,
            non-negative).
        vectors : (e, k) array_like
            The target of :math:`p_i - p_j` for each edge row ``(i, j)``, in the order of the
            edges; ``k >= 2`` is the dimension of the layout.
        anchors : Handles or mapping, optional
            ``{"indices": (a,), "positions": (a, k)}``: soft targets :math:`z_i`, the term
            :math:`\sum_i u_i \lVert p_i - z_i \rVert^2`. A connected component with neither
            anchors nor pins is centred at the origin.
        anchor_weights : (a,) array_like, optional
            The weight :math:`u_i \ge 0` of each anchor, in the order of ``anchors.indices``;
            all 1 when omitted. Only together with ``anchors``.
        pins : Handles or mapping, optional
            ``{"indices": (p,), "positions": (p, k)}``: vertices (nodes) held at these
            positions exactly.
        weighting : {"uniform", "cotangent", "tangent"}, default "uniform"
            Mesh edge weights ``w``: ``"uniform"`` 1, ``"cotangent"``
            :math:`(\cot\alpha + \cot\beta)/2` (negative across edges opposite obtuse
            angles) or ``"tangent"`` (Floater's mean value weights, never negative). A graph
            takes only ``"uniform"`` (its own weights).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``layout.poisson``; its results hold ``positions``, ``energy``, ``edge_rmse``, ``anchor_rmse``, ``free_components``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] P. Pérez, M. Gangnet, A. Blake, "Poisson image editing", ACM TOG 22(3) (2003).

        Examples
        --------
        >>> job = client.layout.poisson(  # doctest: +SKIP
        ...     graph={'nodes': 3, 'edges': [[0, 1], [1, 2]]},
        ...     vectors=[[-1.0, 0.0], [-1.0, 0.0]],
        ...     anchors={'indices': [0], 'positions': [[0.0, 0.0]]},
        ...     wait=30)
        >>> job.results()["positions"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "graph": graph, "vectors": vectors, "anchors": anchors, "anchor_weights": anchor_weights, "pins": pins, "weighting": weighting}
        return self._client.execute(
            "layout.poisson",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_LAYOUT_POISSON),
        )

    def stress(
        self,
        distances: ArrayLike | None = None,
        *,
        distance_pairs: ArrayLike | None = None,
        n_points: int | None = None,
        graph: GraphLike | None = None,
        n_components: int = 2,
        weighting: Literal["inverse_square", "inverse", "uniform"] = "inverse_square",
        init: Literal["classical", "random"] = "classical",
        initial_positions: PointsLike | None = None,
        max_iterations: int = 300,
        tolerance: float = 1e-06,
        relaxation: float = 1.0,
        seed: int = 0,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Stress majorization (SMACOF).

        The layout minimising the weighted stress Σ wᵢⱼ(‖xᵢ − xⱼ‖ − dᵢⱼ)² over the known pairs by
        Guttman transforms (never increasing), from classical MDS; distances from a matrix, a list of
        pairs, or a graph's shortest paths. Progress per iteration, cancellable; reports the stress
        history.

        Minimises the weighted stress over the known pairs

        .. math::

            \sigma(X) = \sum_{i<j} w_{ij} \left(\lVert x_i - x_j \rVert - d_{ij}\right)^2,
            \qquad w_{ij} = d_{ij}^{-2}\ (\text{default}),\ d_{ij}^{-1}\ \text{or}\ 1,

        by iterating the Guttman transform :math:`X \leftarrow V^{+} B(X) X` (optionally
        relaxed, ``relaxation``), with
        :math:`V = \sum_{i<j} w_{ij} (e_i - e_j)(e_i - e_j)^\mathsf{T}` (the weighted
        Laplacian) and :math:`B(X)_{ij} = -w_{ij} d_{ij} / \lVert x_i - x_j \rVert` off the
        diagonal (0 where :math:`x_i = x_j`), rows summing to zero. Each step minimises a
        quadratic majorizer of :math:`\sigma` touching it at the current layout, so the stress
        never increases. :math:`V^{+}` is computed once (a Cholesky factorization of
        :math:`V + \tfrac1n \mathbf 1 \mathbf 1^\mathsf{T}`); with uniform weights and every
        distance known :math:`V^{+} B X = B X / n`. The iteration stops when one step lowers
        the stress by less than ``tolerance`` times :math:`\eta^2(X) = \sum_{i<j} w_{ij}
        \lVert x_i - x_j \rVert^2` (scikit-learn's rule: with uniform weights the same
        start gives the same iterates and the same stopping point).

        Missing distances (NaN entries, pairs not listed) get weight 0: the stress counts only
        known pairs. A ``graph`` gives the distances of Gansner, Koren and North: shortest-path
        lengths.

        Parameters
        ----------
        distances : (n, n) array_like, optional
            Pairwise distances, non-negative, the diagonal zero; NaN (``null`` in JSON) marks
            an unknown distance, which gets weight 0. Symmetric where ``d_ij`` and ``d_ji``
            are both known (to a relative 1e-5, as scikit-learn's MDS checks; an asymmetric
            matrix is refused); where one is known it stands for both. Exactly one of
            ``distances``, ``distance_pairs`` and ``graph``.
        distance_pairs : (m, 3) array_like, optional
            Instead of ``distances``: the known distances as rows ``(i, j, d)``, points ``i``
            and ``j`` (0-based) ``d`` apart; every other pair is unknown. A pair listed twice
            (either order) must give one distance.
        n_points : int, optional
            With ``distance_pairs``: the number of points (default: the largest index + 1).
        graph : Graph or mapping, optional
            Instead of ``distances``: a connected graph ``{"nodes", "edges", "weights"?}``;
            the distances are its shortest-path lengths, ``weights`` being edge lengths
            (default 1).
        n_components : int, default 2
            The dimension ``k`` of the layout, at most the number of points.
        weighting : {"inverse_square", "inverse", "uniform"}, default "inverse_square"
            :math:`w_{ij} = d_{ij}^{-2}` (Gansner, Koren and North: relative errors count
            equally, local structure first), :math:`d_{ij}^{-1}`, or 1 (scikit-learn's metric
            MDS: absolute errors, large distances first). The inverse weightings need positive
            distances between distinct points.
        init : {"classical", "random"}, default "classical"
            The starting layout: classical MDS (:func:`~algorithms.layout.mds`, completing a
            partial matrix first), or standard normal coordinates drawn with ``seed``.
        initial_positions : (n, k) array_like, optional
            A starting layout, one row per point, ``k = n_components`` columns; overrides
            ``init``.
        max_iterations : int, default 300
            Most Guttman transforms; 0 evaluates the starting layout.
        tolerance : float, default 1e-6
            Stop when one iteration lowers the stress by less than ``tolerance`` times
            :math:`\eta^2(X) = \sum_{i<j} w_{ij} \lVert x_i - x_j \rVert^2` (scikit-learn's
            rule), or the stress is zero to rounding; 0 runs all ``max_iterations``.
        relaxation : float, default 1.0
            The step :math:`\alpha \in [1, 2)` of the relaxed update, the next layout
            :math:`X + \alpha (V^{+} B(X) X - X)` (de Leeuw and Heiser): 1 is plain SMACOF;
            larger steps keep the stress non-increasing and reach a given stress in fewer
            iterations (1.9 took 30-45 % fewer here).
        seed : int or numpy Generator, optional, default 0
            Seeds the random start of ``init="random"``: the same seed, the same layout.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``layout.stress``; its results hold ``positions``, ``stress``, ``normalized_stress``, ``stress_history``, ``iterations``, ``converged``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] E. R. Gansner, Y. Koren, S. North, "Graph drawing by stress majorization",
           Graph Drawing 2004, LNCS 3383.
        .. [2] J. de Leeuw, "Applications of convex analysis to multidimensional scaling",
           Recent Developments in Statistics (1977).
        .. [3] I. Borg, P. J. F. Groenen, *Modern Multidimensional Scaling*, 2nd ed.,
           Springer (2005), ch. 8.
        .. [4] J. de Leeuw, W. J. Heiser, "Multidimensional scaling with restrictions on the
           configuration", Multivariate Analysis V (1980) (the relaxed update).

        Examples
        --------
        >>> job = client.layout.stress(  # doctest: +SKIP
        ...     distances=[[0, 1, 1.4142135623730951, 1], [1, 0, 1, None], [1.4142135623730951, 1, 0, 1], [1, None, 1, 0]],
        ...     wait=30)
        >>> job.results()["positions"]  # doctest: +SKIP
        """
        inputs = {"distances": distances, "distance_pairs": distance_pairs, "n_points": n_points, "graph": graph, "n_components": n_components, "weighting": weighting, "init": init, "initial_positions": initial_positions, "max_iterations": max_iterations, "tolerance": tolerance, "relaxation": relaxation, "seed": seed}
        return self._client.execute(
            "layout.stress",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_LAYOUT_STRESS),
        )


class Clustering(_Family):
    """The clustering processes, through a :class:`Client`: ``markov``, ``spectral``."""

    def markov(
        self,
        points: PointsLike | None = None,
        *,
        graph: GraphLike | None = None,
        neighbors: Literal["knn", "radius", "all"] = "knn",
        n_neighbors: int = 10,
        radius: float | None = None,
        weighting: Literal["uniform", "distance", "heat"] = "uniform",
        sigma: float | None = None,
        expansion: int = 2,
        inflation: float = 2.0,
        self_loops: float = 1.0,
        pruning_threshold: float = 0.0001,
        max_iterations: int = 100,
        tolerance: float = 1e-06,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Markov clustering (MCL).

        Alternates expansion (a matrix power: random-walk steps) and inflation (elementwise power,
        columns renormalised) of the column-stochastic matrix of a graph or of the points' neighbour
        graph, pruning small entries, until it stops changing; the attractors name the clusters. The
        number of clusters follows from the inflation. Progress per iteration, cancellable.

        From the weighted adjacency :math:`A` with self-loops added, the column-stochastic
        matrix :math:`M = A D^{-1}` (a random walk's transition probabilities) is iterated:

        * expansion :math:`M \leftarrow M^e` (``e`` steps of the walk at once);
        * inflation :math:`m_{ij} \leftarrow m_{ij}^r / \sum_i m_{ij}^r` (strong transitions
          get stronger, weak ones fade);
        * pruning: entries below ``pruning_threshold`` are dropped (and each column
          renormalised), which keeps :math:`M` sparse;

        until :math:`\max_{ij} |M_t - M_{t-1}| <` ``tolerance``. The limit is idempotent: the
        rows with mass on the diagonal are the *attractors*, and every column puts its mass on
        the attractors of its cluster. Each point joins the attractor holding most of its
        column (lowest index on ties); attractors that share mass form one cluster.

        Parameters
        ----------
        points : (n, d) float array, optional
            Points whose neighbour graph is clustered, ``n >= 2``. Exactly one of ``points``
            and ``graph``.
        graph : Graph or mapping, optional
            Instead of ``points``: a graph ``{"nodes": n, "edges": (e, 2), "weights"?: (e,)}``
            with non-negative weights (default 1), clustered as it is.
        neighbors : {"knn", "radius", "all"}, default "knn"
            The neighbour graph of ``points``: ``"knn"`` joins each point to its
            ``n_neighbors`` nearest (the union of the two directions), ``"radius"`` to every
            point within ``radius``, ``"all"`` to every point (at most 10,000 points).
        n_neighbors : int, default 10
            Neighbours per point with ``neighbors="knn"``, other points only (MCL adds its own
            self-loops; its reference implementations take a graph, not points, so there is
            no peer count to follow, unlike :func:`spectral`'s); at most the number of points
            minus one.
        radius : float, optional
            The radius with ``neighbors="radius"``, required there.
        weighting : {"uniform", "distance", "heat"}, default "uniform"
            Edge weights of the neighbour graph from the edge lengths :math:`d`: ``"uniform"``
            1, ``"distance"`` :math:`1/d`, or ``"heat"`` the heat kernel
            :math:`\exp(-d^2/2\sigma^2)`, which suits MCL best where distances vary.
        sigma : float, optional
            The heat kernel's width :math:`\sigma`; the mean edge length when omitted.
        expansion : int, default 2
            The power ``e >= 2`` of the expansion, the walk's steps per round.
        inflation : float, default 2.0
            The elementwise power ``r > 1`` of the inflation; larger gives more, smaller
            clusters.
        self_loops : float, default 1.0
            Weight added on the diagonal of :math:`A` before normalising (van Dongen's
            recommendation; avoids parity oscillations). 0 adds none.
        pruning_threshold : float, default 1e-4
            Entries of :math:`M` below this are set to zero after each inflation (a column's
            largest entry is always kept), in ``[0, 1)``.
        max_iterations : int, default 100
            Most expansion-inflation rounds.
        tolerance : float, default 1e-6
            Stop when no entry of :math:`M` changes by ``tolerance`` or more in a round.
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``clustering.markov``; its results hold ``labels``, ``sizes``, ``n_clusters``, ``attractors``, ``iterations``, ``converged``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] S. van Dongen, "Graph clustering by flow simulation", PhD thesis, University of
           Utrecht, 2000.
        .. [2] A. J. Enright, S. van Dongen, C. A. Ouzounis, "An efficient algorithm for
           large-scale detection of protein families", Nucleic Acids Research 30(7), 2002.

        Examples
        --------
        >>> job = client.clustering.markov(  # doctest: +SKIP
        ...     points=[[0, 0], [0, 1], [1, 0], [1, 1], [10, 10], [10, 11], [11, 10], [11, 11]],
        ...     n_neighbors=3,
        ...     wait=30)
        >>> job.results()["labels"]  # doctest: +SKIP
        """
        inputs = {"points": points, "graph": graph, "neighbors": neighbors, "n_neighbors": n_neighbors, "radius": radius, "weighting": weighting, "sigma": sigma, "expansion": expansion, "inflation": inflation, "self_loops": self_loops, "pruning_threshold": pruning_threshold, "max_iterations": max_iterations, "tolerance": tolerance, "labels": labels}
        return self._client.execute(
            "clustering.markov",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_CLUSTERING_MARKOV),
        )

    def spectral(
        self,
        points: PointsLike,
        *,
        n_clusters: int = 8,
        neighbors: Literal["knn", "radius", "all"] = "knn",
        n_neighbors: int = 10,
        radius: float | None = None,
        weighting: Literal["uniform", "distance", "heat"] = "uniform",
        sigma: float | None = None,
        n_init: int = 10,
        seed: int = 0,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Spectral clustering (Ng, Jordan, Weiss).

        k-means (k-means++ seeding, seeded) on the bottom eigenvectors of the symmetric normalised
        Laplacian of the points' neighbour graph, rows scaled to unit length. Reports labels, cluster
        sizes, the embedding and its eigenvalues.

        With :math:`W` the weights of the neighbour graph and :math:`D` its degrees, the
        embedding is made of the eigenvectors :math:`u_1, \dots, u_k` of the ``k = n_clusters``
        smallest eigenvalues of the symmetric normalised Laplacian

        .. math:: L_\mathrm{sym} = D^{-1/2} (D - W) D^{-1/2} = I - D^{-1/2} W D^{-1/2},

        its rows scaled to unit length (Ng, Jordan and Weiss); k-means with k-means++ seeding
        (``n_init`` starts, the best kept) then groups the rows.

        Parameters
        ----------
        points : (n, d) float array
            The points to cluster, ``n >= 2``.
        n_clusters : int, default 8
            The number of clusters ``k``, at most the number of points.
        neighbors : {"knn", "radius", "all"}, default "knn"
            The neighbour graph: ``"knn"`` joins each point to its ``n_neighbors`` nearest
            (the union of the two directions), ``"radius"`` to every point within ``radius``,
            ``"all"`` to every point (at most 10,000 points).
        n_neighbors : int, default 10
            Neighbours per point with ``neighbors="knn"``, the point itself counted among them
            as scikit-learn's ``SpectralClustering`` counts it (``n_neighbors - 1`` other
            points; ties by lower index); at most the number of points minus one.
        radius : float, optional
            The radius with ``neighbors="radius"``, required there.
        weighting : {"uniform", "distance", "heat"}, default "uniform"
            Edge weights from the edge lengths :math:`d`: ``"uniform"`` 1 (scikit-learn's
            ``affinity="nearest_neighbors"``), ``"distance"`` :math:`1/d`, or ``"heat"`` the
            heat kernel :math:`\exp(-d^2/2\sigma^2)`.
        sigma : float, optional
            The heat kernel's width :math:`\sigma`; the mean edge length when omitted.
        n_init : int, default 10
            k-means++ starts; the one with the least inertia is kept.
        seed : int or numpy Generator, default 0
            Seeds k-means++; the same seed gives the same labels.
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``clustering.spectral``; its results hold ``labels``, ``sizes``, ``embedding``, ``eigenvalues``, ``inertia``, ``graph_components``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] A. Y. Ng, M. I. Jordan, Y. Weiss, "On spectral clustering: analysis and an
           algorithm", NIPS 2001.
        .. [2] U. von Luxburg, "A tutorial on spectral clustering", Statistics and Computing
           17(4), 2007.
        .. [3] D. Arthur, S. Vassilvitskii, "k-means++: the advantages of careful seeding",
           SODA 2007.

        Examples
        --------
        >>> job = client.clustering.spectral(  # doctest: +SKIP
        ...     [[0, 0], [0, 1], [1, 0], [1, 1], [10, 10], [10, 11], [11, 10], [11, 11]],
        ...     n_clusters=2,
        ...     n_neighbors=3,
        ...     wait=30)
        >>> job.results()["labels"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_clusters": n_clusters, "neighbors": neighbors, "n_neighbors": n_neighbors, "radius": radius, "weighting": weighting, "sigma": sigma, "n_init": n_init, "seed": seed, "labels": labels}
        return self._client.execute(
            "clustering.spectral",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_CLUSTERING_SPECTRAL),
        )


class Deformation(_Family):
    """The deformation processes, through a :class:`Client`: ``arap``, ``biharmonic``, ``deformation_transfer``, ``harmonic``, ``isotropic_scaling``, ``laplacian``, ``laplacian_editing``."""

    def arap(
        self,
        mesh: MeshLike,
        handles: HandlesLike,
        *,
        energy: Literal["spokes_and_rims", "spokes"] = "spokes_and_rims",
        similarity: bool = False,
        max_iterations: int = 30,
        tolerance: float = 1e-05,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""As-rigid-as-possible deformation (local/global).

        Alternates per-vertex best rotations (batched, proper) and one prefactored cotangent-Laplacian
        solve; handles met exactly, energy never increasing; spokes or spokes-and-rims energy, optional
        per-vertex scale.

        Minimises over the new positions :math:`p'` and one rotation :math:`R_i` per vertex

        .. math::

            E(p', R) = \sum_i \sum_{(j,k) \in \mathcal{E}(i)} w_{jk}
            \lVert (p'_j - p'_k) - R_i (p_j - p_k) \rVert^2,

        with :math:`\mathcal{E}(i)` the spokes of vertex :math:`i` (edges :math:`(i, j)`,
        ``energy="spokes"``, Sorkine & Alexa's energy) or its spokes and rims (every edge of the
        faces around :math:`i`, each face's edge weighted by that face's :math:`\tfrac12\cot`,
        ``"spokes_and_rims"``), and :math:`w` the cotangent weights; handle vertices are held at
        their targets. Block coordinate descent alternates the local step (each :math:`R_i`
        maximises :math:`\operatorname{tr}(R_i S_i)` for the weighted covariance
        :math:`S_i = \sum w\, e\, e'^\mathsf{T}`: a rigid alignment, proper rotation enforced)
        and the global step (:math:`L p' = b(R)`, a Laplacian solve with the factor computed
        once). Each step minimises the energy over its block exactly, so the energy never
        increases.

        With ``similarity=True`` each vertex also gets a scale :math:`s_i \ge 0`
        (:math:`R_i \to s_i R_i`), fitted in the local step as
        :math:`s_i = \max(\operatorname{tr}(R_i S_i), 0) / \sum w \lVert e\rVert^2`.

        Parameters
        ----------
        mesh : Mesh or {"vertices", "faces"}
            The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
            0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
            are.
        handles : Handles or {"indices", "positions"}
            The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
            ``(p, d)`` positions; at least one handle in every connected component.
        energy : {"spokes_and_rims", "spokes"}, default "spokes_and_rims"
            The edges each vertex's rotation answers for: ``"spokes_and_rims"`` every edge of
            the faces around the vertex (Chao et al.; libigl's default,
            ``ARAP_ENERGY_TYPE_SPOKES_AND_RIMS``), ``"spokes"`` only the edges at the vertex
            (Sorkine & Alexa; ``ARAP_ENERGY_TYPE_SPOKES``).
        similarity : bool, default False
            Fit a non-negative scale per vertex too, besides its rotation
            (as-similar-as-possible).
        max_iterations : int, default 30
            Upper bound on local/global iterations (libigl's ``ARAPData.max_iter`` is 10, run
            to the end; ours stops earlier by ``tolerance``, so a larger bound costs nothing on
            easy edits and lets hard ones converge).
        tolerance : float, default 1e-5
            Stop when an iteration lowers the energy by at most this fraction; ``0`` runs all
            ``max_iterations`` (libigl's behaviour), unless the energy reaches zero.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``deformation.arap``; its results hold ``mesh``, ``energy``, ``handle_residual``, ``iterations``, ``converged``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] O. Sorkine and M. Alexa, "As-rigid-as-possible surface modeling", Symposium on
           Geometry Processing, 109-116, 2007.
        .. [2] I. Chao, U. Pinkall, P. Sanan and P. Schröder, "A simple geometric model for
           elastic deformations", ACM Transactions on Graphics 29(4), 38, 2010.
        """
        inputs = {"mesh": mesh, "handles": handles, "energy": energy, "similarity": similarity, "max_iterations": max_iterations, "tolerance": tolerance}
        return self._client.execute(
            "deformation.arap",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_DEFORMATION_ARAP),
        )

    def biharmonic(
        self,
        mesh: MeshLike,
        handles: HandlesLike,
        *,
        order: int = 2,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Biharmonic deformation.

        Spreads the handle displacements by the bi-Laplace equation L M⁻¹ L u = 0 (cotangent Laplacian,
        Voronoi mass), smooth at the handles; as igl.harmonic with k = 2 (or 3).

        The displacement :math:`u = p' - p` minimises the Laplacian energy
        :math:`\int (\Delta u)^2`, discretised with the cotangent Laplacian :math:`L` and the
        Voronoi mass matrix :math:`M`, with the handle displacements fixed:

        .. math::

            \min_u \sum_c u_c^\mathsf{T} L M^{-1} L\, u_c
            \quad\Longrightarrow\quad Q_{ff} u_f = -Q_{fp} u_p,\quad Q = L M^{-1} L,
            \qquad p' = p + u.

        Thin-plate-like: smooth (:math:`C^1`) at the handles, so handle regions (several
        vertices moved together) carry their rotation into the surroundings. ``order=3``
        (:math:`Q = L M^{-1} L M^{-1} L`, triharmonic) is smoother still.
        ``igl.harmonic(V, F, b, bc, k)`` with ``k = order`` and ``bc`` the handle
        displacements computes the same.

        Parameters
        ----------
        mesh : Mesh or {"vertices", "faces"}
            The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
            0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
            are.
        handles : Handles or {"indices", "positions"}
            The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
            ``(p, d)`` positions; at least one handle in every connected component (two rings
            of handles pin a boundary's position and slope).
        order : {2, 3}, default 2
            The power ``k`` of the Laplacian: 2 (biharmonic, :math:`Q = L M^{-1} L`) or 3
            (triharmonic, smoother still).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``deformation.biharmonic``; its results hold ``mesh``, ``energy``, ``handle_residual``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] M. Botsch and L. Kobbelt, "An intuitive framework for real-time freeform
           modeling", ACM TOG 23(3), 630-634, 2004.
        .. [2] A. Jacobson, E. Tosun, O. Sorkine and D. Zorin, "Mixed finite elements for
           variational surface modeling", Computer Graphics Forum 29(5), 2010.
        """
        inputs = {"mesh": mesh, "handles": handles, "order": order}
        return self._client.execute(
            "deformation.biharmonic",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_DEFORMATION_BIHARMONIC),
        )

    def deformation_transfer(
        self,
        mesh: MeshLike,
        handles: HandlesLike,
        *,
        source: PointsLike,
        source_deformed: PointsLike,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Deformation transfer (same connectivity).

        Gives the target mesh the per-face deformation gradients of a source mesh that deforms from
        source to source_deformed (same faces): min Σ‖T_c − Q_c‖²_F with shared vertices (and, in 3-D, a
        free fourth vertex per face); one factored solve.

        The three share connectivity: ``source`` and ``source_deformed`` are vertex arrays on
        ``mesh.faces`` (face ``c`` of the source corresponds to face ``c`` of the target). For
        each face, the source's deformation gradient is :math:`Q_c = \tilde V'_c
        \tilde V_c^{-1}` with :math:`\tilde V` the face's edge frame (:func:`frames`; in 3-D the
        third column is the scaled normal, Sumner & Popović's fourth vertex). The target's new
        vertices :math:`x` (plus, in 3-D, one free fourth vertex per face) minimise

        .. math::

            \min_{x} \sum_c \lVert T_c(x) - Q_c \rVert_F^2, \qquad
            T_c(x) = \tilde X_c\, \tilde W_c^{-1},

        :math:`\tilde W_c` the target's rest frame and :math:`\tilde X_c` the frame of the
        unknowns, with the handle vertices held at their targets. :math:`T_c` is linear in
        :math:`x`, the coordinates separate, and the normal equations
        :math:`A^\mathsf{T} A x = A^\mathsf{T} q` are factored once for all coordinates.

        Parameters
        ----------
        mesh : Mesh or {"vertices", "faces"}
            The target in its rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)``
            triangles of 0-based vertex indices, no zero-area ones. Vertices no face uses stay
            where they are.
        handles : Handles or {"indices", "positions"}
            Target vertices held at given positions: ``(p,)`` distinct vertex indices and their
            ``(p, d)`` positions; at least one in every connected component (the per-face
            gradients leave a translation free). To transfer without user constraints, pin one
            vertex per component where the source's motion puts it (e.g. its rest position plus
            the source's displacement there).
        source : (n, d) float array
            The source's rest vertices on the faces of ``mesh`` (the same connectivity: vertex
            ``i`` corresponds to target vertex ``i``); no zero-area faces.
        source_deformed : (n, d) float array
            The source's deformed vertices, on the faces of ``mesh`` too.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``deformation.deformation_transfer``; its results hold ``mesh``, ``energy``, ``handle_residual``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] R. W. Sumner and J. Popović, "Deformation transfer for triangle meshes", ACM
           Transactions on Graphics 23(3), 399-405, 2004.
        """
        inputs = {"mesh": mesh, "handles": handles, "source": source, "source_deformed": source_deformed}
        return self._client.execute(
            "deformation.deformation_transfer",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_DEFORMATION_DEFORMATION_TRANSFER),
        )

    def harmonic(
        self,
        mesh: MeshLike,
        handles: HandlesLike,
        *,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Harmonic deformation.

        Spreads the handle displacements by the Laplace equation (cotangent Laplacian): L_ff u_f = −L_fp
        u_p, x' = x + u; as igl.harmonic with k = 1.

        The displacement :math:`u = p' - p` minimises the Dirichlet energy
        :math:`\int \lVert \nabla u \rVert^2`, discretised with the cotangent Laplacian
        :math:`L`, with the handle displacements fixed:

        .. math::

            \min_u \sum_c u_c^\mathsf{T} L\, u_c
            \quad\Longrightarrow\quad L_{ff} u_f = -L_{fp} u_p,\qquad p' = p + u.

        Membrane-like: the deformation is as smooth as a soap film, with kinks (:math:`C^0`) at
        the handles. The same as :func:`~algorithms.deformation.laplacian` with cotangent
        weights (both solve :math:`L_{ff} p'_f = (L p)_f - L_{fp} c`), and as
        ``igl.harmonic(V, F, b, bc, 1)`` applied to the handle displacements ``bc``.

        Parameters
        ----------
        mesh : Mesh or {"vertices", "faces"}
            The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
            0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
            are.
        handles : Handles or {"indices", "positions"}
            The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
            ``(p, d)`` positions; at least one handle in every connected component.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``deformation.harmonic``; its results hold ``mesh``, ``energy``, ``handle_residual``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] M. Botsch and O. Sorkine, "On linear variational surface deformation methods",
           IEEE TVCG 14(1), 213-230, 2008.
        .. [2] A. Jacobson, I. Baran, J. Popović and O. Sorkine, "Bounded biharmonic weights
           for real-time deformation", ACM TOG 30(4), 78, 2011 (libigl's ``harmonic``).
        """
        inputs = {"mesh": mesh, "handles": handles}
        return self._client.execute(
            "deformation.harmonic",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_DEFORMATION_HARMONIC),
        )

    def isotropic_scaling(
        self,
        mesh: MeshLike,
        handles: HandlesLike,
        *,
        regularization: float = 1.0,
        max_iterations: int = 200,
        tolerance: float = 1e-06,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Isotropic scaling deformation (scale-and-stretch).

        Each face may only scale, edges keep their directions and adapt their lengths: block coordinate
        descent between closed-form per-face scales and one prefactored Laplacian solve, length ratios
        from the previous iterate (a correction of the paper, whose fixed ratios cannot be split off
        from the positions they depend on).

        With :math:`e_{ij} = p_i - p_j` the rest edges and :math:`e'_{ij}` the new ones, each
        face :math:`c` gets a scale :math:`s_c` and each edge a length ratio :math:`l_{ij}`:

        .. math::

            \min_{p', s} \sum_c \sum_{(i,j) \in c} \lVert e'_{ij} - s_c\, e_{ij} \rVert^2
            + \lambda \sum_c \sum_{(i,j) \in c} \lVert e'_{ij} - l_{ij}\, e_{ij} \rVert^2,
            \qquad l_{ij} = \frac{\lVert e'_{ij} \rVert}{\lVert e_{ij} \rVert},

        with the handles fixed. Block coordinate descent: with :math:`p'` fixed,
        :math:`s_c = \sum_{(i,j)\in c} e'^\mathsf{T}_{ij} e_{ij} / \sum_{(i,j)\in c}
        \lVert e_{ij}\rVert^2` (closed form, no SVD) and :math:`l_{ij}` from the current
        lengths; with :math:`s, l` fixed, :math:`p'` solves
        :math:`(1 + \lambda) L\, p' = b` with the graph Laplacian :math:`L` of the face edges
        (an edge shared by two faces counts twice), factored once.

        Parameters
        ----------
        mesh : Mesh or {"vertices", "faces"}
            The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
            0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
            are.
        handles : Handles or {"indices", "positions"}
            The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
            ``(p, d)`` positions; at least one handle in every connected component.
        regularization : float, default 1.0
            :math:`\lambda \ge 0`, the weight of the edge-length term. ``0`` leaves only the
            scales, with which faces overlap easily; larger values keep edge directions
            stiffer.
        max_iterations : int, default 200
            Upper bound on iterations (the fixed-point iteration converges linearly; each
            iteration is one solve with the factor computed once).
        tolerance : float, default 1e-6
            Stop when no vertex moved by more than this fraction of the bounding-box diagonal
            in an iteration.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``deformation.isotropic_scaling``; its results hold ``mesh``, ``scales``, ``energy``, ``handle_residual``, ``iterations``, ``converged``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] Y.-S. Wang, C.-L. Tai, O. Sorkine and T.-Y. Lee, "Optimized scale-and-stretch for
           image resizing", ACM Transactions on Graphics 27(5), 118, 2008.
        """
        inputs = {"mesh": mesh, "handles": handles, "regularization": regularization, "max_iterations": max_iterations, "tolerance": tolerance}
        return self._client.execute(
            "deformation.isotropic_scaling",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_DEFORMATION_ISOTROPIC_SCALING),
        )

    def laplacian(
        self,
        mesh: MeshLike,
        handles: HandlesLike,
        *,
        weights: Literal["cotangent", "uniform", "tangent"] = "cotangent",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Laplacian-preserving deformation.

        Moves the handles and every other vertex so that the weighted edge vectors change least: L_ff x'
        = (L x)_f − L_fp c, one factored solve for all coordinates.

        .. math::

            \min_{p'} \sum_{(i,j)} w_{ij} \lVert (p'_i - p'_j) - (p_i - p_j) \rVert^2
            \quad\text{s.t. } p'_h = c_h
            \quad\Longrightarrow\quad L_{ff}\, p'_f = (L p)_f - L_{fp}\, c,

        one sparse solve per coordinate (all coordinates as columns of one factored system):
        the Laplacian coordinates :math:`\delta = L p` are kept wherever no handle pins the
        vertex.

        Parameters
        ----------
        mesh : Mesh or {"vertices", "faces"}
            The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
            0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
            are.
        handles : Handles or {"indices", "positions"}
            The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
            ``(p, d)`` positions; at least one handle in every connected component.
        weights : {"cotangent", "uniform", "tangent"}, default "cotangent"
            The edge weights :math:`w_{ij}` of the Laplacian :math:`L = D - W`:
            ``"cotangent"`` (the Dirichlet energy; may be negative on obtuse triangles),
            ``"uniform"`` (the graph Laplacian, as in Sorkine et al.'s Laplacian coordinates)
            or ``"tangent"`` (incentre weights, never negative).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``deformation.laplacian``; its results hold ``mesh``, ``energy``, ``handle_residual``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] Y. Lipman, O. Sorkine, D. Cohen-Or, D. Levin, C. Rössl and H.-P. Seidel,
           "Differential coordinates for interactive mesh editing", Shape Modeling
           International, 181-190, 2004.
        .. [2] M. Botsch and O. Sorkine, "On linear variational surface deformation methods",
           IEEE TVCG 14(1), 213-230, 2008.
        """
        inputs = {"mesh": mesh, "handles": handles, "weights": weights}
        return self._client.execute(
            "deformation.laplacian",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_DEFORMATION_LAPLACIAN),
        )

    def laplacian_editing(
        self,
        mesh: MeshLike,
        handles: HandlesLike,
        *,
        weights: Literal["uniform", "cotangent"] = "uniform",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Laplacian surface editing (linearised per-vertex similarities).

        Laplacian coordinates that rotate and scale with the surface: min Σ‖T_i(x') δ_i − L(x')_i‖² with
        each T_i the linearised similarity fitted to the vertex's one-ring, handles fixed; one sparse
        least-squares solve.

        With the rest shape's Laplacian coordinates :math:`\delta_i = L(p)_i`, solve

        .. math::

            \min_{p'} \sum_i \lVert T_i(p')\, \delta_i - L(p')_i \rVert^2
            \quad\text{s.t. } p'_h = c_h,

        where :math:`T_i(p')` is the similarity transform — linearised, so that the problem
        stays linear — that best maps the closed one-ring :math:`\{i\} \cup N(i)` of the rest
        shape onto the new positions:
        :math:`T_i = \arg\min_T \sum_{j} \lVert T p_j - p'_j \rVert^2` with
        :math:`T p = s p + h \times p + t` in 3-D (:math:`(s, h, t)`, 7 parameters) and
        :math:`T p = \begin{psmallmatrix} s & -w \\ w & s \end{psmallmatrix} p + t` in 2-D.
        Each :math:`T_i` is a linear function of :math:`p'` (a least-squares fit), so the whole
        problem is one sparse linear least-squares system in the :math:`d n` coordinates,
        coupled across coordinates, solved through its normal equations with the handles
        eliminated (factored once).

        Parameters
        ----------
        mesh : Mesh or {"vertices", "faces"}
            The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
            0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
            are.
        handles : Handles or {"indices", "positions"}
            The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
            ``(p, d)`` positions. Every connected component needs handles whose rest positions
            span a plane in 3-D (three not on a line) or a line in 2-D (two distinct): fewer
            leave a global similarity transform about them undetermined.
        weights : {"uniform", "cotangent"}, default "uniform"
            The Laplacian: ``"uniform"`` gives :math:`\delta_i = p_i - \operatorname{mean}_j
            p_j` (the paper's), ``"cotangent"`` the cotangent-weighted average instead (both
            row-normalised).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``deformation.laplacian_editing``; its results hold ``mesh``, ``energy``, ``handle_residual``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] O. Sorkine, D. Cohen-Or, Y. Lipman, M. Alexa, C. Rössl and H.-P. Seidel,
           "Laplacian surface editing", Symposium on Geometry Processing, 175-184, 2004.
        """
        inputs = {"mesh": mesh, "handles": handles, "weights": weights}
        return self._client.execute(
            "deformation.laplacian_editing",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_DEFORMATION_LAPLACIAN_EDITING),
        )


class Embedding(_Family):
    """The embedding processes, through a :class:`Client`: ``isomap``, ``laplacian_eigenmaps``, ``lle``, ``lpp``, ``mds``, ``pca``, ``random_projection``, ``sne``, ``som``, ``tsne``."""

    def isomap(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        neighbors: Literal["knn", "radius", "all"] = "knn",
        n_neighbors: int = 5,
        radius: float | None = None,
        weighting: Literal["distance", "uniform"] = "distance",
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Isomap.

        Classical MDS of geodesic distances: shortest paths along the neighbourhood graph (Dijkstra),
        then the top eigenvectors of −½JG⁽²⁾J. A disconnected graph is an error that says into how many
        components it falls. Reports eigenvalues and trustworthiness.

        1. A neighbourhood graph on the points (``neighbors``), each edge as long as the
           distance between its ends (``weighting="distance"``) or 1 (``"uniform"``: hops);
        2. the geodesic distances :math:`G`: all-pairs shortest paths (Dijkstra);
        3. classical MDS of :math:`G` (the ``k`` largest eigenpairs of
           :math:`-\tfrac12 J G^{(2)} J`), the code shared with ``layout.mds``.

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 2 (and more than ``n_neighbors``) and at
            most 20,000 points (the method keeps the ``n×n`` geodesic distances: 3.2 GB).
        n_components : int, default 2
            The dimension ``k`` of the embedding, ``1 <= k <= n``. It may exceed the dimension
            ``D`` of the points (geodesic distances need not be Euclidean in ``D``), as in
            scikit-learn's ``Isomap``.
        neighbors : {"knn", "radius", "all"}, default "knn"
            The neighbourhood graph: ``"knn"`` joins each point to its ``n_neighbors``
            nearest (either way round), ``"radius"`` every pair at most ``radius`` apart,
            ``"all"`` every pair (then Isomap is plain classical MDS).
        n_neighbors : int, default 5
            Neighbours per point with ``neighbors="knn"`` (the point itself not counted, as
            scikit-learn's ``Isomap``), at most ``n - 1``. Equidistant candidates are taken by
            lower index (scikit-learn's choice among them varies with its search and thread
            count: see :func:`algorithms.core.graphs.nearest_sorted`).
        radius : float, optional
            The radius with ``neighbors="radius"``, required there.
        weighting : {"distance", "uniform"}, default "distance"
            Edge *lengths* for the shortest paths: ``"distance"`` the Euclidean distance
            between the ends, ``"uniform"`` 1 per edge (hop counts). (A heat kernel is a
            similarity, not a length: there is none here.)
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``embedding.isomap``; its results hold ``embedding``, ``eigenvalues``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] J. B. Tenenbaum, V. de Silva, J. C. Langford, "A global geometric framework for
           nonlinear dimensionality reduction", Science 290 (2000).

        Examples
        --------
        >>> job = client.embedding.isomap(  # doctest: +SKIP
        ...     [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122], [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108], [70, 70, 122], [88, 60, 130]],
        ...     wait=30)
        >>> job.results()["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_components": n_components, "neighbors": neighbors, "n_neighbors": n_neighbors, "radius": radius, "weighting": weighting, "quality_neighbors": quality_neighbors, "labels": labels}
        return self._client.execute(
            "embedding.isomap",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_ISOMAP),
        )

    def laplacian_eigenmaps(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        neighbors: Literal["knn", "radius", "all"] = "knn",
        n_neighbors: int | None = None,
        radius: float | None = None,
        weighting: Literal["uniform", "distance", "heat"] = "uniform",
        sigma: float | None = None,
        laplacian: Literal["random_walk", "symmetric", "unnormalized"] = "random_walk",
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Laplacian eigenmaps (spectral embedding).

        The eigenvectors of the smallest non-trivial eigenvalues of the neighbourhood graph's Laplacian,
        Lv = λDv by default. A disconnected graph is an error that says into how many components it
        falls. Reports eigenvalues and trustworthiness.

        On a neighbourhood graph with weights :math:`W`, degrees :math:`D` and Laplacian
        :math:`L = D - W`, the embedding minimises :math:`\sum_{ij} w_{ij} \lVert y_i - y_j
        \rVert^2 = \operatorname{tr}(Y^\mathsf{T} L Y)` under a normalisation, which the
        trivial constant solution is excluded from:

        * ``"random_walk"`` (default; the paper, scikit-learn): :math:`L v = \lambda D v`
          with :math:`v^\mathsf{T} D v = 1`, i.e. the eigenvectors of :math:`D^{-1} L`;
        * ``"symmetric"``: :math:`D^{-1/2} L D^{-1/2} y = \lambda y`,
          :math:`\lVert y \rVert = 1` (:math:`y = D^{1/2} v`);
        * ``"unnormalized"``: :math:`L y = \lambda y`, :math:`\lVert y \rVert = 1`.

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 3 points.
        n_components : int, default 2
            The dimension ``k`` of the embedding, ``1 <= k <= n - 2``. It may exceed the
            dimension ``D`` of the points, as in scikit-learn's ``SpectralEmbedding``.
        neighbors : {"knn", "radius", "all"}, default "knn"
            The neighbourhood graph: ``"knn"`` joins each point to its ``n_neighbors``
            nearest (either way round), ``"radius"`` every pair at most ``radius`` apart,
            ``"all"`` every pair.
        n_neighbors : int, optional
            Neighbours per point with ``neighbors="knn"``, the point itself counted among them
            as in scikit-learn's ``SpectralEmbedding`` (``n_neighbors - 1`` other points; ties
            by lower index), at most ``n - 1``; ``max(n // 10, 2)`` when omitted
            (scikit-learn's ``max(n // 10, 1)``, except that below 20 points 1 would leave
            each point alone).
        radius : float, optional
            The radius with ``neighbors="radius"``, required there.
        weighting : {"uniform", "distance", "heat"}, default "uniform"
            Edge weights from the edge lengths :math:`d`: ``"uniform"`` 1, ``"distance"``
            :math:`1/d`, ``"heat"`` the heat kernel :math:`\exp(-d^2/2\sigma^2)`.
            Every edge of the symmetrised graph (``i`` among ``j``'s neighbours or ``j`` among
            ``i``'s) weighs the same: scikit-learn's ``SpectralEmbedding`` gives an edge found
            from one side only half the weight (``(A + Aᵀ)/2``), which moves the embedding
            slightly (a Procrustes disparity of 3.7e-3 on a 400-point swiss roll, k = 10;
            ``affinity="precomputed"`` on our graph agrees to 1e-28). Weight 1 keeps the graph
            the same whichever side found an edge, as spectral clustering here does.
        sigma : float, optional
            The heat kernel's width :math:`\sigma`; the mean edge length when omitted.
        laplacian : {"random_walk", "symmetric", "unnormalized"}, default "random_walk"
            The normalisation of :math:`L = D - W`: ``"random_walk"`` solves
            :math:`L v = \lambda D v` (the paper, scikit-learn); ``"symmetric"`` returns instead
            the unit eigenvectors :math:`y = \sqrt{D}\, v` of the symmetric normalised
            Laplacian; ``"unnormalized"`` solves :math:`L y = \lambda y`.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``embedding.laplacian_eigenmaps``; its results hold ``embedding``, ``eigenvalues``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] M. Belkin, P. Niyogi, "Laplacian eigenmaps for dimensionality reduction and
           data representation", Neural Computation 15 (2003).

        Examples
        --------
        >>> job = client.embedding.laplacian_eigenmaps(  # doctest: +SKIP
        ...     [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122], [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108], [70, 70, 122], [88, 60, 130]],
        ...     n_neighbors=4,
        ...     wait=30)
        >>> job.results()["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_components": n_components, "neighbors": neighbors, "n_neighbors": n_neighbors, "radius": radius, "weighting": weighting, "sigma": sigma, "laplacian": laplacian, "quality_neighbors": quality_neighbors, "labels": labels}
        return self._client.execute(
            "embedding.laplacian_eigenmaps",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_LAPLACIAN_EIGENMAPS),
        )

    def lle(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        neighbors: Literal["knn", "radius"] = "knn",
        n_neighbors: int = 5,
        radius: float | None = None,
        regularization: float = 0.001,
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Locally linear embedding.

        Sum-to-one weights reconstructing each point from its neighbours (regularised), then the bottom
        non-trivial eigenvectors of (I − W)ᵀ(I − W). Reports eigenvalues, the reconstruction error in
        the embedding and of the weights, and trustworthiness.

        1. Neighbours of each point: its ``n_neighbors`` nearest (``"knn"``, each point's own
           list, not symmetrised) or all within ``radius``; no edge weights are chosen.
        2. Reconstruction weights :math:`W` (:func:`barycenter_weights`): each row minimises
           :math:`\lVert x_i - \sum_j W_{ij} x_j \rVert^2` subject to :math:`\sum_j W_{ij} = 1`.
        3. The embedding: the eigenvectors of the ``k`` smallest eigenvalues of
           :math:`M = (I - W)^\mathsf{T}(I - W)` after the trivial constant one, i.e. the unit
           :math:`Y` minimising :math:`\sum_i \lVert y_i - \sum_j W_{ij} y_j \rVert^2`.

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 3 points.
        n_components : int, default 2
            The dimension ``k`` of the embedding, ``1 <= k <= min(D, n - 2)`` (scikit-learn's
            bound ``k <= D`` too).
        neighbors : {"knn", "radius"}, default "knn"
            The points each point is reconstructed from: ``"knn"`` its own ``n_neighbors``
            nearest (not symmetrised), ``"radius"`` all within ``radius``.
        n_neighbors : int, default 5
            Neighbours per point with ``neighbors="knn"`` (the point itself not counted, as
            scikit-learn's ``n_neighbors``), at most ``n - 1``. Equidistant candidates are
            taken by lower index (scikit-learn's choice among them varies with its search
            and thread count: see :func:`algorithms.core.graphs.nearest_sorted`).
        radius : float, optional
            The radius with ``neighbors="radius"``, required there; every point needs at
            least one neighbour within it.
        regularization : float, default 1e-3
            ``r``: the local Gram matrix :math:`C` gets :math:`r \operatorname{tr}(C)` on its
            diagonal. Needed when ``n_neighbors > D`` (then :math:`C` is singular); 0 turns it
            off.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``embedding.lle``; its results hold ``embedding``, ``eigenvalues``, ``reconstruction_error``, ``weight_error``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] S. T. Roweis, L. K. Saul, "Nonlinear dimensionality reduction by locally linear
           embedding", Science 290 (2000).

        Examples
        --------
        >>> job = client.embedding.lle(  # doctest: +SKIP
        ...     [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122], [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108], [70, 70, 122], [88, 60, 130]],
        ...     wait=30)
        >>> job.results()["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_components": n_components, "neighbors": neighbors, "n_neighbors": n_neighbors, "radius": radius, "regularization": regularization, "quality_neighbors": quality_neighbors, "labels": labels}
        return self._client.execute(
            "embedding.lle",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_LLE),
        )

    def lpp(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        neighbors: Literal["knn", "radius", "all"] = "knn",
        n_neighbors: int | None = None,
        radius: float | None = None,
        weighting: Literal["uniform", "distance", "heat"] = "uniform",
        sigma: float | None = None,
        laplacian: Literal["random_walk", "symmetric", "unnormalized"] = "random_walk",
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Locality preserving projections.

        The linear map closest to Laplacian eigenmaps: generalized eigenvectors of XᵀLXa = λXᵀDXa on the
        centred data. Reports the projection (applies to new points), eigenvalues and trustworthiness.

        Laplacian eigenmaps restricted to linear maps :math:`y = A^\mathsf{T}(x - \mu)`: with
        the centred data :math:`\tilde X` (rows are points), the graph's :math:`W`, :math:`D`,
        :math:`L = D - W`, the columns of :math:`A` are the generalized eigenvectors of the
        ``k`` smallest eigenvalues of

        * ``"random_walk"`` (default; the paper): :math:`\tilde X^\mathsf{T} L \tilde X a =
          \lambda \tilde X^\mathsf{T} D \tilde X a`, centred at the degree-weighted mean (so
          the constant map is excluded, as the trivial vector in Laplacian eigenmaps);
        * ``"symmetric"``: :math:`\tilde X^\mathsf{T} D^{-1/2} L D^{-1/2}
          \tilde X a = \lambda \tilde X^\mathsf{T} \tilde X a`, i.e. :math:`\min
          \operatorname{tr}(Y^\mathsf{T} D^{-1/2} L D^{-1/2} Y)` subject to
          :math:`Y^\mathsf{T} Y = I`, centred at the mean;
        * ``"unnormalized"``: :math:`\tilde X^\mathsf{T} L \tilde X a = \lambda
          \tilde X^\mathsf{T} \tilde X a`, centred at the mean.

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 3 points, spanning all ``D`` dimensions
            (else reduce them first, e.g. by PCA).
        n_components : int, default 2
            The dimension ``k`` of the embedding, ``1 <= k <= min(n, D)``.
        neighbors : {"knn", "radius", "all"}, default "knn"
            The neighbourhood graph: ``"knn"`` joins each point to its ``n_neighbors``
            nearest (either way round), ``"radius"`` every pair at most ``radius`` apart,
            ``"all"`` every pair.
        n_neighbors : int, optional
            Neighbours per point with ``neighbors="knn"``, the point itself counted among them
            (``n_neighbors - 1`` other points), the graph of :func:`laplacian_eigenmaps` and
            scikit-learn's ``SpectralEmbedding``; at most ``n - 1``; ``max(n // 10, 2)`` when
            omitted.
        radius : float, optional
            The radius with ``neighbors="radius"``, required there.
        weighting : {"uniform", "distance", "heat"}, default "uniform"
            Edge weights from the edge lengths :math:`d`: ``"uniform"`` 1, ``"distance"``
            :math:`1/d`, ``"heat"`` the heat kernel :math:`\exp(-d^2/2\sigma^2)`.
            Every edge of the symmetrised graph weighs the same, whichever side found it (not
            half for one side, as scikit-learn's ``SpectralEmbedding``; see
            :func:`~algorithms.embedding.laplacian_eigenmaps`).
        sigma : float, optional
            The heat kernel's width :math:`\sigma`; the mean edge length when omitted.
        laplacian : {"random_walk", "symmetric", "unnormalized"}, default "random_walk"
            The generalized eigenproblem for the directions :math:`a`, with :math:`X` the
            centred data and :math:`L = D - W`: ``"random_walk"`` :math:`X^\mathsf{T} L X a =
            \lambda X^\mathsf{T} D X a` (the paper; centred at the degree-weighted mean);
            ``"symmetric"`` the symmetric normalised Laplacian in place of :math:`L` and
            :math:`X^\mathsf{T} X` on the right; ``"unnormalized"`` :math:`X^\mathsf{T} L X a =
            \lambda X^\mathsf{T} X a`.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``embedding.lpp``; its results hold ``embedding``, ``components``, ``eigenvalues``, ``mean``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] X. He, P. Niyogi, "Locality preserving projections", NIPS 16 (2003).

        Examples
        --------
        >>> job = client.embedding.lpp(  # doctest: +SKIP
        ...     [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122], [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108], [70, 70, 122], [88, 60, 130]],
        ...     n_neighbors=4,
        ...     wait=30)
        >>> job.results()["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_components": n_components, "neighbors": neighbors, "n_neighbors": n_neighbors, "radius": radius, "weighting": weighting, "sigma": sigma, "laplacian": laplacian, "quality_neighbors": quality_neighbors, "labels": labels}
        return self._client.execute(
            "embedding.lpp",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_LPP),
        )

    def mds(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        metric: bool = False,
        max_iterations: int = 300,
        tolerance: float = 1e-06,
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Multidimensional scaling (classical or metric).

        Classical MDS: the top eigenvectors of the double-centred squared distances −½JD⁽²⁾J (for
        Euclidean input the PCA scores); optionally refined by SMACOF stress majorization. Reports
        eigenvalues, raw and normalized stress, trustworthiness.

        **Classical** (default): with the squared distances :math:`D^{(2)}` and the centring
        :math:`J = I - \tfrac1n \mathbf 1 \mathbf 1^\mathsf{T}`, the Gram matrix
        :math:`B = -\tfrac12 J D^{(2)} J`; the embedding is
        :math:`[\sqrt{\lambda_1} e_1, \dots, \sqrt{\lambda_k} e_k]` from its ``k`` largest
        eigenpairs (:func:`algorithms.layout.mds.classical_coordinates`, shared with
        ``layout.mds``). **Metric** (``metric=True``): from the classical embedding, stress
        majorization minimises :math:`\sum_{i<j} (\lVert y_i - y_j \rVert - d_{ij})^2`
        (:func:`algorithms.layout.stress` with uniform weights, scikit-learn's ``MDS``).

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 2 and at most 4,000 points (the method
            keeps dense ``n×n`` matrices).
        n_components : int, default 2
            The dimension ``k`` of the embedding, ``1 <= k <= n``. It may exceed the dimension
            ``D`` of the points, as in scikit-learn's ``ClassicalMDS`` and ``MDS``: the classical
            coordinates beyond the rank of the centred points are then zero.
        metric : bool, default False
            False: classical MDS only (scikit-learn's ``ClassicalMDS``). True: refine the
            classical embedding by SMACOF, which minimises the raw stress (scikit-learn's
            ``MDS(metric=True)``). Not scikit-learn's flag of the same name: there ``False``
            selects non-metric (ordinal) SMACOF, which this function does not offer.
        max_iterations : int, default 300
            Most SMACOF iterations; used only with ``metric=True`` (0 keeps the classical
            embedding).
        tolerance : float, default 1e-6
            SMACOF stops when one iteration lowers the stress by less than this fraction of
            the embedding's squared distances' sum
            :math:`\eta^2(X) = \sum_{i<j} \lVert x_i - x_j \rVert^2` (scikit-learn's rule from
            1.7, as :func:`algorithms.layout.stress`); used only with ``metric=True``.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``embedding.mds``; its results hold ``embedding``, ``eigenvalues``, ``stress``, ``normalized_stress``, ``iterations``, ``converged``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] W. S. Torgerson, "Multidimensional scaling: I. Theory and method",
           Psychometrika 17 (1952).
        .. [2] J. de Leeuw, "Applications of convex analysis to multidimensional scaling",
           Recent Developments in Statistics (1977) (SMACOF).

        Examples
        --------
        >>> job = client.embedding.mds(  # doctest: +SKIP
        ...     [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122], [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108], [70, 70, 122], [88, 60, 130]],
        ...     wait=30)
        >>> job.results()["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_components": n_components, "metric": metric, "max_iterations": max_iterations, "tolerance": tolerance, "quality_neighbors": quality_neighbors, "labels": labels}
        return self._client.execute(
            "embedding.mds",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_MDS),
        )

    def pca(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Principal component analysis.

        Projects the centred data on its k principal axes (thin SVD): the orthogonal projection keeping
        the most variance. Reports the axes, the variance along each (eigenvalues), their share, and
        trustworthiness; signs fixed (each axis's largest entry positive).

        With :math:`\tilde X = X - \bar x = U \Sigma V^\mathsf{T}` (thin SVD), the embedding is
        :math:`\tilde X V_k = U_k \Sigma_k`, the projection on the ``k`` right singular vectors
        of largest singular value: of all orthogonal projections to ``k`` dimensions it keeps
        the most variance (equivalently, the sum of squared projection distances is least).

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 2 points.
        n_components : int, default 2
            The dimension ``k`` of the embedding, ``1 <= k <= min(n, D)``.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``embedding.pca``; its results hold ``embedding``, ``components``, ``eigenvalues``, ``explained_variance_ratio``, ``singular_values``, ``mean``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] K. Pearson, "On lines and planes of closest fit to systems of points in space",
           Philosophical Magazine 2 (1901).

        Examples
        --------
        >>> job = client.embedding.pca(  # doctest: +SKIP
        ...     [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122], [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108], [70, 70, 122], [88, 60, 130]],
        ...     wait=30)
        >>> job.results()["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_components": n_components, "quality_neighbors": quality_neighbors, "labels": labels}
        return self._client.execute(
            "embedding.pca",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_PCA),
        )

    def random_projection(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        kind: Literal["gaussian", "sparse"] = "gaussian",
        density: float | None = None,
        seed: int = 0,
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Random projection (Johnson–Lindenstrauss).

        Maps the points by a random k×D matrix, Gaussian or sparse, that keeps squared distances in
        expectation. Reports the matrix, the largest relative distortion of squared distances and
        trustworthiness.

        * ``"gaussian"``: :math:`R_{cj} \sim \mathcal N(0, 1/k)`;
        * ``"sparse"``: :math:`R_{cj} = \pm\sqrt{s/k}` with probability :math:`1/(2s)` each and
          0 otherwise, :math:`s = 1/\text{density}` (default density :math:`1/\sqrt D`).

        Either way :math:`\mathbb E\,\lVert R x \rVert^2 = \lVert x \rVert^2`, and with
        :math:`k = O(\varepsilon^{-2}\log n)` every pairwise distance is kept within a factor
        :math:`1 \pm \varepsilon` with high probability.

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point.
        n_components : int, default 2
            The dimension ``k`` of the embedding, ``1 <= k <= min(n, D)`` (a projection adds
            no dimensions).
        kind : {"gaussian", "sparse"}, default "gaussian"
            The matrix entries: ``"gaussian"`` independent :math:`\mathcal{N}(0, 1/k)`;
            ``"sparse"`` :math:`\pm\sqrt{(s/k)}` with probability :math:`1/(2s)` each and 0
            otherwise, :math:`s = 1/\text{density}` (Achlioptas; Li, Hastie and Church).
        density : float, optional
            The fraction of non-zero entries with ``kind="sparse"`` (only there), in
            ``(0, 1]``; :math:`1/\sqrt{D}` when omitted.
        seed : int or numpy Generator, default 0
            Draws the matrix; the same seed gives the same matrix.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``embedding.random_projection``; its results hold ``embedding``, ``components``, ``distortion``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] W. B. Johnson, J. Lindenstrauss, "Extensions of Lipschitz mappings into a
           Hilbert space", Contemporary Mathematics 26 (1984).
        .. [2] D. Achlioptas, "Database-friendly random projections", PODS (2001).
        .. [3] P. Li, T. J. Hastie, K. W. Church, "Very sparse random projections", KDD (2006).

        Examples
        --------
        >>> job = client.embedding.random_projection(  # doctest: +SKIP
        ...     [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122], [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108], [70, 70, 122], [88, 60, 130]],
        ...     wait=30)
        >>> job.results()["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_components": n_components, "kind": kind, "density": density, "seed": seed, "quality_neighbors": quality_neighbors, "labels": labels}
        return self._client.execute(
            "embedding.random_projection",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_RANDOM_PROJECTION),
        )

    def sne(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        perplexity: float = 30.0,
        init: Literal["pca", "random"] = "pca",
        learning_rate: float | Literal["auto"] = "auto",
        max_iterations: int = 750,
        early_exaggeration: float = 4.0,
        exaggeration_iterations: int = 250,
        min_grad_norm: float = 1e-07,
        seed: int = 0,
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Symmetric SNE (stochastic neighbour embedding).

        t-SNE's input affinities with a Gaussian kernel in the embedding too (the light tails crowd
        clusters together: t-SNE's motivation); exact all-pairs gradient, at most 5,000 points. Reports
        KL, trustworthiness and iterations. Progress every iteration, cancellable.

        The input affinities are t-SNE's (perplexity-calibrated Gaussians over all pairs,
        symmetrised, :math:`p_{ij} = (p_{j|i} + p_{i|j}) / 2n`); the embedding's are Gaussian
        too,

        .. math:: q_{ij} = \frac{e^{-\lVert y_i - y_j\rVert^2}}
                                {\sum_{k \ne l} e^{-\lVert y_k - y_l\rVert^2}}, \qquad
                  \frac{\partial\, \mathrm{KL}(P\|Q)}{\partial y_i}
                  = 4 \sum_j (p_{ij} - q_{ij})(y_i - y_j),

        minimised by the same descent as :func:`~algorithms.embedding.tsne.tsne` (momentum,
        gains, early exaggeration).

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 2 and at most 5,000 points.
        n_components : int, default 2
            The embedding's dimension ``k``.
        perplexity : float, default 30
            The effective number of neighbours of each point's Gaussian (its entropy is
            :math:`\log(\text{perplexity})`, found by binary search), ``0 < perplexity < n``.
        init : {"pca", "random"}, default "pca"
            The start: ``"pca"`` the PCA scores scaled to a first-column standard deviation
            of 1e-4, ``"random"`` Gaussian draws of that size from ``seed``.
        learning_rate : float or "auto", default "auto"
            The step, ``> 0``. ``"auto"``: :math:`\max(n / 4\alpha, 50)`, :math:`\alpha` the
            exaggeration in force (as t-SNE).
        max_iterations : int, default 750
            Gradient steps in all, the exaggeration phase included.
        early_exaggeration : float, default 4
            The factor :math:`\alpha \ge 1` on :math:`P` for the first
            ``exaggeration_iterations`` steps (4, the value of the t-SNE paper; the Gaussian
            kernel cannot hold clusters apart under t-SNE's 12).
        exaggeration_iterations : int, default 250
            The number of steps with :math:`P` multiplied by ``early_exaggeration``;
            counted in ``max_iterations``.
        min_grad_norm : float, default 1e-7
            After the exaggeration phase, stop once the gradient's norm falls below this.
        seed : int or numpy Generator, default 0
            Draws the random start (and the extra columns of a PCA start when ``k`` exceeds
            the data's dimension); the same seed gives the same embedding.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``embedding.sne``; its results hold ``embedding``, ``kl_divergence``, ``trustworthiness``, ``iterations``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] G. Hinton, S. Roweis, "Stochastic neighbor embedding", NIPS 15 (2002).
        .. [2] L. van der Maaten, G. Hinton, "Visualizing data using t-SNE", JMLR 9 (2008).
        """
        inputs = {"points": points, "n_components": n_components, "perplexity": perplexity, "init": init, "learning_rate": learning_rate, "max_iterations": max_iterations, "early_exaggeration": early_exaggeration, "exaggeration_iterations": exaggeration_iterations, "min_grad_norm": min_grad_norm, "seed": seed, "quality_neighbors": quality_neighbors, "labels": labels}
        return self._client.execute(
            "embedding.sne",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_SNE),
        )

    def som(
        self,
        points: PointsLike,
        *,
        rows: int = 10,
        columns: int = 10,
        method: Literal["online", "batch"] = "online",
        max_iterations: int | None = None,
        learning_rate: float = 0.5,
        sigma: float | None = None,
        init: Literal["pca", "random"] = "pca",
        seed: int = 0,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Self-organising map.

        A rows × columns grid of nodes pulled onto the data (Kohonen's online rule or the batch map);
        each point is embedded at its best-matching node's grid position. Reports the codebook,
        quantization and topographic errors and trustworthiness. Progress per 1 % of the steps,
        cancellable.

        Each node :math:`j` has a grid position :math:`g_j` and a data-space position
        :math:`w_j`. Online training (Kohonen) presents one point :math:`x` at step :math:`t`,
        finds its best-matching node :math:`b = \arg\min_j \lVert x - w_j \rVert` and pulls
        every node towards it, grid neighbours of :math:`b` the most:

        .. math:: w_j \leftarrow w_j + \eta(t)\, h_{bj}(t)\, (x - w_j), \qquad
                  h_{bj}(t) = e^{-\lVert g_b - g_j \rVert^2 / 2\sigma(t)^2},

        with :math:`\eta(t) = \eta_0 / (1 + 2t/T)` and :math:`\sigma(t) = \sigma_0 / (1 +
        2t/T)` (MiniSom's default decay). Batch training replaces each epoch of such steps by
        their fixed point, :math:`w_j = \sum_i h_{b_i j} x_i / \sum_i h_{b_i j}`, with
        :math:`\sigma` decaying from :math:`\sigma_0` to 1 over the epochs.

        Parameters
        ----------
        points : (n, d) float array
            The points to map, one row per point; at least 2 points.
        rows, columns : int, default 10
            The number of grid rows and columns; at least 1 each and 2 nodes in all.
        method : {"online", "batch"}, default "online"
            ``"online"``: Kohonen's rule, one randomly drawn point per step (a stochastic
            gradient step); ``"batch"``: each epoch moves every node to the fixed point of
            an epoch of such steps, the neighbourhood-weighted mean of the points.
        max_iterations : int, optional
            Training steps: samples presented with ``"online"`` (``max(1000, 10 n)`` up to
            100,000 when omitted) or epochs with ``"batch"`` (30 when omitted).
        learning_rate : float, default 0.5
            :math:`\eta_0`, the starting step of online training, in ``(0, 1]`` (unused by
            ``"batch"``).
        sigma : float, optional
            :math:`\sigma_0`, the neighbourhood's starting width in grid units; half the
            larger grid side (at least 1) when omitted.
        init : {"pca", "random"}, default "pca"
            Starting nodes: ``"pca"`` spread over the plane of the two principal axes (one
            standard deviation per half side), ``"random"`` at random data points drawn with
            ``seed``.
        seed : int or numpy Generator, default 0
            Draws the order of the samples (online) and the random start; the same seed gives
            the same map.
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``embedding.som``; its results hold ``embedding``, ``codebook``, ``bmu``, ``quantization_error``, ``topographic_error``, ``trustworthiness``, ``iterations``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] T. Kohonen, "Self-organized formation of topologically correct feature maps",
           Biological Cybernetics 43, 1982.
        .. [2] T. Kohonen, *Self-Organizing Maps*, 3rd ed., Springer 2001 (batch map, §3.14).
        .. [3] G. Vettigli, MiniSom, https://github.com/JustGlowing/minisom.

        Examples
        --------
        >>> job = client.embedding.som(  # doctest: +SKIP
        ...     [[0, 0], [0.1, 0], [5, 5], [5.1, 5], [0, 5], [5, 0]],
        ...     rows=2,
        ...     columns=2,
        ...     wait=30)
        >>> job.results()["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "rows": rows, "columns": columns, "method": method, "max_iterations": max_iterations, "learning_rate": learning_rate, "sigma": sigma, "init": init, "seed": seed, "labels": labels}
        return self._client.execute(
            "embedding.som",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_SOM),
        )

    def tsne(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        perplexity: float = 30.0,
        method: Literal["auto", "exact", "fft"] = "auto",
        init: Literal["pca", "random"] | PointsLike = "pca",
        learning_rate: float | Literal["auto"] = "auto",
        max_iterations: int = 750,
        early_exaggeration: float = 12.0,
        exaggeration_iterations: int = 250,
        min_grad_norm: float = 1e-07,
        seed: int = 0,
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""t-SNE (t-distributed stochastic neighbour embedding).

        Perplexity-calibrated Gaussian affinities (binary search per point), Cauchy affinities in the
        embedding, KL(P‖Q) minimised by gradient descent with momentum, gains and early exaggeration;
        exact all-pairs gradient for small inputs, FFT-interpolated repulsion (FIt-SNE) for up to
        100,000s of points. Reports KL, trustworthiness and iterations. Progress every iteration,
        cancellable.

        Input affinities: for each point a Gaussian over its neighbours, its precision
        :math:`\beta_i` found by binary search so that the perplexity :math:`2^{H(P_i)}`
        equals ``perplexity``, then symmetrised,

        .. math:: p_{j|i} = \frac{e^{-\beta_i \lVert x_i - x_j\rVert^2}}
                                 {\sum_{k \ne i} e^{-\beta_i \lVert x_i - x_k\rVert^2}},
                  \qquad p_{ij} = \frac{p_{j|i} + p_{i|j}}{2n}.

        Embedding affinities: the Cauchy (Student-t, one degree of freedom) kernel
        :math:`w_{ij} = (1 + \lVert y_i - y_j\rVert^2)^{-1}`, :math:`q_{ij} = w_{ij} / Z`,
        :math:`Z = \sum_{k \ne l} w_{kl}`. The embedding minimises

        .. math:: C = \mathrm{KL}(P \,\|\, Q) = \sum_{i \ne j} p_{ij} \log \frac{p_{ij}}{q_{ij}},
                  \qquad \frac{\partial C}{\partial y_i} = 4 \sum_j (p_{ij} - q_{ij})\, w_{ij}\,
                  (y_i - y_j),

        by gradient descent with momentum (scikit-learn's 0.5 then 0.8 for ``"exact"``,
        openTSNE's 0.8 for ``"fft"``), per-coordinate gains and, for the first
        ``exaggeration_iterations`` steps, :math:`P` multiplied by ``early_exaggeration``.

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 2 points.
        n_components : int, default 2
            The embedding's dimension ``k``. ``method="fft"`` needs ``k <= 2``; larger ``k``
            is exact only (at most 5,000 points).
        perplexity : float, default 30
            The effective number of neighbours of each point's Gaussian (its entropy is
            :math:`\log(\text{perplexity})`, found by binary search), ``0 < perplexity < n``.
        method : {"auto", "exact", "fft"}, default "auto"
            ``"exact"``: all pairs each iteration, affinities over all pairs (as scikit-learn's
            ``method="exact"``; at most 5,000 points). ``"fft"``: affinities over the
            :math:`\min(n - 1, 3\,\text{perplexity})` nearest neighbours (rounded down), the
            repulsion by FFT-accelerated interpolation (FIt-SNE; openTSNE's default;
            ``n_components <= 2``). ``"auto"``: exact below 500 points or for
            ``n_components > 2``, else fft.
        init : {"pca", "random"} or (n, k) float array, default "pca"
            The start: ``"pca"`` the PCA scores scaled to a first-column standard deviation
            of 1e-4 (openTSNE, scikit-learn), ``"random"`` Gaussian draws of that size from
            ``seed``, or the start positions themselves, one row per point and
            ``n_components`` columns, used as given (as scikit-learn and openTSNE do: e.g. a
            previous embedding to continue from). An embedding started from an array keeps
            its orientation: its column signs are not normalised.
        learning_rate : float or "auto", default "auto"
            The step, ``> 0``. ``"auto"``: :math:`\max(n / 4\alpha, 50)` with :math:`\alpha`
            the exaggeration in force — scikit-learn's :math:`\max(n / 4 \cdot 12, 50)` during
            the exaggeration, then openTSNE's :math:`n / \alpha` (openTSNE's gradient lacks
            the factor 4) with :math:`\alpha = 1`, 12× larger, which converges in fewer steps.
        max_iterations : int, default 750
            Gradient steps in all, the exaggeration phase included (openTSNE's 250 + 500;
            scikit-learn's ``max_iter`` is 1000 with its smaller step).
        early_exaggeration : float, default 12
            The factor :math:`\alpha \ge 1` on :math:`P` during the first
            ``exaggeration_iterations`` steps (it pulls clusters together early on).
        exaggeration_iterations : int, default 250
            The number of steps with :math:`P` multiplied by ``early_exaggeration``;
            counted in ``max_iterations``.
        min_grad_norm : float, default 1e-7
            After the exaggeration phase, stop once the gradient's norm falls below this.
        seed : int or numpy Generator, default 0
            Draws the random start (and the extra columns of a PCA start when ``k`` exceeds
            the data's dimension); the same seed gives the same embedding.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``embedding.tsne``; its results hold ``embedding``, ``kl_divergence``, ``trustworthiness``, ``iterations``, ``method``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] L. van der Maaten, G. Hinton, "Visualizing data using t-SNE", JMLR 9 (2008).
        .. [2] G. C. Linderman, M. Rachh, J. G. Hoskins, S. Steinerberger, Y. Kluger, "Fast
           interpolation-based t-SNE for improved visualization of single-cell RNA-seq
           data", Nature Methods 16 (2019).
        .. [3] P. G. Poličar, M. Stražar, B. Zupan, "openTSNE: a modular Python library for
           t-SNE dimensionality reduction and embedding", J. Stat. Softw. 109 (2024).
        """
        inputs = {"points": points, "n_components": n_components, "perplexity": perplexity, "method": method, "init": init, "learning_rate": learning_rate, "max_iterations": max_iterations, "early_exaggeration": early_exaggeration, "exaggeration_iterations": exaggeration_iterations, "min_grad_norm": min_grad_norm, "seed": seed, "quality_neighbors": quality_neighbors, "labels": labels}
        return self._client.execute(
            "embedding.tsne",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_TSNE),
        )


class Interpolation(_Family):
    """The interpolation processes, through a :class:`Client`: ``affine``, ``arap``, ``poisson``, ``rigid``."""

    def affine(
        self,
        source: ShapeLike,
        target: ShapeLike | None = None,
        *,
        transform: ArrayLike | None = None,
        times: ArrayLike | None = None,
        reflection: Literal["refuse", "flip"] = "refuse",
        pivot: Literal["centroid", "origin"] = "centroid",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Affine interpolation by polar decomposition.

        A = R S (polar decomposition); R turns along the shortest arc (slerp), S and the translation
        move linearly, so det A(t) > 0 all along the path. The map is given or fitted to the target (its
        residual blended in, so t = 1 is the target).

        The map :math:`p \mapsto A p + b` is the ``transform`` given, or the least-squares fit
        to ``target`` (:func:`algorithms.alignment.affine`). With the polar decomposition
        :math:`A = R S` (:math:`R` a rotation, :math:`S` symmetric) and the pivot :math:`c`,

        .. math::

            A(t) = \operatorname{slerp}(I, R; t)\,\bigl((1 - t) I + t S\bigr), \qquad
            p(t) = A(t)\,(p - c) + c + t\,(A c + b - c) + t\,r_p,

        where :math:`\operatorname{slerp}(I, R; t) = \exp(t \log R)` turns about the fixed
        axis of :math:`R` through :math:`t` times its angle in :math:`[0, \pi]` (the shortest
        arc) and :math:`r_p = y_p - (A p + b)` is the fit's residual at point :math:`p` (zero
        for a given transform). So :math:`p(0) = p` and :math:`p(1) = A p + b + r_p`: the
        target itself.

        Parameters
        ----------
        source : (n, d) float array or mesh
            The shape at t = 0: a point set or a mesh ``{vertices, faces}`` (triangles, or
            tetrahedra in 3-D); ``d`` = 2 or 3.
        target : (n, d) float array or mesh, optional
            The shape at t = 1, point ``i`` for source point ``i``: points, or a mesh with
            exactly the source's faces (the same connectivity); the fitted map needs at least
            ``d + 1`` affinely independent source points. Give this or ``transform``.
        transform : (d+1, d+1) float array, optional
            A homogeneous affine matrix ``[[A, b], [0, 1]]`` applied to the source instead of
            ``target``.
        times : (T,) float array, optional
            Strictly increasing times in [0, 1] (no extrapolation), one frame each; 11 evenly
            spaced (0, 0.1, ..., 1) when omitted.
        reflection : {"refuse", "flip"}, default "refuse"
            For a map that mirrors (:math:`\det A < 0`), which no path of invertible maps
            reaches: ``"refuse"`` raises an error; ``"flip"`` takes a rotation and a stretch
            with one negative eigenvalue, so the path flattens the shape once on the way.
        pivot : {"centroid", "origin"}, default "centroid"
            The point :math:`c` the linear part acts about: ``"centroid"`` the source's
            centroid, which then moves on a straight line; ``"origin"`` the origin, so that the
            translation is interpolated as :math:`t b`.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``interpolation.affine``; its results hold ``frames``, ``times``, ``faces``, ``transform``, ``rotation``, ``stretch``, ``angle``, ``det``, ``max_edge_error``, ``rmse``, ``reflection``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] K. Shoemake and T. Duff, "Matrix animation and polar decomposition", Graphics
           Interface 1992, 258-264.
        .. [2] M. Alexa, D. Cohen-Or and D. Levin, "As-rigid-as-possible shape interpolation",
           SIGGRAPH 2000, 157-164 (§3, the single-triangle case).

        Examples
        --------
        >>> job = client.interpolation.affine(  # doctest: +SKIP
        ...     [[0, 0], [1, 0], [1, 1], [0, 1]],
        ...     transform=[[0.0, -1.0, 2.0], [2.0, 0.0, 1.0], [0.0, 0.0, 1.0]],
        ...     times=[0.0, 0.25, 0.5, 0.75, 1.0],
        ...     wait=30)
        >>> job.results()["frames"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "transform": transform, "times": times, "reflection": reflection, "pivot": pivot}
        return self._client.execute(
            "interpolation.affine",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_INTERPOLATION_AFFINE),
        )

    def arap(
        self,
        source: ShapeLike,
        target: ShapeLike | None = None,
        *,
        transform: ArrayLike | None = None,
        times: ArrayLike | None = None,
        anchor: int = 0,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""As-rigid-as-possible shape interpolation.

        Per face, A_f = R_f S_f interpolated as slerp(R_f) lerp(I, S_f); the vertices of each frame
        solve min Σ_f ‖B_f(x) − A_f(t)‖² with one vertex on its straight path (one factored sparse
        system, one solve per frame).

        Each face's affine map :math:`A_f` from source to target (see the module docstring of
        :mod:`algorithms.interpolation._faces`: the face's edges, plus the normal as third
        axis for triangles in 3-D) is split by the polar decomposition :math:`A_f = R_f S_f`
        and interpolated as :math:`A_f(t) = \operatorname{slerp}(I, R_f; t)\,((1 - t) I + t
        S_f)`, the rotation along its shortest arc. The vertices at time :math:`t` minimise

        .. math::

            \sum_f \lVert B_f(X) - A_f(t) \rVert_F^2,

        :math:`B_f(X)` the map face :math:`f` takes under positions :math:`X` (its edges'
        least-squares fit), with one vertex held on its straight path
        :math:`(1 - t)\,p_a + t\,q_a`. The normal equations are one sparse system, factored
        once; each frame is one solve with a new right-hand side.

        Parameters
        ----------
        source : Mesh or {"vertices", "faces"}
            The mesh at t = 0: ``(n, d)`` vertices and ``(m, 3)`` triangles (``d`` = 2 or 3)
            or, in 3-D, ``(m, 4)`` tetrahedra; no zero-area (zero-volume) faces. A point set
            is refused: the method interpolates per face.
        target : (n, d) float array or mesh, optional
            The mesh at t = 1 with exactly the source's faces (the same connectivity), or its
            vertices alone. Give this or ``transform``.
        transform : (d+1, d+1) float array, optional
            A homogeneous affine matrix ``[[A, b], [0, 1]]`` applied to the source instead of
            ``target``.
        times : (T,) float array, optional
            Strictly increasing times in [0, 1] (no extrapolation), one frame each; 11 evenly
            spaced (0, 0.1, ..., 1) when omitted.
        anchor : int, default 0
            The vertex that moves on a straight line from its source to its target position
            (it fixes the free translation); every other connected component holds its
            lowest-numbered vertex on its line.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``interpolation.arap``; its results hold ``frames``, ``times``, ``faces``, ``min_det``, ``max_edge_error``, ``max_angle``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] M. Alexa, D. Cohen-Or and D. Levin, "As-rigid-as-possible shape interpolation",
           SIGGRAPH 2000, 157-164.
        .. [2] R. W. Sumner and J. Popović, "Deformation transfer for triangle meshes", ACM TOG
           23(3), 2004 (the normal as fourth vertex of a triangle in space).
        """
        inputs = {"source": source, "target": target, "transform": transform, "times": times, "anchor": anchor}
        return self._client.execute(
            "interpolation.arap",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_INTERPOLATION_ARAP),
        )

    def poisson(
        self,
        source: ShapeLike,
        target: ShapeLike | None = None,
        *,
        transform: ArrayLike | None = None,
        times: ArrayLike | None = None,
        anchor: int = 0,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Poisson shape interpolation.

        Per-face gradients interpolated (rotations made continuous across the mesh then slerped,
        stretches lerped) and each frame recovered by a Poisson solve L x = div(gradients) with the
        prefactored cotangent Laplacian.

        Each face's map :math:`A_f = R_f S_f` (polar decomposition; the face's edges, plus the
        normal as third axis for triangles in 3-D) is interpolated as
        :math:`A_f(t) = \exp(t \log R_f)\,((1 - t) I + t S_f)`; row :math:`r` of
        :math:`A_f(t)` is the wanted gradient of coordinate :math:`r` over the face. The
        coordinates at time :math:`t` solve the Poisson equation

        .. math::

            L\, X(t) = G^\mathsf{T} M\, [A_f(t)^\mathsf{T}]_f ,

        :math:`L` the cotangent Laplacian (:func:`~algorithms.core.laplacian.cotangent_laplacian`;
        for tetrahedra the same FEM stiffness assembled from the gradients), :math:`M` the face
        areas (volumes) and :math:`G^\mathsf{T} M` the divergence: the area-weighted
        least-squares fit of the gradients. One vertex moves on its straight path (the
        Dirichlet condition); :math:`L` is factored once and each frame is one solve.

        The rotation vectors :math:`\log R_f` are made continuous across the mesh before
        interpolating (:func:`~algorithms.interpolation._faces.unwrap_rotations`): from the
        face that turns least, each face takes the multiple of a whole turn that puts it
        nearest the neighbour it was reached from, so a part turned by more than half a turn
        does not tear.

        Parameters
        ----------
        source : Mesh or {"vertices", "faces"}
            The mesh at t = 0: ``(n, d)`` vertices and ``(m, 3)`` triangles (``d`` = 2 or 3)
            or, in 3-D, ``(m, 4)`` tetrahedra; no zero-area (zero-volume) faces. A point set
            is refused: the method interpolates per face.
        target : (n, d) float array or mesh, optional
            The mesh at t = 1 with exactly the source's faces (the same connectivity), or its
            vertices alone. Give this or ``transform``.
        transform : (d+1, d+1) float array, optional
            A homogeneous affine matrix ``[[A, b], [0, 1]]`` applied to the source instead of
            ``target``.
        times : (T,) float array, optional
            Strictly increasing times in [0, 1] (no extrapolation), one frame each; 11 evenly
            spaced (0, 0.1, ..., 1) when omitted.
        anchor : int, default 0
            The vertex that moves on a straight line from its source to its target position
            (it fixes the free translation); every other connected component holds its
            lowest-numbered vertex on its line.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``interpolation.poisson``; its results hold ``frames``, ``times``, ``faces``, ``min_det``, ``max_edge_error``, ``max_angle``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] D. Xu, H. Zhang, Q. Wang and H. Bao, "Poisson shape interpolation", ACM
           Symposium on Solid and Physical Modeling 2005, 267-274.
        .. [2] M. Alexa, D. Cohen-Or and D. Levin, "As-rigid-as-possible shape interpolation",
           SIGGRAPH 2000, 157-164.
        """
        inputs = {"source": source, "target": target, "transform": transform, "times": times, "anchor": anchor}
        return self._client.execute(
            "interpolation.poisson",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_INTERPOLATION_POISSON),
        )

    def rigid(
        self,
        source: ShapeLike,
        target: ShapeLike | None = None,
        *,
        transform: ArrayLike | None = None,
        times: ArrayLike | None = None,
        scale: bool = False,
        pivot: Literal["centroid", "origin"] = "centroid",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Rigid (or similarity) motion interpolation.

        Fits a rigid motion (Kabsch) or similarity (Umeyama) to the target, or takes the one given, and
        moves the shape along it: rotation by slerp (shortest arc), pivot on a straight line, scale
        geometric (s^t).

        The motion :math:`p \mapsto s R p + b` is the ``transform`` given (checked to be one),
        or the least-squares fit to ``target``: Kabsch (:func:`algorithms.alignment.rigid`), or
        Umeyama with ``scale=True`` (:func:`algorithms.alignment.similarity`). With the pivot
        :math:`c`,

        .. math::

            p(t) = s^t \exp(t \log R)\,(p - c) + c + t\,(s R c + b - c) + t\,r_p,

        :math:`r_p = y_p - (s R p + b)` the fit's residual (zero for a given transform), so
        :math:`p(0) = p` and :math:`p(1) = y_p`. The rotation turns about its fixed axis
        through :math:`t` times its angle in :math:`[0, \pi]` (the shortest arc), the pivot
        moves on a straight line, and the scale changes geometrically (:math:`\log s` is
        interpolated linearly), so equal time steps give equal ratios.

        Parameters
        ----------
        source : (n, d) float array or mesh
            The shape at t = 0: a point set or a mesh ``{vertices, faces}`` (triangles, or
            tetrahedra in 3-D); ``d`` = 2 or 3. Fitting a target needs at least ``d`` points,
            not all on one line in 3-D, not all at one point in 2-D.
        target : (n, d) float array or mesh, optional
            The shape at t = 1, point ``i`` for source point ``i``: points, or a mesh with
            exactly the source's faces (the same connectivity). Give this or ``transform``.
        transform : (d+1, d+1) float array, optional
            A homogeneous rigid motion ``[[R, b], [0, 1]]`` (with ``scale=True`` a similarity
            ``[[s R, b], [0, 1]]``) applied to the source instead of ``target``.
        times : (T,) float array, optional
            Strictly increasing times in [0, 1] (no extrapolation), one frame each; 11 evenly
            spaced (0, 0.1, ..., 1) when omitted.
        scale : bool, default False
            Fit and interpolate a uniform scale too, geometrically (:math:`s^t`).
        pivot : {"centroid", "origin"}, default "centroid"
            The point :math:`c` the rotation turns about: ``"centroid"`` the source's centroid,
            which then moves on a straight line; ``"origin"`` the origin.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``interpolation.rigid``; its results hold ``frames``, ``times``, ``faces``, ``transform``, ``rotation``, ``scale``, ``translation``, ``angle``, ``max_edge_error``, ``rmse``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] K. Shoemake, "Animating rotation with quaternion curves", SIGGRAPH 1985,
           245-254.
        .. [2] S. Umeyama, "Least-squares estimation of transformation parameters between two
           point patterns", IEEE TPAMI 13(4), 376-380, 1991.

        Examples
        --------
        >>> job = client.interpolation.rigid(  # doctest: +SKIP
        ...     [[0, 0], [1, 0], [1, 1], [0, 1]],
        ...     transform=[[0.0, -1.0, 2.0], [1.0, 0.0, 1.0], [0.0, 0.0, 1.0]],
        ...     times=[0.0, 0.25, 0.5, 0.75, 1.0],
        ...     wait=30)
        >>> job.results()["frames"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "transform": transform, "times": times, "scale": scale, "pivot": pivot}
        return self._client.execute(
            "interpolation.rigid",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_INTERPOLATION_RIGID),
        )


class Parameterization(_Family):
    """The parameterization processes, through a :class:`Client`: ``abf``, ``arap``, ``asap``, ``bijective``, ``conformal``, ``harmonic``, ``stretch_minimizing``, ``tutte``."""

    def abf(
        self,
        mesh: MeshLike,
        *,
        max_iterations: int = 20,
        tolerance: float = 1e-08,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Angle-based flattening (ABF++).

        Solves for the flat angles nearest the surface's (relative error, weights 1/β²) under the
        triangle, planarity and wheel constraints by Newton's method on a sparse reduced system (angle
        and triangle multipliers eliminated, one sparse Cholesky per iteration), then lays the mesh out
        from the angles by a least-squares conformal step with two boundary vertices pinned; free
        boundary. Reports flipped faces, angle distortion and area distortion.

        Finds the angles :math:`\alpha` of a flat mesh nearest the surface's, in relative
        terms,

        .. math::

            \min_\alpha \sum_c \frac{(\alpha_c - \beta_c)^2}{\beta_c^2}
            \quad\text{s.t.}\quad
            \begin{cases}
            \sum_{c \in t} \alpha_c = \pi & \text{every face } t,\\
            \sum_{c \ni v} \alpha_c = 2\pi & \text{every interior vertex } v,\\
            \sum_{c \ni v} \log\sin\alpha_{c^+} - \log\sin\alpha_{c^-} = 0
                & \text{every interior vertex } v,
            \end{cases}

        (:math:`\beta` the surface's angles scaled at each interior vertex to sum to
        :math:`2\pi`; :math:`c^\pm` the next and previous corner of corner :math:`c`'s face:
        the wheel condition that the edge-length ratios around a vertex multiply to one), by
        Newton's method on the Lagrangian from :math:`\alpha = \beta`, :math:`\lambda = 0`.
        Each step solves the KKT system by ABF++'s elimination: the angle block is diagonal,
        the triangle block then too, leaving one sparse symmetric positive definite system in
        the :math:`2q` vertex multipliers (:math:`q` interior vertices), factored by sparse
        Cholesky. Then the mesh is laid out from the angles by a least-squares conformal step
        (:func:`angles_to_uv`), two boundary vertices pinned.

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        max_iterations : int, default 20
            Upper bound on Newton iterations.
        tolerance : float, default 1e-8
            Stop when the Euclidean norm of the gradient of the Lagrangian (in the angles and
            the multipliers: the optimality residual and every constraint's residual, radians)
            is at most this; ``0`` runs all ``max_iterations``. Not converging warns
            (:class:`~algorithms.core.errors.ConvergenceWarning`) unless ``tolerance`` is 0.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``parameterization.abf``; its results hold ``uv``, ``mesh``, ``angles``, ``pinned``, ``energy``, ``gradient_norm``, ``iterations``, ``converged``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] A. Sheffer, B. Lévy, M. Mogilnitsky and A. Bogomyakov, "ABF++: fast and robust
           angle based flattening", ACM Transactions on Graphics 24(2), 2005.
        .. [2] A. Sheffer and E. de Sturler, "Parameterization of faceted surfaces for meshing
           using angle-based flattening", Engineering with Computers 17, 2001.

        Examples
        --------
        >>> job = client.parameterization.abf(  # doctest: +SKIP
        ...     {'vertices': [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0], [0, 2, 0], [1, 2, 0.3], [2, 2, 0]], 'faces': [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]},
        ...     wait=30)
        >>> job.results()["uv"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "max_iterations": max_iterations, "tolerance": tolerance}
        return self._client.execute(
            "parameterization.abf",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_ABF),
        )

    def arap(
        self,
        mesh: MeshLike,
        *,
        init: Literal["lscm", "harmonic"] = "lscm",
        max_iterations: int = 100,
        tolerance: float = 1e-06,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""As-rigid-as-possible parameterization (local/global).

        Alternates per-face nearest rotations (closed form) and one prefactored cotangent-Laplacian
        solve with a per-half-edge right-hand side; free boundary, energy never increasing. Reports
        flipped faces, angle distortion and area distortion.

        Minimises over the UV positions :math:`u` and one rotation :math:`R_t` per face

        .. math::

            E(u, R) = \sum_t A_t \lVert J_t(u) - R_t \rVert_F^2
            = \sum_t \sum_{k} \tfrac12\cot\theta_t^k
            \lVert (u_a - u_b) - R_t\, e_t^k \rVert^2,

        by block coordinate descent from ``init``: the local step gives each face the rotation
        nearest its Jacobian (closed form in 2-D), the global step solves for :math:`u` with
        the rotations fixed (one prefactored cotangent-Laplacian solve per iteration). Each
        step minimises the energy over its block exactly, so it never increases. One vertex is
        held where ``init`` put it (the energy does not see translations).

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        init : {"lscm", "harmonic"}, default "lscm"
            The starting map, scaled to the surface's area: ``"lscm"`` the least-squares
            conformal map (farthest boundary pair pinned), ``"harmonic"`` the harmonic map onto
            the circle.
        max_iterations : int, default 100
            Upper bound on local/global iterations (libigl's ``ARAPData.max_iter`` is 10, run
            to the end; ours stops by ``tolerance``, so the larger bound costs nothing where
            fewer iterations settle; ``max_iterations=10, tolerance=0`` is libigl's run).
        tolerance : float, default 1e-6
            Stop when an iteration lowers the energy by at most this fraction; ``0`` runs all
            ``max_iterations`` (libigl's behaviour), unless the energy reaches zero.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``parameterization.arap``; its results hold ``uv``, ``mesh``, ``energy``, ``iterations``, ``converged``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] L. Liu, L. Zhang, Y. Xu, C. Gotsman and S. J. Gortler, "A local/global approach
           to mesh parameterization", Computer Graphics Forum 27(5) (SGP), 2008.

        Examples
        --------
        >>> job = client.parameterization.arap(  # doctest: +SKIP
        ...     {'vertices': [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0], [0, 2, 0], [1, 2, 0.3], [2, 2, 0]], 'faces': [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]},
        ...     wait=30)
        >>> job.results()["uv"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "init": init, "max_iterations": max_iterations, "tolerance": tolerance}
        return self._client.execute(
            "parameterization.arap",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_ARAP),
        )

    def asap(
        self,
        mesh: MeshLike,
        *,
        init: Literal["lscm", "harmonic"] = "harmonic",
        max_iterations: int = 100,
        tolerance: float = 1e-06,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""As-similar-as-possible parameterization (local/global).

        Alternates per-face nearest similarities and one prefactored solve, two boundary vertices held;
        converges to the LSCM map with those pins. Reports flipped faces, angle distortion and area
        distortion.

        Minimises over the UV positions :math:`u` and one similarity
        :math:`S_t = \begin{pmatrix} p_t & -s_t \\ s_t & p_t \end{pmatrix}` per face

        .. math:: E(u, S) = \sum_t A_t \lVert J_t(u) - S_t \rVert_F^2

        by the local/global iteration of :func:`~algorithms.parameterization.arap` with the
        similarity nearest each Jacobian in the local step (closed form, no SVD). The energy
        is zero on the collapsed map, so two vertices (the boundary pair farthest apart) are
        held where ``init`` put them.

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        init : {"lscm", "harmonic"}, default "harmonic"
            The starting map, scaled to the surface's area: ``"harmonic"`` the harmonic map
            onto the circle; ``"lscm"`` the least-squares conformal map with the same two pins,
            already the minimum of the ASAP energy (the iteration stops at once).
        max_iterations : int, default 100
            Upper bound on local/global iterations.
        tolerance : float, default 1e-6
            Stop when an iteration lowers the energy by at most this fraction; ``0`` runs all
            ``max_iterations``.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``parameterization.asap``; its results hold ``uv``, ``mesh``, ``energy``, ``iterations``, ``converged``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] L. Liu, L. Zhang, Y. Xu, C. Gotsman and S. J. Gortler, "A local/global approach
           to mesh parameterization", Computer Graphics Forum 27(5) (SGP), 2008.

        Examples
        --------
        >>> job = client.parameterization.asap(  # doctest: +SKIP
        ...     {'vertices': [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0], [0, 2, 0], [1, 2, 0.3], [2, 2, 0]], 'faces': [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]},
        ...     wait=30)
        >>> job.results()["uv"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "init": init, "max_iterations": max_iterations, "tolerance": tolerance}
        return self._client.execute(
            "parameterization.asap",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_ASAP),
        )

    def bijective(
        self,
        mesh: MeshLike,
        *,
        max_iterations: int = 100,
        tolerance: float = 1e-06,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Bijective parameterization (symmetric Dirichlet, free boundary).

        Minimises the symmetric Dirichlet energy plus a boundary barrier from a flip-free Tutte start by
        SLIM steps; the line search never lets a face flip or the boundary cross itself (quadratic step
        bounds), so the map is bijective by construction. Reports flipped faces, angle distortion and
        area distortion.

        Minimises, over the UV positions :math:`u`,

        .. math::

            E(u) = \frac{\sum_t A_t \left(\lVert J_t\rVert_F^2 + \lVert J_t^{-1}\rVert_F^2
            \right)}{\sum_t A_t} + \lambda \sum_{e} \sum_{k}
            \max\!\left(0, \frac{\varepsilon}{d(u_k, e)} - 1\right)^2,

        the area-weighted symmetric Dirichlet energy (infinite on a collapsed face, so it
        keeps every face's orientation) plus Smith and Schaefer's boundary barrier
        (:math:`e` a boundary edge, :math:`k` a boundary vertex not on it or next to it,
        :math:`d` the distance from the vertex to the edge segment, :math:`\varepsilon` a
        quarter of the mean boundary edge length, :math:`\lambda = 10^{-2}`).

        * Start: the mean value Tutte map onto the circle, scaled to the surface's area:
          flip-free with a simple boundary (Tutte's theorem).
        * Direction: the SLIM step (Rabinovich et al. 2017): the minimiser of the reweighted
          quadratic proxy :math:`\sum_t A_t \lVert W_t (J_t - R_t)\rVert_F^2` whose gradient
          equals the energy's at the current map, plus the barrier's Gauss-Newton term; one
          sparse Cholesky solve over :math:`(u, v)`.
        * Line search: the first trial is 0.8 of the largest step at which no triangle's
          signed area reaches zero (per triangle, the smallest positive root of a quadratic in
          the step), capped at 1, then halved until the objective falls enough (Armijo).
          Trials at or beyond the first contact of a boundary vertex with a boundary edge (a
          quadratic in the step too, for the pairs a k-d tree finds within reach) are skipped.

        Every accepted step is therefore flip-free and keeps the boundary from touching itself
        all along the way: the map is bijective by construction, not by luck. While the
        barrier and the contact bound are idle, every step is libigl's SLIM step (the same
        proxy, proximal term and halving), so the two agree to rounding; where SLIM's
        free boundary overlaps itself (a strip wound more than once around an axis), this
        map stops at contact.

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        max_iterations : int, default 100
            Upper bound on SLIM iterations.
        tolerance : float, default 1e-6
            Stop when an iteration lowers the objective by at most this fraction; ``0`` runs
            all ``max_iterations`` (unless no step lowers it any more).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``parameterization.bijective``; its results hold ``uv``, ``mesh``, ``energy``, ``symmetric_dirichlet``, ``iterations``, ``converged``, ``boundary_crossings``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] J. Smith and S. Schaefer, "Bijective parameterization with free boundaries",
           ACM Trans. Graph. 34(4) (SIGGRAPH), 2015.
        .. [2] M. Rabinovich, R. Poranne, D. Panozzo and O. Sorkine-Hornung, "Scalable locally
           injective mappings", ACM Trans. Graph. 36(2), 2017.

        Examples
        --------
        >>> job = client.parameterization.bijective(  # doctest: +SKIP
        ...     {'vertices': [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0], [0, 2, 0], [1, 2, 0.3], [2, 2, 0]], 'faces': [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]},
        ...     wait=30)
        >>> job.results()["uv"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "max_iterations": max_iterations, "tolerance": tolerance}
        return self._client.execute(
            "parameterization.bijective",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_BIJECTIVE),
        )

    def conformal(
        self,
        mesh: MeshLike,
        *,
        method: Literal["lscm", "spectral"] = "lscm",
        pins: HandlesLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Conformal parameterization (LSCM, spectral).

        Minimises the conformal energy (Dirichlet minus area): LSCM with two or more pins (chosen
        automatically or given; as igl.lscm), or spectral conformal with a free boundary (generalized
        eigenproblem). Reports flipped faces, angle distortion and area distortion.

        Both methods minimise the conformal energy

        .. math::

            E_C(u) = \tfrac12 \int \lVert \nabla u \rVert^2 - A(u)
            = \sum_t A_t \lVert J_t - S_t \rVert_F^2,

        Dirichlet energy minus the area of the image (:math:`J_t` each face's Jacobian,
        :math:`S_t` the nearest similarity), which vanishes exactly on conformal maps and is
        unchanged by similarities of the plane, so they differ in how that freedom is fixed:

        * ``"lscm"`` (Lévy et al. 2002; Desbrun et al. 2002): pin at least two vertices and solve
          :math:`Q_{ff} u_f = -Q_{fp} c`, one sparse Cholesky solve of size :math:`2n`. Without
          ``pins`` the two boundary vertices farthest apart in space are pinned at
          :math:`(0, 0)` and :math:`(d, 0)`, :math:`d` their distance. Equal to ``igl.lscm``
          with the same pins.
        * ``"spectral"`` (Mullen et al. 2008): no pins; the minimiser of :math:`E_C` under
          :math:`u^\mathsf{T} B u = 1` and :math:`u \perp_B` the constants, :math:`B` the lumped
          boundary length: the first non-trivial eigenvector of :math:`Q u = \lambda B u`
          (shift-invert Lanczos). The result is centred, scaled so its area equals the
          surface's, and turned so the farthest boundary pair lies along +x. A planar mesh comes
          back as itself up to a similarity.

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        method : {"lscm", "spectral"}, default "lscm"
            ``"lscm"``: the least-squares conformal map with at least two vertices pinned
            (``pins``); ``"spectral"``: free boundary and no pins, the first non-trivial
            generalized eigenvector, centred, scaled to the surface's area and turned so the
            farthest boundary pair lies along +x.
        pins : Handles or mapping, optional
            LSCM only: at least two vertices and their positions in the plane,
            ``{"indices": (p,), "positions": (p, 2)}``. Omitted: the two boundary vertices
            farthest apart in space, at :math:`(0, 0)` and :math:`(d, 0)`, :math:`d` their
            distance.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``parameterization.conformal``; its results hold ``uv``, ``mesh``, ``pinned``, ``energy``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] B. Lévy, S. Petitjean, N. Ray and J. Maillot, "Least squares conformal maps for
           automatic texture atlas generation", SIGGRAPH 2002.
        .. [2] M. Desbrun, M. Meyer and P. Alliez, "Intrinsic parameterizations of surface
           meshes", Eurographics 2002.
        .. [3] P. Mullen, Y. Tong, P. Alliez and M. Desbrun, "Spectral conformal
           parameterization", SGP 2008.
        """
        inputs = {"mesh": mesh, "method": method, "pins": pins}
        return self._client.execute(
            "parameterization.conformal",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_CONFORMAL),
        )

    def harmonic(
        self,
        mesh: MeshLike,
        *,
        boundary: Literal["circle", "square"] = "circle",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Harmonic parameterization.

        Boundary fixed to a circle or square, interior by the cotangent Laplace equation (minimal
        Dirichlet energy); as igl.harmonic. Reports flipped faces, angle distortion and area distortion.

        .. math::

            \min_u \int \lVert \nabla u \rVert^2 = \min_u\; u_x^\mathsf{T} L u_x
            + u_y^\mathsf{T} L u_y \quad\text{s.t.}\quad u_{\text{boundary}} = c
            \qquad\Longleftrightarrow\qquad L_{00}\, u = -L_{01}\, c,

        :math:`L` the cotangent Laplacian (:math:`w_{ij} = \tfrac12(\cot\alpha_{ij} +
        \cot\beta_{ij})`) and :math:`c` the boundary loop on the unit circle (arc length, as
        ``igl.map_vertices_to_circle``) or the square :math:`[-1, 1]^2`. One factored solve
        for both coordinates (what :func:`algorithms.layout.laplacian` solves with these pins);
        the same as ``igl.harmonic(V, F, loop, c, 1)``.

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        boundary : {"circle", "square"}, default "circle"
            The convex polygon the boundary loop is pinned to, its vertices spaced by boundary
            edge length: ``"circle"`` the unit circle; ``"square"`` the square
            :math:`[-1, 1]^2`, its corners at the four boundary vertices of smallest angle sum
            (the surface's own corners; at least 4 boundary vertices).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``parameterization.harmonic``; its results hold ``uv``, ``mesh``, ``pinned``, ``energy``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] U. Pinkall and K. Polthier, "Computing discrete minimal surfaces and their
           conjugates", Experimental Mathematics 2(1), 1993.
        .. [2] M. Eck, T. DeRose, T. Duchamp, H. Hoppe, M. Lounsbery and W. Stuetzle,
           "Multiresolution analysis of arbitrary meshes", SIGGRAPH 1995.

        Examples
        --------
        >>> job = client.parameterization.harmonic(  # doctest: +SKIP
        ...     {'vertices': [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0], [0, 2, 0], [1, 2, 0.3], [2, 2, 0]], 'faces': [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]},
        ...     wait=30)
        >>> job.results()["uv"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "boundary": boundary}
        return self._client.execute(
            "parameterization.harmonic",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_HARMONIC),
        )

    def stretch_minimizing(
        self,
        mesh: MeshLike,
        *,
        boundary: Literal["circle", "square"] = "circle",
        power: float = 1.0,
        max_iterations: int = 20,
        tolerance: float = 0.0001,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Stretch-minimizing parameterization (fixed boundary).

        Starts from the mean value Tutte map (boundary on a circle or square), then divides each weight
        w_ij by the stretch around vertex j and solves again while Sander et al.'s L2 stretch falls;
        keeps the best map. Positive weights and a convex boundary: no flipped faces. Reports the L2 and
        L-infinity stretch, flipped faces, angle distortion and area distortion.

        Lowers Sander et al.'s L2 stretch (the root mean square, over the surface, of the
        stretch a texture suffers when mapped back onto the surface)

        .. math:: L^2(M)^2 = \frac{\sum_t A_t \tfrac12(\Gamma_t^2 + \gamma_t^2)}{\sum_t A_t}
           \cdot \frac{\sum_t A'_t}{\sum_t A_t}

        (:math:`\Gamma_t \ge \gamma_t` the singular values of the map from the plane to face
        :math:`t`; :math:`A_t`, :math:`A'_t` its surface and plane areas) by Yoshizawa et al.'s
        reweighting:

        1. start from the mean value Tutte map (Floater's weights :math:`w^0_{ij}`, boundary on
           the convex polygon);
        2. compute each vertex's stretch :math:`\sigma_j = \sqrt{\sum_{t \ni j} A_t L^2(t)^2 /
           \sum_{t \ni j} A_t}`;
        3. reweight :math:`w_{ij} \leftarrow w_{ij} / \sigma_j^{p}` (a stretched neighbour pulls
           harder, so the region around it grows) and solve
           :math:`\sum_j w_{ij}(u_i - u_j) = 0` for the interior again (one sparse LU);
        4. repeat while the L2 stretch falls; return the map with the smallest.

        The weights stay positive and the boundary convex, so by Tutte's theorem in Floater's
        form no face flips at any step.

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        boundary : {"circle", "square"}, default "circle"
            The convex polygon the boundary loop is pinned to, its vertices spaced by boundary
            edge length: ``"circle"`` the unit circle; ``"square"`` the square
            :math:`[-1, 1]^2`, its corners at the four boundary vertices of smallest angle sum
            (the surface's own corners; at least 4 boundary vertices).
        power : float, default 1.0
            The exponent :math:`p` of the reweighting :math:`w_{ij} \leftarrow w_{ij} /
            \sigma_j^p`, :math:`\sigma_j` the stretch around vertex :math:`j`; ``0 < p <= 4``
            (Yoshizawa et al.: 1). Smaller steps are safer on very stretched meshes; larger
            ones converge faster when they work.
        max_iterations : int, default 20
            Upper bound on reweightings.
        tolerance : float, default 1e-4
            Stop when a reweighting lowers the L2 stretch by at most this fraction (or raises
            it: the method's stopping rule).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``parameterization.stretch_minimizing``; its results hold ``uv``, ``mesh``, ``pinned``, ``stretch``, ``l2_stretch``, ``max_stretch``, ``iterations``, ``converged``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] P. V. Sander, J. Snyder, S. J. Gortler and H. Hoppe, "Texture mapping
           progressive meshes", SIGGRAPH 2001.
        .. [2] S. Yoshizawa, A. Belyaev and H.-P. Seidel, "A fast and simple stretch-minimizing
           mesh parameterization", Shape Modeling International 2004.

        Examples
        --------
        >>> job = client.parameterization.stretch_minimizing(  # doctest: +SKIP
        ...     {'vertices': [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0], [0, 2, 0], [1, 2, 0.3], [2, 2, 0]], 'faces': [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]},
        ...     wait=30)
        >>> job.results()["uv"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "boundary": boundary, "power": power, "max_iterations": max_iterations, "tolerance": tolerance}
        return self._client.execute(
            "parameterization.stretch_minimizing",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_STRETCH_MINIMIZING),
        )

    def tutte(
        self,
        mesh: MeshLike,
        *,
        boundary: Literal["circle", "square"] = "circle",
        weighting: Literal["uniform", "mean_value"] = "uniform",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Tutte embedding (circle or square boundary).

        Pins the boundary loop to a circle or square and puts every interior vertex at a convex
        combination of its neighbours (uniform or mean value weights): one sparse solve, no flipped
        faces. Reports flipped faces, angle distortion and area distortion.

        Solves, for the interior vertices :math:`u_i`,

        .. math:: \sum_j w_{ij} (u_i - u_j) = 0, \qquad u_{\text{boundary}} = c,

        with :math:`c` the boundary loop on the unit circle or the square :math:`[-1, 1]^2`,
        spaced by boundary edge length. Weights: ``"uniform"`` (:math:`w_{ij} = 1`, Tutte's
        barycentric map; symmetric, one Cholesky solve through
        :func:`algorithms.layout.laplacian`) or ``"mean_value"`` (Floater's mean value weights,
        :func:`mean_value_weights`: not symmetric, one LU solve; they reproduce a planar mesh
        whose boundary is pinned to its own convex outline).

        By Tutte's spring theorem in Floater's form (positive weights, each interior vertex a
        convex combination of its neighbours, boundary on a convex polygon), no face flips.

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        boundary : {"circle", "square"}, default "circle"
            The convex polygon the boundary loop is pinned to, its vertices spaced by boundary
            edge length: ``"circle"`` the unit circle; ``"square"`` the square
            :math:`[-1, 1]^2`, its corners at the four boundary vertices of smallest angle sum
            (the surface's own corners; at least 4 boundary vertices).
        weighting : {"uniform", "mean_value"}, default "uniform"
            The interior weights: ``"uniform"`` 1 per edge (Tutte's barycentric map);
            ``"mean_value"`` Floater's mean value weights (closer to conformal; a planar mesh
            pinned to its own convex outline comes back as itself). Both are positive, so no
            face flips.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``parameterization.tutte``; its results hold ``uv``, ``mesh``, ``pinned``, ``energy``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] W. T. Tutte, "How to draw a graph", Proc. London Math. Soc. 13 (1963).
        .. [2] M. S. Floater, "Mean value coordinates", CAGD 20(1), 19-27, 2003.

        Examples
        --------
        >>> job = client.parameterization.tutte(  # doctest: +SKIP
        ...     {'vertices': [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0], [0, 2, 0], [1, 2, 0.3], [2, 2, 0]], 'faces': [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]},
        ...     wait=30)
        >>> job.results()["uv"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "boundary": boundary, "weighting": weighting}
        return self._client.execute(
            "parameterization.tutte",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_TUTTE),
        )


class Registration(_Family):
    """The registration processes, through a :class:`Client`: ``cpd``, ``icp``, ``multiway``, ``ransac``."""

    def cpd(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        model: Literal["rigid", "affine", "nonrigid"] = "rigid",
        scale: bool = True,
        w: float = 0.0,
        beta: float = 2.0,
        alpha: float = 2.0,
        low_rank: int | None = None,
        normalize: bool = True,
        sigma2: float | None = None,
        max_iterations: int = 100,
        tolerance: float = 1e-05,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Register ``source`` onto ``target`` by coherent point drift; no correspondences.

        The moved source points :math:`T(y_m)` are the centroids of an equally weighted Gaussian
        mixture of variance :math:`\sigma^2`, plus a uniform component of weight ``w`` for
        outliers; the target points :math:`x_n` are its data. EM alternates

        - **E-step:** the posterior of centroid :math:`m` for point :math:`n`,

          .. math::

              P_{mn} = \frac{\exp(-\lVert x_n - T(y_m)\rVert^2 / 2\sigma^2)}
              {\sum_k \exp(-\lVert x_n - T(y_k)\rVert^2 / 2\sigma^2) + c}, \qquad
              c = (2\pi\sigma^2)^{d/2}\,\frac{w}{1-w}\,\frac{M}{N};

        - **M-step:** the map and :math:`\sigma^2` minimising
          :math:`\sum_{mn} P_{mn} \lVert x_n - T(y_m)\rVert^2 / 2\sigma^2 + N_P d/2 \log\sigma^2`
          (:math:`N_P = \sum_{mn} P_{mn}`), in closed form for each ``model``:

          - ``rigid``: :math:`T(y) = sRy + t`, with :math:`R` from the SVD of
            :math:`A = \hat X^\mathsf{T} P^\mathsf{T} \hat Y` (reflection fixed) and
            :math:`s = \operatorname{tr}(A^\mathsf{T} R) / \operatorname{tr}(\hat Y^\mathsf{T}
            d(P1) \hat Y)`, or :math:`s = 1` with ``scale=False``;
          - ``affine``: :math:`T(y) = By + t`, :math:`B = A (\hat Y^\mathsf{T} d(P1)
            \hat Y)^{-1}`;
          - ``nonrigid``: :math:`T(Y) = Y + GW`, :math:`G_{ij} = \exp(-\lVert y_i - y_j\rVert^2
            / 2\beta^2)`, with :math:`(d(P1) G + \lambda\sigma^2 I) W = PX - d(P1) Y` (the
            motion coherence regulariser :math:`\tfrac{\lambda}{2}\operatorname{tr}(W^\mathsf{T}
            GW)`; ``alpha`` is the paper's :math:`\lambda`).

        The iterations stop when the relative change of the negative log-likelihood (plus the
        regulariser) falls below ``tolerance``, when σ² reaches rounding level, or after
        ``max_iterations``.

        Parameters
        ----------
        source : (M, d) float array
            The points to move (the mixture's centroids), ``d ≥ 2``.
        target : (N, d) float array
            The points to register onto, same ``d``; ``N`` need not equal ``M`` and no
            correspondence with ``source`` is needed.
        model : {"rigid", "affine", "nonrigid"}, default "rigid"
            The family of maps: ``"rigid"`` a rotation and a translation (and, with ``scale``,
            a uniform scale); ``"affine"`` any linear map and a translation; ``"nonrigid"`` a
            smooth displacement of every source point (Gaussian kernel, motion coherence).
        scale : bool, default True
            Rigid only: estimate the uniform scale ``s`` too (a similarity); False keeps
            ``s = 1``.
        w : float in [0, 1), default 0.0
            The weight of the uniform outlier component, ``0 <= w < 1``: raise it for noise and
            for points of one set missing from the other.
        beta : float > 0, default 2.0
            Nonrigid: the width :math:`\beta` of the Gaussian kernel ``G``; larger is smoother.
            In the units of the normalised sets (unit RMS radius) when ``normalize``, else in
            the points' units.
        alpha : float > 0, default 2.0
            Nonrigid: the regularisation weight :math:`\lambda` of the paper (pycpd's
            ``alpha``); larger keeps the motion closer to a translation.
        low_rank : int >= 1, optional
            Nonrigid: the number ``K`` of leading eigenpairs of ``G`` to use (the paper's fast
            version). Default: the exact kernel up to 1000 source points, else
            ``K = ceil(sqrt(M))`` (the authors' code's default). A value ``≥ M``
            asks for the exact kernel, allowed up to 4000 source points (it takes
            :math:`16M^2` bytes).
        normalize : bool, default True
            Nonrigid: centre each set on its mean and divide it by its RMS radius before
            registering (as the authors' code), so ``beta`` and ``alpha`` need not follow the
            data's units (``sigma2`` stays in squared target units); ``moved`` is returned in
            target units. False: ``beta`` is
            in the points' own units (as pycpd). Rigid and affine results do not depend on it
            (they are computed on centred sets under one common scale, which they commute
            with).
        sigma2 : float > 0, optional
            The initial variance σ² of the mixture, in squared target units. Default: the
            paper's :math:`\sum_{mn}\lVert x_n - y_m\rVert^2 / dMN`, the mean squared
            distance of all pairs per dimension.
        max_iterations : int >= 1, default 100
            The most EM iterations.
        tolerance : float >= 0, default 1e-5
            Stop when the negative log-likelihood changes by less than this fraction in an
            iteration (the relative rule and default of Myronenko and Song's reference code;
            pycpd's ``tolerance``, default 0.001, bounds the absolute change of its objective
            instead, so the two stop at different iterations on the same input).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``registration.cpd``; its results hold ``transform``, ``linear``, ``rotation``, ``scale``, ``translation``, ``moved``, ``sigma2``, ``rmse``, ``iterations``, ``converged``, ``reason``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] A. Myronenko and X. Song, "Point set registration: coherent point drift", IEEE
           TPAMI 32(12), 2262-2275, 2010. arXiv:0905.2635.
        .. [2] N. Halko, P.-G. Martinsson and J. A. Tropp, "Finding structure with randomness",
           SIAM Review 53(2), 217-288, 2011 (the eigenpairs of ``G``).
        """
        inputs = {"source": source, "target": target, "model": model, "scale": scale, "w": w, "beta": beta, "alpha": alpha, "low_rank": low_rank, "normalize": normalize, "sigma2": sigma2, "max_iterations": max_iterations, "tolerance": tolerance}
        return self._client.execute(
            "registration.cpd",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_REGISTRATION_CPD),
        )

    def icp(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        model: Literal["rigid", "similarity", "affine"] = "rigid",
        metric: Literal["point_to_point", "point_to_plane", "symmetric"] = "point_to_point",
        init: Literal["identity", "pca"] | ArrayLike = "identity",
        max_iterations: int = 30,
        tolerance: float = 1e-06,
        max_correspondence_distance: float | None = None,
        overlap: float = 1.0,
        kernel: Literal["none", "huber", "tukey"] = "none",
        kernel_scale: float | None = None,
        target_normals: PointsLike | None = None,
        source_normals: PointsLike | None = None,
        normal_neighbors: int = 10,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Register ``source`` onto ``target`` by iterative closest point; no correspondences.

        Starting from the initial transform :math:`T_0`, each iteration

        1. pairs every moved source point :math:`T_k x_i` with its nearest target point
           :math:`y_{j(i)}` (one kd-tree of the target, built once), dropping pairs farther
           apart than ``max_correspondence_distance`` and, with ``overlap < 1``, all but the
           ``overlap`` fraction of source points with the smallest distances (trimmed ICP);
        2. finds the transform of the ``model`` that minimises the ``metric`` over those pairs,
           weighted by the robust ``kernel``:

           .. math::

               \text{point\_to\_point:}\ \min_T \sum_i w_i \lVert T x_i - y_{j(i)} \rVert^2,
               \qquad
               \text{point\_to\_plane:}\ \min_T \sum_i w_i
               \big( (T x_i - y_{j(i)}) \cdot n_{j(i)} \big)^2,

           and the symmetric metric :math:`\sum_i w_i ((R_{1/2} p_i - R_{1/2}^{-1} q_i + t)
           \cdot (n_{p_i} + n_{q_i}))^2` with both sets' normals (Rusinkiewicz 2019);
        3. stops when the pairs are the same as in the previous iteration (a fixed point), when
           the RMSE changed by less than ``tolerance`` relative to its previous value, or after
           ``max_iterations``.

        Point-to-point steps are the closed forms of :mod:`algorithms.alignment` (Kabsch /
        Umeyama / least squares, weighted); point-to-plane and symmetric steps solve the
        linearised objective (small rotation :math:`R \approx I + [\omega]_\times`, exact for
        affine) by one ``6×6`` to ``12×12`` normal-equation solve in coordinates centred and
        scaled at the moved source, then apply the exact rotation of :math:`\omega`.

        Parameters
        ----------
        source : (n, d) float array
            The points to move, ``d >= 2`` (``d = 3`` for the plane metrics).
        target : (m, d) float array
            The points to register onto, the same ``d``, any size ``m``; no correspondence
            with ``source`` is needed.
        model : {"rigid", "similarity", "affine"}, default "rigid"
            The transform: ``"rigid"`` a rotation and a translation, ``"similarity"`` also a
            uniform scale, ``"affine"`` any linear map and a translation.
        metric : {"point_to_point", "point_to_plane", "symmetric"}, default "point_to_point"
            The distance minimised: ``"point_to_point"`` from each moved source point to its
            partner (any ``d``); ``"point_to_plane"`` to the partner's tangent plane (3-D;
            target normals estimated when not given); ``"symmetric"`` along the sum of both
            points' normals, Rusinkiewicz's objective (3-D, ``model="rigid"`` only).
        init : {"identity", "pca"} or (d+1, d+1) float array, default "identity"
            The initial transform: ``"identity"``, ``"pca"`` or a homogeneous matrix.
            ``"pca"`` lays the principal axes onto each other (:func:`algorithms.alignment.pca`,
            scaled as the model allows), runs ICP from every proper sign choice of the axes
            (``2^(d-1)``: 4 in 3-D) and keeps the result of highest fitness, then lowest RMSE.
            A matrix must have the last row ``(0, ..., 0, 1)`` and a linear part of the model
            (orthogonal with determinant +1 for rigid, a positive multiple of one for
            similarity, invertible for affine).
        max_iterations : int, default 30
            Most iterations (fits) to run, ``>= 1``; per sign choice with ``init="pca"``.
        tolerance : float, default 1e-6
            Stop when the RMSE changes by less than this fraction of its previous value in an
            iteration, ``>= 0``; the iterations also stop when the correspondences no longer
            change, so 0 stops only there or at ``max_iterations``. Open3D's
            ``ICPConvergenceCriteria`` has the same defaults (30 iterations, 1e-6) but stops when
            both the fitness and the inlier RMSE change by less than 1e-6 in absolute terms; a
            relative change does not depend on the data's units.
        max_correspondence_distance : float, optional
            Pairs farther apart than this (``> 0``) are ignored in the fit and in ``rmse`` and
            do not count towards ``fitness``. No bound when omitted.
        overlap : float, default 1.0
            Trimmed ICP (Chetverikov et al. 2002): keep only the ``ceil(overlap * n)`` pairs of
            smallest distance, ``0 < overlap <= 1``.
        kernel : {"none", "huber", "tukey"}, default "none"
            Robust kernel, applied by iteratively reweighted least squares: ``"none"`` plain
            least squares, ``"huber"`` weights :math:`\min(1, k/|r|)`, ``"tukey"`` the
            biweight :math:`(1 - (r/c)^2)^2` for :math:`|r| < c`, else 0; ``r`` is the pair's
            distance (point-to-point) or its plane distance.
        kernel_scale : float, optional
            The kernel's threshold ``k`` or ``c`` in the points' units (``> 0``). Omitted: each
            iteration estimates it as :math:`1.345\,\hat\sigma` (Huber) or :math:`4.685\,\hat\sigma`
            (Tukey) with :math:`\hat\sigma = 1.4826\,\operatorname{median}|r|`.
        target_normals : (m, 3) float array, optional
            Normals of the target points for the plane metrics (normalised here; sign free).
            Estimated when omitted: the smallest principal axis of each point's
            ``normal_neighbors`` nearest neighbours.
        source_normals : (n, 3) float array, optional
            Normals of the source points for ``metric="symmetric"``, their signs matched to the
            target's pair by pair (checked but unused with the other metrics). Estimated when
            omitted: the smallest principal axis of each point's ``normal_neighbors`` nearest
            neighbours.
        normal_neighbors : int, default 10
            Neighbours per estimated normal, ``>= 2``: the point and this many others
            (Open3D's ``KDTreeSearchParamKNN(knn)`` counts the point itself, so this is its
            ``knn - 1``; Open3D's default ``knn=30`` smooths more: pass 29 for its normals).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``registration.icp``; its results hold ``transform``, ``linear``, ``rotation``, ``scale``, ``translation``, ``rmse``, ``fitness``, ``iterations``, ``converged``, ``reason``, ``rmse_history``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] P. J. Besl and N. D. McKay, "A method for registration of 3-D shapes", IEEE
           TPAMI 14(2), 239-256, 1992.
        .. [2] Y. Chen and G. Medioni, "Object modelling by registration of multiple range
           images", Image and Vision Computing 10(3), 145-155, 1992 (point-to-plane).
        .. [3] D. Chetverikov, D. Svirko, D. Stepanov and P. Krsek, "The trimmed iterative
           closest point algorithm", ICPR 2002.
        .. [4] S. Rusinkiewicz, "A symmetric objective function for ICP", ACM TOG 38(4), 85,
           2019.
        .. [5] Q.-Y. Zhou, J. Park and V. Koltun, "Open3D: a modern library for 3D data
           processing", arXiv:1801.09847, 2018 (``fitness`` and ``inlier_rmse``).
        """
        inputs = {"source": source, "target": target, "model": model, "metric": metric, "init": init, "max_iterations": max_iterations, "tolerance": tolerance, "max_correspondence_distance": max_correspondence_distance, "overlap": overlap, "kernel": kernel, "kernel_scale": kernel_scale, "target_normals": target_normals, "source_normals": source_normals, "normal_neighbors": normal_neighbors}
        return self._client.execute(
            "registration.icp",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_REGISTRATION_ICP),
        )

    def multiway(
        self,
        sets: ArrayLike,
        *,
        correspondences: bool = True,
        model: Literal["rigid", "similarity"] = "rigid",
        init: ArrayLike | None = None,
        max_iterations: int = 100,
        tolerance: float = 1e-09,
        max_correspondence_distance: float | None = None,
        metric: Literal["symmetric", "point_to_plane", "point_to_point"] = "symmetric",
        neighbors: int | None = None,
        min_fitness: float = 0.3,
        edge_prune_threshold: float = 0.25,
        preference_loop_closure: float = 1.0,
        icp_max_iterations: int = 30,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""Multiway registration: generalised Procrustes or pose graph.

        Registers several point sets at once into the frame of set 0. With correspondences: generalised
        Procrustes analysis (rigid or similarity, any dimension), iterated to the mean shape. Without:
        pairwise ICP (coarse to fine, symmetric metric, point-to-point polish) with information
        matrices, then pose-graph optimisation on SE(3) by Levenberg-Marquardt with line processes for
        loop closures, low-fitness and inconsistent edges pruned (as Open3D's multiway registration).

        **With correspondences** (row ``j`` of every set is the same point): generalised
        Procrustes analysis (Gower 1975), :func:`~algorithms.registration.generalized_procrustes`:
        every set is rotated (and, for similarity, scaled) onto the mean shape of the moved
        sets, and the mean recomputed, until the sum of squared distances to the mean stops
        decreasing; any dimension.

        **Without correspondences** (``correspondences=False``, 3-D):
        :func:`~algorithms.registration.pose_graph`, as Open3D's multiway registration (Choi,
        Zhou & Koltun 2015): every pair of sets (or each with its next ``neighbors``) is
        registered by coarse-to-fine ICP, the pairwise results weighted by their information
        matrices, then the poses optimised on SE(3) by Levenberg-Marquardt with line processes
        that switch off inconsistent loop closures.

        The options of the other method are ignored: ``max_correspondence_distance``,
        ``metric``, ``neighbors``, ``min_fitness``, ``edge_prune_threshold``,
        ``preference_loop_closure`` and ``icp_max_iterations`` are the pose graph's.

        Parameters
        ----------
        sets : sequence of (n_i, d) float arrays
            At least two point sets, ``(n_i, d)`` arrays of the same dimension ``d``. With
            correspondences: all of the same length ``n``, row ``j`` of each the same point, any
            ``d >= 1``. Without: 3-D, of any sizes (at least 6 points each, 3 with
            ``metric="point_to_point"``).
        correspondences : bool, default True
            True: row ``j`` of every set is the same point (generalised Procrustes). False:
            the correspondences are unknown (pairwise ICP and pose-graph optimisation on
            SE(3), 3-D only).
        model : {"rigid", "similarity"}, default "rigid"
            ``"rigid"``: a rotation and a translation per set; ``"similarity"``: also a
            uniform scale, relative to set 0's (generalised Procrustes only).
        init : (k, d+1, d+1) float array, optional
            A start transform per set into a common frame (rigid; similarity allowed for
            Procrustes); only their relative transforms matter. Procrustes starts its mean
            from the sets as they move them; the pose graph starts each pairwise ICP from
            them. Omitted: Procrustes starts from set 0, the pose graph from the identity (the
            sets taken as roughly aligned, as by a scanner).
        max_iterations : int, default 100
            Most Procrustes passes, or Levenberg-Marquardt iterations per pose-graph
            optimisation round (two rounds), ``>= 1``.
        tolerance : float, default 1e-9
            Stop when the objective decreases by less than this fraction of its value in an
            iteration, ``>= 0`` (tighter than Open3D's pose-graph criteria, 1e-6: the
            iterations are cheap at the sizes of a multiway problem).
        max_correspondence_distance : float, optional
            Pose graph: the pairs' distance bound (``> 0``, in the points' units) of the fine
            pairwise ICP (the coarse stages use 4 and 2 × it), of the edges' information
            matrices and of ``fitness``; it also scales the line process's loop-closure
            weight. Omitted: 2 × the median distance between nearest neighbours within the
            sets.
        metric : {"symmetric", "point_to_plane", "point_to_point"}, default "symmetric"
            Pose graph: the metric of the coarse-to-fine pairwise ICP stages, followed by a
            point-to-point polish: ``"symmetric"`` uses both sets' normals (Rusinkiewicz
            2019), ``"point_to_plane"`` the target's, ``"point_to_point"`` plain distances.
            Normals are estimated from 10 neighbours; a pair whose target is flat (the plane
            metrics undetermined) falls back to point-to-point.
        neighbors : int, optional
            Pose graph: register each set with its next ``neighbors`` sets in order, ``1 <=
            neighbors <= k - 1`` (1 gives a chain); consecutive pairs then count as trusted
            odometry. Omitted: every pair up to 10 sets (no odometry), 2 beyond.
        min_fitness : float, default 0.3
            Pose graph: drop pairwise edges whose ICP fitness (the share of points with a
            partner within ``max_correspondence_distance``) is below this, ``0 <= min_fitness
            <= 1``: they overlap too little to be trusted.
        edge_prune_threshold : float, default 0.25
            Pose graph: prune the loop closures whose line-process weight falls below this
            after the first optimisation round (Open3D's default), ``0 <= ... < 1``.
        preference_loop_closure : float, default 1.0
            Pose graph: the weight of loop closures in the line process (Open3D's option),
            ``> 0``; larger keeps more loop closures.
        icp_max_iterations : int, default 30
            Pose graph: most iterations per pairwise ICP stage (four stages per pair),
            ``>= 1``.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``registration.multiway``; its results hold ``transforms``, ``rotations``, ``scales``, ``translations``, ``mean_shape``, ``rmse``, ``fitness``, ``edges``, ``edge_fitness``, ``edge_kept``, ``iterations``, ``converged``, ``reason``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] J. C. Gower, "Generalized Procrustes analysis", Psychometrika 40(1), 33-51,
           1975.
        .. [2] S. Choi, Q.-Y. Zhou and V. Koltun, "Robust reconstruction of indoor scenes",
           CVPR 2015.

        Examples
        --------
        >>> job = client.registration.multiway(  # doctest: +SKIP
        ...     [[[0, 0], [2, 0], [0, 1], [0, 2], [1, 0]], [[5, 0], [5, 2], [4, 0], [3, 0], [5, 1]], [[0, 3], [4, 3], [0, 5], [0, 7], [2, 3]]],
        ...     wait=30)
        >>> job.results()["transforms"]  # doctest: +SKIP
        """
        inputs = {"sets": sets, "correspondences": correspondences, "model": model, "init": init, "max_iterations": max_iterations, "tolerance": tolerance, "max_correspondence_distance": max_correspondence_distance, "metric": metric, "neighbors": neighbors, "min_fitness": min_fitness, "edge_prune_threshold": edge_prune_threshold, "preference_loop_closure": preference_loop_closure, "icp_max_iterations": icp_max_iterations}
        return self._client.execute(
            "registration.multiway",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_REGISTRATION_MULTIWAY),
        )

    def ransac(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        features: Literal["fpfh", "none"] = "fpfh",
        voxel_size: float | None = None,
        feature_radius: float | None = None,
        max_correspondence_distance: float | None = None,
        max_iterations: int = 100000,
        confidence: float = 0.999,
        mutual_filter: bool = True,
        refine: bool = True,
        seed: int = 0,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> Job:
        r"""RANSAC global registration (FPFH features or random triples) + ICP.

        Registers source onto target rigidly without a start: candidate pairs from mutually matched FPFH
        features (or, for small sets, random point triples of each set), seeded random samples of 3
        pairs checked by edge lengths, Kabsch fits scored by truncated squared error, confidence-based
        stopping. Without voxel_size: two down-sampling passes (1.5 and 3 × the point spacing), the best
        hypotheses re-scored and ICP-checked on the point sets, a robust (Tukey) ICP refinement against
        the full target; with voxel_size: Open3D's single pass, then point-to-plane ICP. The same seed
        gives the same result; converged=false with a reason instead of a silent identity.

        1. **Down-sampling**: with ``voxel_size`` each set is replaced by the centroids of its
           points in each occupied voxel. With features and no ``voxel_size``, two passes of
           steps 1-4 run, at 1.5 and 3 × the source's point spacing :math:`h` (those that leave
           enough points; none: one pass without down-sampling), and the pass whose pose has
           the least truncated error :math:`\sum_i \min(r_i^2, \tau_s^2)` of the full source
           against the full target wins (:math:`r_i` the distance to the nearest target
           point, :math:`\tau_s = \tau / 3` of the smaller voxel).
        2. **Candidates.** ``features="fpfh"`` (3-D): FPFH descriptors of both sets
           (:func:`~algorithms.registration.fpfh`, radius ``feature_radius``), matched by
           nearest neighbour in feature space, mutually with ``mutual_filter``.
           ``features="none"``: every (source point, target point) pair is a candidate and
           samples are drawn from each set independently (see Notes).
        3. **Hypotheses.** Each draws :math:`s = \max(3, d)` candidate pairs with the generator
           seeded by ``seed`` and is skipped unless every edge of the sample and of its image agree
           within a factor 0.9 (Open3D's edge-length checker) and the sample is not nearly
           collinear; the rest get the Kabsch fit :math:`(R, t)` of their pairs, are skipped
           unless every sampled pair then lies within ``max_correspondence_distance``
           (Open3D's distance checker), and are scored by the truncated squared error
           (MSAC, Torr & Zisserman 2000)

           .. math::

               E(R, t) = \sum_i \min\big(\lVert R x_i + t - y_i \rVert^2, \tau^2\big)

           over the candidate pairs (features) or over the source points and their nearest
           target points (no features), :math:`\tau` = ``max_correspondence_distance``. The
           hypothesis of least error is kept; its inliers (residual :math:`\le\tau`) give the
           inlier ratio :math:`w` of the candidates.
        4. **Stopping**: after :math:`N = \log(1 - c) / \log(1 - w^s)` hypotheses for the
           ``confidence`` :math:`c` (the number after which an all-inlier sample has been
           drawn with probability :math:`c`), or ``max_iterations``. With features and no
           ``voxel_size``, never before 4096 hypotheses; then the 100 of least error are
           re-scored by the truncated error of the down-sampled source against the
           down-sampled target (threshold :math:`\tau`), the best 5 distinct poses refined
           by 10 ICP iterations (``refine``) and compared on the full sets
           (threshold :math:`\tau_s`): the pose with the most matches is not always the one
           that fits (an airplane turned over on its back shares most of its features).
        5. **Refinement** (``refine``): ICP from the RANSAC transform
           (:func:`~algorithms.registration.icp`, point-to-plane against the (down-sampled)
           target with its normals in 3-D when it has at least 30 points and is not flat, else
           point-to-point; at most 20,000 source points, pairs within
           ``max_correspondence_distance``); kept only when it lowers the truncated error
           :math:`\sum_i \min(r_i^2, \tau^2)` of its metric (plane or point distances).
           With features and no ``voxel_size``: against the full target (normals of 10
           neighbours) with Tukey's kernel (its scale from the median residual, so that the
           points outside the overlap do not pull the pose; a plain threshold of
           :math:`1.5 h` left 1-3° on the pyvista ant and airplane crops, the kernel
           0.2-1°), kept when it lowers the truncated point error at :math:`\tau_s`.

        Parameters
        ----------
        source : (n, d) float array
            The points to move; ``d = 3`` with features, any ``d >= 2`` without.
        target : (m, d) float array
            The points to register onto, same ``d``, any size ``m``; the overlap may be
            partial. No correspondence with ``source`` and no start are needed.
        features : {"fpfh", "none"}, default "fpfh"
            Where candidate pairs come from: ``"fpfh"`` (3-D) from Fast Point Feature
            Histograms matched between the sets; ``"none"`` every pair of a source and a target
            point, samples of point triples drawn from each set at random. ``"none"`` needs no
            local structure but finds an all-inlier sample with probability about
            :math:`(k/nm)^3` per hypothesis (``k`` overlapping points): it is for small sets,
            tens of points.
        voxel_size : float, optional
            Down-sample both sets on a grid of this step first (``> 0``); also the length
            scale of the default radii; one pass of Open3D's pipeline (normals of 10
            neighbours). Noisy scans need a voxel several times the noise. When omitted with
            features: two passes, at 1.5 and 3 × the source's point spacing (median distance
            to the 4th nearest neighbour, :func:`~.features.point_spacing`), with normals of
            30 neighbours, and the best-fitting pose wins; without features: no
            down-sampling, the scale is the point spacing.
        feature_radius : float, optional
            FPFH neighbourhood radius (``> 0``). Omitted: 5 × the length scale, the voxel step
            of the pass (``voxel_size`` or a default pass's) or, without down-sampling, the
            source's point spacing.
        max_correspondence_distance : float, optional
            The inlier threshold :math:`\tau` (``> 0``) of scoring, checking, refinement and
            the reported ``fitness``. Omitted: 1.5 × the length scale (the voxel step, or the
            source's point spacing without down-sampling), except with
            ``features="none"`` and no ``voxel_size``: half the median distance from a source
            point to its nearest neighbour (so that a point's partner is unambiguous).
        max_iterations : int, default 100000
            Most hypotheses (samples) to draw, ``>= 1``; the default is Open3D's.
        confidence : float, default 0.999
            Stop once an all-inlier sample has been drawn with this probability (estimated
            from the best inlier ratio), ``0 < confidence <= 1``; 1 never stops early.
        mutual_filter : bool, default True
            Keep only mutual nearest neighbours in feature space; falls back to the one-sided
            matches when fewer than 9 remain (as Open3D). False: each point's nearest
            neighbour in feature space, from both sets (each pair once).
        refine : bool, default True
            Refine the RANSAC transform with ICP (point-to-plane in 3-D when the target has
            enough points, else point-to-point), kept only when it lowers the truncated
            error.
        seed : int or numpy.random.Generator, default 0
            Seeds the sampling; the same seed gives the same result, bit for bit (no step
            depends on the number of threads).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        Job
            The job of ``registration.ransac``; its results hold ``transform``, ``rotation``, ``translation``, ``rmse``, ``fitness``, ``inlier_count``, ``correspondence_count``, ``iterations``, ``converged``, ``reason``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] M. A. Fischler and R. C. Bolles, "Random sample consensus", Comm. ACM 24(6),
           381-395, 1981.
        .. [2] P. H. S. Torr and A. Zisserman, "MLESAC: a new robust estimator with
           application to estimating image geometry", CVIU 78(1), 138-156, 2000 (MSAC).
        .. [3] R. B. Rusu, N. Blodow and M. Beetz, "Fast Point Feature Histograms (FPFH) for
           3D registration", ICRA 2009.
        .. [4] Q.-Y. Zhou, J. Park and V. Koltun, "Open3D: a modern library for 3D data
           processing", arXiv:1801.09847, 2018 (checkers, fitness, stopping rule).
        """
        inputs = {"source": source, "target": target, "features": features, "voxel_size": voxel_size, "feature_radius": feature_radius, "max_correspondence_distance": max_correspondence_distance, "max_iterations": max_iterations, "confidence": confidence, "mutual_filter": mutual_filter, "refine": refine, "seed": seed}
        return self._client.execute(
            "registration.ransac",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_REGISTRATION_RANSAC),
        )


class TypedCalls:
    """The typed calls of :class:`Client`: one attribute per family of processes."""

    __slots__ = ()

    @property
    def alignment(self) -> Alignment:
        """The alignment processes."""
        return Alignment(cast("Client", self))

    @property
    def assignment(self) -> Assignment:
        """The assignment processes."""
        return Assignment(cast("Client", self))

    @property
    def classification(self) -> Classification:
        """The classification processes."""
        return Classification(cast("Client", self))

    @property
    def layout(self) -> Layout:
        """The layout processes."""
        return Layout(cast("Client", self))

    @property
    def clustering(self) -> Clustering:
        """The clustering processes."""
        return Clustering(cast("Client", self))

    @property
    def deformation(self) -> Deformation:
        """The deformation processes."""
        return Deformation(cast("Client", self))

    @property
    def embedding(self) -> Embedding:
        """The embedding processes."""
        return Embedding(cast("Client", self))

    @property
    def interpolation(self) -> Interpolation:
        """The interpolation processes."""
        return Interpolation(cast("Client", self))

    @property
    def parameterization(self) -> Parameterization:
        """The parameterization processes."""
        return Parameterization(cast("Client", self))

    @property
    def registration(self) -> Registration:
        """The registration processes."""
        return Registration(cast("Client", self))


class AsyncAlignment(_AsyncFamily):
    """The alignment processes, through a :class:`AsyncClient`: ``affine``, ``homography``, ``pca``, ``principal_scaling``, ``rigid``, ``similarity``."""

    async def affine(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        weights: ArrayLike | None = None,
        symmetric: bool = False,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Affine alignment (linear least squares).

        The matrix A and translation b minimising Σ wᵢ‖A xᵢ + b − yᵢ‖² for paired points in any
        dimension: A = Ỹ X̃⁺ by least squares, b through the centroids.

        Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The model is
        ``y = A x + b`` with any ``d×d`` matrix ``A``:

        .. math::

            \min_{A,\ b}\ \sum_{i=1}^{n} w_i \lVert A x_i + b - y_i \rVert^2 .

        With weighted centroids :math:`\bar x, \bar y` and centred points stacked as the columns
        of :math:`\tilde X, \tilde Y` (each scaled by :math:`\sqrt{w_i}`), the solution is

        .. math::

            A = \tilde Y \tilde X^{+} = \tilde Y \tilde X^\mathsf{T}
                (\tilde X \tilde X^\mathsf{T})^{-1}, \qquad b = \bar y - A \bar x,

        computed by :func:`numpy.linalg.lstsq` on :math:`\tilde X^\mathsf{T} A^\mathsf{T} =
        \tilde Y^\mathsf{T}` (an SVD of the ``n×d`` data), never by forming the inverse.

        Parameters
        ----------
        source : (n, d) float array
            The points to move, any ``d >= 1``, at least ``d + 1`` of them affinely independent.
        target : (n, d) float array
            Where they should land, paired row by row with ``source``.
        weights : (n,) float array, optional
            Non-negative per-pair weights with a positive sum; all equal when omitted. Pairs of
            weight zero are ignored, but the pairs left must still span ``d`` dimensions.
        symmetric : bool, default False
            Minimise the forward and the inverse residuals together,
            :math:`\sum_i w_i (\lVert A x_i + b - y_i \rVert^2
            + \lVert A^{-1}(y_i - b) - x_i \rVert^2)`; iterative, see Notes.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``alignment.affine``; its results hold ``transform``, ``linear``, ``translation``, ``rmse``, ``iterations``, ``converged``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] S. Schaefer, T. McPhail and J. Warren, "Image deformation using moving least
           squares", ACM Transactions on Graphics 25(3), 533-540, 2006 (the affine case).
        .. [2] G. H. Golub and C. F. Van Loan, Matrix Computations, 4th ed., §5.5 (least squares
           by the SVD), 2013.

        Examples
        --------
        >>> job = await client.alignment.affine(  # doctest: +SKIP
        ...     [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
        ...     [[1, 0, 0], [3, 0, 0], [2, 1, 0], [1, 0, 3]],
        ...     wait=30)
        >>> (await job.results())["transform"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "weights": weights, "symmetric": symmetric}
        return await self._client.execute(
            "alignment.affine",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ALIGNMENT_AFFINE),
        )

    async def homography(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        weights: ArrayLike | None = None,
        symmetric: bool = False,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Projective alignment (normalised DLT).

        The (d+1)×(d+1) projective matrix P (P[d, d] = 1 when possible) with y ≈ dehomogenize(P [x; 1]),
        by the direct linear transformation on Hartley-normalised points, in any dimension; at least d +
        2 pairs in general position.

        Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The model is
        :math:`y = \operatorname{dehom}(P\,[x; 1])` with a ``(d+1)×(d+1)`` matrix ``P``
        defined up to scale, where :math:`\operatorname{dehom}(h) = h_{1..d} / h_{d+1}`.
        Writing :math:`p_j` for the rows of ``P`` and :math:`h_i = [x_i; 1]`, each pair gives
        ``d`` equations linear in ``P`` once the scale is multiplied out,

        .. math::

            p_j^\mathsf{T} h_i - y_{ij}\, p_{d+1}^\mathsf{T} h_i = 0, \qquad j = 1, \dots, d,

        stacked into :math:`A\,\operatorname{vec}(P) = 0`. The estimate minimises the
        algebraic error :math:`\sum_i w_i \lVert A_i \operatorname{vec}(P)\rVert^2` subject to
        :math:`\lVert P \rVert_F = 1`: ``vec(P)`` is the right singular vector of the smallest
        singular value of ``A``. Points are first normalised (Hartley): each set is centred at
        its weighted centroid and scaled so that its root-mean-square distance from it is
        :math:`\sqrt d`; the matrix found for the normalised points is mapped back,
        :math:`P = T_y^{-1} \hat P T_x`.

        Parameters
        ----------
        source : (n, d) float array
            The points to move, any ``d >= 1``, at least ``d + 2`` of them in general position.
        target : (n, d) float array
            Where they should land, paired row by row with ``source``.
        weights : (n,) float array, optional
            Non-negative per-pair weights with a positive sum; all equal when omitted. The
            ``d`` DLT rows of pair ``i`` are multiplied by :math:`\sqrt{w_i}` (so they weight the
            algebraic error), and the normalisation uses the weighted centroid and spread.
        symmetric : bool, default False
            Report the forward and backward transfer errors together in ``rmse``. The DLT
            equations of the inverse map are the same equations, so the estimate is unchanged.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``alignment.homography``; its results hold ``transform``, ``linear``, ``translation``, ``perspective``, ``rmse``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] R. Hartley and A. Zisserman, Multiple View Geometry in Computer Vision, 2nd ed.,
           §4.1-4.4 (DLT and normalisation), Cambridge University Press, 2004.
        .. [2] R. Hartley, "In defense of the eight-point algorithm", IEEE TPAMI 19(6),
           580-593, 1997.
        .. [3] J. Zaragoza, T.-J. Chin, M. S. Brown and D. Suter, "As-projective-as-possible
           image stitching with moving DLT", CVPR 2013 (the weighted DLT).

        Examples
        --------
        >>> job = await client.alignment.homography(  # doctest: +SKIP
        ...     [[0, 0], [1, 0], [1, 1], [0, 1]],
        ...     [[0, 0], [0.5, 0], [0.5, 0.5], [0, 1]],
        ...     wait=30)
        >>> (await job.results())["transform"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "weights": weights, "symmetric": symmetric}
        return await self._client.execute(
            "alignment.homography",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ALIGNMENT_HOMOGRAPHY),
        )

    async def pca(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        mode: Literal["unoriented", "oriented"] = "unoriented",
        choose: Literal["residual", "rotation"] = "residual",
        scale: Literal["anisotropic", "isotropic", "none"] = "anisotropic",
        allow_reflection: bool = False,
        symmetric: bool = False,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Principal-axis alignment (no correspondences).

        Lays the principal axes of the source onto those of the target (sets of any sizes): A = E′ S K
        Eᵀ with signs S from skewness (oriented) or the best of the proper sign choices (unoriented),
        scale K none, isotropic or anisotropic √(D′D⁻¹).

        Each set is centred and its covariance diagonalised,
        :math:`\frac1n \tilde X^\mathsf{T} \tilde X = E D E^\mathsf{T}` and
        :math:`\frac1m \tilde Y^\mathsf{T} \tilde Y = E' D' E'^\mathsf{T}`, eigenvalues in
        decreasing order. The axes are paired by that order and the map is

        .. math::

            A = E' S K E^\mathsf{T}, \qquad t = \bar y - A \bar x,

        with :math:`S = \operatorname{diag}(\pm 1)` the chosen signs and ``K`` the scale:
        ``"anisotropic"`` :math:`K = \sqrt{D' D^{-1}}`, ``"isotropic"``
        :math:`K = \sqrt{\operatorname{tr} D' / \operatorname{tr} D}\, I`, ``"none"``
        :math:`K = I`. ``rotation`` is :math:`R = E' S E^\mathsf{T}`.

        The signs of eigenvectors are arbitrary; ``mode`` fixes them:

        - ``"oriented"``: each axis points where the set's third moment along it is positive
          (towards its long tail: the skewness), in both sets; then, if :math:`\det R = -1` and
          reflections are not allowed, the axis of the smallest eigenvalue is flipped (of all
          single flips, it increases the residual least).
        - ``"unoriented"``: every sign choice is tried, the :math:`2^{d-1}` proper ones
          (:math:`2^d` with ``allow_reflection``), and ``choose`` picks one: ``"residual"``
          (default) the one of smallest Chamfer distance between the moved source and the
          target (kd-tree), ``"rotation"`` the one of smallest rotation angle, i.e. largest
          :math:`\operatorname{tr} R`.

        Parameters
        ----------
        source : (n, d) float array
            The points to move, ``d >= 2``, ``n >= 2``.
        target : (m, d) float array
            The points to align to; same ``d``, any ``m >= 2``.
        mode : {"unoriented", "oriented"}, default "unoriented"
            How the signs of the axes are fixed: ``"unoriented"`` tries every proper sign
            choice of the principal axes and keeps the one ``choose`` prefers; ``"oriented"``
            points each axis towards its set's skew (third moment) and pairs the axes in order
            of variance.
        choose : {"residual", "rotation"}, default "residual"
            With ``mode="unoriented"``, which sign choice is kept: ``"residual"`` the one of
            least Chamfer distance, ``"rotation"`` the one of smallest rotation angle (largest
            trace). Ignored when oriented.
        scale : {"anisotropic", "isotropic", "none"}, default "anisotropic"
            How the source is stretched: ``"anisotropic"`` each principal axis by the ratio of
            the two sets' standard deviations along it, ``"isotropic"`` by one factor, the ratio
            of RMS radii, ``"none"`` not at all (rotate only).
        allow_reflection : bool, default False
            Let ``rotation`` be a reflection when that pairs the axes better.
        symmetric : bool, default False
            Count the inverse residuals in ``rmse`` too (target moved back onto the source).
            The Chamfer distance that ``choose="residual"`` minimises already counts both ways.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``alignment.pca``; its results hold ``transform``, ``linear``, ``rotation``, ``scale``, ``axes``, ``translation``, ``rmse``, ``chamfer``, ``reflection``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] T. Ju, "CSE 554 Lecture 7: Alignment", Washington University in St. Louis
           (principal-axis alignment and the sign ambiguity).

        Examples
        --------
        >>> job = await client.alignment.pca(  # doctest: +SKIP
        ...     [[-1, 0], [-1, 0], [2, 0], [0, 0.5], [0, 0.5], [0, -1]],
        ...     [[4, 2], [-0.5, 2], [-0.5, 2], [1, 8], [1, -1], [1, -1]],
        ...     wait=30)
        >>> (await job.results())["transform"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "mode": mode, "choose": choose, "scale": scale, "allow_reflection": allow_reflection, "symmetric": symmetric}
        return await self._client.execute(
            "alignment.pca",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ALIGNMENT_PCA),
        )

    async def principal_scaling(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        weights: ArrayLike | None = None,
        allow_reflection: bool = False,
        symmetric: bool = False,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Principal scaling alignment (the cross-covariance map M = Ỹ X̃ᵀ).

        Scale along perpendicular axes, then rotate: y = UΣVᵀx + t with UΣVᵀ = Σ wᵢ ỹᵢ x̃ᵢᵀ. Equals the
        least-squares affine map exactly when the source is whitened (Σ wᵢ x̃ᵢ x̃ᵢᵀ = I); otherwise a
        worse fit.

        Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The map
        :math:`y = U \Sigma V^\mathsf{T} x + t` (``U``, ``V`` orthonormal, :math:`\Sigma \ge 0`
        diagonal) is taken from the cross-covariance itself,

        .. math::

            M = \sum_{i=1}^{n} w_i \tilde y_i \tilde x_i^\mathsf{T} = \tilde Y \tilde X^\mathsf{T}
              = U \Sigma V^\mathsf{T}, \qquad t = \bar y - M \bar x,

        with weighted centroids :math:`\bar x, \bar y` and centred points :math:`\tilde x_i,
        \tilde y_i`. This function computes exactly that (the weights enter unnormalised, so
        that all-ones weights give :math:`\tilde Y \tilde X^\mathsf{T}`), with the reflection
        fix of :func:`~algorithms.alignment.rigid`. It is **not** a least-squares fit in general;
        see Notes.

        Parameters
        ----------
        source : (n, d) float array
            The points to move, ``d >= 2`` and ``n >= d``.
        target : (n, d) float array
            Where they should land, paired row by row with ``source``.
        weights : (n,) float array, optional
            Non-negative per-pair weights with a positive sum; all ones when omitted. Unlike in
            the other alignment methods their overall size matters: doubling every weight
            doubles ``M``.
        allow_reflection : bool, default False
            Keep :math:`U \Sigma V^\mathsf{T}` when :math:`\det(U V^\mathsf{T}) = -1`. Off: the
            left singular vector of the smallest singular value is negated, so the map never
            mirrors.
        symmetric : bool, default False
            Report the forward and inverse residuals together in ``rmse``. ``M`` is a formula,
            not a minimiser, so the flag changes only the figure (and requires ``M``
            invertible).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``alignment.principal_scaling``; its results hold ``transform``, ``linear``, ``rotation``, ``scale``, ``axes``, ``translation``, ``rmse``, ``reflection``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] S. Umeyama, "Least-squares estimation of transformation parameters between two
           point patterns", IEEE TPAMI 13(4), 376-380, 1991: the same cross-covariance, whose
           rotation factor is the rigid fit.

        Examples
        --------
        >>> job = await client.alignment.principal_scaling(  # doctest: +SKIP
        ...     [[0.5, 0.5], [-0.5, 0.5], [-0.5, -0.5], [0.5, -0.5]],
        ...     [[2.5, 1.25], [-0.5, 1.25], [-0.5, 0.75], [2.5, 0.75]],
        ...     wait=30)
        >>> (await job.results())["transform"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "weights": weights, "allow_reflection": allow_reflection, "symmetric": symmetric}
        return await self._client.execute(
            "alignment.principal_scaling",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ALIGNMENT_PRINCIPAL_SCALING),
        )

    async def rigid(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        weights: ArrayLike | None = None,
        allow_reflection: bool = False,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Rigid alignment (Kabsch / Umeyama without scale).

        The rotation R (det +1 unless reflections are allowed) and translation t minimising Σ wᵢ‖R xᵢ +
        t − yᵢ‖² for paired points in any dimension d ≥ 2.

        Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The model is
        ``y = R x + t`` with ``R`` orthogonal, solved in closed form (Kabsch 1976; Umeyama 1991
        without the scale):

        .. math::

            \min_{R^\mathsf{T} R = I,\ \det R = 1,\ t}\ \sum_{i=1}^{n} w_i
            \lVert R x_i + t - y_i \rVert^2

        With :math:`\bar x = \sum_i w_i x_i / \sum_i w_i` and :math:`\bar y` likewise, the
        weighted cross-covariance :math:`C = \sum_i w_i (y_i - \bar y)(x_i - \bar x)^\mathsf{T}
        = U \Sigma V^\mathsf{T}` gives :math:`R = U D V^\mathsf{T}` with
        :math:`D = \operatorname{diag}(1, \dots, 1, \operatorname{sign}\det(U V^\mathsf{T}))`
        and :math:`t = \bar y - R \bar x`.

        Parameters
        ----------
        source : (n, d) float array
            The points to move, ``d >= 2`` and ``n >= d``.
        target : (n, d) float array
            Where they should land, paired row by row with ``source``.
        weights : (n,) float array, optional
            Non-negative per-pair weights with a positive sum; all equal when omitted. Pairs of
            weight zero are ignored, but the pairs left must still determine the rotation.
        allow_reflection : bool, default False
            Also consider improper orthogonal matrices (determinant -1), i.e. solve the plain
            orthogonal Procrustes problem without the constraint :math:`\det R = 1`.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``alignment.rigid``; its results hold ``transform``, ``linear``, ``rotation``, ``translation``, ``scale``, ``rmse``, ``reflection``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] W. Kabsch, "A solution for the best rotation to relate two sets of vectors",
           Acta Crystallographica A 32(5), 922-923, 1976; and "A discussion of the solution for
           the best rotation to relate two sets of vectors", Acta Cryst. A 34(5), 827-828, 1978.
        .. [2] S. Umeyama, "Least-squares estimation of transformation parameters between two
           point patterns", IEEE Transactions on Pattern Analysis and Machine Intelligence
           13(4), 376-380, 1991.

        Examples
        --------
        >>> job = await client.alignment.rigid(  # doctest: +SKIP
        ...     [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
        ...     [[1, 2, 3], [1, 3, 3], [0, 2, 3], [1, 2, 4]],
        ...     wait=30)
        >>> (await job.results())["transform"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "weights": weights, "allow_reflection": allow_reflection}
        return await self._client.execute(
            "alignment.rigid",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ALIGNMENT_RIGID),
        )

    async def similarity(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        weights: ArrayLike | None = None,
        allow_reflection: bool = False,
        symmetric: bool = False,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Similarity alignment (Umeyama).

        The rotation R (det +1 unless reflections are allowed), uniform scale s and translation t
        minimising Σ wᵢ‖s R xᵢ + t − yᵢ‖² for paired points, d ≥ 2; s = tr(DΣ)/σx² with Umeyama's
        reflection-corrected trace.

        Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The model is
        ``y = s R x + t`` with ``R`` orthogonal and ``s > 0``, solved in closed form (Umeyama
        1991):

        .. math::

            \min_{R^\mathsf{T} R = I,\ \det R = 1,\ s > 0,\ t}\ \sum_{i=1}^{n} w_i
            \lVert s R x_i + t - y_i \rVert^2 .

        With weighted centroids :math:`\bar x, \bar y`, centred points :math:`\tilde x_i,
        \tilde y_i`, normalised weights :math:`p_i = w_i / \sum_j w_j`, the cross-covariance
        :math:`C = \sum_i p_i \tilde y_i \tilde x_i^\mathsf{T} = U \Sigma V^\mathsf{T}` and
        :math:`\sigma_x^2 = \sum_i p_i \lVert \tilde x_i \rVert^2`:

        .. math::

            R = U D V^\mathsf{T}, \qquad
            s = \frac{\operatorname{tr}(D \Sigma)}{\sigma_x^2}, \qquad
            t = \bar y - s R \bar x,

        where :math:`D = \operatorname{diag}(1, \dots, 1, \operatorname{sign}\det(U V^\mathsf{T}))`
        (the identity with ``allow_reflection=True``).

        Parameters
        ----------
        source : (n, d) float array
            The points to move, ``d >= 2`` and ``n >= d``.
        target : (n, d) float array
            Where they should land, paired row by row with ``source``.
        weights : (n,) float array, optional
            Non-negative per-pair weights with a positive sum; all equal when omitted. Pairs of
            weight zero are ignored, but the pairs left must still determine the rotation.
        allow_reflection : bool, default False
            Also consider improper orthogonal matrices (determinant -1).
        symmetric : bool, default False
            Minimise the forward and the inverse residuals together,
            :math:`\sum_i w_i (\lVert s R x_i + t - y_i \rVert^2
            + \lVert s^{-1} R^\mathsf{T}(y_i - t) - x_i \rVert^2)`; see Notes.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``alignment.similarity``; its results hold ``transform``, ``linear``, ``rotation``, ``translation``, ``scale``, ``rmse``, ``reflection``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] S. Umeyama, "Least-squares estimation of transformation parameters between two
           point patterns", IEEE Transactions on Pattern Analysis and Machine Intelligence
           13(4), 376-380, 1991.
        .. [2] B. K. P. Horn, "Closed-form solution of absolute orientation using unit
           quaternions", Journal of the Optical Society of America A 4(4), 629-642, 1987.

        Examples
        --------
        >>> job = await client.alignment.similarity(  # doctest: +SKIP
        ...     [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
        ...     [[1, 2, 3], [1, 4, 3], [-1, 2, 3], [1, 2, 5]],
        ...     wait=30)
        >>> (await job.results())["transform"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "weights": weights, "allow_reflection": allow_reflection, "symmetric": symmetric}
        return await self._client.execute(
            "alignment.similarity",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ALIGNMENT_SIMILARITY),
        )


class AsyncAssignment(_AsyncFamily):
    """The assignment processes, through a :class:`AsyncClient`: ``bipartite``, ``closest_pair``, ``distance``, ``nearest``, ``optimal_transport``."""

    async def bipartite(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        metric: Literal["euclidean", "sqeuclidean"] = "euclidean",
        max_cost: float | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Optimal one-to-one matching (linear assignment).

        Matches the points of two sets one to one at the least total cost; sets may differ in size (the
        surplus stays unmatched), and max_cost leaves far points single. At most 16 million pairs n·m.

        With :math:`c_{ij}` the ``metric`` cost between :math:`x_i` and :math:`y_j`, this solves
        the (rectangular) linear assignment problem

        .. math::

            \min_{\pi}\ \sum_{(i, j) \in \pi} c_{ij}

        over matchings :math:`\pi` (sets of pairs in which no point appears twice) of size
        :math:`\min(n, m)`: when the sets differ in size, the surplus points of the larger set
        stay unmatched. With ``max_cost`` = :math:`\tau` every point may stay unmatched at a
        price of :math:`\tau / 2`, so a pair is worth making only when it costs less than
        :math:`\tau`:

        .. math::

            \min_{\pi}\ \sum_{(i, j) \in \pi} c_{ij}
            + \frac{\tau}{2}\,\bigl(n + m - 2\lvert\pi\rvert\bigr),
            \qquad c_{ij} \le \tau \ \text{for every}\ (i, j) \in \pi,

        that is, the matching maximises the total saving :math:`\sum_\pi (\tau - c_{ij})`.
        No returned pair costs more than :math:`\tau`.

        Parameters
        ----------
        source : (n, d) float array
            The first point set, any ``d >= 1``, at least one point.
        target : (m, d) float array
            The second point set, same ``d``; its size may differ from ``source`` (the surplus
            of the larger set stays unmatched). At most 16 million pairs ``n·m``
            (``MAX_COST_ENTRIES``).
        metric : {"euclidean", "sqeuclidean"}, default "euclidean"
            The cost of a pair: the distance :math:`\lVert x_i - y_j \rVert`, or its square.
            The squared distance favours many small displacements over a few large ones.
        max_cost : float, optional
            The largest cost of a pair (``> 0``, in the units of ``metric``): leaving a point
            unmatched costs half of it, so points whose every partner costs more stay
            unmatched. Omitted: every point of the smaller set is matched.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``assignment.bipartite``; its results hold ``pairs``, ``distances``, ``cost``, ``rmse``, ``n_pairs``, ``unmatched_source``, ``unmatched_target``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] H. W. Kuhn, "The Hungarian method for the assignment problem", Naval Research
           Logistics Quarterly 2, 83-97, 1955.
        .. [2] R. Jonker and A. Volgenant, "A shortest augmenting path algorithm for dense and
           sparse linear assignment problems", Computing 38, 325-340, 1987.
        .. [3] D. F. Crouse, "On implementing 2D rectangular assignment algorithms", IEEE
           Transactions on Aerospace and Electronic Systems 52(4), 1679-1696, 2016.

        Examples
        --------
        >>> job = await client.assignment.bipartite(  # doctest: +SKIP
        ...     [[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]],
        ...     [[0.1, 0.0], [2.0, 0.0]],
        ...     wait=30)
        >>> (await job.results())["pairs"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "metric": metric, "max_cost": max_cost}
        return await self._client.execute(
            "assignment.bipartite",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ASSIGNMENT_BIPARTITE),
        )

    async def closest_pair(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Closest pair between two point sets (kd-tree).

        The single pair of points, one from each set, at the smallest distance.

        .. math::

            (i^\ast, j^\ast) = \operatorname*{arg\,min}_{i, j}\ \lVert x_i - y_j \rVert

        Parameters
        ----------
        source : (n, d) float array
            The first point set, any ``d >= 1``, at least one point.
        target : (m, d) float array
            The second point set, same ``d``; its size may differ from ``source``.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``assignment.closest_pair``; its results hold ``source_index``, ``target_index``, ``distance``, ``pairs``, ``distances``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] J. L. Bentley, "Multidimensional binary search trees used for associative
           searching", Communications of the ACM 18(9), 509-517, 1975.

        Examples
        --------
        >>> job = await client.assignment.closest_pair(  # doctest: +SKIP
        ...     [[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]],
        ...     [[0.1, 0.0], [2.0, 0.0]],
        ...     wait=30)
        >>> (await job.results())["source_index"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target}
        return await self._client.execute(
            "assignment.closest_pair",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ASSIGNMENT_CLOSEST_PAIR),
        )

    async def distance(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Chamfer, Hausdorff and RMSE distances between point sets.

        How far apart two point sets are, from their nearest-neighbour assignment in both directions:
        Chamfer (sum and mean), Hausdorff (and both directed halves), RMSE, and every point's distance
        to the other set.

        With the nearest-neighbour distances :math:`d_i = \min_j \lVert x_i - y_j \rVert`
        (forward, one per source point) and :math:`e_j = \min_i \lVert x_i - y_j \rVert`
        (backward, one per target point):

        .. math::

            \text{chamfer} &= \sum_i d_i + \sum_j e_j, \qquad
            \text{chamfer\_mean} = \tfrac{1}{n}\sum_i d_i + \tfrac{1}{m}\sum_j e_j, \\
            \text{hausdorff} &= \max\bigl(\max_i d_i,\ \max_j e_j\bigr), \qquad
            \text{rmse} = \sqrt{\frac{\sum_i d_i^2 + \sum_j e_j^2}{n + m}} .

        ``chamfer`` measures the difference of two sets by a sum of distances (Barrow et al.
        1977 [1]_); it equals the sum of the distances of :func:`nearest` with
        ``direction="both"``.

        Parameters
        ----------
        source : (n, d) float array
            The first point set, any ``d >= 1``, at least one point.
        target : (m, d) float array
            The second point set, same ``d``; its size may differ from ``source``.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``assignment.distance``; its results hold ``chamfer``, ``chamfer_mean``, ``hausdorff``, ``hausdorff_forward``, ``hausdorff_backward``, ``rmse``, ``rmse_forward``, ``rmse_backward``, ``forward_distances``, ``backward_distances``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] H. G. Barrow, J. M. Tenenbaum, R. C. Bolles and H. C. Wolf, "Parametric
           correspondence and chamfer matching: two new techniques for image matching",
           IJCAI 1977, 659-663.
        .. [2] D. P. Huttenlocher, G. A. Klanderman and W. J. Rucklidge, "Comparing images
           using the Hausdorff distance", IEEE TPAMI 15(9), 850-863, 1993.

        Examples
        --------
        >>> job = await client.assignment.distance(  # doctest: +SKIP
        ...     [[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]],
        ...     [[0.1, 0.0], [2.0, 0.0]],
        ...     wait=30)
        >>> (await job.results())["chamfer"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target}
        return await self._client.execute(
            "assignment.distance",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ASSIGNMENT_DISTANCE),
        )

    async def nearest(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        k: int = 1,
        direction: Literal["forward", "backward", "union", "intersection", "both"] = "forward",
        max_distance: float | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Nearest-neighbour assignment (kd-tree).

        Pairs each point with its k nearest neighbours in the other set, in one or both directions,
        optionally within a distance.

        For ``direction="forward"`` every source point :math:`x_i` is paired with the ``k``
        target points closest to it,

        .. math::

            \mathcal{P}_\to = \{(i, j) : y_j \in \operatorname{kNN}_k(x_i; Y)\},

        and ``"backward"`` does the same from the target side,
        :math:`\mathcal{P}_\leftarrow = \{(i, j) : x_i \in \operatorname{kNN}_k(y_j; X)\}`.
        ``"union"`` is :math:`\mathcal{P}_\to \cup \mathcal{P}_\leftarrow`, ``"intersection"``
        is :math:`\mathcal{P}_\to \cap \mathcal{P}_\leftarrow` (mutual nearest neighbours), and
        ``"both"`` is the forward list followed by the backward list without removing
        duplicates, so that with ``k=1`` the sum of ``distances`` is the Chamfer distance

        .. math::

            \sum_i \min_j \lVert x_i - y_j \rVert + \sum_j \min_i \lVert x_i - y_j \rVert .

        Parameters
        ----------
        source : (n, d) float array
            The first point set, any ``d >= 1``.
        target : (m, d) float array
            The second point set, same ``d``; its size may differ from ``source``.
        k : int, default 1
            Neighbours per query point, ``1 <= k <=`` the size of the set searched: ``target``
            for forward, ``source`` for backward, the smaller of the two otherwise.
        direction : {"forward", "backward", "union", "intersection", "both"}, default "forward"
            Which pairs to return: ``"forward"`` each source point with its ``k`` nearest
            target points; ``"backward"`` each target point with its ``k`` nearest source
            points; ``"union"`` the pairs found in either direction, ``"intersection"`` those
            found in both (mutual nearest neighbours), each pair once; ``"both"`` the forward
            list followed by the backward one, duplicates kept (with ``k=1`` its distances sum
            to the Chamfer distance).
        max_distance : float, optional
            Drop pairs farther apart than this (``> 0``, in the points' units); pairs at exactly
            this distance are kept. Applied in each direction before union or intersection.
            Omitted: no pair is dropped.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``assignment.nearest``; its results hold ``pairs``, ``distances``, ``rmse``, ``n_pairs``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] J. L. Bentley, "Multidimensional binary search trees used for associative
           searching", Communications of the ACM 18(9), 509-517, 1975.
        .. [2] S. Maneewongvatana and D. M. Mount, "Analysis of approximate nearest neighbor
           searching with clustered point sets", arXiv:cs/9901013, 1999 (the sliding-midpoint
           kd-tree of scipy's ``cKDTree``).

        Examples
        --------
        >>> job = await client.assignment.nearest(  # doctest: +SKIP
        ...     [[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]],
        ...     [[0.1, 0.0], [2.0, 0.0]],
        ...     wait=30)
        >>> (await job.results())["pairs"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "k": k, "direction": direction, "max_distance": max_distance}
        return await self._client.execute(
            "assignment.nearest",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ASSIGNMENT_NEAREST),
        )

    async def optimal_transport(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        source_weights: ArrayLike | None = None,
        target_weights: ArrayLike | None = None,
        method: Literal["exact", "sinkhorn"] = "exact",
        reg: float = 0.05,
        max_iterations: int = 1000,
        tolerance: float = 1e-09,
        metric: Literal["euclidean", "sqeuclidean"] = "sqeuclidean",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Optimal transport between weighted point sets (exact or Sinkhorn).

        The transport plan moving the mass of one weighted point set onto another at the least cost,
        returned sparse as (source, target, mass) pairs, with its cost (Wasserstein distance). Exact
        linear program, or entropic Sinkhorn in the log domain. At most 16 million pairs n·m.

        With masses :math:`a \in \mathbb{R}^n_{\ge 0}`, :math:`b \in \mathbb{R}^m_{\ge 0}`
        (each summing to 1) and the ``metric`` cost :math:`C_{ij}` between :math:`x_i` and
        :math:`y_j`, the exact method solves the Kantorovich problem

        .. math::

            \min_{P \ge 0}\ \langle C, P \rangle = \sum_{ij} C_{ij} P_{ij}
            \quad\text{subject to}\quad P \mathbf{1} = a,\ \ P^\mathsf{T} \mathbf{1} = b,

        and ``method="sinkhorn"`` its entropic regularisation (Cuturi 2013)

        .. math::

            \min_{P \ge 0,\ P \mathbf{1} = a,\ P^\mathsf{T} \mathbf{1} = b}\
            \langle C, P \rangle - \varepsilon H(P), \qquad
            H(P) = -\sum_{ij} P_{ij} (\log P_{ij} - 1),

        whose solution :math:`P_{ij} = \exp((f_i + g_j - C_{ij})/\varepsilon)` is found by
        alternating the dual updates, in the log domain,

        .. math::

            f_i \leftarrow \varepsilon \log a_i
                - \varepsilon \operatorname{LSE}_j \bigl((g_j - C_{ij})/\varepsilon\bigr), \qquad
            g_j \leftarrow \varepsilon \log b_j
                - \varepsilon \operatorname{LSE}_i \bigl((f_i - C_{ij})/\varepsilon\bigr).

        Parameters
        ----------
        source : (n, d) float array
            The points mass leaves from, any ``d >= 1``, at least one point.
        target : (m, d) float array
            The points mass arrives at, same ``d``; its size may differ from ``source``. At
            most 16 million pairs ``n·m`` (``MAX_COST_ENTRIES``).
        source_weights : (n,) float array, optional
            Non-negative masses of the source points with a positive sum; uniform when omitted.
            They are relative: normalised to sum to 1 (so the totals of the two sets never
            disagree). Points of mass 0 take no part.
        target_weights : (m,) float array, optional
            Non-negative masses of the target points with a positive sum, normalised to sum
            to 1; uniform when omitted. Points of mass 0 take no part.
        method : {"exact", "sinkhorn"}, default "exact"
            ``"exact"``: the transport linear program (an assignment when the masses are
            uniform on sets of equal size, else the network simplex); ``"sinkhorn"``: its
            entropic regularisation, solved by log-domain Sinkhorn iterations (faster on
            large sets, a blurred plan).
        reg : float, default 0.05
            Sinkhorn's :math:`\varepsilon` (``> 0``), in the units of the cost (absolute, as in
            POT): smaller is closer to the exact plan but needs more iterations. Checked but
            unused by the exact method.
        max_iterations : int, default 1000
            Sinkhorn's iteration limit (``>= 1``); one iteration updates both potentials.
        tolerance : float, default 1e-9
            Sinkhorn stops when the L1 error of the plan's marginals is at most this (``> 0``),
            checked every iteration. POT's ``sinkhorn`` has the same default (``stopThr=1e-9``)
            but checks the L2 norm of the column marginals' error every 10 iterations, so it
            may run a few iterations more; the L1 rule bounds the mass misplaced, which is what
            the plan's users read.
        metric : {"sqeuclidean", "euclidean"}, default "sqeuclidean"
            The cost of moving unit mass from :math:`x_i` to :math:`y_j`:
            :math:`\lVert x_i - y_j \rVert^2` (2-Wasserstein) or :math:`\lVert x_i - y_j \rVert`
            (1-Wasserstein, earth mover's distance).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``assignment.optimal_transport``; its results hold ``pairs``, ``masses``, ``distances``, ``cost``, ``rmse``, ``marginal_error``, ``n_pairs``, ``iterations``, ``converged``, ``solver``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] L. Kantorovich, "On the translocation of masses", Doklady Akademii Nauk SSSR 37,
           199-201, 1942.
        .. [2] M. Cuturi, "Sinkhorn distances: lightspeed computation of optimal transport",
           NeurIPS 26, 2013.
        .. [3] G. Peyré and M. Cuturi, "Computational optimal transport", Foundations and
           Trends in Machine Learning 11(5-6), 355-607, 2019 (sections 3 and 4.4, the
           log-domain Sinkhorn).
        .. [4] N. Bonneel, M. van de Panne, S. Paris and W. Heidrich, "Displacement
           interpolation using Lagrangian mass transport", ACM Transactions on Graphics 30(6),
           158, 2011 (the network simplex POT implements).
        .. [5] A. Thibault, L. Chizat, C. Dossal and N. Papadakis, "Overrelaxed Sinkhorn-Knopp
           algorithm for regularized optimal transport", Algorithms 14(5), 143, 2021.
        .. [6] G. Birkhoff, "Tres observaciones sobre el algebra lineal", Universidad Nacional
           de Tucumán Revista, Serie A 5, 147-151, 1946.

        Examples
        --------
        >>> job = await client.assignment.optimal_transport(  # doctest: +SKIP
        ...     [[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]],
        ...     [[0.1, 0.0], [2.0, 0.0]],
        ...     wait=30)
        >>> (await job.results())["pairs"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "source_weights": source_weights, "target_weights": target_weights, "method": method, "reg": reg, "max_iterations": max_iterations, "tolerance": tolerance, "metric": metric}
        return await self._client.execute(
            "assignment.optimal_transport",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_ASSIGNMENT_OPTIMAL_TRANSPORT),
        )


class AsyncClassification(_AsyncFamily):
    """The classification processes, through a :class:`AsyncClient`: ``lda``, ``nca``."""

    async def lda(
        self,
        points: PointsLike,
        labels: ArrayLike,
        *,
        n_components: int | None = None,
        query: PointsLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
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
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``classification.lda``; its results hold ``embedding``, ``scalings``, ``mean``, ``classes``, ``class_means``, ``predictions``, ``accuracy``, ``explained_variance_ratio``, ``query_embedding``, ``query_predictions``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] R. A. Fisher, "The use of multiple measurements in taxonomic problems", Annals
           of Eugenics 7(2), 1936.
        .. [2] T. Hastie, R. Tibshirani, J. Friedman, *The Elements of Statistical Learning*,
           2nd ed., Springer 2009, §4.3.

        Examples
        --------
        >>> job = await client.classification.lda(  # doctest: +SKIP
        ...     [[0, 0], [1, 0], [0, 1], [1, 1.5], [5, 5], [6, 5], [5, 6], [6.5, 6]],
        ...     ['a', 'a', 'a', 'a', 'b', 'b', 'b', 'b'],
        ...     query=[[0.5, 0.5], [5.5, 5.0]],
        ...     wait=30)
        >>> (await job.results())["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "labels": labels, "n_components": n_components, "query": query}
        return await self._client.execute(
            "classification.lda",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_CLASSIFICATION_LDA),
        )

    async def nca(
        self,
        points: PointsLike,
        labels: ArrayLike,
        *,
        n_components: int | None = None,
        init: Literal["auto", "pca", "lda", "identity", "random"] = "auto",
        max_iterations: int = 50,
        tolerance: float = 1e-05,
        query: PointsLike | None = None,
        seed: int = 0,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Neighbourhood components analysis.

        The linear map maximising the expected number of points whose stochastic nearest neighbour
        (softmax over squared distances) has their class, by L-BFGS as scikit-learn. Reports the map,
        the embedding, leave-one-out 1-NN accuracy, query predictions and trustworthiness. Progress per
        iteration, cancellable.

        With :math:`z_i = A x_i`, each point picks a neighbour at random with probability

        .. math:: p_{ij} = \frac{e^{-\lVert z_i - z_j \rVert^2}}
                  {\sum_{l \ne i} e^{-\lVert z_i - z_l \rVert^2}}, \qquad p_{ii} = 0,

        and NCA maximises the expected number of points that pick one of their own class,
        :math:`f(A) = \sum_i \sum_{j \in C_i} p_{ij}`, with gradient

        .. math:: \frac{\partial f}{\partial A} = 2A \sum_i \Big(p_i \sum_k p_{ik}
                  x_{ik} x_{ik}^\mathsf{T} - \sum_{j \in C_i} p_{ij} x_{ij} x_{ij}^\mathsf{T}\Big),
                  \quad x_{ij} = x_i - x_j,

        by L-BFGS (scipy), as scikit-learn's ``NeighborhoodComponentsAnalysis`` does (same
        defaults, same initialisations, the same objective). Each gradient costs
        :math:`O(n^2 (d + k))` with dense ``n×n`` matrices.

        Parameters
        ----------
        points : (n, d) float array
            The training points, one row per point; at least 3 and at most 20,000 points (the
            method holds dense ``n×n`` matrices).
        labels : (n,) int or str array
            The class of each point (integers or strings); at least 2 classes.
        n_components : int, optional
            The output dimension ``k``, ``1 <= k <= d``; ``d`` when omitted.
        init : {"auto", "pca", "lda", "identity", "random"}, default "auto"
            The starting map: ``"pca"`` the ``k`` principal axes, ``"lda"`` the discriminant
            directions (needs ``k <= min(d, c - 1)`` for ``c`` classes; when the classes
            differ only along directions in which they are flat, PCA starts instead),
            ``"identity"`` the first ``k`` coordinates, ``"random"`` a standard normal
            ``k×d`` matrix drawn with ``seed``; ``"auto"`` is LDA when ``k <= min(d, c - 1)``,
            else PCA when ``k < d``, else the identity (scikit-learn's rule).
        max_iterations : int, default 50
            Most L-BFGS iterations (``converged`` is False when they run out).
        tolerance : float, default 1e-5
            L-BFGS stops when the relative decrease of the objective, or the largest gradient
            entry, falls below this (scipy's ``tol``, as scikit-learn passes it).
        query : (m, d) float array, optional
            Points to embed and classify (1-nearest neighbour in the embedding); none when
            omitted (the query outputs are then empty).
        seed : int or numpy Generator, default 0
            Draws the start of ``init="random"`` (unused otherwise); the same seed gives the
            same map.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``classification.nca``; its results hold ``embedding``, ``transform``, ``objective``, ``accuracy``, ``query_embedding``, ``query_predictions``, ``trustworthiness``, ``iterations``, ``converged``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] J. Goldberger, S. Roweis, G. Hinton, R. Salakhutdinov, "Neighbourhood
           components analysis", NIPS 2004.

        Examples
        --------
        >>> job = await client.classification.nca(  # doctest: +SKIP
        ...     [[0, 0], [1, 0], [0, 1], [1, 1.5], [5, 5], [6, 5], [5, 6], [6.5, 6]],
        ...     ['a', 'a', 'a', 'a', 'b', 'b', 'b', 'b'],
        ...     n_components=1,
        ...     query=[[0.5, 0.5], [5.5, 5.0]],
        ...     wait=30)
        >>> (await job.results())["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "labels": labels, "n_components": n_components, "init": init, "max_iterations": max_iterations, "tolerance": tolerance, "query": query, "seed": seed}
        return await self._client.execute(
            "classification.nca",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_CLASSIFICATION_NCA),
        )


class AsyncLayout(_AsyncFamily):
    """The layout processes, through a :class:`AsyncClient`: ``laplacian``, ``mds``, ``poisson``, ``stress``."""

    async def laplacian(
        self,
        mesh: MeshLike | None = None,
        *,
        graph: GraphLike | None = None,
        pins: HandlesLike | None = None,
        weighting: Literal["uniform", "cotangent", "tangent"] = "uniform",
        boundary_spacing: Literal["arc_length", "uniform"] = "arc_length",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Laplacian (spring) layout; Tutte embedding.

        Places every free vertex at the weighted average of its neighbours, some vertices pinned: L₀₀x =
        −L₀₁c, one factored solve for all coordinates. A mesh's boundary pinned to the unit circle by
        default (Tutte's embedding: with uniform or tangent weights no face flips). Reports the spring
        energy and flipped faces.

        Minimises the spring energy with the pinned positions :math:`c` fixed,

        .. math::

            \min_{p} \sum_{(i,j) \in E} w_{ij} \lVert p_i - p_j \rVert^2
            \quad\text{s.t.}\quad p_P = c
            \qquad\Longleftrightarrow\qquad L_{00}\, x = -L_{01}\, c,

        one solve of the free block of :math:`L = D - W` per coordinate (one factorization):
        every free vertex lands at the weighted average of its neighbours.

        Without ``pins``, a mesh's longest boundary loop is pinned to the unit circle in its
        order (counter-clockwise for counter-clockwise faces), its vertices spaced by the
        lengths of the boundary edges (``boundary_spacing="arc_length"``, as
        ``igl.map_vertices_to_circle``) or evenly (``"uniform"``); this is Tutte's embedding,
        a parameterization of a disk-like surface. By Tutte's spring theorem (Floater's
        generalisation to positive weights), non-negative weights and a boundary on a convex
        polygon give a layout in which no face flips.

        Parameters
        ----------
        mesh : Mesh or mapping, optional
            A triangle mesh, ``{"vertices": (n, 2|3), "faces": (m, 3)}``, whose edges are the
            springs; without ``pins`` its longest boundary loop is pinned to the unit circle
            (Tutte's embedding). Exactly one of ``mesh`` and ``graph``.
        graph : Graph or mapping, optional
            Instead of ``mesh``: a graph ``{"nodes": n, "edges": (e, 2), "weights": (e,)?}``;
            its weights (default 1, non-negative) are the spring stiffnesses. A repeated edge
            counts once (its first weight). Needs ``pins``.
        pins : Handles or mapping, optional
            ``{"indices": (p,), "positions": (p, k)}``: the pinned vertices (nodes) and their
            positions, in any dimension ``k >= 2``, the dimension of the layout; at least one
            in every connected component. Default for a mesh: its boundary on the unit circle
            (then ``k = 2``).
        weighting : {"uniform", "cotangent", "tangent"}, default "uniform"
            Mesh edge weights: ``"uniform"`` 1 (Tutte's barycentric map), ``"cotangent"``
            :math:`(\cot\alpha + \cot\beta)/2` (the harmonic map; negative across edges
            opposite obtuse angles, so faces may flip) or ``"tangent"`` :math:`\sum
            \tan(\theta/2) / \lVert p_i - p_j \rVert` (Floater's mean value weights, never
            negative: no flips). A graph takes only ``"uniform"`` (its own weights).
        boundary_spacing : {"arc_length", "uniform"}, default "arc_length"
            Where the default boundary's vertices go on the circle: ``"arc_length"`` spaced by
            the lengths of the boundary edges, ``"uniform"`` evenly. Unused with ``pins``.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``layout.laplacian``; its results hold ``positions``, ``pinned``, ``energy``, ``flipped_faces``, ``degenerate_faces``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] W. T. Tutte, "How to draw a graph", Proc. London Math. Soc. 13 (1963).
        .. [2] M. S. Floater, "Parametrization and smooth approximation of surface
           triangulations", CAGD 14 (1997); "Mean value coordinates", CAGD 20 (2003).

        Examples
        --------
        >>> job = await client.layout.laplacian(  # doctest: +SKIP
        ...     mesh={'vertices': [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]], 'faces': [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]},
        ...     wait=30)
        >>> (await job.results())["positions"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "graph": graph, "pins": pins, "weighting": weighting, "boundary_spacing": boundary_spacing}
        return await self._client.execute(
            "layout.laplacian",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_LAYOUT_LAPLACIAN),
        )

    async def mds(
        self,
        distances: ArrayLike | None = None,
        *,
        distance_pairs: ArrayLike | None = None,
        n_points: int | None = None,
        graph: GraphLike | None = None,
        n_components: int = 2,
        rank: int | None = None,
        max_iterations: int = 500,
        tolerance: float = 1e-07,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Classical multidimensional scaling (with completion of missing distances).

        Coordinates from the top eigenvectors of the double-centred squared distances −½JD⁽²⁾J. Missing
        distances are completed first: rank-(k+2) truncation of the squared distances (Drineas et al.'s
        one-shot estimate), refined by alternating projections. Reports the stress over the known pairs.

        With the squared distances :math:`D^{(2)} = D \odot D` and the centring matrix
        :math:`J = I - \tfrac1n \mathbf 1 \mathbf 1^\mathsf{T}`, points :math:`X` with those
        distances satisfy :math:`X X^\mathsf{T} = -\tfrac12 J D^{(2)} J`. Its ``k`` largest
        eigenpairs :math:`(\lambda_c, e_c)` give :math:`X = [\sqrt{\lambda_1} e_1, \dots,
        \sqrt{\lambda_k} e_k]`, the best rank-``k`` fit of the centred Gram matrix.

        **Completion** (Drineas, Javed, Magdon-Ismail, Pandurangan, Virrankoski and Savvides
        2006). Squared Euclidean distances of points in :math:`\mathbb R^k` form a matrix of
        rank at most :math:`k + 2`. Missing entries are set to zero and the known
        off-diagonal ones divided by the fraction ``p`` of known pairs (an unbiased estimate
        of the full matrix), and the result is truncated to rank ``r = rank`` (default
        ``k + 2``): that is the paper's one-shot estimate. It is then refined by alternating
        projections: the missing entries are replaced by the current estimate, the known ones
        (and the zero diagonal) restored, and the matrix truncated to rank ``r`` again, until
        the missing entries change by less than ``tolerance`` (relative) or
        ``max_iterations`` is reached; ``max_iterations=0`` keeps the one-shot estimate.
        Completed squared distances are clipped at zero.

        The truncation keeps the eigenpairs a squared-distance matrix has: its largest
        (positive) eigenvalue and its ``r - 1`` most negative ones (Schoenberg: a Euclidean
        squared-distance matrix is negative semidefinite on the vectors summing to zero, so it
        has exactly one positive eigenvalue).

        Parameters
        ----------
        distances : (n, n) array_like, optional
            Pairwise distances, non-negative, the diagonal zero; NaN (``null`` in JSON) marks
            a missing entry. Symmetric where ``d_ij`` and ``d_ji`` are both known (to a
            relative 1e-5, as scikit-learn's MDS checks; an asymmetric matrix is refused);
            where one is known it stands for both. Exactly one of ``distances``,
            ``distance_pairs`` and ``graph``.
        distance_pairs : (m, 3) array_like, optional
            Instead of ``distances``: the known distances as rows ``(i, j, d)``, points ``i``
            and ``j`` (0-based) ``d`` apart; every other pair is missing. A pair listed twice
            (either order) must give one distance.
        n_points : int, optional
            With ``distance_pairs``: the number of points (default: the largest index + 1).
        graph : Graph or mapping, optional
            Instead of ``distances``: a connected graph whose shortest-path lengths are the
            distances (``graph.weights`` are edge lengths, default 1).
        n_components : int, default 2
            The dimension ``k`` of the layout, at most the number of points.
        rank : int, optional
            The rank of the completed squared-distance matrix, from ``n_components`` to the
            number of points; default ``n_components + 2``. Only used when entries are
            missing.
        max_iterations : int, default 500
            Refinement iterations of the completion after its one-shot estimate; 0 keeps the
            one-shot estimate of Drineas et al.
        tolerance : float, default 1e-7
            The completion stops when the missing squared distances change by less than this,
            relative to their size.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``layout.mds``; its results hold ``positions``, ``eigenvalues``, ``stress``, ``normalized_stress``, ``missing_pairs``, ``completion_iterations``, ``converged``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] W. S. Torgerson, "Multidimensional scaling: I. Theory and method",
           Psychometrika 17 (1952).
        .. [2] P. Drineas, A. Javed, M. Magdon-Ismail, G. Pandurangan, R. Virrankoski,
           A. Savvides, "Distance matrix reconstruction from incomplete distance information
           for sensor network localization", IEEE SECON (2006).

        Examples
        --------
        >>> job = await client.layout.mds(  # doctest: +SKIP
        ...     distances=[[0, 3, 4], [3, 0, 5], [4, 5, 0]],
        ...     wait=30)
        >>> (await job.results())["positions"]  # doctest: +SKIP
        """
        inputs = {"distances": distances, "distance_pairs": distance_pairs, "n_points": n_points, "graph": graph, "n_components": n_components, "rank": rank, "max_iterations": max_iterations, "tolerance": tolerance}
        return await self._client.execute(
            "layout.mds",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_LAYOUT_MDS),
        )

    async def poisson(
        self,
        mesh: MeshLike | None = None,
        *,
        graph: GraphLike | None = None,
        vectors: ArrayLike,
        anchors: HandlesLike | None = None,
        anchor_weights: ArrayLike | None = None,
        pins: HandlesLike | None = None,
        weighting: Literal["uniform", "cotangent", "tangent"] = "uniform",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Poisson layout (edge vectors to match, soft anchors).

        Positions whose edge differences best match given vectors, pulled towards anchors and held at
        pins: min Σ wᵢⱼ‖(pᵢ − pⱼ) − vᵢⱼ‖² + Σ uᵢ‖pᵢ − zᵢ‖², solved as (DᵀWD + U)x = DᵀWv + Uz with one
        sparse factorization.

        .. math::

            \min_x \sum_{(i,j)} w_{ij} \lVert (p_i - p_j) - v_{ij} \rVert^2
                + \sum_i u_i \lVert p_i - z_i \rVert^2
            \;=\; \min_x (Dx - v)^\mathsf{T} W (Dx - v) + (x - z)^\mathsf{T} U (x - z)

        with :math:`D` the ``e×n`` difference matrix (row ``(i, j)``: +1 at ``i``, −1 at
        ``j``), so that

        .. math:: (D^\mathsf{T} W D + U)\, x = D^\mathsf{T} W v + U z ,

        solved once for all ``k`` coordinates (one sparse Cholesky factorization). With
        ``pins`` the pinned rows are fixed and the system is split as in
        :func:`~algorithms.layout.laplacian`.

        Parameters
        ----------
        mesh : Mesh or mapping, optional
            A triangle mesh ``{"vertices": (n, 2|3), "faces": (m, 3)}``; its edges, in the
            order of ``vectors``, are its unique edges ``(i, j)``, ``i < j``, sorted
            lexicographically. Exactly one of ``mesh`` and ``graph``.
        graph : Graph or mapping, optional
            Instead of ``mesh``: a graph ``{"nodes": n, "edges": (e, 2), "weights": (e,)?}``;
            edges in their given order and orientation, weights ``w`` (default 1,
            non-negative).
        vectors : (e, k) array_like
            The target of :math:`p_i - p_j` for each edge row ``(i, j)``, in the order of the
            edges; ``k >= 2`` is the dimension of the layout.
        anchors : Handles or mapping, optional
            ``{"indices": (a,), "positions": (a, k)}``: soft targets :math:`z_i`, the term
            :math:`\sum_i u_i \lVert p_i - z_i \rVert^2`. A connected component with neither
            anchors nor pins is centred at the origin.
        anchor_weights : (a,) array_like, optional
            The weight :math:`u_i \ge 0` of each anchor, in the order of ``anchors.indices``;
            all 1 when omitted. Only together with ``anchors``.
        pins : Handles or mapping, optional
            ``{"indices": (p,), "positions": (p, k)}``: vertices (nodes) held at these
            positions exactly.
        weighting : {"uniform", "cotangent", "tangent"}, default "uniform"
            Mesh edge weights ``w``: ``"uniform"`` 1, ``"cotangent"``
            :math:`(\cot\alpha + \cot\beta)/2` (negative across edges opposite obtuse
            angles) or ``"tangent"`` (Floater's mean value weights, never negative). A graph
            takes only ``"uniform"`` (its own weights).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``layout.poisson``; its results hold ``positions``, ``energy``, ``edge_rmse``, ``anchor_rmse``, ``free_components``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] P. Pérez, M. Gangnet, A. Blake, "Poisson image editing", ACM TOG 22(3) (2003).

        Examples
        --------
        >>> job = await client.layout.poisson(  # doctest: +SKIP
        ...     graph={'nodes': 3, 'edges': [[0, 1], [1, 2]]},
        ...     vectors=[[-1.0, 0.0], [-1.0, 0.0]],
        ...     anchors={'indices': [0], 'positions': [[0.0, 0.0]]},
        ...     wait=30)
        >>> (await job.results())["positions"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "graph": graph, "vectors": vectors, "anchors": anchors, "anchor_weights": anchor_weights, "pins": pins, "weighting": weighting}
        return await self._client.execute(
            "layout.poisson",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_LAYOUT_POISSON),
        )

    async def stress(
        self,
        distances: ArrayLike | None = None,
        *,
        distance_pairs: ArrayLike | None = None,
        n_points: int | None = None,
        graph: GraphLike | None = None,
        n_components: int = 2,
        weighting: Literal["inverse_square", "inverse", "uniform"] = "inverse_square",
        init: Literal["classical", "random"] = "classical",
        initial_positions: PointsLike | None = None,
        max_iterations: int = 300,
        tolerance: float = 1e-06,
        relaxation: float = 1.0,
        seed: int = 0,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Stress majorization (SMACOF).

        The layout minimising the weighted stress Σ wᵢⱼ(‖xᵢ − xⱼ‖ − dᵢⱼ)² over the known pairs by
        Guttman transforms (never increasing), from classical MDS; distances from a matrix, a list of
        pairs, or a graph's shortest paths. Progress per iteration, cancellable; reports the stress
        history.

        Minimises the weighted stress over the known pairs

        .. math::

            \sigma(X) = \sum_{i<j} w_{ij} \left(\lVert x_i - x_j \rVert - d_{ij}\right)^2,
            \qquad w_{ij} = d_{ij}^{-2}\ (\text{default}),\ d_{ij}^{-1}\ \text{or}\ 1,

        by iterating the Guttman transform :math:`X \leftarrow V^{+} B(X) X` (optionally
        relaxed, ``relaxation``), with
        :math:`V = \sum_{i<j} w_{ij} (e_i - e_j)(e_i - e_j)^\mathsf{T}` (the weighted
        Laplacian) and :math:`B(X)_{ij} = -w_{ij} d_{ij} / \lVert x_i - x_j \rVert` off the
        diagonal (0 where :math:`x_i = x_j`), rows summing to zero. Each step minimises a
        quadratic majorizer of :math:`\sigma` touching it at the current layout, so the stress
        never increases. :math:`V^{+}` is computed once (a Cholesky factorization of
        :math:`V + \tfrac1n \mathbf 1 \mathbf 1^\mathsf{T}`); with uniform weights and every
        distance known :math:`V^{+} B X = B X / n`. The iteration stops when one step lowers
        the stress by less than ``tolerance`` times :math:`\eta^2(X) = \sum_{i<j} w_{ij}
        \lVert x_i - x_j \rVert^2` (scikit-learn's rule: with uniform weights the same
        start gives the same iterates and the same stopping point).

        Missing distances (NaN entries, pairs not listed) get weight 0: the stress counts only
        known pairs. A ``graph`` gives the distances of Gansner, Koren and North: shortest-path
        lengths.

        Parameters
        ----------
        distances : (n, n) array_like, optional
            Pairwise distances, non-negative, the diagonal zero; NaN (``null`` in JSON) marks
            an unknown distance, which gets weight 0. Symmetric where ``d_ij`` and ``d_ji``
            are both known (to a relative 1e-5, as scikit-learn's MDS checks; an asymmetric
            matrix is refused); where one is known it stands for both. Exactly one of
            ``distances``, ``distance_pairs`` and ``graph``.
        distance_pairs : (m, 3) array_like, optional
            Instead of ``distances``: the known distances as rows ``(i, j, d)``, points ``i``
            and ``j`` (0-based) ``d`` apart; every other pair is unknown. A pair listed twice
            (either order) must give one distance.
        n_points : int, optional
            With ``distance_pairs``: the number of points (default: the largest index + 1).
        graph : Graph or mapping, optional
            Instead of ``distances``: a connected graph ``{"nodes", "edges", "weights"?}``;
            the distances are its shortest-path lengths, ``weights`` being edge lengths
            (default 1).
        n_components : int, default 2
            The dimension ``k`` of the layout, at most the number of points.
        weighting : {"inverse_square", "inverse", "uniform"}, default "inverse_square"
            :math:`w_{ij} = d_{ij}^{-2}` (Gansner, Koren and North: relative errors count
            equally, local structure first), :math:`d_{ij}^{-1}`, or 1 (scikit-learn's metric
            MDS: absolute errors, large distances first). The inverse weightings need positive
            distances between distinct points.
        init : {"classical", "random"}, default "classical"
            The starting layout: classical MDS (:func:`~algorithms.layout.mds`, completing a
            partial matrix first), or standard normal coordinates drawn with ``seed``.
        initial_positions : (n, k) array_like, optional
            A starting layout, one row per point, ``k = n_components`` columns; overrides
            ``init``.
        max_iterations : int, default 300
            Most Guttman transforms; 0 evaluates the starting layout.
        tolerance : float, default 1e-6
            Stop when one iteration lowers the stress by less than ``tolerance`` times
            :math:`\eta^2(X) = \sum_{i<j} w_{ij} \lVert x_i - x_j \rVert^2` (scikit-learn's
            rule), or the stress is zero to rounding; 0 runs all ``max_iterations``.
        relaxation : float, default 1.0
            The step :math:`\alpha \in [1, 2)` of the relaxed update, the next layout
            :math:`X + \alpha (V^{+} B(X) X - X)` (de Leeuw and Heiser): 1 is plain SMACOF;
            larger steps keep the stress non-increasing and reach a given stress in fewer
            iterations (1.9 took 30-45 % fewer here).
        seed : int or numpy Generator, optional, default 0
            Seeds the random start of ``init="random"``: the same seed, the same layout.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``layout.stress``; its results hold ``positions``, ``stress``, ``normalized_stress``, ``stress_history``, ``iterations``, ``converged``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] E. R. Gansner, Y. Koren, S. North, "Graph drawing by stress majorization",
           Graph Drawing 2004, LNCS 3383.
        .. [2] J. de Leeuw, "Applications of convex analysis to multidimensional scaling",
           Recent Developments in Statistics (1977).
        .. [3] I. Borg, P. J. F. Groenen, *Modern Multidimensional Scaling*, 2nd ed.,
           Springer (2005), ch. 8.
        .. [4] J. de Leeuw, W. J. Heiser, "Multidimensional scaling with restrictions on the
           configuration", Multivariate Analysis V (1980) (the relaxed update).

        Examples
        --------
        >>> job = await client.layout.stress(  # doctest: +SKIP
        ...     distances=[[0, 1, 1.4142135623730951, 1], [1, 0, 1, None], [1.4142135623730951, 1, 0, 1], [1, None, 1, 0]],
        ...     wait=30)
        >>> (await job.results())["positions"]  # doctest: +SKIP
        """
        inputs = {"distances": distances, "distance_pairs": distance_pairs, "n_points": n_points, "graph": graph, "n_components": n_components, "weighting": weighting, "init": init, "initial_positions": initial_positions, "max_iterations": max_iterations, "tolerance": tolerance, "relaxation": relaxation, "seed": seed}
        return await self._client.execute(
            "layout.stress",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_LAYOUT_STRESS),
        )


class AsyncClustering(_AsyncFamily):
    """The clustering processes, through a :class:`AsyncClient`: ``markov``, ``spectral``."""

    async def markov(
        self,
        points: PointsLike | None = None,
        *,
        graph: GraphLike | None = None,
        neighbors: Literal["knn", "radius", "all"] = "knn",
        n_neighbors: int = 10,
        radius: float | None = None,
        weighting: Literal["uniform", "distance", "heat"] = "uniform",
        sigma: float | None = None,
        expansion: int = 2,
        inflation: float = 2.0,
        self_loops: float = 1.0,
        pruning_threshold: float = 0.0001,
        max_iterations: int = 100,
        tolerance: float = 1e-06,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Markov clustering (MCL).

        Alternates expansion (a matrix power: random-walk steps) and inflation (elementwise power,
        columns renormalised) of the column-stochastic matrix of a graph or of the points' neighbour
        graph, pruning small entries, until it stops changing; the attractors name the clusters. The
        number of clusters follows from the inflation. Progress per iteration, cancellable.

        From the weighted adjacency :math:`A` with self-loops added, the column-stochastic
        matrix :math:`M = A D^{-1}` (a random walk's transition probabilities) is iterated:

        * expansion :math:`M \leftarrow M^e` (``e`` steps of the walk at once);
        * inflation :math:`m_{ij} \leftarrow m_{ij}^r / \sum_i m_{ij}^r` (strong transitions
          get stronger, weak ones fade);
        * pruning: entries below ``pruning_threshold`` are dropped (and each column
          renormalised), which keeps :math:`M` sparse;

        until :math:`\max_{ij} |M_t - M_{t-1}| <` ``tolerance``. The limit is idempotent: the
        rows with mass on the diagonal are the *attractors*, and every column puts its mass on
        the attractors of its cluster. Each point joins the attractor holding most of its
        column (lowest index on ties); attractors that share mass form one cluster.

        Parameters
        ----------
        points : (n, d) float array, optional
            Points whose neighbour graph is clustered, ``n >= 2``. Exactly one of ``points``
            and ``graph``.
        graph : Graph or mapping, optional
            Instead of ``points``: a graph ``{"nodes": n, "edges": (e, 2), "weights"?: (e,)}``
            with non-negative weights (default 1), clustered as it is.
        neighbors : {"knn", "radius", "all"}, default "knn"
            The neighbour graph of ``points``: ``"knn"`` joins each point to its
            ``n_neighbors`` nearest (the union of the two directions), ``"radius"`` to every
            point within ``radius``, ``"all"`` to every point (at most 10,000 points).
        n_neighbors : int, default 10
            Neighbours per point with ``neighbors="knn"``, other points only (MCL adds its own
            self-loops; its reference implementations take a graph, not points, so there is
            no peer count to follow, unlike :func:`spectral`'s); at most the number of points
            minus one.
        radius : float, optional
            The radius with ``neighbors="radius"``, required there.
        weighting : {"uniform", "distance", "heat"}, default "uniform"
            Edge weights of the neighbour graph from the edge lengths :math:`d`: ``"uniform"``
            1, ``"distance"`` :math:`1/d`, or ``"heat"`` the heat kernel
            :math:`\exp(-d^2/2\sigma^2)`, which suits MCL best where distances vary.
        sigma : float, optional
            The heat kernel's width :math:`\sigma`; the mean edge length when omitted.
        expansion : int, default 2
            The power ``e >= 2`` of the expansion, the walk's steps per round.
        inflation : float, default 2.0
            The elementwise power ``r > 1`` of the inflation; larger gives more, smaller
            clusters.
        self_loops : float, default 1.0
            Weight added on the diagonal of :math:`A` before normalising (van Dongen's
            recommendation; avoids parity oscillations). 0 adds none.
        pruning_threshold : float, default 1e-4
            Entries of :math:`M` below this are set to zero after each inflation (a column's
            largest entry is always kept), in ``[0, 1)``.
        max_iterations : int, default 100
            Most expansion-inflation rounds.
        tolerance : float, default 1e-6
            Stop when no entry of :math:`M` changes by ``tolerance`` or more in a round.
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``clustering.markov``; its results hold ``labels``, ``sizes``, ``n_clusters``, ``attractors``, ``iterations``, ``converged``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] S. van Dongen, "Graph clustering by flow simulation", PhD thesis, University of
           Utrecht, 2000.
        .. [2] A. J. Enright, S. van Dongen, C. A. Ouzounis, "An efficient algorithm for
           large-scale detection of protein families", Nucleic Acids Research 30(7), 2002.

        Examples
        --------
        >>> job = await client.clustering.markov(  # doctest: +SKIP
        ...     points=[[0, 0], [0, 1], [1, 0], [1, 1], [10, 10], [10, 11], [11, 10], [11, 11]],
        ...     n_neighbors=3,
        ...     wait=30)
        >>> (await job.results())["labels"]  # doctest: +SKIP
        """
        inputs = {"points": points, "graph": graph, "neighbors": neighbors, "n_neighbors": n_neighbors, "radius": radius, "weighting": weighting, "sigma": sigma, "expansion": expansion, "inflation": inflation, "self_loops": self_loops, "pruning_threshold": pruning_threshold, "max_iterations": max_iterations, "tolerance": tolerance, "labels": labels}
        return await self._client.execute(
            "clustering.markov",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_CLUSTERING_MARKOV),
        )

    async def spectral(
        self,
        points: PointsLike,
        *,
        n_clusters: int = 8,
        neighbors: Literal["knn", "radius", "all"] = "knn",
        n_neighbors: int = 10,
        radius: float | None = None,
        weighting: Literal["uniform", "distance", "heat"] = "uniform",
        sigma: float | None = None,
        n_init: int = 10,
        seed: int = 0,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Spectral clustering (Ng, Jordan, Weiss).

        k-means (k-means++ seeding, seeded) on the bottom eigenvectors of the symmetric normalised
        Laplacian of the points' neighbour graph, rows scaled to unit length. Reports labels, cluster
        sizes, the embedding and its eigenvalues.

        With :math:`W` the weights of the neighbour graph and :math:`D` its degrees, the
        embedding is made of the eigenvectors :math:`u_1, \dots, u_k` of the ``k = n_clusters``
        smallest eigenvalues of the symmetric normalised Laplacian

        .. math:: L_\mathrm{sym} = D^{-1/2} (D - W) D^{-1/2} = I - D^{-1/2} W D^{-1/2},

        its rows scaled to unit length (Ng, Jordan and Weiss); k-means with k-means++ seeding
        (``n_init`` starts, the best kept) then groups the rows.

        Parameters
        ----------
        points : (n, d) float array
            The points to cluster, ``n >= 2``.
        n_clusters : int, default 8
            The number of clusters ``k``, at most the number of points.
        neighbors : {"knn", "radius", "all"}, default "knn"
            The neighbour graph: ``"knn"`` joins each point to its ``n_neighbors`` nearest
            (the union of the two directions), ``"radius"`` to every point within ``radius``,
            ``"all"`` to every point (at most 10,000 points).
        n_neighbors : int, default 10
            Neighbours per point with ``neighbors="knn"``, the point itself counted among them
            as scikit-learn's ``SpectralClustering`` counts it (``n_neighbors - 1`` other
            points; ties by lower index); at most the number of points minus one.
        radius : float, optional
            The radius with ``neighbors="radius"``, required there.
        weighting : {"uniform", "distance", "heat"}, default "uniform"
            Edge weights from the edge lengths :math:`d`: ``"uniform"`` 1 (scikit-learn's
            ``affinity="nearest_neighbors"``), ``"distance"`` :math:`1/d`, or ``"heat"`` the
            heat kernel :math:`\exp(-d^2/2\sigma^2)`.
        sigma : float, optional
            The heat kernel's width :math:`\sigma`; the mean edge length when omitted.
        n_init : int, default 10
            k-means++ starts; the one with the least inertia is kept.
        seed : int or numpy Generator, default 0
            Seeds k-means++; the same seed gives the same labels.
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``clustering.spectral``; its results hold ``labels``, ``sizes``, ``embedding``, ``eigenvalues``, ``inertia``, ``graph_components``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] A. Y. Ng, M. I. Jordan, Y. Weiss, "On spectral clustering: analysis and an
           algorithm", NIPS 2001.
        .. [2] U. von Luxburg, "A tutorial on spectral clustering", Statistics and Computing
           17(4), 2007.
        .. [3] D. Arthur, S. Vassilvitskii, "k-means++: the advantages of careful seeding",
           SODA 2007.

        Examples
        --------
        >>> job = await client.clustering.spectral(  # doctest: +SKIP
        ...     [[0, 0], [0, 1], [1, 0], [1, 1], [10, 10], [10, 11], [11, 10], [11, 11]],
        ...     n_clusters=2,
        ...     n_neighbors=3,
        ...     wait=30)
        >>> (await job.results())["labels"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_clusters": n_clusters, "neighbors": neighbors, "n_neighbors": n_neighbors, "radius": radius, "weighting": weighting, "sigma": sigma, "n_init": n_init, "seed": seed, "labels": labels}
        return await self._client.execute(
            "clustering.spectral",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_CLUSTERING_SPECTRAL),
        )


class AsyncDeformation(_AsyncFamily):
    """The deformation processes, through a :class:`AsyncClient`: ``arap``, ``biharmonic``, ``deformation_transfer``, ``harmonic``, ``isotropic_scaling``, ``laplacian``, ``laplacian_editing``."""

    async def arap(
        self,
        mesh: MeshLike,
        handles: HandlesLike,
        *,
        energy: Literal["spokes_and_rims", "spokes"] = "spokes_and_rims",
        similarity: bool = False,
        max_iterations: int = 30,
        tolerance: float = 1e-05,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""As-rigid-as-possible deformation (local/global).

        Alternates per-vertex best rotations (batched, proper) and one prefactored cotangent-Laplacian
        solve; handles met exactly, energy never increasing; spokes or spokes-and-rims energy, optional
        per-vertex scale.

        Minimises over the new positions :math:`p'` and one rotation :math:`R_i` per vertex

        .. math::

            E(p', R) = \sum_i \sum_{(j,k) \in \mathcal{E}(i)} w_{jk}
            \lVert (p'_j - p'_k) - R_i (p_j - p_k) \rVert^2,

        with :math:`\mathcal{E}(i)` the spokes of vertex :math:`i` (edges :math:`(i, j)`,
        ``energy="spokes"``, Sorkine & Alexa's energy) or its spokes and rims (every edge of the
        faces around :math:`i`, each face's edge weighted by that face's :math:`\tfrac12\cot`,
        ``"spokes_and_rims"``), and :math:`w` the cotangent weights; handle vertices are held at
        their targets. Block coordinate descent alternates the local step (each :math:`R_i`
        maximises :math:`\operatorname{tr}(R_i S_i)` for the weighted covariance
        :math:`S_i = \sum w\, e\, e'^\mathsf{T}`: a rigid alignment, proper rotation enforced)
        and the global step (:math:`L p' = b(R)`, a Laplacian solve with the factor computed
        once). Each step minimises the energy over its block exactly, so the energy never
        increases.

        With ``similarity=True`` each vertex also gets a scale :math:`s_i \ge 0`
        (:math:`R_i \to s_i R_i`), fitted in the local step as
        :math:`s_i = \max(\operatorname{tr}(R_i S_i), 0) / \sum w \lVert e\rVert^2`.

        Parameters
        ----------
        mesh : Mesh or {"vertices", "faces"}
            The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
            0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
            are.
        handles : Handles or {"indices", "positions"}
            The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
            ``(p, d)`` positions; at least one handle in every connected component.
        energy : {"spokes_and_rims", "spokes"}, default "spokes_and_rims"
            The edges each vertex's rotation answers for: ``"spokes_and_rims"`` every edge of
            the faces around the vertex (Chao et al.; libigl's default,
            ``ARAP_ENERGY_TYPE_SPOKES_AND_RIMS``), ``"spokes"`` only the edges at the vertex
            (Sorkine & Alexa; ``ARAP_ENERGY_TYPE_SPOKES``).
        similarity : bool, default False
            Fit a non-negative scale per vertex too, besides its rotation
            (as-similar-as-possible).
        max_iterations : int, default 30
            Upper bound on local/global iterations (libigl's ``ARAPData.max_iter`` is 10, run
            to the end; ours stops earlier by ``tolerance``, so a larger bound costs nothing on
            easy edits and lets hard ones converge).
        tolerance : float, default 1e-5
            Stop when an iteration lowers the energy by at most this fraction; ``0`` runs all
            ``max_iterations`` (libigl's behaviour), unless the energy reaches zero.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``deformation.arap``; its results hold ``mesh``, ``energy``, ``handle_residual``, ``iterations``, ``converged``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] O. Sorkine and M. Alexa, "As-rigid-as-possible surface modeling", Symposium on
           Geometry Processing, 109-116, 2007.
        .. [2] I. Chao, U. Pinkall, P. Sanan and P. Schröder, "A simple geometric model for
           elastic deformations", ACM Transactions on Graphics 29(4), 38, 2010.
        """
        inputs = {"mesh": mesh, "handles": handles, "energy": energy, "similarity": similarity, "max_iterations": max_iterations, "tolerance": tolerance}
        return await self._client.execute(
            "deformation.arap",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_DEFORMATION_ARAP),
        )

    async def biharmonic(
        self,
        mesh: MeshLike,
        handles: HandlesLike,
        *,
        order: int = 2,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Biharmonic deformation.

        Spreads the handle displacements by the bi-Laplace equation L M⁻¹ L u = 0 (cotangent Laplacian,
        Voronoi mass), smooth at the handles; as igl.harmonic with k = 2 (or 3).

        The displacement :math:`u = p' - p` minimises the Laplacian energy
        :math:`\int (\Delta u)^2`, discretised with the cotangent Laplacian :math:`L` and the
        Voronoi mass matrix :math:`M`, with the handle displacements fixed:

        .. math::

            \min_u \sum_c u_c^\mathsf{T} L M^{-1} L\, u_c
            \quad\Longrightarrow\quad Q_{ff} u_f = -Q_{fp} u_p,\quad Q = L M^{-1} L,
            \qquad p' = p + u.

        Thin-plate-like: smooth (:math:`C^1`) at the handles, so handle regions (several
        vertices moved together) carry their rotation into the surroundings. ``order=3``
        (:math:`Q = L M^{-1} L M^{-1} L`, triharmonic) is smoother still.
        ``igl.harmonic(V, F, b, bc, k)`` with ``k = order`` and ``bc`` the handle
        displacements computes the same.

        Parameters
        ----------
        mesh : Mesh or {"vertices", "faces"}
            The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
            0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
            are.
        handles : Handles or {"indices", "positions"}
            The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
            ``(p, d)`` positions; at least one handle in every connected component (two rings
            of handles pin a boundary's position and slope).
        order : {2, 3}, default 2
            The power ``k`` of the Laplacian: 2 (biharmonic, :math:`Q = L M^{-1} L`) or 3
            (triharmonic, smoother still).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``deformation.biharmonic``; its results hold ``mesh``, ``energy``, ``handle_residual``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] M. Botsch and L. Kobbelt, "An intuitive framework for real-time freeform
           modeling", ACM TOG 23(3), 630-634, 2004.
        .. [2] A. Jacobson, E. Tosun, O. Sorkine and D. Zorin, "Mixed finite elements for
           variational surface modeling", Computer Graphics Forum 29(5), 2010.
        """
        inputs = {"mesh": mesh, "handles": handles, "order": order}
        return await self._client.execute(
            "deformation.biharmonic",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_DEFORMATION_BIHARMONIC),
        )

    async def deformation_transfer(
        self,
        mesh: MeshLike,
        handles: HandlesLike,
        *,
        source: PointsLike,
        source_deformed: PointsLike,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Deformation transfer (same connectivity).

        Gives the target mesh the per-face deformation gradients of a source mesh that deforms from
        source to source_deformed (same faces): min Σ‖T_c − Q_c‖²_F with shared vertices (and, in 3-D, a
        free fourth vertex per face); one factored solve.

        The three share connectivity: ``source`` and ``source_deformed`` are vertex arrays on
        ``mesh.faces`` (face ``c`` of the source corresponds to face ``c`` of the target). For
        each face, the source's deformation gradient is :math:`Q_c = \tilde V'_c
        \tilde V_c^{-1}` with :math:`\tilde V` the face's edge frame (:func:`frames`; in 3-D the
        third column is the scaled normal, Sumner & Popović's fourth vertex). The target's new
        vertices :math:`x` (plus, in 3-D, one free fourth vertex per face) minimise

        .. math::

            \min_{x} \sum_c \lVert T_c(x) - Q_c \rVert_F^2, \qquad
            T_c(x) = \tilde X_c\, \tilde W_c^{-1},

        :math:`\tilde W_c` the target's rest frame and :math:`\tilde X_c` the frame of the
        unknowns, with the handle vertices held at their targets. :math:`T_c` is linear in
        :math:`x`, the coordinates separate, and the normal equations
        :math:`A^\mathsf{T} A x = A^\mathsf{T} q` are factored once for all coordinates.

        Parameters
        ----------
        mesh : Mesh or {"vertices", "faces"}
            The target in its rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)``
            triangles of 0-based vertex indices, no zero-area ones. Vertices no face uses stay
            where they are.
        handles : Handles or {"indices", "positions"}
            Target vertices held at given positions: ``(p,)`` distinct vertex indices and their
            ``(p, d)`` positions; at least one in every connected component (the per-face
            gradients leave a translation free). To transfer without user constraints, pin one
            vertex per component where the source's motion puts it (e.g. its rest position plus
            the source's displacement there).
        source : (n, d) float array
            The source's rest vertices on the faces of ``mesh`` (the same connectivity: vertex
            ``i`` corresponds to target vertex ``i``); no zero-area faces.
        source_deformed : (n, d) float array
            The source's deformed vertices, on the faces of ``mesh`` too.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``deformation.deformation_transfer``; its results hold ``mesh``, ``energy``, ``handle_residual``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] R. W. Sumner and J. Popović, "Deformation transfer for triangle meshes", ACM
           Transactions on Graphics 23(3), 399-405, 2004.
        """
        inputs = {"mesh": mesh, "handles": handles, "source": source, "source_deformed": source_deformed}
        return await self._client.execute(
            "deformation.deformation_transfer",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_DEFORMATION_DEFORMATION_TRANSFER),
        )

    async def harmonic(
        self,
        mesh: MeshLike,
        handles: HandlesLike,
        *,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Harmonic deformation.

        Spreads the handle displacements by the Laplace equation (cotangent Laplacian): L_ff u_f = −L_fp
        u_p, x' = x + u; as igl.harmonic with k = 1.

        The displacement :math:`u = p' - p` minimises the Dirichlet energy
        :math:`\int \lVert \nabla u \rVert^2`, discretised with the cotangent Laplacian
        :math:`L`, with the handle displacements fixed:

        .. math::

            \min_u \sum_c u_c^\mathsf{T} L\, u_c
            \quad\Longrightarrow\quad L_{ff} u_f = -L_{fp} u_p,\qquad p' = p + u.

        Membrane-like: the deformation is as smooth as a soap film, with kinks (:math:`C^0`) at
        the handles. The same as :func:`~algorithms.deformation.laplacian` with cotangent
        weights (both solve :math:`L_{ff} p'_f = (L p)_f - L_{fp} c`), and as
        ``igl.harmonic(V, F, b, bc, 1)`` applied to the handle displacements ``bc``.

        Parameters
        ----------
        mesh : Mesh or {"vertices", "faces"}
            The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
            0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
            are.
        handles : Handles or {"indices", "positions"}
            The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
            ``(p, d)`` positions; at least one handle in every connected component.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``deformation.harmonic``; its results hold ``mesh``, ``energy``, ``handle_residual``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] M. Botsch and O. Sorkine, "On linear variational surface deformation methods",
           IEEE TVCG 14(1), 213-230, 2008.
        .. [2] A. Jacobson, I. Baran, J. Popović and O. Sorkine, "Bounded biharmonic weights
           for real-time deformation", ACM TOG 30(4), 78, 2011 (libigl's ``harmonic``).
        """
        inputs = {"mesh": mesh, "handles": handles}
        return await self._client.execute(
            "deformation.harmonic",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_DEFORMATION_HARMONIC),
        )

    async def isotropic_scaling(
        self,
        mesh: MeshLike,
        handles: HandlesLike,
        *,
        regularization: float = 1.0,
        max_iterations: int = 200,
        tolerance: float = 1e-06,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Isotropic scaling deformation (scale-and-stretch).

        Each face may only scale, edges keep their directions and adapt their lengths: block coordinate
        descent between closed-form per-face scales and one prefactored Laplacian solve, length ratios
        from the previous iterate (a correction of the paper, whose fixed ratios cannot be split off
        from the positions they depend on).

        With :math:`e_{ij} = p_i - p_j` the rest edges and :math:`e'_{ij}` the new ones, each
        face :math:`c` gets a scale :math:`s_c` and each edge a length ratio :math:`l_{ij}`:

        .. math::

            \min_{p', s} \sum_c \sum_{(i,j) \in c} \lVert e'_{ij} - s_c\, e_{ij} \rVert^2
            + \lambda \sum_c \sum_{(i,j) \in c} \lVert e'_{ij} - l_{ij}\, e_{ij} \rVert^2,
            \qquad l_{ij} = \frac{\lVert e'_{ij} \rVert}{\lVert e_{ij} \rVert},

        with the handles fixed. Block coordinate descent: with :math:`p'` fixed,
        :math:`s_c = \sum_{(i,j)\in c} e'^\mathsf{T}_{ij} e_{ij} / \sum_{(i,j)\in c}
        \lVert e_{ij}\rVert^2` (closed form, no SVD) and :math:`l_{ij}` from the current
        lengths; with :math:`s, l` fixed, :math:`p'` solves
        :math:`(1 + \lambda) L\, p' = b` with the graph Laplacian :math:`L` of the face edges
        (an edge shared by two faces counts twice), factored once.

        Parameters
        ----------
        mesh : Mesh or {"vertices", "faces"}
            The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
            0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
            are.
        handles : Handles or {"indices", "positions"}
            The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
            ``(p, d)`` positions; at least one handle in every connected component.
        regularization : float, default 1.0
            :math:`\lambda \ge 0`, the weight of the edge-length term. ``0`` leaves only the
            scales, with which faces overlap easily; larger values keep edge directions
            stiffer.
        max_iterations : int, default 200
            Upper bound on iterations (the fixed-point iteration converges linearly; each
            iteration is one solve with the factor computed once).
        tolerance : float, default 1e-6
            Stop when no vertex moved by more than this fraction of the bounding-box diagonal
            in an iteration.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``deformation.isotropic_scaling``; its results hold ``mesh``, ``scales``, ``energy``, ``handle_residual``, ``iterations``, ``converged``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] Y.-S. Wang, C.-L. Tai, O. Sorkine and T.-Y. Lee, "Optimized scale-and-stretch for
           image resizing", ACM Transactions on Graphics 27(5), 118, 2008.
        """
        inputs = {"mesh": mesh, "handles": handles, "regularization": regularization, "max_iterations": max_iterations, "tolerance": tolerance}
        return await self._client.execute(
            "deformation.isotropic_scaling",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_DEFORMATION_ISOTROPIC_SCALING),
        )

    async def laplacian(
        self,
        mesh: MeshLike,
        handles: HandlesLike,
        *,
        weights: Literal["cotangent", "uniform", "tangent"] = "cotangent",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Laplacian-preserving deformation.

        Moves the handles and every other vertex so that the weighted edge vectors change least: L_ff x'
        = (L x)_f − L_fp c, one factored solve for all coordinates.

        .. math::

            \min_{p'} \sum_{(i,j)} w_{ij} \lVert (p'_i - p'_j) - (p_i - p_j) \rVert^2
            \quad\text{s.t. } p'_h = c_h
            \quad\Longrightarrow\quad L_{ff}\, p'_f = (L p)_f - L_{fp}\, c,

        one sparse solve per coordinate (all coordinates as columns of one factored system):
        the Laplacian coordinates :math:`\delta = L p` are kept wherever no handle pins the
        vertex.

        Parameters
        ----------
        mesh : Mesh or {"vertices", "faces"}
            The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
            0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
            are.
        handles : Handles or {"indices", "positions"}
            The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
            ``(p, d)`` positions; at least one handle in every connected component.
        weights : {"cotangent", "uniform", "tangent"}, default "cotangent"
            The edge weights :math:`w_{ij}` of the Laplacian :math:`L = D - W`:
            ``"cotangent"`` (the Dirichlet energy; may be negative on obtuse triangles),
            ``"uniform"`` (the graph Laplacian, as in Sorkine et al.'s Laplacian coordinates)
            or ``"tangent"`` (incentre weights, never negative).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``deformation.laplacian``; its results hold ``mesh``, ``energy``, ``handle_residual``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] Y. Lipman, O. Sorkine, D. Cohen-Or, D. Levin, C. Rössl and H.-P. Seidel,
           "Differential coordinates for interactive mesh editing", Shape Modeling
           International, 181-190, 2004.
        .. [2] M. Botsch and O. Sorkine, "On linear variational surface deformation methods",
           IEEE TVCG 14(1), 213-230, 2008.
        """
        inputs = {"mesh": mesh, "handles": handles, "weights": weights}
        return await self._client.execute(
            "deformation.laplacian",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_DEFORMATION_LAPLACIAN),
        )

    async def laplacian_editing(
        self,
        mesh: MeshLike,
        handles: HandlesLike,
        *,
        weights: Literal["uniform", "cotangent"] = "uniform",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Laplacian surface editing (linearised per-vertex similarities).

        Laplacian coordinates that rotate and scale with the surface: min Σ‖T_i(x') δ_i − L(x')_i‖² with
        each T_i the linearised similarity fitted to the vertex's one-ring, handles fixed; one sparse
        least-squares solve.

        With the rest shape's Laplacian coordinates :math:`\delta_i = L(p)_i`, solve

        .. math::

            \min_{p'} \sum_i \lVert T_i(p')\, \delta_i - L(p')_i \rVert^2
            \quad\text{s.t. } p'_h = c_h,

        where :math:`T_i(p')` is the similarity transform — linearised, so that the problem
        stays linear — that best maps the closed one-ring :math:`\{i\} \cup N(i)` of the rest
        shape onto the new positions:
        :math:`T_i = \arg\min_T \sum_{j} \lVert T p_j - p'_j \rVert^2` with
        :math:`T p = s p + h \times p + t` in 3-D (:math:`(s, h, t)`, 7 parameters) and
        :math:`T p = \begin{psmallmatrix} s & -w \\ w & s \end{psmallmatrix} p + t` in 2-D.
        Each :math:`T_i` is a linear function of :math:`p'` (a least-squares fit), so the whole
        problem is one sparse linear least-squares system in the :math:`d n` coordinates,
        coupled across coordinates, solved through its normal equations with the handles
        eliminated (factored once).

        Parameters
        ----------
        mesh : Mesh or {"vertices", "faces"}
            The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
            0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
            are.
        handles : Handles or {"indices", "positions"}
            The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
            ``(p, d)`` positions. Every connected component needs handles whose rest positions
            span a plane in 3-D (three not on a line) or a line in 2-D (two distinct): fewer
            leave a global similarity transform about them undetermined.
        weights : {"uniform", "cotangent"}, default "uniform"
            The Laplacian: ``"uniform"`` gives :math:`\delta_i = p_i - \operatorname{mean}_j
            p_j` (the paper's), ``"cotangent"`` the cotangent-weighted average instead (both
            row-normalised).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``deformation.laplacian_editing``; its results hold ``mesh``, ``energy``, ``handle_residual``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] O. Sorkine, D. Cohen-Or, Y. Lipman, M. Alexa, C. Rössl and H.-P. Seidel,
           "Laplacian surface editing", Symposium on Geometry Processing, 175-184, 2004.
        """
        inputs = {"mesh": mesh, "handles": handles, "weights": weights}
        return await self._client.execute(
            "deformation.laplacian_editing",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_DEFORMATION_LAPLACIAN_EDITING),
        )


class AsyncEmbedding(_AsyncFamily):
    """The embedding processes, through a :class:`AsyncClient`: ``isomap``, ``laplacian_eigenmaps``, ``lle``, ``lpp``, ``mds``, ``pca``, ``random_projection``, ``sne``, ``som``, ``tsne``."""

    async def isomap(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        neighbors: Literal["knn", "radius", "all"] = "knn",
        n_neighbors: int = 5,
        radius: float | None = None,
        weighting: Literal["distance", "uniform"] = "distance",
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Isomap.

        Classical MDS of geodesic distances: shortest paths along the neighbourhood graph (Dijkstra),
        then the top eigenvectors of −½JG⁽²⁾J. A disconnected graph is an error that says into how many
        components it falls. Reports eigenvalues and trustworthiness.

        1. A neighbourhood graph on the points (``neighbors``), each edge as long as the
           distance between its ends (``weighting="distance"``) or 1 (``"uniform"``: hops);
        2. the geodesic distances :math:`G`: all-pairs shortest paths (Dijkstra);
        3. classical MDS of :math:`G` (the ``k`` largest eigenpairs of
           :math:`-\tfrac12 J G^{(2)} J`), the code shared with ``layout.mds``.

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 2 (and more than ``n_neighbors``) and at
            most 20,000 points (the method keeps the ``n×n`` geodesic distances: 3.2 GB).
        n_components : int, default 2
            The dimension ``k`` of the embedding, ``1 <= k <= n``. It may exceed the dimension
            ``D`` of the points (geodesic distances need not be Euclidean in ``D``), as in
            scikit-learn's ``Isomap``.
        neighbors : {"knn", "radius", "all"}, default "knn"
            The neighbourhood graph: ``"knn"`` joins each point to its ``n_neighbors``
            nearest (either way round), ``"radius"`` every pair at most ``radius`` apart,
            ``"all"`` every pair (then Isomap is plain classical MDS).
        n_neighbors : int, default 5
            Neighbours per point with ``neighbors="knn"`` (the point itself not counted, as
            scikit-learn's ``Isomap``), at most ``n - 1``. Equidistant candidates are taken by
            lower index (scikit-learn's choice among them varies with its search and thread
            count: see :func:`algorithms.core.graphs.nearest_sorted`).
        radius : float, optional
            The radius with ``neighbors="radius"``, required there.
        weighting : {"distance", "uniform"}, default "distance"
            Edge *lengths* for the shortest paths: ``"distance"`` the Euclidean distance
            between the ends, ``"uniform"`` 1 per edge (hop counts). (A heat kernel is a
            similarity, not a length: there is none here.)
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``embedding.isomap``; its results hold ``embedding``, ``eigenvalues``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] J. B. Tenenbaum, V. de Silva, J. C. Langford, "A global geometric framework for
           nonlinear dimensionality reduction", Science 290 (2000).

        Examples
        --------
        >>> job = await client.embedding.isomap(  # doctest: +SKIP
        ...     [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122], [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108], [70, 70, 122], [88, 60, 130]],
        ...     wait=30)
        >>> (await job.results())["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_components": n_components, "neighbors": neighbors, "n_neighbors": n_neighbors, "radius": radius, "weighting": weighting, "quality_neighbors": quality_neighbors, "labels": labels}
        return await self._client.execute(
            "embedding.isomap",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_ISOMAP),
        )

    async def laplacian_eigenmaps(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        neighbors: Literal["knn", "radius", "all"] = "knn",
        n_neighbors: int | None = None,
        radius: float | None = None,
        weighting: Literal["uniform", "distance", "heat"] = "uniform",
        sigma: float | None = None,
        laplacian: Literal["random_walk", "symmetric", "unnormalized"] = "random_walk",
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Laplacian eigenmaps (spectral embedding).

        The eigenvectors of the smallest non-trivial eigenvalues of the neighbourhood graph's Laplacian,
        Lv = λDv by default. A disconnected graph is an error that says into how many components it
        falls. Reports eigenvalues and trustworthiness.

        On a neighbourhood graph with weights :math:`W`, degrees :math:`D` and Laplacian
        :math:`L = D - W`, the embedding minimises :math:`\sum_{ij} w_{ij} \lVert y_i - y_j
        \rVert^2 = \operatorname{tr}(Y^\mathsf{T} L Y)` under a normalisation, which the
        trivial constant solution is excluded from:

        * ``"random_walk"`` (default; the paper, scikit-learn): :math:`L v = \lambda D v`
          with :math:`v^\mathsf{T} D v = 1`, i.e. the eigenvectors of :math:`D^{-1} L`;
        * ``"symmetric"``: :math:`D^{-1/2} L D^{-1/2} y = \lambda y`,
          :math:`\lVert y \rVert = 1` (:math:`y = D^{1/2} v`);
        * ``"unnormalized"``: :math:`L y = \lambda y`, :math:`\lVert y \rVert = 1`.

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 3 points.
        n_components : int, default 2
            The dimension ``k`` of the embedding, ``1 <= k <= n - 2``. It may exceed the
            dimension ``D`` of the points, as in scikit-learn's ``SpectralEmbedding``.
        neighbors : {"knn", "radius", "all"}, default "knn"
            The neighbourhood graph: ``"knn"`` joins each point to its ``n_neighbors``
            nearest (either way round), ``"radius"`` every pair at most ``radius`` apart,
            ``"all"`` every pair.
        n_neighbors : int, optional
            Neighbours per point with ``neighbors="knn"``, the point itself counted among them
            as in scikit-learn's ``SpectralEmbedding`` (``n_neighbors - 1`` other points; ties
            by lower index), at most ``n - 1``; ``max(n // 10, 2)`` when omitted
            (scikit-learn's ``max(n // 10, 1)``, except that below 20 points 1 would leave
            each point alone).
        radius : float, optional
            The radius with ``neighbors="radius"``, required there.
        weighting : {"uniform", "distance", "heat"}, default "uniform"
            Edge weights from the edge lengths :math:`d`: ``"uniform"`` 1, ``"distance"``
            :math:`1/d`, ``"heat"`` the heat kernel :math:`\exp(-d^2/2\sigma^2)`.
            Every edge of the symmetrised graph (``i`` among ``j``'s neighbours or ``j`` among
            ``i``'s) weighs the same: scikit-learn's ``SpectralEmbedding`` gives an edge found
            from one side only half the weight (``(A + Aᵀ)/2``), which moves the embedding
            slightly (a Procrustes disparity of 3.7e-3 on a 400-point swiss roll, k = 10;
            ``affinity="precomputed"`` on our graph agrees to 1e-28). Weight 1 keeps the graph
            the same whichever side found an edge, as spectral clustering here does.
        sigma : float, optional
            The heat kernel's width :math:`\sigma`; the mean edge length when omitted.
        laplacian : {"random_walk", "symmetric", "unnormalized"}, default "random_walk"
            The normalisation of :math:`L = D - W`: ``"random_walk"`` solves
            :math:`L v = \lambda D v` (the paper, scikit-learn); ``"symmetric"`` returns instead
            the unit eigenvectors :math:`y = \sqrt{D}\, v` of the symmetric normalised
            Laplacian; ``"unnormalized"`` solves :math:`L y = \lambda y`.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``embedding.laplacian_eigenmaps``; its results hold ``embedding``, ``eigenvalues``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] M. Belkin, P. Niyogi, "Laplacian eigenmaps for dimensionality reduction and
           data representation", Neural Computation 15 (2003).

        Examples
        --------
        >>> job = await client.embedding.laplacian_eigenmaps(  # doctest: +SKIP
        ...     [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122], [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108], [70, 70, 122], [88, 60, 130]],
        ...     n_neighbors=4,
        ...     wait=30)
        >>> (await job.results())["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_components": n_components, "neighbors": neighbors, "n_neighbors": n_neighbors, "radius": radius, "weighting": weighting, "sigma": sigma, "laplacian": laplacian, "quality_neighbors": quality_neighbors, "labels": labels}
        return await self._client.execute(
            "embedding.laplacian_eigenmaps",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_LAPLACIAN_EIGENMAPS),
        )

    async def lle(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        neighbors: Literal["knn", "radius"] = "knn",
        n_neighbors: int = 5,
        radius: float | None = None,
        regularization: float = 0.001,
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Locally linear embedding.

        Sum-to-one weights reconstructing each point from its neighbours (regularised), then the bottom
        non-trivial eigenvectors of (I − W)ᵀ(I − W). Reports eigenvalues, the reconstruction error in
        the embedding and of the weights, and trustworthiness.

        1. Neighbours of each point: its ``n_neighbors`` nearest (``"knn"``, each point's own
           list, not symmetrised) or all within ``radius``; no edge weights are chosen.
        2. Reconstruction weights :math:`W` (:func:`barycenter_weights`): each row minimises
           :math:`\lVert x_i - \sum_j W_{ij} x_j \rVert^2` subject to :math:`\sum_j W_{ij} = 1`.
        3. The embedding: the eigenvectors of the ``k`` smallest eigenvalues of
           :math:`M = (I - W)^\mathsf{T}(I - W)` after the trivial constant one, i.e. the unit
           :math:`Y` minimising :math:`\sum_i \lVert y_i - \sum_j W_{ij} y_j \rVert^2`.

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 3 points.
        n_components : int, default 2
            The dimension ``k`` of the embedding, ``1 <= k <= min(D, n - 2)`` (scikit-learn's
            bound ``k <= D`` too).
        neighbors : {"knn", "radius"}, default "knn"
            The points each point is reconstructed from: ``"knn"`` its own ``n_neighbors``
            nearest (not symmetrised), ``"radius"`` all within ``radius``.
        n_neighbors : int, default 5
            Neighbours per point with ``neighbors="knn"`` (the point itself not counted, as
            scikit-learn's ``n_neighbors``), at most ``n - 1``. Equidistant candidates are
            taken by lower index (scikit-learn's choice among them varies with its search
            and thread count: see :func:`algorithms.core.graphs.nearest_sorted`).
        radius : float, optional
            The radius with ``neighbors="radius"``, required there; every point needs at
            least one neighbour within it.
        regularization : float, default 1e-3
            ``r``: the local Gram matrix :math:`C` gets :math:`r \operatorname{tr}(C)` on its
            diagonal. Needed when ``n_neighbors > D`` (then :math:`C` is singular); 0 turns it
            off.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``embedding.lle``; its results hold ``embedding``, ``eigenvalues``, ``reconstruction_error``, ``weight_error``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] S. T. Roweis, L. K. Saul, "Nonlinear dimensionality reduction by locally linear
           embedding", Science 290 (2000).

        Examples
        --------
        >>> job = await client.embedding.lle(  # doctest: +SKIP
        ...     [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122], [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108], [70, 70, 122], [88, 60, 130]],
        ...     wait=30)
        >>> (await job.results())["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_components": n_components, "neighbors": neighbors, "n_neighbors": n_neighbors, "radius": radius, "regularization": regularization, "quality_neighbors": quality_neighbors, "labels": labels}
        return await self._client.execute(
            "embedding.lle",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_LLE),
        )

    async def lpp(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        neighbors: Literal["knn", "radius", "all"] = "knn",
        n_neighbors: int | None = None,
        radius: float | None = None,
        weighting: Literal["uniform", "distance", "heat"] = "uniform",
        sigma: float | None = None,
        laplacian: Literal["random_walk", "symmetric", "unnormalized"] = "random_walk",
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Locality preserving projections.

        The linear map closest to Laplacian eigenmaps: generalized eigenvectors of XᵀLXa = λXᵀDXa on the
        centred data. Reports the projection (applies to new points), eigenvalues and trustworthiness.

        Laplacian eigenmaps restricted to linear maps :math:`y = A^\mathsf{T}(x - \mu)`: with
        the centred data :math:`\tilde X` (rows are points), the graph's :math:`W`, :math:`D`,
        :math:`L = D - W`, the columns of :math:`A` are the generalized eigenvectors of the
        ``k`` smallest eigenvalues of

        * ``"random_walk"`` (default; the paper): :math:`\tilde X^\mathsf{T} L \tilde X a =
          \lambda \tilde X^\mathsf{T} D \tilde X a`, centred at the degree-weighted mean (so
          the constant map is excluded, as the trivial vector in Laplacian eigenmaps);
        * ``"symmetric"``: :math:`\tilde X^\mathsf{T} D^{-1/2} L D^{-1/2}
          \tilde X a = \lambda \tilde X^\mathsf{T} \tilde X a`, i.e. :math:`\min
          \operatorname{tr}(Y^\mathsf{T} D^{-1/2} L D^{-1/2} Y)` subject to
          :math:`Y^\mathsf{T} Y = I`, centred at the mean;
        * ``"unnormalized"``: :math:`\tilde X^\mathsf{T} L \tilde X a = \lambda
          \tilde X^\mathsf{T} \tilde X a`, centred at the mean.

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 3 points, spanning all ``D`` dimensions
            (else reduce them first, e.g. by PCA).
        n_components : int, default 2
            The dimension ``k`` of the embedding, ``1 <= k <= min(n, D)``.
        neighbors : {"knn", "radius", "all"}, default "knn"
            The neighbourhood graph: ``"knn"`` joins each point to its ``n_neighbors``
            nearest (either way round), ``"radius"`` every pair at most ``radius`` apart,
            ``"all"`` every pair.
        n_neighbors : int, optional
            Neighbours per point with ``neighbors="knn"``, the point itself counted among them
            (``n_neighbors - 1`` other points), the graph of :func:`laplacian_eigenmaps` and
            scikit-learn's ``SpectralEmbedding``; at most ``n - 1``; ``max(n // 10, 2)`` when
            omitted.
        radius : float, optional
            The radius with ``neighbors="radius"``, required there.
        weighting : {"uniform", "distance", "heat"}, default "uniform"
            Edge weights from the edge lengths :math:`d`: ``"uniform"`` 1, ``"distance"``
            :math:`1/d`, ``"heat"`` the heat kernel :math:`\exp(-d^2/2\sigma^2)`.
            Every edge of the symmetrised graph weighs the same, whichever side found it (not
            half for one side, as scikit-learn's ``SpectralEmbedding``; see
            :func:`~algorithms.embedding.laplacian_eigenmaps`).
        sigma : float, optional
            The heat kernel's width :math:`\sigma`; the mean edge length when omitted.
        laplacian : {"random_walk", "symmetric", "unnormalized"}, default "random_walk"
            The generalized eigenproblem for the directions :math:`a`, with :math:`X` the
            centred data and :math:`L = D - W`: ``"random_walk"`` :math:`X^\mathsf{T} L X a =
            \lambda X^\mathsf{T} D X a` (the paper; centred at the degree-weighted mean);
            ``"symmetric"`` the symmetric normalised Laplacian in place of :math:`L` and
            :math:`X^\mathsf{T} X` on the right; ``"unnormalized"`` :math:`X^\mathsf{T} L X a =
            \lambda X^\mathsf{T} X a`.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``embedding.lpp``; its results hold ``embedding``, ``components``, ``eigenvalues``, ``mean``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] X. He, P. Niyogi, "Locality preserving projections", NIPS 16 (2003).

        Examples
        --------
        >>> job = await client.embedding.lpp(  # doctest: +SKIP
        ...     [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122], [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108], [70, 70, 122], [88, 60, 130]],
        ...     n_neighbors=4,
        ...     wait=30)
        >>> (await job.results())["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_components": n_components, "neighbors": neighbors, "n_neighbors": n_neighbors, "radius": radius, "weighting": weighting, "sigma": sigma, "laplacian": laplacian, "quality_neighbors": quality_neighbors, "labels": labels}
        return await self._client.execute(
            "embedding.lpp",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_LPP),
        )

    async def mds(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        metric: bool = False,
        max_iterations: int = 300,
        tolerance: float = 1e-06,
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Multidimensional scaling (classical or metric).

        Classical MDS: the top eigenvectors of the double-centred squared distances −½JD⁽²⁾J (for
        Euclidean input the PCA scores); optionally refined by SMACOF stress majorization. Reports
        eigenvalues, raw and normalized stress, trustworthiness.

        **Classical** (default): with the squared distances :math:`D^{(2)}` and the centring
        :math:`J = I - \tfrac1n \mathbf 1 \mathbf 1^\mathsf{T}`, the Gram matrix
        :math:`B = -\tfrac12 J D^{(2)} J`; the embedding is
        :math:`[\sqrt{\lambda_1} e_1, \dots, \sqrt{\lambda_k} e_k]` from its ``k`` largest
        eigenpairs (:func:`algorithms.layout.mds.classical_coordinates`, shared with
        ``layout.mds``). **Metric** (``metric=True``): from the classical embedding, stress
        majorization minimises :math:`\sum_{i<j} (\lVert y_i - y_j \rVert - d_{ij})^2`
        (:func:`algorithms.layout.stress` with uniform weights, scikit-learn's ``MDS``).

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 2 and at most 4,000 points (the method
            keeps dense ``n×n`` matrices).
        n_components : int, default 2
            The dimension ``k`` of the embedding, ``1 <= k <= n``. It may exceed the dimension
            ``D`` of the points, as in scikit-learn's ``ClassicalMDS`` and ``MDS``: the classical
            coordinates beyond the rank of the centred points are then zero.
        metric : bool, default False
            False: classical MDS only (scikit-learn's ``ClassicalMDS``). True: refine the
            classical embedding by SMACOF, which minimises the raw stress (scikit-learn's
            ``MDS(metric=True)``). Not scikit-learn's flag of the same name: there ``False``
            selects non-metric (ordinal) SMACOF, which this function does not offer.
        max_iterations : int, default 300
            Most SMACOF iterations; used only with ``metric=True`` (0 keeps the classical
            embedding).
        tolerance : float, default 1e-6
            SMACOF stops when one iteration lowers the stress by less than this fraction of
            the embedding's squared distances' sum
            :math:`\eta^2(X) = \sum_{i<j} \lVert x_i - x_j \rVert^2` (scikit-learn's rule from
            1.7, as :func:`algorithms.layout.stress`); used only with ``metric=True``.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``embedding.mds``; its results hold ``embedding``, ``eigenvalues``, ``stress``, ``normalized_stress``, ``iterations``, ``converged``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] W. S. Torgerson, "Multidimensional scaling: I. Theory and method",
           Psychometrika 17 (1952).
        .. [2] J. de Leeuw, "Applications of convex analysis to multidimensional scaling",
           Recent Developments in Statistics (1977) (SMACOF).

        Examples
        --------
        >>> job = await client.embedding.mds(  # doctest: +SKIP
        ...     [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122], [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108], [70, 70, 122], [88, 60, 130]],
        ...     wait=30)
        >>> (await job.results())["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_components": n_components, "metric": metric, "max_iterations": max_iterations, "tolerance": tolerance, "quality_neighbors": quality_neighbors, "labels": labels}
        return await self._client.execute(
            "embedding.mds",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_MDS),
        )

    async def pca(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Principal component analysis.

        Projects the centred data on its k principal axes (thin SVD): the orthogonal projection keeping
        the most variance. Reports the axes, the variance along each (eigenvalues), their share, and
        trustworthiness; signs fixed (each axis's largest entry positive).

        With :math:`\tilde X = X - \bar x = U \Sigma V^\mathsf{T}` (thin SVD), the embedding is
        :math:`\tilde X V_k = U_k \Sigma_k`, the projection on the ``k`` right singular vectors
        of largest singular value: of all orthogonal projections to ``k`` dimensions it keeps
        the most variance (equivalently, the sum of squared projection distances is least).

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 2 points.
        n_components : int, default 2
            The dimension ``k`` of the embedding, ``1 <= k <= min(n, D)``.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``embedding.pca``; its results hold ``embedding``, ``components``, ``eigenvalues``, ``explained_variance_ratio``, ``singular_values``, ``mean``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] K. Pearson, "On lines and planes of closest fit to systems of points in space",
           Philosophical Magazine 2 (1901).

        Examples
        --------
        >>> job = await client.embedding.pca(  # doctest: +SKIP
        ...     [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122], [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108], [70, 70, 122], [88, 60, 130]],
        ...     wait=30)
        >>> (await job.results())["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_components": n_components, "quality_neighbors": quality_neighbors, "labels": labels}
        return await self._client.execute(
            "embedding.pca",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_PCA),
        )

    async def random_projection(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        kind: Literal["gaussian", "sparse"] = "gaussian",
        density: float | None = None,
        seed: int = 0,
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Random projection (Johnson–Lindenstrauss).

        Maps the points by a random k×D matrix, Gaussian or sparse, that keeps squared distances in
        expectation. Reports the matrix, the largest relative distortion of squared distances and
        trustworthiness.

        * ``"gaussian"``: :math:`R_{cj} \sim \mathcal N(0, 1/k)`;
        * ``"sparse"``: :math:`R_{cj} = \pm\sqrt{s/k}` with probability :math:`1/(2s)` each and
          0 otherwise, :math:`s = 1/\text{density}` (default density :math:`1/\sqrt D`).

        Either way :math:`\mathbb E\,\lVert R x \rVert^2 = \lVert x \rVert^2`, and with
        :math:`k = O(\varepsilon^{-2}\log n)` every pairwise distance is kept within a factor
        :math:`1 \pm \varepsilon` with high probability.

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point.
        n_components : int, default 2
            The dimension ``k`` of the embedding, ``1 <= k <= min(n, D)`` (a projection adds
            no dimensions).
        kind : {"gaussian", "sparse"}, default "gaussian"
            The matrix entries: ``"gaussian"`` independent :math:`\mathcal{N}(0, 1/k)`;
            ``"sparse"`` :math:`\pm\sqrt{(s/k)}` with probability :math:`1/(2s)` each and 0
            otherwise, :math:`s = 1/\text{density}` (Achlioptas; Li, Hastie and Church).
        density : float, optional
            The fraction of non-zero entries with ``kind="sparse"`` (only there), in
            ``(0, 1]``; :math:`1/\sqrt{D}` when omitted.
        seed : int or numpy Generator, default 0
            Draws the matrix; the same seed gives the same matrix.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``embedding.random_projection``; its results hold ``embedding``, ``components``, ``distortion``, ``trustworthiness``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] W. B. Johnson, J. Lindenstrauss, "Extensions of Lipschitz mappings into a
           Hilbert space", Contemporary Mathematics 26 (1984).
        .. [2] D. Achlioptas, "Database-friendly random projections", PODS (2001).
        .. [3] P. Li, T. J. Hastie, K. W. Church, "Very sparse random projections", KDD (2006).

        Examples
        --------
        >>> job = await client.embedding.random_projection(  # doctest: +SKIP
        ...     [[112, 60, 70], [130, 70, 78], [140, 88, 92], [140, 112, 108], [130, 130, 122], [112, 140, 130], [88, 140, 70], [70, 130, 78], [60, 112, 92], [60, 88, 108], [70, 70, 122], [88, 60, 130]],
        ...     wait=30)
        >>> (await job.results())["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "n_components": n_components, "kind": kind, "density": density, "seed": seed, "quality_neighbors": quality_neighbors, "labels": labels}
        return await self._client.execute(
            "embedding.random_projection",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_RANDOM_PROJECTION),
        )

    async def sne(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        perplexity: float = 30.0,
        init: Literal["pca", "random"] = "pca",
        learning_rate: float | Literal["auto"] = "auto",
        max_iterations: int = 750,
        early_exaggeration: float = 4.0,
        exaggeration_iterations: int = 250,
        min_grad_norm: float = 1e-07,
        seed: int = 0,
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Symmetric SNE (stochastic neighbour embedding).

        t-SNE's input affinities with a Gaussian kernel in the embedding too (the light tails crowd
        clusters together: t-SNE's motivation); exact all-pairs gradient, at most 5,000 points. Reports
        KL, trustworthiness and iterations. Progress every iteration, cancellable.

        The input affinities are t-SNE's (perplexity-calibrated Gaussians over all pairs,
        symmetrised, :math:`p_{ij} = (p_{j|i} + p_{i|j}) / 2n`); the embedding's are Gaussian
        too,

        .. math:: q_{ij} = \frac{e^{-\lVert y_i - y_j\rVert^2}}
                                {\sum_{k \ne l} e^{-\lVert y_k - y_l\rVert^2}}, \qquad
                  \frac{\partial\, \mathrm{KL}(P\|Q)}{\partial y_i}
                  = 4 \sum_j (p_{ij} - q_{ij})(y_i - y_j),

        minimised by the same descent as :func:`~algorithms.embedding.tsne.tsne` (momentum,
        gains, early exaggeration).

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 2 and at most 5,000 points.
        n_components : int, default 2
            The embedding's dimension ``k``.
        perplexity : float, default 30
            The effective number of neighbours of each point's Gaussian (its entropy is
            :math:`\log(\text{perplexity})`, found by binary search), ``0 < perplexity < n``.
        init : {"pca", "random"}, default "pca"
            The start: ``"pca"`` the PCA scores scaled to a first-column standard deviation
            of 1e-4, ``"random"`` Gaussian draws of that size from ``seed``.
        learning_rate : float or "auto", default "auto"
            The step, ``> 0``. ``"auto"``: :math:`\max(n / 4\alpha, 50)`, :math:`\alpha` the
            exaggeration in force (as t-SNE).
        max_iterations : int, default 750
            Gradient steps in all, the exaggeration phase included.
        early_exaggeration : float, default 4
            The factor :math:`\alpha \ge 1` on :math:`P` for the first
            ``exaggeration_iterations`` steps (4, the value of the t-SNE paper; the Gaussian
            kernel cannot hold clusters apart under t-SNE's 12).
        exaggeration_iterations : int, default 250
            The number of steps with :math:`P` multiplied by ``early_exaggeration``;
            counted in ``max_iterations``.
        min_grad_norm : float, default 1e-7
            After the exaggeration phase, stop once the gradient's norm falls below this.
        seed : int or numpy Generator, default 0
            Draws the random start (and the extra columns of a PCA start when ``k`` exceeds
            the data's dimension); the same seed gives the same embedding.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``embedding.sne``; its results hold ``embedding``, ``kl_divergence``, ``trustworthiness``, ``iterations``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] G. Hinton, S. Roweis, "Stochastic neighbor embedding", NIPS 15 (2002).
        .. [2] L. van der Maaten, G. Hinton, "Visualizing data using t-SNE", JMLR 9 (2008).
        """
        inputs = {"points": points, "n_components": n_components, "perplexity": perplexity, "init": init, "learning_rate": learning_rate, "max_iterations": max_iterations, "early_exaggeration": early_exaggeration, "exaggeration_iterations": exaggeration_iterations, "min_grad_norm": min_grad_norm, "seed": seed, "quality_neighbors": quality_neighbors, "labels": labels}
        return await self._client.execute(
            "embedding.sne",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_SNE),
        )

    async def som(
        self,
        points: PointsLike,
        *,
        rows: int = 10,
        columns: int = 10,
        method: Literal["online", "batch"] = "online",
        max_iterations: int | None = None,
        learning_rate: float = 0.5,
        sigma: float | None = None,
        init: Literal["pca", "random"] = "pca",
        seed: int = 0,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Self-organising map.

        A rows × columns grid of nodes pulled onto the data (Kohonen's online rule or the batch map);
        each point is embedded at its best-matching node's grid position. Reports the codebook,
        quantization and topographic errors and trustworthiness. Progress per 1 % of the steps,
        cancellable.

        Each node :math:`j` has a grid position :math:`g_j` and a data-space position
        :math:`w_j`. Online training (Kohonen) presents one point :math:`x` at step :math:`t`,
        finds its best-matching node :math:`b = \arg\min_j \lVert x - w_j \rVert` and pulls
        every node towards it, grid neighbours of :math:`b` the most:

        .. math:: w_j \leftarrow w_j + \eta(t)\, h_{bj}(t)\, (x - w_j), \qquad
                  h_{bj}(t) = e^{-\lVert g_b - g_j \rVert^2 / 2\sigma(t)^2},

        with :math:`\eta(t) = \eta_0 / (1 + 2t/T)` and :math:`\sigma(t) = \sigma_0 / (1 +
        2t/T)` (MiniSom's default decay). Batch training replaces each epoch of such steps by
        their fixed point, :math:`w_j = \sum_i h_{b_i j} x_i / \sum_i h_{b_i j}`, with
        :math:`\sigma` decaying from :math:`\sigma_0` to 1 over the epochs.

        Parameters
        ----------
        points : (n, d) float array
            The points to map, one row per point; at least 2 points.
        rows, columns : int, default 10
            The number of grid rows and columns; at least 1 each and 2 nodes in all.
        method : {"online", "batch"}, default "online"
            ``"online"``: Kohonen's rule, one randomly drawn point per step (a stochastic
            gradient step); ``"batch"``: each epoch moves every node to the fixed point of
            an epoch of such steps, the neighbourhood-weighted mean of the points.
        max_iterations : int, optional
            Training steps: samples presented with ``"online"`` (``max(1000, 10 n)`` up to
            100,000 when omitted) or epochs with ``"batch"`` (30 when omitted).
        learning_rate : float, default 0.5
            :math:`\eta_0`, the starting step of online training, in ``(0, 1]`` (unused by
            ``"batch"``).
        sigma : float, optional
            :math:`\sigma_0`, the neighbourhood's starting width in grid units; half the
            larger grid side (at least 1) when omitted.
        init : {"pca", "random"}, default "pca"
            Starting nodes: ``"pca"`` spread over the plane of the two principal axes (one
            standard deviation per half side), ``"random"`` at random data points drawn with
            ``seed``.
        seed : int or numpy Generator, default 0
            Draws the order of the samples (online) and the random start; the same seed gives
            the same map.
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``embedding.som``; its results hold ``embedding``, ``codebook``, ``bmu``, ``quantization_error``, ``topographic_error``, ``trustworthiness``, ``iterations``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] T. Kohonen, "Self-organized formation of topologically correct feature maps",
           Biological Cybernetics 43, 1982.
        .. [2] T. Kohonen, *Self-Organizing Maps*, 3rd ed., Springer 2001 (batch map, §3.14).
        .. [3] G. Vettigli, MiniSom, https://github.com/JustGlowing/minisom.

        Examples
        --------
        >>> job = await client.embedding.som(  # doctest: +SKIP
        ...     [[0, 0], [0.1, 0], [5, 5], [5.1, 5], [0, 5], [5, 0]],
        ...     rows=2,
        ...     columns=2,
        ...     wait=30)
        >>> (await job.results())["embedding"]  # doctest: +SKIP
        """
        inputs = {"points": points, "rows": rows, "columns": columns, "method": method, "max_iterations": max_iterations, "learning_rate": learning_rate, "sigma": sigma, "init": init, "seed": seed, "labels": labels}
        return await self._client.execute(
            "embedding.som",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_SOM),
        )

    async def tsne(
        self,
        points: PointsLike,
        *,
        n_components: int = 2,
        perplexity: float = 30.0,
        method: Literal["auto", "exact", "fft"] = "auto",
        init: Literal["pca", "random"] | PointsLike = "pca",
        learning_rate: float | Literal["auto"] = "auto",
        max_iterations: int = 750,
        early_exaggeration: float = 12.0,
        exaggeration_iterations: int = 250,
        min_grad_norm: float = 1e-07,
        seed: int = 0,
        quality_neighbors: int = 5,
        labels: ArrayLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""t-SNE (t-distributed stochastic neighbour embedding).

        Perplexity-calibrated Gaussian affinities (binary search per point), Cauchy affinities in the
        embedding, KL(P‖Q) minimised by gradient descent with momentum, gains and early exaggeration;
        exact all-pairs gradient for small inputs, FFT-interpolated repulsion (FIt-SNE) for up to
        100,000s of points. Reports KL, trustworthiness and iterations. Progress every iteration,
        cancellable.

        Input affinities: for each point a Gaussian over its neighbours, its precision
        :math:`\beta_i` found by binary search so that the perplexity :math:`2^{H(P_i)}`
        equals ``perplexity``, then symmetrised,

        .. math:: p_{j|i} = \frac{e^{-\beta_i \lVert x_i - x_j\rVert^2}}
                                 {\sum_{k \ne i} e^{-\beta_i \lVert x_i - x_k\rVert^2}},
                  \qquad p_{ij} = \frac{p_{j|i} + p_{i|j}}{2n}.

        Embedding affinities: the Cauchy (Student-t, one degree of freedom) kernel
        :math:`w_{ij} = (1 + \lVert y_i - y_j\rVert^2)^{-1}`, :math:`q_{ij} = w_{ij} / Z`,
        :math:`Z = \sum_{k \ne l} w_{kl}`. The embedding minimises

        .. math:: C = \mathrm{KL}(P \,\|\, Q) = \sum_{i \ne j} p_{ij} \log \frac{p_{ij}}{q_{ij}},
                  \qquad \frac{\partial C}{\partial y_i} = 4 \sum_j (p_{ij} - q_{ij})\, w_{ij}\,
                  (y_i - y_j),

        by gradient descent with momentum (scikit-learn's 0.5 then 0.8 for ``"exact"``,
        openTSNE's 0.8 for ``"fft"``), per-coordinate gains and, for the first
        ``exaggeration_iterations`` steps, :math:`P` multiplied by ``early_exaggeration``.

        Parameters
        ----------
        points : (n, D) float array
            The data, one row per point; at least 2 points.
        n_components : int, default 2
            The embedding's dimension ``k``. ``method="fft"`` needs ``k <= 2``; larger ``k``
            is exact only (at most 5,000 points).
        perplexity : float, default 30
            The effective number of neighbours of each point's Gaussian (its entropy is
            :math:`\log(\text{perplexity})`, found by binary search), ``0 < perplexity < n``.
        method : {"auto", "exact", "fft"}, default "auto"
            ``"exact"``: all pairs each iteration, affinities over all pairs (as scikit-learn's
            ``method="exact"``; at most 5,000 points). ``"fft"``: affinities over the
            :math:`\min(n - 1, 3\,\text{perplexity})` nearest neighbours (rounded down), the
            repulsion by FFT-accelerated interpolation (FIt-SNE; openTSNE's default;
            ``n_components <= 2``). ``"auto"``: exact below 500 points or for
            ``n_components > 2``, else fft.
        init : {"pca", "random"} or (n, k) float array, default "pca"
            The start: ``"pca"`` the PCA scores scaled to a first-column standard deviation
            of 1e-4 (openTSNE, scikit-learn), ``"random"`` Gaussian draws of that size from
            ``seed``, or the start positions themselves, one row per point and
            ``n_components`` columns, used as given (as scikit-learn and openTSNE do: e.g. a
            previous embedding to continue from). An embedding started from an array keeps
            its orientation: its column signs are not normalised.
        learning_rate : float or "auto", default "auto"
            The step, ``> 0``. ``"auto"``: :math:`\max(n / 4\alpha, 50)` with :math:`\alpha`
            the exaggeration in force — scikit-learn's :math:`\max(n / 4 \cdot 12, 50)` during
            the exaggeration, then openTSNE's :math:`n / \alpha` (openTSNE's gradient lacks
            the factor 4) with :math:`\alpha = 1`, 12× larger, which converges in fewer steps.
        max_iterations : int, default 750
            Gradient steps in all, the exaggeration phase included (openTSNE's 250 + 500;
            scikit-learn's ``max_iter`` is 1000 with its smaller step).
        early_exaggeration : float, default 12
            The factor :math:`\alpha \ge 1` on :math:`P` during the first
            ``exaggeration_iterations`` steps (it pulls clusters together early on).
        exaggeration_iterations : int, default 250
            The number of steps with :math:`P` multiplied by ``early_exaggeration``;
            counted in ``max_iterations``.
        min_grad_norm : float, default 1e-7
            After the exaggeration phase, stop once the gradient's norm falls below this.
        seed : int or numpy Generator, default 0
            Draws the random start (and the extra columns of a PCA start when ``k`` exceeds
            the data's dimension); the same seed gives the same embedding.
        quality_neighbors : int, default 5
            The neighbourhood size of the reported trustworthiness (clipped to
            ``(n - 1) // 2`` when larger).
        labels : array_like, optional
            Optional class labels, one per point (integers or strings), for the display only:
            the result's GLB and the workbench colour the points by class (a clustering's
            clusters take the colour of the class they match best). The method does not read
            them.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``embedding.tsne``; its results hold ``embedding``, ``kl_divergence``, ``trustworthiness``, ``iterations``, ``method``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] L. van der Maaten, G. Hinton, "Visualizing data using t-SNE", JMLR 9 (2008).
        .. [2] G. C. Linderman, M. Rachh, J. G. Hoskins, S. Steinerberger, Y. Kluger, "Fast
           interpolation-based t-SNE for improved visualization of single-cell RNA-seq
           data", Nature Methods 16 (2019).
        .. [3] P. G. Poličar, M. Stražar, B. Zupan, "openTSNE: a modular Python library for
           t-SNE dimensionality reduction and embedding", J. Stat. Softw. 109 (2024).
        """
        inputs = {"points": points, "n_components": n_components, "perplexity": perplexity, "method": method, "init": init, "learning_rate": learning_rate, "max_iterations": max_iterations, "early_exaggeration": early_exaggeration, "exaggeration_iterations": exaggeration_iterations, "min_grad_norm": min_grad_norm, "seed": seed, "quality_neighbors": quality_neighbors, "labels": labels}
        return await self._client.execute(
            "embedding.tsne",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_EMBEDDING_TSNE),
        )


class AsyncInterpolation(_AsyncFamily):
    """The interpolation processes, through a :class:`AsyncClient`: ``affine``, ``arap``, ``poisson``, ``rigid``."""

    async def affine(
        self,
        source: ShapeLike,
        target: ShapeLike | None = None,
        *,
        transform: ArrayLike | None = None,
        times: ArrayLike | None = None,
        reflection: Literal["refuse", "flip"] = "refuse",
        pivot: Literal["centroid", "origin"] = "centroid",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Affine interpolation by polar decomposition.

        A = R S (polar decomposition); R turns along the shortest arc (slerp), S and the translation
        move linearly, so det A(t) > 0 all along the path. The map is given or fitted to the target (its
        residual blended in, so t = 1 is the target).

        The map :math:`p \mapsto A p + b` is the ``transform`` given, or the least-squares fit
        to ``target`` (:func:`algorithms.alignment.affine`). With the polar decomposition
        :math:`A = R S` (:math:`R` a rotation, :math:`S` symmetric) and the pivot :math:`c`,

        .. math::

            A(t) = \operatorname{slerp}(I, R; t)\,\bigl((1 - t) I + t S\bigr), \qquad
            p(t) = A(t)\,(p - c) + c + t\,(A c + b - c) + t\,r_p,

        where :math:`\operatorname{slerp}(I, R; t) = \exp(t \log R)` turns about the fixed
        axis of :math:`R` through :math:`t` times its angle in :math:`[0, \pi]` (the shortest
        arc) and :math:`r_p = y_p - (A p + b)` is the fit's residual at point :math:`p` (zero
        for a given transform). So :math:`p(0) = p` and :math:`p(1) = A p + b + r_p`: the
        target itself.

        Parameters
        ----------
        source : (n, d) float array or mesh
            The shape at t = 0: a point set or a mesh ``{vertices, faces}`` (triangles, or
            tetrahedra in 3-D); ``d`` = 2 or 3.
        target : (n, d) float array or mesh, optional
            The shape at t = 1, point ``i`` for source point ``i``: points, or a mesh with
            exactly the source's faces (the same connectivity); the fitted map needs at least
            ``d + 1`` affinely independent source points. Give this or ``transform``.
        transform : (d+1, d+1) float array, optional
            A homogeneous affine matrix ``[[A, b], [0, 1]]`` applied to the source instead of
            ``target``.
        times : (T,) float array, optional
            Strictly increasing times in [0, 1] (no extrapolation), one frame each; 11 evenly
            spaced (0, 0.1, ..., 1) when omitted.
        reflection : {"refuse", "flip"}, default "refuse"
            For a map that mirrors (:math:`\det A < 0`), which no path of invertible maps
            reaches: ``"refuse"`` raises an error; ``"flip"`` takes a rotation and a stretch
            with one negative eigenvalue, so the path flattens the shape once on the way.
        pivot : {"centroid", "origin"}, default "centroid"
            The point :math:`c` the linear part acts about: ``"centroid"`` the source's
            centroid, which then moves on a straight line; ``"origin"`` the origin, so that the
            translation is interpolated as :math:`t b`.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``interpolation.affine``; its results hold ``frames``, ``times``, ``faces``, ``transform``, ``rotation``, ``stretch``, ``angle``, ``det``, ``max_edge_error``, ``rmse``, ``reflection``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] K. Shoemake and T. Duff, "Matrix animation and polar decomposition", Graphics
           Interface 1992, 258-264.
        .. [2] M. Alexa, D. Cohen-Or and D. Levin, "As-rigid-as-possible shape interpolation",
           SIGGRAPH 2000, 157-164 (§3, the single-triangle case).

        Examples
        --------
        >>> job = await client.interpolation.affine(  # doctest: +SKIP
        ...     [[0, 0], [1, 0], [1, 1], [0, 1]],
        ...     transform=[[0.0, -1.0, 2.0], [2.0, 0.0, 1.0], [0.0, 0.0, 1.0]],
        ...     times=[0.0, 0.25, 0.5, 0.75, 1.0],
        ...     wait=30)
        >>> (await job.results())["frames"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "transform": transform, "times": times, "reflection": reflection, "pivot": pivot}
        return await self._client.execute(
            "interpolation.affine",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_INTERPOLATION_AFFINE),
        )

    async def arap(
        self,
        source: ShapeLike,
        target: ShapeLike | None = None,
        *,
        transform: ArrayLike | None = None,
        times: ArrayLike | None = None,
        anchor: int = 0,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""As-rigid-as-possible shape interpolation.

        Per face, A_f = R_f S_f interpolated as slerp(R_f) lerp(I, S_f); the vertices of each frame
        solve min Σ_f ‖B_f(x) − A_f(t)‖² with one vertex on its straight path (one factored sparse
        system, one solve per frame).

        Each face's affine map :math:`A_f` from source to target (see the module docstring of
        :mod:`algorithms.interpolation._faces`: the face's edges, plus the normal as third
        axis for triangles in 3-D) is split by the polar decomposition :math:`A_f = R_f S_f`
        and interpolated as :math:`A_f(t) = \operatorname{slerp}(I, R_f; t)\,((1 - t) I + t
        S_f)`, the rotation along its shortest arc. The vertices at time :math:`t` minimise

        .. math::

            \sum_f \lVert B_f(X) - A_f(t) \rVert_F^2,

        :math:`B_f(X)` the map face :math:`f` takes under positions :math:`X` (its edges'
        least-squares fit), with one vertex held on its straight path
        :math:`(1 - t)\,p_a + t\,q_a`. The normal equations are one sparse system, factored
        once; each frame is one solve with a new right-hand side.

        Parameters
        ----------
        source : Mesh or {"vertices", "faces"}
            The mesh at t = 0: ``(n, d)`` vertices and ``(m, 3)`` triangles (``d`` = 2 or 3)
            or, in 3-D, ``(m, 4)`` tetrahedra; no zero-area (zero-volume) faces. A point set
            is refused: the method interpolates per face.
        target : (n, d) float array or mesh, optional
            The mesh at t = 1 with exactly the source's faces (the same connectivity), or its
            vertices alone. Give this or ``transform``.
        transform : (d+1, d+1) float array, optional
            A homogeneous affine matrix ``[[A, b], [0, 1]]`` applied to the source instead of
            ``target``.
        times : (T,) float array, optional
            Strictly increasing times in [0, 1] (no extrapolation), one frame each; 11 evenly
            spaced (0, 0.1, ..., 1) when omitted.
        anchor : int, default 0
            The vertex that moves on a straight line from its source to its target position
            (it fixes the free translation); every other connected component holds its
            lowest-numbered vertex on its line.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``interpolation.arap``; its results hold ``frames``, ``times``, ``faces``, ``min_det``, ``max_edge_error``, ``max_angle``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] M. Alexa, D. Cohen-Or and D. Levin, "As-rigid-as-possible shape interpolation",
           SIGGRAPH 2000, 157-164.
        .. [2] R. W. Sumner and J. Popović, "Deformation transfer for triangle meshes", ACM TOG
           23(3), 2004 (the normal as fourth vertex of a triangle in space).
        """
        inputs = {"source": source, "target": target, "transform": transform, "times": times, "anchor": anchor}
        return await self._client.execute(
            "interpolation.arap",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_INTERPOLATION_ARAP),
        )

    async def poisson(
        self,
        source: ShapeLike,
        target: ShapeLike | None = None,
        *,
        transform: ArrayLike | None = None,
        times: ArrayLike | None = None,
        anchor: int = 0,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Poisson shape interpolation.

        Per-face gradients interpolated (rotations made continuous across the mesh then slerped,
        stretches lerped) and each frame recovered by a Poisson solve L x = div(gradients) with the
        prefactored cotangent Laplacian.

        Each face's map :math:`A_f = R_f S_f` (polar decomposition; the face's edges, plus the
        normal as third axis for triangles in 3-D) is interpolated as
        :math:`A_f(t) = \exp(t \log R_f)\,((1 - t) I + t S_f)`; row :math:`r` of
        :math:`A_f(t)` is the wanted gradient of coordinate :math:`r` over the face. The
        coordinates at time :math:`t` solve the Poisson equation

        .. math::

            L\, X(t) = G^\mathsf{T} M\, [A_f(t)^\mathsf{T}]_f ,

        :math:`L` the cotangent Laplacian (:func:`~algorithms.core.laplacian.cotangent_laplacian`;
        for tetrahedra the same FEM stiffness assembled from the gradients), :math:`M` the face
        areas (volumes) and :math:`G^\mathsf{T} M` the divergence: the area-weighted
        least-squares fit of the gradients. One vertex moves on its straight path (the
        Dirichlet condition); :math:`L` is factored once and each frame is one solve.

        The rotation vectors :math:`\log R_f` are made continuous across the mesh before
        interpolating (:func:`~algorithms.interpolation._faces.unwrap_rotations`): from the
        face that turns least, each face takes the multiple of a whole turn that puts it
        nearest the neighbour it was reached from, so a part turned by more than half a turn
        does not tear.

        Parameters
        ----------
        source : Mesh or {"vertices", "faces"}
            The mesh at t = 0: ``(n, d)`` vertices and ``(m, 3)`` triangles (``d`` = 2 or 3)
            or, in 3-D, ``(m, 4)`` tetrahedra; no zero-area (zero-volume) faces. A point set
            is refused: the method interpolates per face.
        target : (n, d) float array or mesh, optional
            The mesh at t = 1 with exactly the source's faces (the same connectivity), or its
            vertices alone. Give this or ``transform``.
        transform : (d+1, d+1) float array, optional
            A homogeneous affine matrix ``[[A, b], [0, 1]]`` applied to the source instead of
            ``target``.
        times : (T,) float array, optional
            Strictly increasing times in [0, 1] (no extrapolation), one frame each; 11 evenly
            spaced (0, 0.1, ..., 1) when omitted.
        anchor : int, default 0
            The vertex that moves on a straight line from its source to its target position
            (it fixes the free translation); every other connected component holds its
            lowest-numbered vertex on its line.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``interpolation.poisson``; its results hold ``frames``, ``times``, ``faces``, ``min_det``, ``max_edge_error``, ``max_angle``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] D. Xu, H. Zhang, Q. Wang and H. Bao, "Poisson shape interpolation", ACM
           Symposium on Solid and Physical Modeling 2005, 267-274.
        .. [2] M. Alexa, D. Cohen-Or and D. Levin, "As-rigid-as-possible shape interpolation",
           SIGGRAPH 2000, 157-164.
        """
        inputs = {"source": source, "target": target, "transform": transform, "times": times, "anchor": anchor}
        return await self._client.execute(
            "interpolation.poisson",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_INTERPOLATION_POISSON),
        )

    async def rigid(
        self,
        source: ShapeLike,
        target: ShapeLike | None = None,
        *,
        transform: ArrayLike | None = None,
        times: ArrayLike | None = None,
        scale: bool = False,
        pivot: Literal["centroid", "origin"] = "centroid",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Rigid (or similarity) motion interpolation.

        Fits a rigid motion (Kabsch) or similarity (Umeyama) to the target, or takes the one given, and
        moves the shape along it: rotation by slerp (shortest arc), pivot on a straight line, scale
        geometric (s^t).

        The motion :math:`p \mapsto s R p + b` is the ``transform`` given (checked to be one),
        or the least-squares fit to ``target``: Kabsch (:func:`algorithms.alignment.rigid`), or
        Umeyama with ``scale=True`` (:func:`algorithms.alignment.similarity`). With the pivot
        :math:`c`,

        .. math::

            p(t) = s^t \exp(t \log R)\,(p - c) + c + t\,(s R c + b - c) + t\,r_p,

        :math:`r_p = y_p - (s R p + b)` the fit's residual (zero for a given transform), so
        :math:`p(0) = p` and :math:`p(1) = y_p`. The rotation turns about its fixed axis
        through :math:`t` times its angle in :math:`[0, \pi]` (the shortest arc), the pivot
        moves on a straight line, and the scale changes geometrically (:math:`\log s` is
        interpolated linearly), so equal time steps give equal ratios.

        Parameters
        ----------
        source : (n, d) float array or mesh
            The shape at t = 0: a point set or a mesh ``{vertices, faces}`` (triangles, or
            tetrahedra in 3-D); ``d`` = 2 or 3. Fitting a target needs at least ``d`` points,
            not all on one line in 3-D, not all at one point in 2-D.
        target : (n, d) float array or mesh, optional
            The shape at t = 1, point ``i`` for source point ``i``: points, or a mesh with
            exactly the source's faces (the same connectivity). Give this or ``transform``.
        transform : (d+1, d+1) float array, optional
            A homogeneous rigid motion ``[[R, b], [0, 1]]`` (with ``scale=True`` a similarity
            ``[[s R, b], [0, 1]]``) applied to the source instead of ``target``.
        times : (T,) float array, optional
            Strictly increasing times in [0, 1] (no extrapolation), one frame each; 11 evenly
            spaced (0, 0.1, ..., 1) when omitted.
        scale : bool, default False
            Fit and interpolate a uniform scale too, geometrically (:math:`s^t`).
        pivot : {"centroid", "origin"}, default "centroid"
            The point :math:`c` the rotation turns about: ``"centroid"`` the source's centroid,
            which then moves on a straight line; ``"origin"`` the origin.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``interpolation.rigid``; its results hold ``frames``, ``times``, ``faces``, ``transform``, ``rotation``, ``scale``, ``translation``, ``angle``, ``max_edge_error``, ``rmse``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] K. Shoemake, "Animating rotation with quaternion curves", SIGGRAPH 1985,
           245-254.
        .. [2] S. Umeyama, "Least-squares estimation of transformation parameters between two
           point patterns", IEEE TPAMI 13(4), 376-380, 1991.

        Examples
        --------
        >>> job = await client.interpolation.rigid(  # doctest: +SKIP
        ...     [[0, 0], [1, 0], [1, 1], [0, 1]],
        ...     transform=[[0.0, -1.0, 2.0], [1.0, 0.0, 1.0], [0.0, 0.0, 1.0]],
        ...     times=[0.0, 0.25, 0.5, 0.75, 1.0],
        ...     wait=30)
        >>> (await job.results())["frames"]  # doctest: +SKIP
        """
        inputs = {"source": source, "target": target, "transform": transform, "times": times, "scale": scale, "pivot": pivot}
        return await self._client.execute(
            "interpolation.rigid",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_INTERPOLATION_RIGID),
        )


class AsyncParameterization(_AsyncFamily):
    """The parameterization processes, through a :class:`AsyncClient`: ``abf``, ``arap``, ``asap``, ``bijective``, ``conformal``, ``harmonic``, ``stretch_minimizing``, ``tutte``."""

    async def abf(
        self,
        mesh: MeshLike,
        *,
        max_iterations: int = 20,
        tolerance: float = 1e-08,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Angle-based flattening (ABF++).

        Solves for the flat angles nearest the surface's (relative error, weights 1/β²) under the
        triangle, planarity and wheel constraints by Newton's method on a sparse reduced system (angle
        and triangle multipliers eliminated, one sparse Cholesky per iteration), then lays the mesh out
        from the angles by a least-squares conformal step with two boundary vertices pinned; free
        boundary. Reports flipped faces, angle distortion and area distortion.

        Finds the angles :math:`\alpha` of a flat mesh nearest the surface's, in relative
        terms,

        .. math::

            \min_\alpha \sum_c \frac{(\alpha_c - \beta_c)^2}{\beta_c^2}
            \quad\text{s.t.}\quad
            \begin{cases}
            \sum_{c \in t} \alpha_c = \pi & \text{every face } t,\\
            \sum_{c \ni v} \alpha_c = 2\pi & \text{every interior vertex } v,\\
            \sum_{c \ni v} \log\sin\alpha_{c^+} - \log\sin\alpha_{c^-} = 0
                & \text{every interior vertex } v,
            \end{cases}

        (:math:`\beta` the surface's angles scaled at each interior vertex to sum to
        :math:`2\pi`; :math:`c^\pm` the next and previous corner of corner :math:`c`'s face:
        the wheel condition that the edge-length ratios around a vertex multiply to one), by
        Newton's method on the Lagrangian from :math:`\alpha = \beta`, :math:`\lambda = 0`.
        Each step solves the KKT system by ABF++'s elimination: the angle block is diagonal,
        the triangle block then too, leaving one sparse symmetric positive definite system in
        the :math:`2q` vertex multipliers (:math:`q` interior vertices), factored by sparse
        Cholesky. Then the mesh is laid out from the angles by a least-squares conformal step
        (:func:`angles_to_uv`), two boundary vertices pinned.

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        max_iterations : int, default 20
            Upper bound on Newton iterations.
        tolerance : float, default 1e-8
            Stop when the Euclidean norm of the gradient of the Lagrangian (in the angles and
            the multipliers: the optimality residual and every constraint's residual, radians)
            is at most this; ``0`` runs all ``max_iterations``. Not converging warns
            (:class:`~algorithms.core.errors.ConvergenceWarning`) unless ``tolerance`` is 0.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``parameterization.abf``; its results hold ``uv``, ``mesh``, ``angles``, ``pinned``, ``energy``, ``gradient_norm``, ``iterations``, ``converged``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] A. Sheffer, B. Lévy, M. Mogilnitsky and A. Bogomyakov, "ABF++: fast and robust
           angle based flattening", ACM Transactions on Graphics 24(2), 2005.
        .. [2] A. Sheffer and E. de Sturler, "Parameterization of faceted surfaces for meshing
           using angle-based flattening", Engineering with Computers 17, 2001.

        Examples
        --------
        >>> job = await client.parameterization.abf(  # doctest: +SKIP
        ...     {'vertices': [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0], [0, 2, 0], [1, 2, 0.3], [2, 2, 0]], 'faces': [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]},
        ...     wait=30)
        >>> (await job.results())["uv"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "max_iterations": max_iterations, "tolerance": tolerance}
        return await self._client.execute(
            "parameterization.abf",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_ABF),
        )

    async def arap(
        self,
        mesh: MeshLike,
        *,
        init: Literal["lscm", "harmonic"] = "lscm",
        max_iterations: int = 100,
        tolerance: float = 1e-06,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""As-rigid-as-possible parameterization (local/global).

        Alternates per-face nearest rotations (closed form) and one prefactored cotangent-Laplacian
        solve with a per-half-edge right-hand side; free boundary, energy never increasing. Reports
        flipped faces, angle distortion and area distortion.

        Minimises over the UV positions :math:`u` and one rotation :math:`R_t` per face

        .. math::

            E(u, R) = \sum_t A_t \lVert J_t(u) - R_t \rVert_F^2
            = \sum_t \sum_{k} \tfrac12\cot\theta_t^k
            \lVert (u_a - u_b) - R_t\, e_t^k \rVert^2,

        by block coordinate descent from ``init``: the local step gives each face the rotation
        nearest its Jacobian (closed form in 2-D), the global step solves for :math:`u` with
        the rotations fixed (one prefactored cotangent-Laplacian solve per iteration). Each
        step minimises the energy over its block exactly, so it never increases. One vertex is
        held where ``init`` put it (the energy does not see translations).

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        init : {"lscm", "harmonic"}, default "lscm"
            The starting map, scaled to the surface's area: ``"lscm"`` the least-squares
            conformal map (farthest boundary pair pinned), ``"harmonic"`` the harmonic map onto
            the circle.
        max_iterations : int, default 100
            Upper bound on local/global iterations (libigl's ``ARAPData.max_iter`` is 10, run
            to the end; ours stops by ``tolerance``, so the larger bound costs nothing where
            fewer iterations settle; ``max_iterations=10, tolerance=0`` is libigl's run).
        tolerance : float, default 1e-6
            Stop when an iteration lowers the energy by at most this fraction; ``0`` runs all
            ``max_iterations`` (libigl's behaviour), unless the energy reaches zero.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``parameterization.arap``; its results hold ``uv``, ``mesh``, ``energy``, ``iterations``, ``converged``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] L. Liu, L. Zhang, Y. Xu, C. Gotsman and S. J. Gortler, "A local/global approach
           to mesh parameterization", Computer Graphics Forum 27(5) (SGP), 2008.

        Examples
        --------
        >>> job = await client.parameterization.arap(  # doctest: +SKIP
        ...     {'vertices': [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0], [0, 2, 0], [1, 2, 0.3], [2, 2, 0]], 'faces': [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]},
        ...     wait=30)
        >>> (await job.results())["uv"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "init": init, "max_iterations": max_iterations, "tolerance": tolerance}
        return await self._client.execute(
            "parameterization.arap",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_ARAP),
        )

    async def asap(
        self,
        mesh: MeshLike,
        *,
        init: Literal["lscm", "harmonic"] = "harmonic",
        max_iterations: int = 100,
        tolerance: float = 1e-06,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""As-similar-as-possible parameterization (local/global).

        Alternates per-face nearest similarities and one prefactored solve, two boundary vertices held;
        converges to the LSCM map with those pins. Reports flipped faces, angle distortion and area
        distortion.

        Minimises over the UV positions :math:`u` and one similarity
        :math:`S_t = \begin{pmatrix} p_t & -s_t \\ s_t & p_t \end{pmatrix}` per face

        .. math:: E(u, S) = \sum_t A_t \lVert J_t(u) - S_t \rVert_F^2

        by the local/global iteration of :func:`~algorithms.parameterization.arap` with the
        similarity nearest each Jacobian in the local step (closed form, no SVD). The energy
        is zero on the collapsed map, so two vertices (the boundary pair farthest apart) are
        held where ``init`` put them.

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        init : {"lscm", "harmonic"}, default "harmonic"
            The starting map, scaled to the surface's area: ``"harmonic"`` the harmonic map
            onto the circle; ``"lscm"`` the least-squares conformal map with the same two pins,
            already the minimum of the ASAP energy (the iteration stops at once).
        max_iterations : int, default 100
            Upper bound on local/global iterations.
        tolerance : float, default 1e-6
            Stop when an iteration lowers the energy by at most this fraction; ``0`` runs all
            ``max_iterations``.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``parameterization.asap``; its results hold ``uv``, ``mesh``, ``energy``, ``iterations``, ``converged``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] L. Liu, L. Zhang, Y. Xu, C. Gotsman and S. J. Gortler, "A local/global approach
           to mesh parameterization", Computer Graphics Forum 27(5) (SGP), 2008.

        Examples
        --------
        >>> job = await client.parameterization.asap(  # doctest: +SKIP
        ...     {'vertices': [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0], [0, 2, 0], [1, 2, 0.3], [2, 2, 0]], 'faces': [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]},
        ...     wait=30)
        >>> (await job.results())["uv"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "init": init, "max_iterations": max_iterations, "tolerance": tolerance}
        return await self._client.execute(
            "parameterization.asap",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_ASAP),
        )

    async def bijective(
        self,
        mesh: MeshLike,
        *,
        max_iterations: int = 100,
        tolerance: float = 1e-06,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Bijective parameterization (symmetric Dirichlet, free boundary).

        Minimises the symmetric Dirichlet energy plus a boundary barrier from a flip-free Tutte start by
        SLIM steps; the line search never lets a face flip or the boundary cross itself (quadratic step
        bounds), so the map is bijective by construction. Reports flipped faces, angle distortion and
        area distortion.

        Minimises, over the UV positions :math:`u`,

        .. math::

            E(u) = \frac{\sum_t A_t \left(\lVert J_t\rVert_F^2 + \lVert J_t^{-1}\rVert_F^2
            \right)}{\sum_t A_t} + \lambda \sum_{e} \sum_{k}
            \max\!\left(0, \frac{\varepsilon}{d(u_k, e)} - 1\right)^2,

        the area-weighted symmetric Dirichlet energy (infinite on a collapsed face, so it
        keeps every face's orientation) plus Smith and Schaefer's boundary barrier
        (:math:`e` a boundary edge, :math:`k` a boundary vertex not on it or next to it,
        :math:`d` the distance from the vertex to the edge segment, :math:`\varepsilon` a
        quarter of the mean boundary edge length, :math:`\lambda = 10^{-2}`).

        * Start: the mean value Tutte map onto the circle, scaled to the surface's area:
          flip-free with a simple boundary (Tutte's theorem).
        * Direction: the SLIM step (Rabinovich et al. 2017): the minimiser of the reweighted
          quadratic proxy :math:`\sum_t A_t \lVert W_t (J_t - R_t)\rVert_F^2` whose gradient
          equals the energy's at the current map, plus the barrier's Gauss-Newton term; one
          sparse Cholesky solve over :math:`(u, v)`.
        * Line search: the first trial is 0.8 of the largest step at which no triangle's
          signed area reaches zero (per triangle, the smallest positive root of a quadratic in
          the step), capped at 1, then halved until the objective falls enough (Armijo).
          Trials at or beyond the first contact of a boundary vertex with a boundary edge (a
          quadratic in the step too, for the pairs a k-d tree finds within reach) are skipped.

        Every accepted step is therefore flip-free and keeps the boundary from touching itself
        all along the way: the map is bijective by construction, not by luck. While the
        barrier and the contact bound are idle, every step is libigl's SLIM step (the same
        proxy, proximal term and halving), so the two agree to rounding; where SLIM's
        free boundary overlaps itself (a strip wound more than once around an axis), this
        map stops at contact.

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        max_iterations : int, default 100
            Upper bound on SLIM iterations.
        tolerance : float, default 1e-6
            Stop when an iteration lowers the objective by at most this fraction; ``0`` runs
            all ``max_iterations`` (unless no step lowers it any more).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``parameterization.bijective``; its results hold ``uv``, ``mesh``, ``energy``, ``symmetric_dirichlet``, ``iterations``, ``converged``, ``boundary_crossings``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] J. Smith and S. Schaefer, "Bijective parameterization with free boundaries",
           ACM Trans. Graph. 34(4) (SIGGRAPH), 2015.
        .. [2] M. Rabinovich, R. Poranne, D. Panozzo and O. Sorkine-Hornung, "Scalable locally
           injective mappings", ACM Trans. Graph. 36(2), 2017.

        Examples
        --------
        >>> job = await client.parameterization.bijective(  # doctest: +SKIP
        ...     {'vertices': [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0], [0, 2, 0], [1, 2, 0.3], [2, 2, 0]], 'faces': [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]},
        ...     wait=30)
        >>> (await job.results())["uv"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "max_iterations": max_iterations, "tolerance": tolerance}
        return await self._client.execute(
            "parameterization.bijective",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_BIJECTIVE),
        )

    async def conformal(
        self,
        mesh: MeshLike,
        *,
        method: Literal["lscm", "spectral"] = "lscm",
        pins: HandlesLike | None = None,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Conformal parameterization (LSCM, spectral).

        Minimises the conformal energy (Dirichlet minus area): LSCM with two or more pins (chosen
        automatically or given; as igl.lscm), or spectral conformal with a free boundary (generalized
        eigenproblem). Reports flipped faces, angle distortion and area distortion.

        Both methods minimise the conformal energy

        .. math::

            E_C(u) = \tfrac12 \int \lVert \nabla u \rVert^2 - A(u)
            = \sum_t A_t \lVert J_t - S_t \rVert_F^2,

        Dirichlet energy minus the area of the image (:math:`J_t` each face's Jacobian,
        :math:`S_t` the nearest similarity), which vanishes exactly on conformal maps and is
        unchanged by similarities of the plane, so they differ in how that freedom is fixed:

        * ``"lscm"`` (Lévy et al. 2002; Desbrun et al. 2002): pin at least two vertices and solve
          :math:`Q_{ff} u_f = -Q_{fp} c`, one sparse Cholesky solve of size :math:`2n`. Without
          ``pins`` the two boundary vertices farthest apart in space are pinned at
          :math:`(0, 0)` and :math:`(d, 0)`, :math:`d` their distance. Equal to ``igl.lscm``
          with the same pins.
        * ``"spectral"`` (Mullen et al. 2008): no pins; the minimiser of :math:`E_C` under
          :math:`u^\mathsf{T} B u = 1` and :math:`u \perp_B` the constants, :math:`B` the lumped
          boundary length: the first non-trivial eigenvector of :math:`Q u = \lambda B u`
          (shift-invert Lanczos). The result is centred, scaled so its area equals the
          surface's, and turned so the farthest boundary pair lies along +x. A planar mesh comes
          back as itself up to a similarity.

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        method : {"lscm", "spectral"}, default "lscm"
            ``"lscm"``: the least-squares conformal map with at least two vertices pinned
            (``pins``); ``"spectral"``: free boundary and no pins, the first non-trivial
            generalized eigenvector, centred, scaled to the surface's area and turned so the
            farthest boundary pair lies along +x.
        pins : Handles or mapping, optional
            LSCM only: at least two vertices and their positions in the plane,
            ``{"indices": (p,), "positions": (p, 2)}``. Omitted: the two boundary vertices
            farthest apart in space, at :math:`(0, 0)` and :math:`(d, 0)`, :math:`d` their
            distance.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``parameterization.conformal``; its results hold ``uv``, ``mesh``, ``pinned``, ``energy``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] B. Lévy, S. Petitjean, N. Ray and J. Maillot, "Least squares conformal maps for
           automatic texture atlas generation", SIGGRAPH 2002.
        .. [2] M. Desbrun, M. Meyer and P. Alliez, "Intrinsic parameterizations of surface
           meshes", Eurographics 2002.
        .. [3] P. Mullen, Y. Tong, P. Alliez and M. Desbrun, "Spectral conformal
           parameterization", SGP 2008.
        """
        inputs = {"mesh": mesh, "method": method, "pins": pins}
        return await self._client.execute(
            "parameterization.conformal",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_CONFORMAL),
        )

    async def harmonic(
        self,
        mesh: MeshLike,
        *,
        boundary: Literal["circle", "square"] = "circle",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Harmonic parameterization.

        Boundary fixed to a circle or square, interior by the cotangent Laplace equation (minimal
        Dirichlet energy); as igl.harmonic. Reports flipped faces, angle distortion and area distortion.

        .. math::

            \min_u \int \lVert \nabla u \rVert^2 = \min_u\; u_x^\mathsf{T} L u_x
            + u_y^\mathsf{T} L u_y \quad\text{s.t.}\quad u_{\text{boundary}} = c
            \qquad\Longleftrightarrow\qquad L_{00}\, u = -L_{01}\, c,

        :math:`L` the cotangent Laplacian (:math:`w_{ij} = \tfrac12(\cot\alpha_{ij} +
        \cot\beta_{ij})`) and :math:`c` the boundary loop on the unit circle (arc length, as
        ``igl.map_vertices_to_circle``) or the square :math:`[-1, 1]^2`. One factored solve
        for both coordinates (what :func:`algorithms.layout.laplacian` solves with these pins);
        the same as ``igl.harmonic(V, F, loop, c, 1)``.

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        boundary : {"circle", "square"}, default "circle"
            The convex polygon the boundary loop is pinned to, its vertices spaced by boundary
            edge length: ``"circle"`` the unit circle; ``"square"`` the square
            :math:`[-1, 1]^2`, its corners at the four boundary vertices of smallest angle sum
            (the surface's own corners; at least 4 boundary vertices).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``parameterization.harmonic``; its results hold ``uv``, ``mesh``, ``pinned``, ``energy``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] U. Pinkall and K. Polthier, "Computing discrete minimal surfaces and their
           conjugates", Experimental Mathematics 2(1), 1993.
        .. [2] M. Eck, T. DeRose, T. Duchamp, H. Hoppe, M. Lounsbery and W. Stuetzle,
           "Multiresolution analysis of arbitrary meshes", SIGGRAPH 1995.

        Examples
        --------
        >>> job = await client.parameterization.harmonic(  # doctest: +SKIP
        ...     {'vertices': [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0], [0, 2, 0], [1, 2, 0.3], [2, 2, 0]], 'faces': [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]},
        ...     wait=30)
        >>> (await job.results())["uv"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "boundary": boundary}
        return await self._client.execute(
            "parameterization.harmonic",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_HARMONIC),
        )

    async def stretch_minimizing(
        self,
        mesh: MeshLike,
        *,
        boundary: Literal["circle", "square"] = "circle",
        power: float = 1.0,
        max_iterations: int = 20,
        tolerance: float = 0.0001,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Stretch-minimizing parameterization (fixed boundary).

        Starts from the mean value Tutte map (boundary on a circle or square), then divides each weight
        w_ij by the stretch around vertex j and solves again while Sander et al.'s L2 stretch falls;
        keeps the best map. Positive weights and a convex boundary: no flipped faces. Reports the L2 and
        L-infinity stretch, flipped faces, angle distortion and area distortion.

        Lowers Sander et al.'s L2 stretch (the root mean square, over the surface, of the
        stretch a texture suffers when mapped back onto the surface)

        .. math:: L^2(M)^2 = \frac{\sum_t A_t \tfrac12(\Gamma_t^2 + \gamma_t^2)}{\sum_t A_t}
           \cdot \frac{\sum_t A'_t}{\sum_t A_t}

        (:math:`\Gamma_t \ge \gamma_t` the singular values of the map from the plane to face
        :math:`t`; :math:`A_t`, :math:`A'_t` its surface and plane areas) by Yoshizawa et al.'s
        reweighting:

        1. start from the mean value Tutte map (Floater's weights :math:`w^0_{ij}`, boundary on
           the convex polygon);
        2. compute each vertex's stretch :math:`\sigma_j = \sqrt{\sum_{t \ni j} A_t L^2(t)^2 /
           \sum_{t \ni j} A_t}`;
        3. reweight :math:`w_{ij} \leftarrow w_{ij} / \sigma_j^{p}` (a stretched neighbour pulls
           harder, so the region around it grows) and solve
           :math:`\sum_j w_{ij}(u_i - u_j) = 0` for the interior again (one sparse LU);
        4. repeat while the L2 stretch falls; return the map with the smallest.

        The weights stay positive and the boundary convex, so by Tutte's theorem in Floater's
        form no face flips at any step.

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        boundary : {"circle", "square"}, default "circle"
            The convex polygon the boundary loop is pinned to, its vertices spaced by boundary
            edge length: ``"circle"`` the unit circle; ``"square"`` the square
            :math:`[-1, 1]^2`, its corners at the four boundary vertices of smallest angle sum
            (the surface's own corners; at least 4 boundary vertices).
        power : float, default 1.0
            The exponent :math:`p` of the reweighting :math:`w_{ij} \leftarrow w_{ij} /
            \sigma_j^p`, :math:`\sigma_j` the stretch around vertex :math:`j`; ``0 < p <= 4``
            (Yoshizawa et al.: 1). Smaller steps are safer on very stretched meshes; larger
            ones converge faster when they work.
        max_iterations : int, default 20
            Upper bound on reweightings.
        tolerance : float, default 1e-4
            Stop when a reweighting lowers the L2 stretch by at most this fraction (or raises
            it: the method's stopping rule).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``parameterization.stretch_minimizing``; its results hold ``uv``, ``mesh``, ``pinned``, ``stretch``, ``l2_stretch``, ``max_stretch``, ``iterations``, ``converged``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] P. V. Sander, J. Snyder, S. J. Gortler and H. Hoppe, "Texture mapping
           progressive meshes", SIGGRAPH 2001.
        .. [2] S. Yoshizawa, A. Belyaev and H.-P. Seidel, "A fast and simple stretch-minimizing
           mesh parameterization", Shape Modeling International 2004.

        Examples
        --------
        >>> job = await client.parameterization.stretch_minimizing(  # doctest: +SKIP
        ...     {'vertices': [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0], [0, 2, 0], [1, 2, 0.3], [2, 2, 0]], 'faces': [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]},
        ...     wait=30)
        >>> (await job.results())["uv"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "boundary": boundary, "power": power, "max_iterations": max_iterations, "tolerance": tolerance}
        return await self._client.execute(
            "parameterization.stretch_minimizing",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_STRETCH_MINIMIZING),
        )

    async def tutte(
        self,
        mesh: MeshLike,
        *,
        boundary: Literal["circle", "square"] = "circle",
        weighting: Literal["uniform", "mean_value"] = "uniform",
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Tutte embedding (circle or square boundary).

        Pins the boundary loop to a circle or square and puts every interior vertex at a convex
        combination of its neighbours (uniform or mean value weights): one sparse solve, no flipped
        faces. Reports flipped faces, angle distortion and area distortion.

        Solves, for the interior vertices :math:`u_i`,

        .. math:: \sum_j w_{ij} (u_i - u_j) = 0, \qquad u_{\text{boundary}} = c,

        with :math:`c` the boundary loop on the unit circle or the square :math:`[-1, 1]^2`,
        spaced by boundary edge length. Weights: ``"uniform"`` (:math:`w_{ij} = 1`, Tutte's
        barycentric map; symmetric, one Cholesky solve through
        :func:`algorithms.layout.laplacian`) or ``"mean_value"`` (Floater's mean value weights,
        :func:`mean_value_weights`: not symmetric, one LU solve; they reproduce a planar mesh
        whose boundary is pinned to its own convex outline).

        By Tutte's spring theorem in Floater's form (positive weights, each interior vertex a
        convex combination of its neighbours, boundary on a convex polygon), no face flips.

        Parameters
        ----------
        mesh : Mesh, (vertices, faces) or mapping
            A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
            vertex indices: connected, manifold, consistently oriented, exactly one boundary
            loop, every vertex in a face, no zero-area face.
        boundary : {"circle", "square"}, default "circle"
            The convex polygon the boundary loop is pinned to, its vertices spaced by boundary
            edge length: ``"circle"`` the unit circle; ``"square"`` the square
            :math:`[-1, 1]^2`, its corners at the four boundary vertices of smallest angle sum
            (the surface's own corners; at least 4 boundary vertices).
        weighting : {"uniform", "mean_value"}, default "uniform"
            The interior weights: ``"uniform"`` 1 per edge (Tutte's barycentric map);
            ``"mean_value"`` Floater's mean value weights (closer to conformal; a planar mesh
            pinned to its own convex outline comes back as itself). Both are positive, so no
            face flips.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``parameterization.tutte``; its results hold ``uv``, ``mesh``, ``pinned``, ``energy``, ``flipped_faces``, ``degenerate_faces``, ``angle_distortion``, ``area_distortion``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] W. T. Tutte, "How to draw a graph", Proc. London Math. Soc. 13 (1963).
        .. [2] M. S. Floater, "Mean value coordinates", CAGD 20(1), 19-27, 2003.

        Examples
        --------
        >>> job = await client.parameterization.tutte(  # doctest: +SKIP
        ...     {'vertices': [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0], [0, 2, 0], [1, 2, 0.3], [2, 2, 0]], 'faces': [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6], [4, 5, 8], [4, 8, 7]]},
        ...     wait=30)
        >>> (await job.results())["uv"]  # doctest: +SKIP
        """
        inputs = {"mesh": mesh, "boundary": boundary, "weighting": weighting}
        return await self._client.execute(
            "parameterization.tutte",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_PARAMETERIZATION_TUTTE),
        )


class AsyncRegistration(_AsyncFamily):
    """The registration processes, through a :class:`AsyncClient`: ``cpd``, ``icp``, ``multiway``, ``ransac``."""

    async def cpd(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        model: Literal["rigid", "affine", "nonrigid"] = "rigid",
        scale: bool = True,
        w: float = 0.0,
        beta: float = 2.0,
        alpha: float = 2.0,
        low_rank: int | None = None,
        normalize: bool = True,
        sigma2: float | None = None,
        max_iterations: int = 100,
        tolerance: float = 1e-05,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Register ``source`` onto ``target`` by coherent point drift; no correspondences.

        The moved source points :math:`T(y_m)` are the centroids of an equally weighted Gaussian
        mixture of variance :math:`\sigma^2`, plus a uniform component of weight ``w`` for
        outliers; the target points :math:`x_n` are its data. EM alternates

        - **E-step:** the posterior of centroid :math:`m` for point :math:`n`,

          .. math::

              P_{mn} = \frac{\exp(-\lVert x_n - T(y_m)\rVert^2 / 2\sigma^2)}
              {\sum_k \exp(-\lVert x_n - T(y_k)\rVert^2 / 2\sigma^2) + c}, \qquad
              c = (2\pi\sigma^2)^{d/2}\,\frac{w}{1-w}\,\frac{M}{N};

        - **M-step:** the map and :math:`\sigma^2` minimising
          :math:`\sum_{mn} P_{mn} \lVert x_n - T(y_m)\rVert^2 / 2\sigma^2 + N_P d/2 \log\sigma^2`
          (:math:`N_P = \sum_{mn} P_{mn}`), in closed form for each ``model``:

          - ``rigid``: :math:`T(y) = sRy + t`, with :math:`R` from the SVD of
            :math:`A = \hat X^\mathsf{T} P^\mathsf{T} \hat Y` (reflection fixed) and
            :math:`s = \operatorname{tr}(A^\mathsf{T} R) / \operatorname{tr}(\hat Y^\mathsf{T}
            d(P1) \hat Y)`, or :math:`s = 1` with ``scale=False``;
          - ``affine``: :math:`T(y) = By + t`, :math:`B = A (\hat Y^\mathsf{T} d(P1)
            \hat Y)^{-1}`;
          - ``nonrigid``: :math:`T(Y) = Y + GW`, :math:`G_{ij} = \exp(-\lVert y_i - y_j\rVert^2
            / 2\beta^2)`, with :math:`(d(P1) G + \lambda\sigma^2 I) W = PX - d(P1) Y` (the
            motion coherence regulariser :math:`\tfrac{\lambda}{2}\operatorname{tr}(W^\mathsf{T}
            GW)`; ``alpha`` is the paper's :math:`\lambda`).

        The iterations stop when the relative change of the negative log-likelihood (plus the
        regulariser) falls below ``tolerance``, when σ² reaches rounding level, or after
        ``max_iterations``.

        Parameters
        ----------
        source : (M, d) float array
            The points to move (the mixture's centroids), ``d ≥ 2``.
        target : (N, d) float array
            The points to register onto, same ``d``; ``N`` need not equal ``M`` and no
            correspondence with ``source`` is needed.
        model : {"rigid", "affine", "nonrigid"}, default "rigid"
            The family of maps: ``"rigid"`` a rotation and a translation (and, with ``scale``,
            a uniform scale); ``"affine"`` any linear map and a translation; ``"nonrigid"`` a
            smooth displacement of every source point (Gaussian kernel, motion coherence).
        scale : bool, default True
            Rigid only: estimate the uniform scale ``s`` too (a similarity); False keeps
            ``s = 1``.
        w : float in [0, 1), default 0.0
            The weight of the uniform outlier component, ``0 <= w < 1``: raise it for noise and
            for points of one set missing from the other.
        beta : float > 0, default 2.0
            Nonrigid: the width :math:`\beta` of the Gaussian kernel ``G``; larger is smoother.
            In the units of the normalised sets (unit RMS radius) when ``normalize``, else in
            the points' units.
        alpha : float > 0, default 2.0
            Nonrigid: the regularisation weight :math:`\lambda` of the paper (pycpd's
            ``alpha``); larger keeps the motion closer to a translation.
        low_rank : int >= 1, optional
            Nonrigid: the number ``K`` of leading eigenpairs of ``G`` to use (the paper's fast
            version). Default: the exact kernel up to 1000 source points, else
            ``K = ceil(sqrt(M))`` (the authors' code's default). A value ``≥ M``
            asks for the exact kernel, allowed up to 4000 source points (it takes
            :math:`16M^2` bytes).
        normalize : bool, default True
            Nonrigid: centre each set on its mean and divide it by its RMS radius before
            registering (as the authors' code), so ``beta`` and ``alpha`` need not follow the
            data's units (``sigma2`` stays in squared target units); ``moved`` is returned in
            target units. False: ``beta`` is
            in the points' own units (as pycpd). Rigid and affine results do not depend on it
            (they are computed on centred sets under one common scale, which they commute
            with).
        sigma2 : float > 0, optional
            The initial variance σ² of the mixture, in squared target units. Default: the
            paper's :math:`\sum_{mn}\lVert x_n - y_m\rVert^2 / dMN`, the mean squared
            distance of all pairs per dimension.
        max_iterations : int >= 1, default 100
            The most EM iterations.
        tolerance : float >= 0, default 1e-5
            Stop when the negative log-likelihood changes by less than this fraction in an
            iteration (the relative rule and default of Myronenko and Song's reference code;
            pycpd's ``tolerance``, default 0.001, bounds the absolute change of its objective
            instead, so the two stop at different iterations on the same input).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``registration.cpd``; its results hold ``transform``, ``linear``, ``rotation``, ``scale``, ``translation``, ``moved``, ``sigma2``, ``rmse``, ``iterations``, ``converged``, ``reason``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] A. Myronenko and X. Song, "Point set registration: coherent point drift", IEEE
           TPAMI 32(12), 2262-2275, 2010. arXiv:0905.2635.
        .. [2] N. Halko, P.-G. Martinsson and J. A. Tropp, "Finding structure with randomness",
           SIAM Review 53(2), 217-288, 2011 (the eigenpairs of ``G``).
        """
        inputs = {"source": source, "target": target, "model": model, "scale": scale, "w": w, "beta": beta, "alpha": alpha, "low_rank": low_rank, "normalize": normalize, "sigma2": sigma2, "max_iterations": max_iterations, "tolerance": tolerance}
        return await self._client.execute(
            "registration.cpd",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_REGISTRATION_CPD),
        )

    async def icp(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        model: Literal["rigid", "similarity", "affine"] = "rigid",
        metric: Literal["point_to_point", "point_to_plane", "symmetric"] = "point_to_point",
        init: Literal["identity", "pca"] | ArrayLike = "identity",
        max_iterations: int = 30,
        tolerance: float = 1e-06,
        max_correspondence_distance: float | None = None,
        overlap: float = 1.0,
        kernel: Literal["none", "huber", "tukey"] = "none",
        kernel_scale: float | None = None,
        target_normals: PointsLike | None = None,
        source_normals: PointsLike | None = None,
        normal_neighbors: int = 10,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Register ``source`` onto ``target`` by iterative closest point; no correspondences.

        Starting from the initial transform :math:`T_0`, each iteration

        1. pairs every moved source point :math:`T_k x_i` with its nearest target point
           :math:`y_{j(i)}` (one kd-tree of the target, built once), dropping pairs farther
           apart than ``max_correspondence_distance`` and, with ``overlap < 1``, all but the
           ``overlap`` fraction of source points with the smallest distances (trimmed ICP);
        2. finds the transform of the ``model`` that minimises the ``metric`` over those pairs,
           weighted by the robust ``kernel``:

           .. math::

               \text{point\_to\_point:}\ \min_T \sum_i w_i \lVert T x_i - y_{j(i)} \rVert^2,
               \qquad
               \text{point\_to\_plane:}\ \min_T \sum_i w_i
               \big( (T x_i - y_{j(i)}) \cdot n_{j(i)} \big)^2,

           and the symmetric metric :math:`\sum_i w_i ((R_{1/2} p_i - R_{1/2}^{-1} q_i + t)
           \cdot (n_{p_i} + n_{q_i}))^2` with both sets' normals (Rusinkiewicz 2019);
        3. stops when the pairs are the same as in the previous iteration (a fixed point), when
           the RMSE changed by less than ``tolerance`` relative to its previous value, or after
           ``max_iterations``.

        Point-to-point steps are the closed forms of :mod:`algorithms.alignment` (Kabsch /
        Umeyama / least squares, weighted); point-to-plane and symmetric steps solve the
        linearised objective (small rotation :math:`R \approx I + [\omega]_\times`, exact for
        affine) by one ``6×6`` to ``12×12`` normal-equation solve in coordinates centred and
        scaled at the moved source, then apply the exact rotation of :math:`\omega`.

        Parameters
        ----------
        source : (n, d) float array
            The points to move, ``d >= 2`` (``d = 3`` for the plane metrics).
        target : (m, d) float array
            The points to register onto, the same ``d``, any size ``m``; no correspondence
            with ``source`` is needed.
        model : {"rigid", "similarity", "affine"}, default "rigid"
            The transform: ``"rigid"`` a rotation and a translation, ``"similarity"`` also a
            uniform scale, ``"affine"`` any linear map and a translation.
        metric : {"point_to_point", "point_to_plane", "symmetric"}, default "point_to_point"
            The distance minimised: ``"point_to_point"`` from each moved source point to its
            partner (any ``d``); ``"point_to_plane"`` to the partner's tangent plane (3-D;
            target normals estimated when not given); ``"symmetric"`` along the sum of both
            points' normals, Rusinkiewicz's objective (3-D, ``model="rigid"`` only).
        init : {"identity", "pca"} or (d+1, d+1) float array, default "identity"
            The initial transform: ``"identity"``, ``"pca"`` or a homogeneous matrix.
            ``"pca"`` lays the principal axes onto each other (:func:`algorithms.alignment.pca`,
            scaled as the model allows), runs ICP from every proper sign choice of the axes
            (``2^(d-1)``: 4 in 3-D) and keeps the result of highest fitness, then lowest RMSE.
            A matrix must have the last row ``(0, ..., 0, 1)`` and a linear part of the model
            (orthogonal with determinant +1 for rigid, a positive multiple of one for
            similarity, invertible for affine).
        max_iterations : int, default 30
            Most iterations (fits) to run, ``>= 1``; per sign choice with ``init="pca"``.
        tolerance : float, default 1e-6
            Stop when the RMSE changes by less than this fraction of its previous value in an
            iteration, ``>= 0``; the iterations also stop when the correspondences no longer
            change, so 0 stops only there or at ``max_iterations``. Open3D's
            ``ICPConvergenceCriteria`` has the same defaults (30 iterations, 1e-6) but stops when
            both the fitness and the inlier RMSE change by less than 1e-6 in absolute terms; a
            relative change does not depend on the data's units.
        max_correspondence_distance : float, optional
            Pairs farther apart than this (``> 0``) are ignored in the fit and in ``rmse`` and
            do not count towards ``fitness``. No bound when omitted.
        overlap : float, default 1.0
            Trimmed ICP (Chetverikov et al. 2002): keep only the ``ceil(overlap * n)`` pairs of
            smallest distance, ``0 < overlap <= 1``.
        kernel : {"none", "huber", "tukey"}, default "none"
            Robust kernel, applied by iteratively reweighted least squares: ``"none"`` plain
            least squares, ``"huber"`` weights :math:`\min(1, k/|r|)`, ``"tukey"`` the
            biweight :math:`(1 - (r/c)^2)^2` for :math:`|r| < c`, else 0; ``r`` is the pair's
            distance (point-to-point) or its plane distance.
        kernel_scale : float, optional
            The kernel's threshold ``k`` or ``c`` in the points' units (``> 0``). Omitted: each
            iteration estimates it as :math:`1.345\,\hat\sigma` (Huber) or :math:`4.685\,\hat\sigma`
            (Tukey) with :math:`\hat\sigma = 1.4826\,\operatorname{median}|r|`.
        target_normals : (m, 3) float array, optional
            Normals of the target points for the plane metrics (normalised here; sign free).
            Estimated when omitted: the smallest principal axis of each point's
            ``normal_neighbors`` nearest neighbours.
        source_normals : (n, 3) float array, optional
            Normals of the source points for ``metric="symmetric"``, their signs matched to the
            target's pair by pair (checked but unused with the other metrics). Estimated when
            omitted: the smallest principal axis of each point's ``normal_neighbors`` nearest
            neighbours.
        normal_neighbors : int, default 10
            Neighbours per estimated normal, ``>= 2``: the point and this many others
            (Open3D's ``KDTreeSearchParamKNN(knn)`` counts the point itself, so this is its
            ``knn - 1``; Open3D's default ``knn=30`` smooths more: pass 29 for its normals).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``registration.icp``; its results hold ``transform``, ``linear``, ``rotation``, ``scale``, ``translation``, ``rmse``, ``fitness``, ``iterations``, ``converged``, ``reason``, ``rmse_history``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] P. J. Besl and N. D. McKay, "A method for registration of 3-D shapes", IEEE
           TPAMI 14(2), 239-256, 1992.
        .. [2] Y. Chen and G. Medioni, "Object modelling by registration of multiple range
           images", Image and Vision Computing 10(3), 145-155, 1992 (point-to-plane).
        .. [3] D. Chetverikov, D. Svirko, D. Stepanov and P. Krsek, "The trimmed iterative
           closest point algorithm", ICPR 2002.
        .. [4] S. Rusinkiewicz, "A symmetric objective function for ICP", ACM TOG 38(4), 85,
           2019.
        .. [5] Q.-Y. Zhou, J. Park and V. Koltun, "Open3D: a modern library for 3D data
           processing", arXiv:1801.09847, 2018 (``fitness`` and ``inlier_rmse``).
        """
        inputs = {"source": source, "target": target, "model": model, "metric": metric, "init": init, "max_iterations": max_iterations, "tolerance": tolerance, "max_correspondence_distance": max_correspondence_distance, "overlap": overlap, "kernel": kernel, "kernel_scale": kernel_scale, "target_normals": target_normals, "source_normals": source_normals, "normal_neighbors": normal_neighbors}
        return await self._client.execute(
            "registration.icp",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_REGISTRATION_ICP),
        )

    async def multiway(
        self,
        sets: ArrayLike,
        *,
        correspondences: bool = True,
        model: Literal["rigid", "similarity"] = "rigid",
        init: ArrayLike | None = None,
        max_iterations: int = 100,
        tolerance: float = 1e-09,
        max_correspondence_distance: float | None = None,
        metric: Literal["symmetric", "point_to_plane", "point_to_point"] = "symmetric",
        neighbors: int | None = None,
        min_fitness: float = 0.3,
        edge_prune_threshold: float = 0.25,
        preference_loop_closure: float = 1.0,
        icp_max_iterations: int = 30,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""Multiway registration: generalised Procrustes or pose graph.

        Registers several point sets at once into the frame of set 0. With correspondences: generalised
        Procrustes analysis (rigid or similarity, any dimension), iterated to the mean shape. Without:
        pairwise ICP (coarse to fine, symmetric metric, point-to-point polish) with information
        matrices, then pose-graph optimisation on SE(3) by Levenberg-Marquardt with line processes for
        loop closures, low-fitness and inconsistent edges pruned (as Open3D's multiway registration).

        **With correspondences** (row ``j`` of every set is the same point): generalised
        Procrustes analysis (Gower 1975), :func:`~algorithms.registration.generalized_procrustes`:
        every set is rotated (and, for similarity, scaled) onto the mean shape of the moved
        sets, and the mean recomputed, until the sum of squared distances to the mean stops
        decreasing; any dimension.

        **Without correspondences** (``correspondences=False``, 3-D):
        :func:`~algorithms.registration.pose_graph`, as Open3D's multiway registration (Choi,
        Zhou & Koltun 2015): every pair of sets (or each with its next ``neighbors``) is
        registered by coarse-to-fine ICP, the pairwise results weighted by their information
        matrices, then the poses optimised on SE(3) by Levenberg-Marquardt with line processes
        that switch off inconsistent loop closures.

        The options of the other method are ignored: ``max_correspondence_distance``,
        ``metric``, ``neighbors``, ``min_fitness``, ``edge_prune_threshold``,
        ``preference_loop_closure`` and ``icp_max_iterations`` are the pose graph's.

        Parameters
        ----------
        sets : sequence of (n_i, d) float arrays
            At least two point sets, ``(n_i, d)`` arrays of the same dimension ``d``. With
            correspondences: all of the same length ``n``, row ``j`` of each the same point, any
            ``d >= 1``. Without: 3-D, of any sizes (at least 6 points each, 3 with
            ``metric="point_to_point"``).
        correspondences : bool, default True
            True: row ``j`` of every set is the same point (generalised Procrustes). False:
            the correspondences are unknown (pairwise ICP and pose-graph optimisation on
            SE(3), 3-D only).
        model : {"rigid", "similarity"}, default "rigid"
            ``"rigid"``: a rotation and a translation per set; ``"similarity"``: also a
            uniform scale, relative to set 0's (generalised Procrustes only).
        init : (k, d+1, d+1) float array, optional
            A start transform per set into a common frame (rigid; similarity allowed for
            Procrustes); only their relative transforms matter. Procrustes starts its mean
            from the sets as they move them; the pose graph starts each pairwise ICP from
            them. Omitted: Procrustes starts from set 0, the pose graph from the identity (the
            sets taken as roughly aligned, as by a scanner).
        max_iterations : int, default 100
            Most Procrustes passes, or Levenberg-Marquardt iterations per pose-graph
            optimisation round (two rounds), ``>= 1``.
        tolerance : float, default 1e-9
            Stop when the objective decreases by less than this fraction of its value in an
            iteration, ``>= 0`` (tighter than Open3D's pose-graph criteria, 1e-6: the
            iterations are cheap at the sizes of a multiway problem).
        max_correspondence_distance : float, optional
            Pose graph: the pairs' distance bound (``> 0``, in the points' units) of the fine
            pairwise ICP (the coarse stages use 4 and 2 × it), of the edges' information
            matrices and of ``fitness``; it also scales the line process's loop-closure
            weight. Omitted: 2 × the median distance between nearest neighbours within the
            sets.
        metric : {"symmetric", "point_to_plane", "point_to_point"}, default "symmetric"
            Pose graph: the metric of the coarse-to-fine pairwise ICP stages, followed by a
            point-to-point polish: ``"symmetric"`` uses both sets' normals (Rusinkiewicz
            2019), ``"point_to_plane"`` the target's, ``"point_to_point"`` plain distances.
            Normals are estimated from 10 neighbours; a pair whose target is flat (the plane
            metrics undetermined) falls back to point-to-point.
        neighbors : int, optional
            Pose graph: register each set with its next ``neighbors`` sets in order, ``1 <=
            neighbors <= k - 1`` (1 gives a chain); consecutive pairs then count as trusted
            odometry. Omitted: every pair up to 10 sets (no odometry), 2 beyond.
        min_fitness : float, default 0.3
            Pose graph: drop pairwise edges whose ICP fitness (the share of points with a
            partner within ``max_correspondence_distance``) is below this, ``0 <= min_fitness
            <= 1``: they overlap too little to be trusted.
        edge_prune_threshold : float, default 0.25
            Pose graph: prune the loop closures whose line-process weight falls below this
            after the first optimisation round (Open3D's default), ``0 <= ... < 1``.
        preference_loop_closure : float, default 1.0
            Pose graph: the weight of loop closures in the line process (Open3D's option),
            ``> 0``; larger keeps more loop closures.
        icp_max_iterations : int, default 30
            Pose graph: most iterations per pairwise ICP stage (four stages per pair),
            ``>= 1``.
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``registration.multiway``; its results hold ``transforms``, ``rotations``, ``scales``, ``translations``, ``mean_shape``, ``rmse``, ``fitness``, ``edges``, ``edge_fitness``, ``edge_kept``, ``iterations``, ``converged``, ``reason``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] J. C. Gower, "Generalized Procrustes analysis", Psychometrika 40(1), 33-51,
           1975.
        .. [2] S. Choi, Q.-Y. Zhou and V. Koltun, "Robust reconstruction of indoor scenes",
           CVPR 2015.

        Examples
        --------
        >>> job = await client.registration.multiway(  # doctest: +SKIP
        ...     [[[0, 0], [2, 0], [0, 1], [0, 2], [1, 0]], [[5, 0], [5, 2], [4, 0], [3, 0], [5, 1]], [[0, 3], [4, 3], [0, 5], [0, 7], [2, 3]]],
        ...     wait=30)
        >>> (await job.results())["transforms"]  # doctest: +SKIP
        """
        inputs = {"sets": sets, "correspondences": correspondences, "model": model, "init": init, "max_iterations": max_iterations, "tolerance": tolerance, "max_correspondence_distance": max_correspondence_distance, "metric": metric, "neighbors": neighbors, "min_fitness": min_fitness, "edge_prune_threshold": edge_prune_threshold, "preference_loop_closure": preference_loop_closure, "icp_max_iterations": icp_max_iterations}
        return await self._client.execute(
            "registration.multiway",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_REGISTRATION_MULTIWAY),
        )

    async def ransac(
        self,
        source: PointsLike,
        target: PointsLike,
        *,
        features: Literal["fpfh", "none"] = "fpfh",
        voxel_size: float | None = None,
        feature_radius: float | None = None,
        max_correspondence_distance: float | None = None,
        max_iterations: int = 100000,
        confidence: float = 0.999,
        mutual_filter: bool = True,
        refine: bool = True,
        seed: int = 0,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
    ) -> AsyncJob:
        r"""RANSAC global registration (FPFH features or random triples) + ICP.

        Registers source onto target rigidly without a start: candidate pairs from mutually matched FPFH
        features (or, for small sets, random point triples of each set), seeded random samples of 3
        pairs checked by edge lengths, Kabsch fits scored by truncated squared error, confidence-based
        stopping. Without voxel_size: two down-sampling passes (1.5 and 3 × the point spacing), the best
        hypotheses re-scored and ICP-checked on the point sets, a robust (Tukey) ICP refinement against
        the full target; with voxel_size: Open3D's single pass, then point-to-plane ICP. The same seed
        gives the same result; converged=false with a reason instead of a silent identity.

        1. **Down-sampling**: with ``voxel_size`` each set is replaced by the centroids of its
           points in each occupied voxel. With features and no ``voxel_size``, two passes of
           steps 1-4 run, at 1.5 and 3 × the source's point spacing :math:`h` (those that leave
           enough points; none: one pass without down-sampling), and the pass whose pose has
           the least truncated error :math:`\sum_i \min(r_i^2, \tau_s^2)` of the full source
           against the full target wins (:math:`r_i` the distance to the nearest target
           point, :math:`\tau_s = \tau / 3` of the smaller voxel).
        2. **Candidates.** ``features="fpfh"`` (3-D): FPFH descriptors of both sets
           (:func:`~algorithms.registration.fpfh`, radius ``feature_radius``), matched by
           nearest neighbour in feature space, mutually with ``mutual_filter``.
           ``features="none"``: every (source point, target point) pair is a candidate and
           samples are drawn from each set independently (see Notes).
        3. **Hypotheses.** Each draws :math:`s = \max(3, d)` candidate pairs with the generator
           seeded by ``seed`` and is skipped unless every edge of the sample and of its image agree
           within a factor 0.9 (Open3D's edge-length checker) and the sample is not nearly
           collinear; the rest get the Kabsch fit :math:`(R, t)` of their pairs, are skipped
           unless every sampled pair then lies within ``max_correspondence_distance``
           (Open3D's distance checker), and are scored by the truncated squared error
           (MSAC, Torr & Zisserman 2000)

           .. math::

               E(R, t) = \sum_i \min\big(\lVert R x_i + t - y_i \rVert^2, \tau^2\big)

           over the candidate pairs (features) or over the source points and their nearest
           target points (no features), :math:`\tau` = ``max_correspondence_distance``. The
           hypothesis of least error is kept; its inliers (residual :math:`\le\tau`) give the
           inlier ratio :math:`w` of the candidates.
        4. **Stopping**: after :math:`N = \log(1 - c) / \log(1 - w^s)` hypotheses for the
           ``confidence`` :math:`c` (the number after which an all-inlier sample has been
           drawn with probability :math:`c`), or ``max_iterations``. With features and no
           ``voxel_size``, never before 4096 hypotheses; then the 100 of least error are
           re-scored by the truncated error of the down-sampled source against the
           down-sampled target (threshold :math:`\tau`), the best 5 distinct poses refined
           by 10 ICP iterations (``refine``) and compared on the full sets
           (threshold :math:`\tau_s`): the pose with the most matches is not always the one
           that fits (an airplane turned over on its back shares most of its features).
        5. **Refinement** (``refine``): ICP from the RANSAC transform
           (:func:`~algorithms.registration.icp`, point-to-plane against the (down-sampled)
           target with its normals in 3-D when it has at least 30 points and is not flat, else
           point-to-point; at most 20,000 source points, pairs within
           ``max_correspondence_distance``); kept only when it lowers the truncated error
           :math:`\sum_i \min(r_i^2, \tau^2)` of its metric (plane or point distances).
           With features and no ``voxel_size``: against the full target (normals of 10
           neighbours) with Tukey's kernel (its scale from the median residual, so that the
           points outside the overlap do not pull the pose; a plain threshold of
           :math:`1.5 h` left 1-3° on the pyvista ant and airplane crops, the kernel
           0.2-1°), kept when it lowers the truncated point error at :math:`\tau_s`.

        Parameters
        ----------
        source : (n, d) float array
            The points to move; ``d = 3`` with features, any ``d >= 2`` without.
        target : (m, d) float array
            The points to register onto, same ``d``, any size ``m``; the overlap may be
            partial. No correspondence with ``source`` and no start are needed.
        features : {"fpfh", "none"}, default "fpfh"
            Where candidate pairs come from: ``"fpfh"`` (3-D) from Fast Point Feature
            Histograms matched between the sets; ``"none"`` every pair of a source and a target
            point, samples of point triples drawn from each set at random. ``"none"`` needs no
            local structure but finds an all-inlier sample with probability about
            :math:`(k/nm)^3` per hypothesis (``k`` overlapping points): it is for small sets,
            tens of points.
        voxel_size : float, optional
            Down-sample both sets on a grid of this step first (``> 0``); also the length
            scale of the default radii; one pass of Open3D's pipeline (normals of 10
            neighbours). Noisy scans need a voxel several times the noise. When omitted with
            features: two passes, at 1.5 and 3 × the source's point spacing (median distance
            to the 4th nearest neighbour, :func:`~.features.point_spacing`), with normals of
            30 neighbours, and the best-fitting pose wins; without features: no
            down-sampling, the scale is the point spacing.
        feature_radius : float, optional
            FPFH neighbourhood radius (``> 0``). Omitted: 5 × the length scale, the voxel step
            of the pass (``voxel_size`` or a default pass's) or, without down-sampling, the
            source's point spacing.
        max_correspondence_distance : float, optional
            The inlier threshold :math:`\tau` (``> 0``) of scoring, checking, refinement and
            the reported ``fitness``. Omitted: 1.5 × the length scale (the voxel step, or the
            source's point spacing without down-sampling), except with
            ``features="none"`` and no ``voxel_size``: half the median distance from a source
            point to its nearest neighbour (so that a point's partner is unambiguous).
        max_iterations : int, default 100000
            Most hypotheses (samples) to draw, ``>= 1``; the default is Open3D's.
        confidence : float, default 0.999
            Stop once an all-inlier sample has been drawn with this probability (estimated
            from the best inlier ratio), ``0 < confidence <= 1``; 1 never stops early.
        mutual_filter : bool, default True
            Keep only mutual nearest neighbours in feature space; falls back to the one-sided
            matches when fewer than 9 remain (as Open3D). False: each point's nearest
            neighbour in feature space, from both sets (each pair once).
        refine : bool, default True
            Refine the RANSAC transform with ICP (point-to-plane in 3-D when the target has
            enough points, else point-to-point), kept only when it lowers the truncated
            error.
        seed : int or numpy.random.Generator, default 0
            Seeds the sampling; the same seed gives the same result, bit for bit (no step
            depends on the number of threads).
        wait : float, optional
            Answer with the results if the job ends within this many seconds; None (default):
            answer at once, the job runs in the background.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit).

        Returns
        -------
        AsyncJob
            The job of ``registration.ransac``; its results hold ``transform``, ``rotation``, ``translation``, ``rmse``, ``fitness``, ``inlier_count``, ``correspondence_count``, ``iterations``, ``converged``, ``reason``.

        Raises
        ------
        InvalidInput
            The service refused an input; ``errors`` names it.
        QueueFull
            Too many jobs are queued; retry after ``retry_after`` seconds.

        References
        ----------
        .. [1] M. A. Fischler and R. C. Bolles, "Random sample consensus", Comm. ACM 24(6),
           381-395, 1981.
        .. [2] P. H. S. Torr and A. Zisserman, "MLESAC: a new robust estimator with
           application to estimating image geometry", CVIU 78(1), 138-156, 2000 (MSAC).
        .. [3] R. B. Rusu, N. Blodow and M. Beetz, "Fast Point Feature Histograms (FPFH) for
           3D registration", ICRA 2009.
        .. [4] Q.-Y. Zhou, J. Park and V. Koltun, "Open3D: a modern library for 3D data
           processing", arXiv:1801.09847, 2018 (checkers, fitness, stopping rule).
        """
        inputs = {"source": source, "target": target, "features": features, "voxel_size": voxel_size, "feature_radius": feature_radius, "max_correspondence_distance": max_correspondence_distance, "max_iterations": max_iterations, "confidence": confidence, "mutual_filter": mutual_filter, "refine": refine, "seed": seed}
        return await self._client.execute(
            "registration.ransac",
            wait=wait,
            outputs=outputs,
            idempotency_key=idempotency_key,
            time_limit=time_limit,
            **_changed(inputs, _DEFAULTS_REGISTRATION_RANSAC),
        )


class AsyncTypedCalls:
    """The typed calls of :class:`AsyncClient`: one attribute per family of processes."""

    __slots__ = ()

    @property
    def alignment(self) -> AsyncAlignment:
        """The alignment processes."""
        return AsyncAlignment(cast("AsyncClient", self))

    @property
    def assignment(self) -> AsyncAssignment:
        """The assignment processes."""
        return AsyncAssignment(cast("AsyncClient", self))

    @property
    def classification(self) -> AsyncClassification:
        """The classification processes."""
        return AsyncClassification(cast("AsyncClient", self))

    @property
    def layout(self) -> AsyncLayout:
        """The layout processes."""
        return AsyncLayout(cast("AsyncClient", self))

    @property
    def clustering(self) -> AsyncClustering:
        """The clustering processes."""
        return AsyncClustering(cast("AsyncClient", self))

    @property
    def deformation(self) -> AsyncDeformation:
        """The deformation processes."""
        return AsyncDeformation(cast("AsyncClient", self))

    @property
    def embedding(self) -> AsyncEmbedding:
        """The embedding processes."""
        return AsyncEmbedding(cast("AsyncClient", self))

    @property
    def interpolation(self) -> AsyncInterpolation:
        """The interpolation processes."""
        return AsyncInterpolation(cast("AsyncClient", self))

    @property
    def parameterization(self) -> AsyncParameterization:
        """The parameterization processes."""
        return AsyncParameterization(cast("AsyncClient", self))

    @property
    def registration(self) -> AsyncRegistration:
        """The registration processes."""
        return AsyncRegistration(cast("AsyncClient", self))
