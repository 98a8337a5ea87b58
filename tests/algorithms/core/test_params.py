"""Parameter declarations: what a signature declares is what every call is held to."""

from __future__ import annotations

import inspect
from typing import Annotated, Any, Literal

import numpy as np
import pytest
from annotated_types import MultipleOf

from algorithms.core.errors import InvalidInputError
from algorithms.core.params import (
    Ge,
    Gt,
    Interval,
    Kind,
    Le,
    Lt,
    PointsLike,
    Scalar,
    Seed,
    WeightsLike,
    declarations,
    validate_params,
)


@validate_params
def _method(
    points: PointsLike,
    k: Annotated[int, Ge(1)] = 3,
    *,
    model: Literal["rigid", "affine"] = "rigid",
    tolerance: Annotated[float, Ge(0)] = 1e-6,
    overlap: Annotated[float, Interval(gt=0, le=1)] = 1.0,
    radius: Annotated[float, Gt(0)] | None = None,
    odd: Annotated[int, Gt(0), Lt(10)] = 5,
    rate: Annotated[float, Gt(0)] | Literal["auto"] = "auto",
    init: Literal["identity", "pca"] | Annotated[Any, Kind.ARRAY] = "identity",
    flag: bool = False,
    weights: WeightsLike | None = None,
    seed: Seed = 0,
    progress: Any = None,
) -> dict[str, Any]:
    """Return what arrived, to see what the validator handed over."""
    return dict(points=points, k=k, model=model, tolerance=tolerance, overlap=overlap,
                radius=radius, odd=odd, rate=rate, init=init, flag=flag, weights=weights,
                seed=seed)


def test_defaults_pass_untouched() -> None:
    got = _method("anything")
    assert got["points"] == "anything"  # arrays are the function's own business
    assert (got["k"], got["model"], got["rate"], got["seed"]) == (3, "rigid", "auto", 0)


def test_values_are_converted() -> None:
    got = _method(None, np.int64(4), tolerance=1, overlap=np.float32(0.5), flag=np.bool_(True),
                  odd=7.0, seed=np.int32(9))
    assert type(got["k"]) is int and got["k"] == 4
    assert type(got["tolerance"]) is float and got["tolerance"] == 1.0
    assert type(got["overlap"]) is float and got["flag"] is True
    assert type(got["odd"]) is int and got["odd"] == 7
    assert type(got["seed"]) is int and got["seed"] == 9


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"k": 0}, "Expected `k` to be an integer >= 1, got 0."),
    ({"k": 2.5}, "Expected `k` to be an integer, got 2.5."),
    ({"k": True}, "Expected `k` to be an integer, got True."),
    ({"model": "similarity"}, "Expected `model` to be one of 'rigid', 'affine', got 'similarity'."),
    ({"model": 1}, "Expected `model` to be one of 'rigid', 'affine', got 1."),
    ({"tolerance": -1e-9}, "Expected `tolerance` to be a number >= 0, got -1e-09."),
    ({"tolerance": float("nan")}, "Expected `tolerance` to be a finite number, got nan."),
    ({"tolerance": "1"}, "Expected `tolerance` to be a number, got '1'."),
    ({"overlap": 0.0}, "Expected `overlap` to be a number > 0 and <= 1, got 0.0."),
    ({"overlap": 1.5}, "Expected `overlap` to be a number > 0 and <= 1, got 1.5."),
    ({"radius": 0}, "Expected `radius` to be a number > 0, got 0.0."),
    # open integer bounds are the closed ones they mean
    ({"odd": 0}, "Expected `odd` to be an integer >= 1 and <= 9, got 0."),
    ({"odd": 10}, "Expected `odd` to be an integer >= 1 and <= 9, got 10."),
    ({"rate": -1.0}, "Expected `rate` to be a number > 0, got -1.0."),
    ({"rate": "fast"}, "Expected `rate` to be one of 'auto', got 'fast'."),
    ({"rate": None}, "Expected `rate` to be a number > 0 or one of 'auto', got None."),
    ({"init": "random"}, "Expected `init` to be one of 'identity', 'pca', got 'random'."),
    ({"init": 3}, "Expected `init` to be one of 'identity', 'pca' or an array (array), got 3."),
    ({"flag": "false"}, "Expected `flag` to be true or false, got 'false'."),
    ({"flag": 0}, "Expected `flag` to be true or false, got 0."),
    ({"seed": -1}, "Expected `seed` to be an integer >= 0, got -1."),
    ({"seed": 1.5}, "Expected `seed` to be an integer, got 1.5."),
])
def test_declarations_are_enforced(kwargs: dict[str, Any], message: str) -> None:
    with pytest.raises(InvalidInputError) as info:
        _method(None, **kwargs)
    assert str(info.value) == message
    assert info.value.field == next(iter(kwargs))


def test_positional_arguments_are_checked() -> None:
    with pytest.raises(InvalidInputError, match="`k` to be an integer >= 1, got -3"):
        _method(None, -3)


def test_optional_none_and_alternatives_pass() -> None:
    gen = np.random.default_rng(0)
    got = _method(None, radius=None, rate=0.5, init=[[1.0]], seed=gen, weights=[1, 2])
    assert got["radius"] is None and got["rate"] == 0.5 and got["init"] == [[1.0]]
    assert got["seed"] is gen and got["weights"] == [1, 2]
    assert _method(None, seed=None)["seed"] is None  # RngLike admits None


def test_unknown_keyword_is_python_s_own_error() -> None:
    with pytest.raises(TypeError, match="max_iter"):
        _method(None, max_iter=3)


def test_signature_and_docs_are_the_function_s() -> None:
    assert list(inspect.signature(_method).parameters)[:2] == ["points", "k"]
    assert _method.__doc__ == "Return what arrived, to see what the validator handed over."
    assert _method.__name__ == "_method"


def test_declarations_read_every_parameter_but_progress() -> None:
    d = declarations(_method)
    assert "progress" not in d and list(d)[:3] == ["points", "k", "model"]
    assert d["points"].kind is Kind.POINTS and d["points"].required and not d["points"].checked
    assert d["weights"].kind is Kind.WEIGHTS and d["weights"].optional
    assert d["k"].scalars == (Scalar(int, (), 1, None, (True, True)),) and d["k"].default == 3
    assert d["overlap"].scalars == (Scalar(float, (), 0, 1, (False, True)),)
    assert d["odd"].scalars == (Scalar(int, (), 1, 9, (True, True)),)
    assert d["radius"].optional and not d["tolerance"].optional
    assert [s.type for s in d["rate"].scalars] == [float, str]
    assert d["init"].kind is Kind.ARRAY and d["init"].scalars[0].choices == ("identity", "pca")
    assert d["seed"].kind is Kind.SEED and d["seed"].checked
    assert d["flag"].scalars == (Scalar(bool),)


def test_unknown_constraint_is_refused_when_read() -> None:
    def f(x: Annotated[int, MultipleOf(2)] = 2) -> None: ...

    with pytest.raises(TypeError, match="unsupported constraint"):
        declarations(f)


def test_literal_of_non_strings_is_refused() -> None:
    def f(x: Literal[1, 2] = 1) -> None: ...

    with pytest.raises(TypeError, match="Literal choices must be strings"):
        declarations(f)


def test_le_bound_and_words() -> None:
    assert Scalar(float, (), None, 2.5, (True, False)).words() == "a number < 2.5"
    assert Scalar(int, (), 1, 9).words() == "an integer >= 1 and <= 9"
    assert Scalar(str, ("a", "b")).words() == "one of 'a', 'b'"

    @validate_params
    def g(x: Annotated[float, Le(2)] = 0.0) -> float:
        return x

    assert g(x=2) == 2.0
    with pytest.raises(InvalidInputError, match=r"<= 2, got 2.5"):
        g(x=2.5)
