"""Tests for registration.multiway, the dispatcher: with correspondences it is generalised
Procrustes, without them the pose graph, bit for bit; the other method's options are
ignored; every error branch names its input, down to the set (``sets[2]``)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from algorithms.core import ConvergenceWarning, DegenerateInputError, InvalidInputError
from algorithms.registration import generalized_procrustes, multiway, pose_graph
from tests.algorithms.registration._shapes import blob, random_rotation
from tests.algorithms.registration._views import apply, assert_same_fields, homogeneous, views


def _noisy_copies(k: int = 4, d: int = 3, seed: int = 0) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    x = rng.standard_normal((20, d))
    return [apply(homogeneous(random_rotation(rng, d), rng.normal(size=d)), x)
            + 0.05 * rng.standard_normal(x.shape) for _ in range(k)]


@pytest.mark.parametrize("model", ["rigid", "similarity"])
def test_with_correspondences_it_is_generalised_procrustes(model):
    sets = _noisy_copies()
    init = np.stack([homogeneous(random_rotation(np.random.default_rng(i)), [i, 0, 0])
                     for i in range(4)])
    assert_same_fields(multiway(sets, model=model), generalized_procrustes(sets, model=model))
    with pytest.warns(ConvergenceWarning, match="max_iterations = 3"):
        a = multiway(sets, model=model, init=init, max_iterations=3, tolerance=0.0)
    with pytest.warns(ConvergenceWarning, match="max_iterations = 3"):
        b = generalized_procrustes(sets, model=model, init=init, max_iterations=3,
                                   tolerance=0.0)
    assert_same_fields(a, b)


def test_without_correspondences_it_is_the_pose_graph():
    sets, _ = views(blob, k=3, n=300, seed=4)
    kw = {"metric": "point_to_plane", "neighbors": 2, "min_fitness": 0.2,
          "icp_max_iterations": 10}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        assert_same_fields(multiway(sets, correspondences=False, **kw), pose_graph(sets, **kw))


def test_the_other_methods_options_are_ignored():
    sets = _noisy_copies(seed=1)
    assert_same_fields(multiway(sets, metric="point_to_point", neighbors=1, min_fitness=0.9,
                   edge_prune_threshold=0.5, preference_loop_closure=3.0,
                   icp_max_iterations=2, max_correspondence_distance=0.1),
          multiway(sets))


def test_the_pose_graph_refuses_similarity():
    cube = blob(50)
    with pytest.raises(InvalidInputError, match="model='rigid' with correspondences=false") \
            as err:
        multiway([cube, cube], correspondences=False, model="similarity")
    assert err.value.field == "model"


# --- errors -------------------------------------------------------------------------------

SQ = [[0, 0], [1, 0], [0, 1], [1, 1]]
CUBE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, 0, 1], [0, 1, 1]]


@pytest.mark.parametrize("kw, field, fragment", [
    ({"sets": [SQ]}, "sets", "at least 2 point sets, got 1"),
    ({"sets": "abc"}, "sets", "list of (n, d) point arrays"),
    ({"sets": [SQ, SQ, SQ[:3]]}, "sets[2]", "as many points as `sets[0]` (4"),
    ({"sets": [SQ, [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]]}, "sets[1]",
     "dimension of `sets[0]` (2)"),
    ({"sets": [SQ, SQ, [[0, 0], [1, float("nan")], [0, 1], [1, 1]]]}, "sets[2]",
     "nan at row 1"),
    ({"sets": [SQ, SQ, [[1, 1]] * 4, SQ], "model": "similarity"}, "sets[2]", "coincident"),
    ({"sets": [SQ, SQ], "correspondences": False}, "sets", "3-D"),
    ({"sets": [CUBE, CUBE], "correspondences": False, "model": "similarity"}, "model",
     "rigid"),
    ({"sets": [CUBE, CUBE[:4]], "correspondences": False}, "sets[1]", "at least 6"),
    ({"sets": [SQ, SQ], "model": "affine"}, "model", "one of 'rigid', 'similarity'"),
    ({"sets": [SQ, SQ], "init": np.eye(3)}, "init", "(2, 3, 3)"),
    ({"sets": [SQ, SQ], "init": [np.eye(3), 2 * np.eye(3)]}, "init", "init[1]"),
    ({"sets": [CUBE, CUBE], "correspondences": False, "neighbors": 2}, "neighbors",
     "an integer >= 1 and <= 1 (the number of other sets), got 2"),
    ({"sets": [SQ, SQ], "neighbors": 0}, "neighbors", ">= 1"),
    ({"sets": [CUBE, CUBE], "correspondences": False, "min_fitness": 1.5}, "min_fitness",
     "<= 1"),
    ({"sets": [CUBE, CUBE], "correspondences": False, "max_correspondence_distance": 0},
     "max_correspondence_distance", "> 0"),
    ({"sets": [SQ, SQ], "correspondences": "no"}, "correspondences", "true or false"),
    ({"sets": [SQ, SQ], "max_iterations": 0}, "max_iterations", ">= 1"),
    ({"sets": [SQ, SQ], "tolerance": -1.0}, "tolerance", ">= 0"),
    ({"sets": [SQ, SQ], "metric": "plane"}, "metric", "one of 'symmetric'"),
    ({"sets": [SQ, SQ], "edge_prune_threshold": 1.0}, "edge_prune_threshold", "< 1"),
    ({"sets": [SQ, SQ], "preference_loop_closure": 0.0}, "preference_loop_closure", "> 0"),
    ({"sets": [SQ, SQ], "icp_max_iterations": 0}, "icp_max_iterations", ">= 1"),
])
def test_invalid_inputs_name_the_field(kw, field, fragment):
    sets = kw.pop("sets")
    with pytest.raises(InvalidInputError) as err:
        multiway(sets, **kw)
    assert err.value.field == field
    assert fragment in str(err.value), str(err.value)


def test_flat_sets_are_degenerate():
    line3 = [[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]]
    with pytest.raises(DegenerateInputError, match="collinear") as err:
        multiway([CUBE[:4], CUBE[:4], line3])
    assert err.value.field == "sets[2]"
    with pytest.raises(DegenerateInputError, match="collinear") as err:
        multiway([CUBE, line3 * 2], correspondences=False)
    assert err.value.field == "sets[1]"
    # collinear in 2-D still fixes the rotation (rank d - 1 = 1): fine
    line2 = np.array([[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]])
    res = multiway([line2, line2 @ np.array([[0.0, -1.0], [1.0, 0.0]]).T])
    np.testing.assert_allclose(res.rotations[1], [[0, 1], [-1, 0]], atol=1e-12)


def test_the_dispatcher_declares_what_its_methods_declare():
    """multiway repeats the parameters of generalized_procrustes and pose_graph in its own
    signature: each shared one has the same type, bounds and default there (no drift)."""
    from algorithms.core.params import declarations

    mine = declarations(multiway)
    shared = 0
    for method in (generalized_procrustes, pose_graph):
        for name, decl in declarations(method).items():
            if name in mine and name != "sets":
                shared += 1
                assert (mine[name].scalars, mine[name].kind, mine[name].optional,
                        mine[name].default) == (decl.scalars, decl.kind, decl.optional,
                                                decl.default), (method.__name__, name)
    assert shared == 14
