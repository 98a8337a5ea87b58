"""Catalog entries of the layout family (positions for a mesh's vertices or a graph's nodes
with pins, or for points known by their pairwise distances)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

import numpy as np
from pydantic import (
    Field,
    PlainSerializer,
    PlainValidator,
    ValidationInfo,
    WithJsonSchema,
    model_validator,
)

from algorithms.core.errors import InvalidInputError
from algorithms.core.mesh import Handles, Mesh, as_handles
from algorithms.core.mesh import edges as mesh_edges
from algorithms.core.validation import as_points, as_weights
from algorithms.layout import (
    Graph,
    LaplacianLayoutResult,
    MDSResult,
    PoissonLayoutResult,
    StressResult,
    as_graph,
    laplacian,
    mds,
    poisson,
    stress,
)
from algorithms.layout._inputs import (
    MAX_DENSE_POINTS,
    as_distance_matrix,
    distance_pairs_matrix,
)
from service.catalog.base import Params
from service.catalog.inputs import GraphInput, MeshInput, Points, Weights
from service import scenes
from service.catalog.registry import Process, registry


# -- input types -----------------------------------------------------------------------------
def _validate_pins(value: Any, info: ValidationInfo) -> Handles:
    name = info.field_name or "pins"
    if not isinstance(value, (Handles, dict)):
        raise InvalidInputError(f"Expected `{name}` to be an object with keys 'indices' and "
                                f"'positions', got {type(value).__name__}.", field=name)
    return as_handles(value, None, name=name)  # against the mesh or graph: model validator


def _pins_json(h: Handles) -> dict[str, Any]:
    return {"indices": h.indices.tolist(), "positions": h.positions.tolist()}


PinsInput = Annotated[
    Handles,
    PlainValidator(_validate_pins),
    PlainSerializer(_pins_json),
    WithJsonSchema({
        "type": "object",
        "description": "Vertices (nodes) held at given positions: their indices and "
        "positions, in the layout's dimension.",
        "properties": {
            "indices": {"type": "array", "minItems": 1, "description": "Distinct vertex "
                        "(node) indices, 0-based.", "items": {"type": "integer", "minimum": 0}},
            "positions": {"type": "array", "minItems": 1, "description": "The position of "
                          "each, row i for indices[i]; k ≥ 2 coordinates.",
                          "items": {"type": "array", "items": {"type": "number"},
                                    "minItems": 2}},
        },
        "required": ["indices", "positions"],
        "additionalProperties": False,
    }),
]
"""Pinned vertices ``{"indices": [...], "positions": [[...], ...]}`` in any dimension
``k >= 2``, validated into :class:`algorithms.core.mesh.Handles` (structure only)."""


def _max_dense(info: ValidationInfo) -> int:
    limit = (info.context or {}).get("max_points")
    return MAX_DENSE_POINTS if limit is None else min(MAX_DENSE_POINTS, int(limit))


def _validate_distances(value: Any, info: ValidationInfo) -> np.ndarray:
    return as_distance_matrix(value, name=info.field_name or "distances",
                              max_points=_max_dense(info))


def _validate_pairs(value: Any, info: ValidationInfo) -> np.ndarray:
    name = info.field_name or "distance_pairs"
    return as_points(value, name=name, dim=3, max_points=_max_dense(info) ** 2)


def _nullable_list(a: np.ndarray) -> list[Any]:
    return [[None if np.isnan(x) else float(x) for x in row] for row in a]


def _tolist(a: np.ndarray) -> list[Any]:
    return a.tolist()


DistanceMatrix = Annotated[
    np.ndarray,
    PlainValidator(_validate_distances),
    PlainSerializer(_nullable_list),
    WithJsonSchema({
        "type": "array",
        "description": "An (n, n) matrix of pairwise distances: non-negative, zero diagonal; "
        "null marks an unknown distance.",
        "items": {"type": "array", "items": {"type": ["number", "null"], "minimum": 0}},
        "minItems": 2,
    }),
]
"""An ``(n, n)`` distance matrix, ``null`` (NaN) for unknown entries."""

DistancePairs = Annotated[
    np.ndarray,
    PlainValidator(_validate_pairs),
    PlainSerializer(_tolist),
    WithJsonSchema({
        "type": "array",
        "description": "Known distances as rows (i, j, d): points i and j (0-based) are d "
        "apart.",
        "items": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3},
        "minItems": 1,
    }),
]
"""Known distances as ``(m, 3)`` rows ``(i, j, d)``."""


# -- shared checks ---------------------------------------------------------------------------
def _one_of(values: dict[str, Any], default: str) -> None:
    given = [k for k, v in values.items() if v is not None]
    if len(given) != 1:
        names = ", ".join(f"`{k}`" for k in values)
        got = "none" if not given else " and ".join(f"`{g}`" for g in given)
        raise InvalidInputError(f"Expected exactly one of {names}, got {got}.",
                                field=given[1] if len(given) > 1 else default)


def _node_count(mesh: Mesh | None, graph: Graph | None) -> int:
    return mesh.n_vertices if mesh is not None else graph.n_nodes  # type: ignore[union-attr]


_WEIGHTING = ("Mesh edge weights: uniform (Tutte's barycentric map), cotangent (harmonic; "
              "negative across obtuse angles, faces may flip) or tangent (Floater's mean "
              "value weights, never negative: no flips). A graph takes only uniform (its own "
              "weights).")
_GRAPH = ("A graph {nodes: n, edges: (e, 2) node indices, weights?: (e,) non-negative}, "
          "instead of mesh.")

_SQUARE = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]],
           "faces": [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]}
_PATH = {"nodes": 3, "edges": [[0, 1], [1, 2]]}
_TRIANGLE = [[0, 3, 4], [3, 0, 5], [4, 5, 0]]
_SQUARE_DISTANCES = [[0, 1, 1.4142135623730951, 1], [1, 0, 1, None],
                     [1.4142135623730951, 1, 0, 1], [1, None, 1, 0]]


# -- layout.laplacian ------------------------------------------------------------------------
class LaplacianParams(Params):
    mesh: MeshInput | None = Field(
        None, description="A triangle mesh {vertices: (n, 2|3), faces: (m, 3)}; without "
        "pins its longest boundary loop is pinned to the unit circle (Tutte's embedding). "
        "Exactly one of mesh and graph.", examples=[_SQUARE])
    graph: GraphInput | None = Field(None, description=_GRAPH + " Its weights are the spring "
                                     "stiffnesses; it needs pins.")
    pins: PinsInput | None = Field(
        None, description="Pinned vertices {indices: (p,), positions: (p, k)}, any dimension "
        "k ≥ 2; at least one in every connected component. Default for a mesh: its boundary "
        "on the unit circle.")
    weighting: Literal["uniform", "cotangent", "tangent"] = Field(
        "uniform", description=_WEIGHTING)
    boundary_spacing: Literal["arc_length", "uniform"] = Field(
        "arc_length", description="How the default boundary is spread over the circle: by "
        "the lengths of its edges, or evenly.")

    @model_validator(mode="after")
    def _consistent(self) -> LaplacianParams:
        _one_of({"mesh": self.mesh, "graph": self.graph}, "mesh")
        if self.graph is not None and self.weighting != "uniform":
            raise InvalidInputError(
                f"Expected `weighting` to be 'uniform' with a `graph` (its own weights are the "
                f"springs; {self.weighting} weights need a mesh), got {self.weighting!r}.",
                field="weighting")
        if self.pins is not None:
            as_handles(self.pins, _node_count(self.mesh, self.graph), name="pins")
        elif self.graph is not None:
            raise InvalidInputError("Expected `pins` with a `graph` (a graph has no boundary "
                                    "to pin by default), got none.", field="pins")
        return self


registry.add(Process(
    id="layout.laplacian",
    geometry=scenes.layout,
    title="Laplacian (spring) layout; Tutte embedding",
    description="Places every free vertex at the weighted average of its neighbours, some "
    "vertices pinned: L₀₀x = −L₀₁c, one factored solve for all coordinates. A mesh's boundary "
    "pinned to the unit circle by default (Tutte's embedding: with uniform or tangent weights "
    "no face flips). Reports the spring energy and flipped faces.",
    function=laplacian,
    params=LaplacianParams,
    result=LaplacianLayoutResult,
    reference="Tutte, W. T. (1963). How to draw a graph. Proc. London Math. Soc. 13, 743–767; "
    "Floater, M. S. (2003). Mean value coordinates. CAGD 20(1), 19–27.",
    fast_path=True,
    keywords=("tutte embedding", "spring layout", "parameterization", "graph drawing",
              "harmonic map"),
))


# -- layout.poisson --------------------------------------------------------------------------
class PoissonParams(Params):
    mesh: MeshInput | None = Field(
        None, description="A triangle mesh; its edges are its unique edges (i, j), i < j, "
        "sorted. Exactly one of mesh and graph.")
    graph: GraphInput | None = Field(None, description=_GRAPH + " Edges keep their order and "
                                     "orientation; weights w (default 1).", examples=[_PATH])
    vectors: Points = Field(
        description="The target of p_i − p_j for each edge row (i, j), in edge order: an "
        "(e, k) array, k ≥ 2 the dimension of the layout.",
        examples=[[[-1.0, 0.0], [-1.0, 0.0]]])
    anchors: PinsInput | None = Field(
        None, description="Soft targets z {indices: (a,), positions: (a, k)}: the term "
        "Σ uᵢ‖pᵢ − zᵢ‖². A component with neither anchors nor pins is centred at the origin.",
        examples=[{"indices": [0], "positions": [[0.0, 0.0]]}])
    anchor_weights: Weights | None = Field(
        None, description="The weight uᵢ ≥ 0 of each anchor, in the order of anchors.indices; "
        "default 1.")
    pins: PinsInput | None = Field(
        None, description="Hard constraints {indices: (p,), positions: (p, k)}, met exactly.")
    weighting: Literal["uniform", "cotangent", "tangent"] = Field(
        "uniform", description="Mesh edge weights w: uniform, cotangent or tangent. A graph "
        "takes only uniform (its own weights).")

    @model_validator(mode="after")
    def _consistent(self) -> PoissonParams:
        _one_of({"mesh": self.mesh, "graph": self.graph}, "mesh")
        if self.graph is not None and self.weighting != "uniform":
            raise InvalidInputError(
                f"Expected `weighting` to be 'uniform' with a `graph` (its own weights are "
                f"used; {self.weighting} weights need a mesh), got {self.weighting!r}.",
                field="weighting")
        n = _node_count(self.mesh, self.graph)
        e = mesh_edges(self.mesh.faces).shape[0] if self.mesh is not None else \
            self.graph.edges.shape[0]  # type: ignore[union-attr]
        if self.vectors.shape[0] != e:
            what = "mesh` (its unique edges i < j sorted" if self.mesh is not None else "graph`"
            raise InvalidInputError(
                f"Expected `vectors` to hold one row per edge of `{what}, {e}), got "
                f"{self.vectors.shape[0]}.", field="vectors")
        k = self.vectors.shape[1]
        for name in ("anchors", "pins"):
            h = getattr(self, name)
            if h is not None:
                as_handles(h, n, name=name)
                if h.positions.shape[1] != k:
                    raise InvalidInputError(
                        f"Expected `{name}.positions` to have the dimension of `vectors` ({k}), "
                        f"got shape {h.positions.shape}.", field=f"{name}.positions")
        if self.anchor_weights is not None:
            if self.anchors is None:
                raise InvalidInputError("Expected `anchor_weights` only together with "
                                        "`anchors`, got weights without anchors.",
                                        field="anchor_weights")
            as_weights(self.anchor_weights, self.anchors.indices.shape[0],
                       name="anchor_weights")
        return self


registry.add(Process(
    id="layout.poisson",
    geometry=scenes.layout,
    title="Poisson layout (edge vectors to match, soft anchors)",
    description="Positions whose edge differences best match given vectors, pulled towards "
    "anchors and held at pins: min Σ wᵢⱼ‖(pᵢ − pⱼ) − vᵢⱼ‖² + Σ uᵢ‖pᵢ − zᵢ‖², solved as "
    "(DᵀWD + U)x = DᵀWv + Uz with one sparse factorization.",
    function=poisson,
    params=PoissonParams,
    result=PoissonLayoutResult,
    reference="Pérez, P., Gangnet, M., Blake, A. (2003). Poisson image editing. ACM TOG "
    "22(3), 313–318.",
    fast_path=True,
    keywords=("poisson", "gradient domain", "least squares", "integration", "anchors"),
))


# -- layout.mds and layout.stress ------------------------------------------------------------
_DISTANCES = ("Pairwise distances: an (n, n) matrix, non-negative, zero diagonal; null marks "
              "an unknown distance. Exactly one of distances, distance_pairs and graph.")
_PAIRS = "Instead of distances: the known distances as rows (i, j, d); the rest are unknown."
_N_POINTS = "With distance_pairs: the number of points (default: the largest index + 1)."
_DGRAPH = ("Instead of distances: a connected graph {nodes, edges, weights?}; the distances "
           "are its shortest-path lengths, weights being edge lengths (default 1).")


class _DistanceParams(Params):
    distances: DistanceMatrix | None = Field(None, description=_DISTANCES)
    distance_pairs: DistancePairs | None = Field(None, description=_PAIRS)
    n_points: int | None = Field(None, ge=2, description=_N_POINTS)
    graph: GraphInput | None = Field(None, description=_DGRAPH)
    n_components: int = Field(2, ge=1, description="The dimension k of the layout.")

    @model_validator(mode="after")
    def _one_source(self) -> _DistanceParams:
        _one_of({"distances": self.distances, "distance_pairs": self.distance_pairs,
                 "graph": self.graph}, "distances")
        if self.n_points is not None and self.distance_pairs is None:
            raise InvalidInputError("Expected `n_points` only together with `distance_pairs` "
                                    "(the other inputs fix the number of points).",
                                    field="n_points")
        if self.distance_pairs is not None:
            n = distance_pairs_matrix(self.distance_pairs, self.n_points).shape[0]
        elif self.distances is not None:
            n = self.distances.shape[0]
        else:
            n = self.graph.n_nodes  # type: ignore[union-attr]
        if self.n_components > n:
            raise InvalidInputError(f"Expected `n_components` to be at most the number of "
                                    f"points ({n}), got {self.n_components}.",
                                    field="n_components")
        return self


class MDSParams(_DistanceParams):
    distances: DistanceMatrix | None = Field(None, description=_DISTANCES,
                                             examples=[_TRIANGLE])
    rank: int | None = Field(None, ge=1, description="Rank of the completed squared-distance "
                             "matrix; default n_components + 2. Only used when distances "
                             "are missing.")
    max_iterations: int = Field(500, ge=0, le=100_000, description="Refinement iterations of "
                                "the completion after its one-shot estimate (0: the one-shot "
                                "estimate of Drineas et al. only).")
    tolerance: float = Field(1e-7, ge=0, description="The completion stops when the missing "
                             "squared distances change by less than this, relatively.")


registry.add(Process(
    id="layout.mds",
    geometry=scenes.layout,
    title="Classical multidimensional scaling (with completion of missing distances)",
    description="Coordinates from the top eigenvectors of the double-centred squared "
    "distances −½JD⁽²⁾J. Missing distances are completed first: rank-(k+2) truncation of "
    "the squared distances (Drineas et al.'s one-shot estimate), refined by alternating "
    "projections. Reports the stress over the known pairs.",
    function=mds,
    params=MDSParams,
    result=MDSResult,
    reference="Torgerson, W. S. (1952). Multidimensional scaling: I. Theory and method. "
    "Psychometrika 17; Drineas, P. et al. (2006). Distance matrix reconstruction from "
    "incomplete distance information for sensor network localization. IEEE SECON.",
    keywords=("mds", "torgerson", "principal coordinates", "matrix completion",
              "localization"),
))


class StressParams(_DistanceParams):
    distances: DistanceMatrix | None = Field(None, description=_DISTANCES + " Unknown "
                                             "distances get weight 0.",
                                             examples=[_SQUARE_DISTANCES])
    weighting: Literal["inverse_square", "inverse", "uniform"] = Field(
        "inverse_square", description="wᵢⱼ = dᵢⱼ⁻² (Gansner, Koren and North: relative "
        "errors), dᵢⱼ⁻¹, or 1 (scikit-learn's metric MDS: absolute errors).")
    init: Literal["classical", "random"] = Field(
        "classical", description="The starting layout: classical MDS (completing missing "
        "distances first) or standard normal coordinates drawn with seed.")
    initial_positions: Points | None = Field(
        None, description="A starting layout (n, k); overrides init.")
    max_iterations: int = Field(300, ge=0, le=100_000, description="Most Guttman transforms.")
    tolerance: float = Field(1e-6, ge=0, description="Stop when one iteration lowers the "
                             "stress by less than this fraction of Σ wᵢⱼ‖xᵢ − xⱼ‖² "
                             "(scikit-learn's rule); 0 runs all max_iterations.")
    relaxation: float = Field(1.0, ge=1.0, lt=2.0, description="Step α of the relaxed update "
                              "X + α(V⁺B(X)X − X): 1 is plain SMACOF; up to 2 (excluded) "
                              "needs fewer iterations, the stress still never rises.")
    seed: int = Field(0, ge=0, description="Seed of the random start.")

    @model_validator(mode="after")
    def _start_fits(self) -> StressParams:
        x = self.initial_positions
        if x is not None and x.shape[1] != self.n_components:
            raise InvalidInputError(
                f"Expected `initial_positions` to have n_components = {self.n_components} "
                f"columns, got shape {x.shape}.", field="initial_positions")
        return self


registry.add(Process(
    id="layout.stress",
    geometry=scenes.layout,
    title="Stress majorization (SMACOF)",
    description="The layout minimising the weighted stress Σ wᵢⱼ(‖xᵢ − xⱼ‖ − dᵢⱼ)² over the "
    "known pairs by Guttman transforms (never increasing), from classical MDS; distances "
    "from a matrix, a list of pairs, or a graph's shortest paths. Progress per iteration, "
    "cancellable; reports the stress history.",
    function=stress,
    params=StressParams,
    result=StressResult,
    reference="Gansner, E. R., Koren, Y., North, S. (2004). Graph drawing by stress "
    "majorization. Graph Drawing 2004, LNCS 3383, 239–250.",
    long=True,
    keywords=("smacof", "stress majorization", "metric mds", "graph drawing",
              "kamada-kawai"),
))
