"""The catalog: every process is well formed, described, runnable on its examples, and its
parameter model is strict (no server, no Dask)."""

from __future__ import annotations

import dataclasses
import inspect
import json
import math
import re
import typing
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest
from pydantic import ValidationError

from algorithms.core.params import Ge, declarations, validate_params
from service import jsonio
from service.catalog import lookup, processes, registry
from service.catalog.registry import (
    DISPLAY_INPUTS,
    Output,
    Process,
    Registry,
    input_description,
    outputs_of,
    references_text,
)
from service.diagnostics import diagnostics
from service.docstrings import (
    numpydoc_entries,
    numpydoc_references,
    numpydoc_section,
    numpydoc_summary,
    plain,
)
from service.problems import pydantic_errors
from service.representation import process_description, process_summary

ALL = [*registry.values(), *diagnostics.values()]
NEVER_RUN = {"diagnostics.crash"}  # ends the process that runs it


def _ids(p: Process) -> str:
    return p.id


def _field_schemas(p: Process) -> dict[str, dict[str, Any]]:
    return p.params.model_json_schema(mode="validation")["properties"]


def _types(schema: dict[str, Any]) -> set[str]:
    """The JSON types a property schema admits besides null."""
    if "anyOf" in schema:
        return set().union(*(_types(s) for s in schema["anyOf"])) - {"null"}
    t = schema.get("type")
    return {t} if isinstance(t, str) else set(t or ())


def _example_inputs(p: Process) -> dict[str, Any]:
    """The first example of every input that has one (required inputs must have one)."""
    out = {}
    for name, schema in _field_schemas(p).items():
        if schema.get("examples"):
            out[name] = schema["examples"][0]
        else:
            assert not p.params.model_fields[name].is_required(), \
                f"{p.id}: required input {name!r} has no example"
    return out


# -- identity ------------------------------------------------------------------------------
def test_catalog_is_not_empty() -> None:
    assert len(registry) >= 2
    assert {"alignment.rigid", "assignment.nearest"} <= set(registry)
    assert set(diagnostics) == {"diagnostics.sleep", "diagnostics.nap", "diagnostics.crash"}
    assert not set(registry) & set(diagnostics)


@pytest.mark.parametrize("p", ALL, ids=_ids)
def test_id_is_family_dot_method(p: Process) -> None:
    assert re.fullmatch(r"[a-z][a-z0-9_]*\.[a-z][a-z0-9_]*", p.id), p.id
    family, method = p.id.split(".")
    assert p.family == family
    # the algorithm's package is named after the family; the method is the function's name
    if p.id in registry:
        assert p.function.__module__.split(".")[:2] == ["algorithms", family]
    assert p.function.__name__ == method
    assert registry.get(p.id, diagnostics.get(p.id)) is p


def test_lookup_and_processes() -> None:
    assert lookup("alignment.rigid") is registry["alignment.rigid"]
    assert lookup("diagnostics.sleep") is None
    assert lookup("diagnostics.sleep", test_processes=True) is diagnostics["diagnostics.sleep"]
    assert lookup("no.such", test_processes=True) is None
    assert processes() == list(registry.values())
    assert processes(test_processes=True) == ALL


# -- descriptions --------------------------------------------------------------------------
@pytest.mark.parametrize("p", ALL, ids=_ids)
def test_every_output_is_described(p: Process) -> None:
    fields = list(p.result.__dataclass_fields__)
    assert list(p.outputs) == fields
    for name, out in p.outputs.items():
        assert out.name == name
        assert out.description.strip(), f"{p.id}: output {name!r} has no description"
        assert out.title.strip()
        assert isinstance(out.schema, dict) and out.schema, f"{p.id}: output {name!r} has no schema"
        assert out.schema.get("type") in ("array", "number", "integer", "boolean", "string",
                                          "object")


@pytest.mark.parametrize("p", ALL, ids=_ids)
def test_every_input_is_described(p: Process) -> None:
    assert p.params.model_fields, p.id
    for name, field in p.params.model_fields.items():
        assert field.description and field.description.strip(), \
            f"{p.id}: input {name!r} has no description"


_SCHEMA_TYPES = {"array", "boolean", "integer", "null", "number", "object", "string"}


def _check_json_schema(s: Any, where: str) -> None:
    """A structural check of the JSON Schema keywords the catalog uses (those of OpenAPI 3.0's
    schema object, which the OGC process description uses: no `const`)."""
    assert isinstance(s, dict), where
    assert "const" not in s, where
    if "type" in s:
        types = s["type"] if isinstance(s["type"], list) else [s["type"]]
        assert types and set(types) <= _SCHEMA_TYPES, (where, s["type"])
    for key in ("anyOf", "oneOf", "allOf"):
        if key in s:
            assert isinstance(s[key], list) and s[key], (where, key)
            for i, sub in enumerate(s[key]):
                _check_json_schema(sub, f"{where}.{key}[{i}]")
    if "items" in s:
        _check_json_schema(s["items"], f"{where}.items")
    for key in ("minItems", "maxItems"):
        if key in s:
            assert isinstance(s[key], int) and s[key] >= 0, (where, key)
    for key in ("minimum", "maximum"):
        if key in s:
            assert isinstance(s[key], int | float) and not isinstance(s[key], bool), (where, key)
    for key, bound in (("exclusiveMinimum", "minimum"), ("exclusiveMaximum", "maximum")):
        if key in s:  # OpenAPI 3.0: a flag on the bound
            assert isinstance(s[key], bool) and bound in s, (where, key)
    if "enum" in s:
        assert isinstance(s["enum"], list) and s["enum"], where
    if "examples" in s:
        assert isinstance(s["examples"], list), where
    if "$ref" in s:
        ref = s["$ref"]
        assert ref.startswith("#/$defs/") and ref.split("/")[-1] in s.get("$defs", {}), where


@pytest.mark.parametrize("p", ALL, ids=_ids)
def test_process_description(p: Process) -> None:
    desc = process_description(p)
    text = json.dumps(desc, allow_nan=False)  # JSON-serialisable, standard JSON
    assert json.loads(text) == desc
    summary = process_summary(p)
    assert {k: desc[k] for k in summary} == summary
    assert desc["id"] == p.id and desc["title"] and desc["description"]
    assert set(desc["inputs"]) == set(p.params.model_fields)
    for name, inp in desc["inputs"].items():
        schema = inp["schema"]
        assert isinstance(schema, dict)
        assert "type" in schema or "oneOf" in schema, (p.id, name, schema)
        _check_json_schema(schema, f"{p.id}.{name}")
        required = p.params.model_fields[name].is_required()
        assert inp["minOccurs"] == (1 if required else 0), (p.id, name)
        assert inp["maxOccurs"] == 1
        assert inp["title"] and inp["description"]
        if not required:  # a default of None is left out (an omitted input is None)
            default = p.params.model_fields[name].default
            assert ("default" in schema) == (default is not None), (p.id, name)
    assert set(desc["outputs"]) == set(p.outputs)
    for name, out in desc["outputs"].items():
        assert out["description"] and out["schema"]
        _check_json_schema(out["schema"], f"{p.id}.outputs.{name}")


# -- one place for each fact --------------------------------------------------------------


def _bound_keywords(schema: dict[str, Any]) -> dict[str, float]:
    alternatives = schema.get("anyOf", [schema])
    return {k: v for alt in alternatives for k, v in alt.items()
            if k in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum")}


@pytest.mark.parametrize("p", ALL, ids=_ids)
def test_inputs_are_the_signature(p: Process) -> None:
    """Every parameter of the function is an input (but the hidden ones), with the
    signature's default and the docstring's description; the only other inputs are the
    display inputs the entry names, optional, after them."""
    decls = declarations(p.function)
    assert list(p.params.model_fields) == [n for n in decls if n not in p.hidden] + list(
        p.display)
    docs = numpydoc_entries(inspect.getdoc(p.function), "Parameters")
    for name, f in p.params.model_fields.items():
        if name in p.display:
            assert not f.is_required() and f.default is None, (p.id, name)
            assert f.description == DISPLAY_INPUTS[name][1], (p.id, name)
            continue
        d = decls[name]
        assert f.is_required() == d.required, (p.id, name)
        if not d.required:
            assert f.default == d.default and type(f.default) is type(d.default), (p.id, name)
        assert docs.get(name), f"{p.id}: {name!r} has no numpydoc description"
        assert f.description == input_description(d, *docs[name]), (p.id, name)
        assert plain(docs[name][1]) in f.description, (p.id, name)


@pytest.mark.parametrize("p", ALL, ids=_ids)
def test_every_input_is_declared(p: Process) -> None:
    """Nothing is left for the service to guess: each input is a checked scalar or has a
    declared kind (points, mesh, graph ...)."""
    for name, d in declarations(p.function).items():
        if name not in p.hidden:
            assert d.checked or d.kind is not None, f"{p.id}: {name!r} declares nothing"
    assert p.kinds == {n: d.kind for n, d in declarations(p.function).items()
                       if d.kind is not None and n not in p.hidden}


@pytest.mark.parametrize("p", ALL, ids=_ids)
def test_defaults_satisfy_their_declarations(p: Process) -> None:
    for name, d in declarations(p.function).items():
        if d.checked and not d.required:
            assert d.check(d.default) == d.default, (p.id, name)


def _metadata(hint: Any) -> Iterator[Any]:
    """Every ``Annotated`` metadata object inside a type: its own and its members' (the
    ``Annotated[...]`` of an ``Annotated[...] | None``, a ``list[Annotated[...]]``)."""
    if typing.get_origin(hint) is typing.Annotated:
        base, *meta = typing.get_args(hint)
        yield from meta
        yield from _metadata(base)
    else:
        for arg in typing.get_args(hint):
            yield from _metadata(arg)


def _schema_items(schema: Any) -> Iterator[tuple[str, Any]]:
    """Every (keyword, value) of a JSON Schema, nested ones too."""
    if isinstance(schema, dict):
        for key, value in schema.items():
            yield key, value
            yield from _schema_items(value)
    elif isinstance(schema, list):
        for value in schema:
            yield from _schema_items(value)


@pytest.mark.parametrize("p", ALL, ids=_ids)
def test_entry_restates_nothing(p: Process) -> None:
    """A catalog entry holds only what is the service's: no defaults or descriptions of
    its own for the function's parameters, and caps that are tighter than the signature's
    bounds (not copies of them). An input type the entry gives (``inputs``) carries no
    ``Field`` (in a union's members too), no JSON Schema default and no JSON description
    that repeats the function's; the only default an input's schema shows is the
    signature's."""
    from pydantic import WithJsonSchema
    from pydantic.fields import FieldInfo

    docs = numpydoc_entries(inspect.getdoc(p.function), "Parameters")
    for name, hint in p.inputs.items():
        meta = list(_metadata(hint))  # Optional[Annotated[...]] too, not only the outer type
        fields = [m for m in meta if isinstance(m, FieldInfo)]
        assert not fields, f"{p.id}: inputs[{name!r}] carries a Field (default/description)"
        own = plain(docs[name][1]) if name in docs else ""
        for m in meta:
            if not isinstance(m, WithJsonSchema) or m.json_schema is None:
                continue
            for key, value in _schema_items(m.json_schema):
                assert key != "default", f"{p.id}: inputs[{name!r}]'s JSON schema has a default"
                if key == "description" and own:
                    assert own not in plain(value), \
                        f"{p.id}: inputs[{name!r}]'s JSON schema restates the description"
    for name, schema in p.params.model_json_schema()["properties"].items():
        nested = [v for k, v in _schema_items({k: v for k, v in schema.items()
                                               if k != "default"}) if k == "default"]
        assert not nested, f"{p.id}: {name!r} has a default besides the signature's: {nested}"
    refs = numpydoc_references(inspect.getdoc(p.function))
    assert p.reference == references_text(p.function), f"{p.id}: reference restated"
    assert all(r.rstrip(".") in (p.reference or "") for r in refs), p.id
    assert refs or p.id not in registry, f"{p.id}: a method cites its papers (References)"
    decls = declarations(p.function)
    for name in p.limits:
        declared = {(s.minimum, s.maximum) for s in decls[name].scalars}
        schema = _bound_keywords(p.params.model_json_schema()["properties"][name])
        assert schema, (p.id, name)
        lo = schema.get("minimum", schema.get("exclusiveMinimum"))
        hi = schema.get("maximum", schema.get("exclusiveMaximum"))
        assert (lo, hi) not in declared, f"{p.id}: limits[{name!r}] restates the signature"


def _given_texts() -> list[tuple[str, str, str]]:
    """(process id, "title" or "description", text) for every text a catalog entry writes
    itself: a ``title=``/``description=`` keyword in a call whose first argument names the
    function."""
    import ast
    import importlib

    from service.catalog import FAMILIES

    out = []
    for family in FAMILIES:
        module = importlib.import_module(f"service.catalog.{family}")
        for node in ast.walk(ast.parse(inspect.getsource(module))):
            if not isinstance(node, ast.Call) or not node.args or \
                    not isinstance(node.args[0], ast.Name):
                continue
            for kw in node.keywords:
                if kw.arg in ("title", "description"):
                    out.append((f"{family}.{node.args[0].id}", kw.arg,
                                ast.literal_eval(kw.value)))
    return out


def test_entries_do_not_restate_the_docstring_summary() -> None:
    """An entry writes a title or description only where the function's docstring does not
    open with one (its short summary and the paragraph after it), never a copy of it."""
    given = _given_texts()
    assert {pid for pid, _, _ in given} == {"registration.icp", "registration.cpd"}
    for pid, what, text in given:
        title, description = numpydoc_summary(inspect.getdoc(registry[pid].function))
        assert text == getattr(registry[pid], what)
        assert text not in (title.rstrip("."), description), (pid, what)


@pytest.mark.parametrize("p", list(registry.values()), ids=_ids)
def test_title_and_description_are_the_docstring_summary(p: Process) -> None:
    """The id is the family and the function's name; the title and description are the
    docstring's short summary and the first paragraph after it (where the entry gives none),
    a name and a paragraph, as a process description shows them."""
    fn = inspect.unwrap(p.function)
    assert p.id == f"{fn.__module__.split('.')[1]}.{fn.__name__}"
    if p.id not in {pid for pid, _, _ in _given_texts()}:
        title, description = numpydoc_summary(inspect.getdoc(fn))
        assert (p.title, p.description) == (title.rstrip("."), description)
    assert 0 < len(p.title) < 90 and not p.title.endswith(".") and "\n" not in p.title
    assert len(p.description) > 60 and p.description.endswith(".") and "``" not in p.description


def test_numpydoc_summary() -> None:
    doc = """Rigid alignment (Kabsch).

    The rotation :math:`R` that best maps ``source``
    onto ``target``.

    More about it.

    Parameters
    ----------
    x : int
    """
    assert numpydoc_summary(doc) == ("Rigid alignment (Kabsch).",
                                     "The rotation R that best maps `source` onto `target`.")
    assert numpydoc_summary("Only a summary.\n\nParameters\n----------\nx : int\n") == \
        ("Only a summary.", "")
    assert numpydoc_summary(None) == ("", "")


def test_check_takes_the_inputs_its_parameters_name() -> None:
    """A check is called with the inputs its parameters name (a parameter with a default
    and no such input keeps its default); one that names no input is refused at start."""
    from service.catalog.registry import build_inputs

    seen: list[tuple[int, str]] = []

    def f(x: int = 1, y: int = 2) -> _HandResult:
        """Parameters
        ----------
        x, y : int
            Ex.
        """
        raise AssertionError

    def check(y: int, name: str = "y") -> None:
        seen.append((y, name))

    model = build_inputs("test.f", f, kinds={}, inputs={}, examples={}, limits={}, hidden=(),
                         check=check)
    model.model_validate({"y": 5})
    assert seen == [(5, "y")]

    def bad(z: int) -> None:
        raise AssertionError

    with pytest.raises(TypeError, match=r"check bad takes no input \['z'\]"):
        build_inputs("test.f", f, kinds={}, inputs={}, examples={}, limits={}, hidden=(),
                     check=bad)


@pytest.mark.parametrize("p", ALL, ids=_ids)
def test_declared_bounds_reach_the_schema(p: Process) -> None:
    props = p.params.model_json_schema()["properties"]
    for name, d in declarations(p.function).items():
        if name in p.hidden or name in p.inputs or len(d.scalars) != 1:
            continue
        s = d.scalars[0]
        got = _bound_keywords(props[name])
        if s.type is str:
            alts = props[name].get("anyOf", [props[name]])
            assert [a["enum"] for a in alts if "enum" in a] == [list(s.choices)], (p.id, name)
        if s.minimum is not None:
            key = "minimum" if s.inclusive[0] else "exclusiveMinimum"
            assert got.get(key) == s.minimum, (p.id, name, got)
        if s.maximum is not None and name not in p.limits:
            key = "maximum" if s.inclusive[1] else "exclusiveMaximum"
            assert got.get(key) == s.maximum, (p.id, name, got)


def test_plain_text_of_docstrings() -> None:
    assert plain("``k >= 1``, see :func:`~algorithms.alignment.pca` [1]_") == \
        "`k >= 1`, see `pca`"
    assert plain(r":math:`\lVert R x_i - y_i \rVert^2` with :math:`\hat\sigma`") == \
        "‖R xᵢ - yᵢ‖² with σ̂"
    assert plain(r":math:`R^\mathsf{T} R = I`, :math:`\exp(-d^2/2\sigma^2)`") == \
        "Rᵀ R = I, exp(-d²/2σ²)"


def test_numpydoc_references() -> None:
    doc = """Summary.

    References
    ----------
    .. [1] A. Author, "A title on
       two lines", A Journal 1(2), 2001.
    .. [2] B. Author, ``code`` in a note.

    Examples
    --------
    >>> 1
    """
    assert numpydoc_references(doc) == [
        'A. Author, "A title on two lines", A Journal 1(2), 2001.',
        "B. Author, `code` in a note."]
    assert numpydoc_references("Summary only.") == []


def test_numpydoc_parameters_with_shared_entries() -> None:
    doc = """Summary.

    Parameters
    ----------
    min_points, max_points : int, optional
        Bounds on the number of points.

        A second paragraph.
    name : str
        The name.

    Returns
    -------
    int
    """
    assert numpydoc_section(doc, "Parameters") == {
        "min_points": "Bounds on the number of points.\n\nA second paragraph.",
        "max_points": "Bounds on the number of points.\n\nA second paragraph.",
        "name": "The name.",
    }


def test_entries_name_only_parameters() -> None:
    from service.catalog.registry import build_inputs

    def f(x: int = 1) -> _HandResult:
        """Parameters
        ----------
        x : int
            Ex.
        """
        raise AssertionError

    for key in ("inputs", "examples", "limits"):
        kw: dict[str, Any] = {"inputs": {}, "examples": {}, "limits": {}, key: {"y": 1}}
        with pytest.raises(TypeError, match=f"{key} names no parameter: \\['y'\\]"):
            build_inputs("test.f", f, kinds={}, hidden=(), check=None, **kw)


@pytest.mark.parametrize("p", ALL, ids=_ids)
def test_geometry_is_declared(p: Process) -> None:
    """A process shows a GLB exactly when its entry declares a scene, and the scene is one
    of service.scenes's builders; for the examples, it is a GLB (or None by design)."""
    from service import scenes

    if p.geometry is None:
        return
    assert p.geometry.__module__ == "service.scenes" and p.geometry.__name__ in scenes.__all__
    if p.id in NEVER_RUN or p.id.startswith("diagnostics."):
        return
    kwargs = p.kwargs(p.params.model_validate(_example_inputs(p), context={"max_points": 1000}))
    glb = p.glb(p.run(kwargs), kwargs)
    assert glb is not None and glb[:4] == b"glTF", p.id


# -- running the examples ------------------------------------------------------------------
_KIND = {"array": (np.ndarray, list, tuple), "number": (float, np.floating),
         "integer": (int, np.integer), "boolean": (bool, np.bool_), "string": str,
         "object": object}  # a nested dataclass (a Mesh) or a dict


@pytest.mark.parametrize("p", [p for p in ALL if p.id not in NEVER_RUN], ids=_ids)
def test_run_first_examples(p: Process) -> None:
    raw = _example_inputs(p)
    if p.id in ("diagnostics.sleep", "diagnostics.nap"):
        raw = {"seconds": 0.0, "steps": 2}  # no examples; keep it instant
    params = p.params.model_validate(raw, context={"max_points": 1000})
    kwargs = p.kwargs(params)
    assert set(kwargs) == set(p.params.model_fields)
    out = p.run(kwargs)
    assert list(out) == list(p.outputs)
    for name, value in out.items():
        assert value is not None, (p.id, name)
        schema = p.outputs[name].schema
        assert isinstance(value, _KIND[schema["type"]]), (p.id, name, type(value))
        if schema["type"] == "object" and "properties" in schema:
            assert dataclasses.is_dataclass(value), (p.id, name, type(value))
            assert [f.name for f in dataclasses.fields(value)] == list(schema["properties"])
        if isinstance(value, np.ndarray):
            assert value.size == 0 or np.isfinite(value).all(), (p.id, name)
    json.loads(jsonio.dumps(out))  # what the service writes


def test_run_reports_progress() -> None:
    p = diagnostics["diagnostics.sleep"]
    assert p.takes_progress and p.long
    seen = []
    out = p.run({"seconds": 0.0, "steps": 3}, progress=lambda *a: seen.append(a))
    assert out["steps"] == 3 and len(seen) == 3


def test_rigid_example_is_solved() -> None:
    p = registry["alignment.rigid"]
    raw = _example_inputs(p)
    out = p.run(p.kwargs(p.params.model_validate(raw)))
    moved = np.asarray(raw["source"], float) @ out["rotation"].T + out["translation"]
    np.testing.assert_allclose(moved, raw["target"], atol=1e-9)
    assert out["rmse"] < 1e-9 and not out["reflection"]


# -- strict parameter models ---------------------------------------------------------------
def _scalar_fields(kinds: set[str]) -> list[tuple[Process, str]]:
    return [(p, name) for p in ALL for name, s in _field_schemas(p).items()
            if _types(s) & kinds]


def _case_id(case: tuple[Process, str]) -> str:
    return f"{case[0].id}:{case[1]}"


def _rejects(p: Process, name: str, value: Any) -> None:
    inputs = {**_example_inputs(p), name: value}
    with pytest.raises(ValidationError) as info:
        p.params.model_validate(inputs)
    locs = [e["loc"] for e in info.value.errors()]
    assert any(loc and loc[0] == name for loc in locs), (p.id, name, value, locs)
    named = [e["input"] for e in pydantic_errors(info.value.errors())]
    assert name in named, (p.id, name, value, named)


@pytest.mark.parametrize("p", ALL, ids=_ids)
def test_unknown_input_refused(p: Process) -> None:
    _rejects(p, "no_such_input", 1)


@pytest.mark.parametrize("case", _scalar_fields({"number", "integer"}), ids=_case_id)
@pytest.mark.parametrize("value", ["3", "1.5", True])
def test_numbers_refuse_strings_and_booleans(case: tuple[Process, str], value: Any) -> None:
    _rejects(*case, value)


@pytest.mark.parametrize("case", _scalar_fields({"integer"}), ids=_case_id)
@pytest.mark.parametrize("value", [3.0, 2.5])
def test_integers_refuse_floats(case: tuple[Process, str], value: float) -> None:
    _rejects(*case, value)


@pytest.mark.parametrize("case", _scalar_fields({"number"}), ids=_case_id)
@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_numbers_refuse_nan_and_inf(case: tuple[Process, str], value: float) -> None:
    _rejects(*case, value)


@pytest.mark.parametrize("case", _scalar_fields({"boolean"}), ids=_case_id)
@pytest.mark.parametrize("value", [1, 0, "true", 1.0])
def test_booleans_refuse_numbers_and_strings(case: tuple[Process, str], value: Any) -> None:
    _rejects(*case, value)


@pytest.mark.parametrize("case", _scalar_fields({"string"}), ids=_case_id)
def test_options_refuse_others(case: tuple[Process, str]) -> None:
    _rejects(*case, "no-such-option")


@pytest.mark.parametrize("case", [c for c in _scalar_fields({"string"})
                                  if not _types(_field_schemas(c[0])[c[1]]) & {"number",
                                                                               "integer"}],
                         ids=_case_id)
def test_options_refuse_numbers(case: tuple[Process, str]) -> None:
    """(An option that is also a number, such as t-SNE's learning_rate, takes numbers.)"""
    _rejects(*case, 1)


def test_scalar_cases_exist() -> None:
    """The parametrised rejection tests above cover something of each kind."""
    assert _scalar_fields({"number"}) and _scalar_fields({"integer"})
    assert _scalar_fields({"boolean"}) and _scalar_fields({"string"})


def test_numbers_accept_integers_and_optional_none() -> None:
    p = registry["assignment.nearest"]
    params = p.params.model_validate({**_example_inputs(p), "max_distance": 2, "k": 2})
    assert params.max_distance == 2 and params.k == 2
    assert p.params.model_validate({**_example_inputs(p), "max_distance": None}).max_distance \
        is None


def test_point_inputs_become_float_arrays() -> None:
    p = registry["alignment.rigid"]
    params = p.params.model_validate({**_example_inputs(p), "weights": [1, 2, 3, 4]})
    assert params.source.dtype == np.float64 and params.source.shape == (4, 3)
    assert params.weights.dtype == np.float64
    with pytest.raises(ValidationError) as info:
        p.params.model_validate({**_example_inputs(p), "source": [[0, 0, math.nan]] * 4})
    assert [e["input"] for e in pydantic_errors(info.value.errors())] == ["source"]


def test_max_points_from_context() -> None:
    p = registry["assignment.nearest"]
    with pytest.raises(ValidationError) as info:
        p.params.model_validate(_example_inputs(p), context={"max_points": 2})
    assert "source" in [e["input"] for e in pydantic_errors(info.value.errors())]


def test_cross_input_check_names_its_input() -> None:
    p = registry["alignment.rigid"]
    with pytest.raises(ValidationError) as info:
        p.params.model_validate({**_example_inputs(p), "weights": [1.0, 2.0]})
    assert [e["input"] for e in pydantic_errors(info.value.errors())] == ["weights"]


# -- the numpydoc parser and outputs_of ----------------------------------------------------
_DOC = """One line summary.

    More text that mentions Attributes but is no section.

    Attributes
    ----------
    alpha : float
        The first value. It has two sentences.
    beta_2 : (n, 3) int64 array
        The second value,
        on two lines.
    gamma : bool

    Notes
    -----
    Some notes: with a colon.
    delta : not an attribute
        Because it is in Notes.
    """


def test_numpydoc_attributes_before_another_section() -> None:
    got = numpydoc_section(_DOC, "Attributes")
    assert "Notes" not in got and "delta" not in got
    assert got["alpha"] == "The first value. It has two sentences."
    assert got["beta_2"] == "The second value, on two lines."


def test_numpydoc_last_attribute_before_another_section_is_kept() -> None:
    assert numpydoc_section(_DOC, "Attributes") == {
        "alpha": "The first value. It has two sentences.",
        "beta_2": "The second value, on two lines.",
        "gamma": "",
    }


def test_numpydoc_single_attribute_before_notes() -> None:
    doc = """Summary.

    Attributes
    ----------
    rmse : float
        The residual.

    Notes
    -----
    Nothing.
    """
    assert numpydoc_section(doc, "Attributes") == {"rmse": "The residual."}


def test_numpydoc_attributes_at_the_end() -> None:
    doc = """Summary.

    Attributes
    ----------
    x : float
        Ex.
    y : int
        Why,
        because.
    """
    assert numpydoc_section(doc, "Attributes") == {"x": "Ex.", "y": "Why, because."}


def test_numpydoc_first_line_on_the_quotes() -> None:
    doc = """Attributes
    ----------
    slept : float
        Seconds.
    """
    assert numpydoc_section(doc, "Attributes") == {"slept": "Seconds."}


@pytest.mark.parametrize("doc", [None, "", "Summary only.", "Attributes\nnot underlined\n",
                                 "Parameters\n----------\nx : int\n    Not an attribute.\n"])
def test_numpydoc_without_attributes(doc: str | None) -> None:
    assert numpydoc_section(doc, "Attributes") == {}


@dataclass(frozen=True)
class _HandResult:
    """A hand-written result.

    Attributes
    ----------
    points : (n, 3) float array
        Where the points went. More detail follows here.
    rmse : float
        The residual.
    count : int
        How many.
    ok : bool
        Whether it worked.
    label : str
        A name.
    """

    points: np.ndarray
    rmse: float
    count: int
    ok: bool
    label: str
    maybe: float | None = None
    undocumented_list: list[int] | None = None


def test_outputs_of_hand_written_dataclass() -> None:
    outs = outputs_of(_HandResult)
    assert list(outs) == ["points", "rmse", "count", "ok", "label", "maybe",
                          "undocumented_list"]
    assert all(isinstance(o, Output) for o in outs.values())
    assert outs["points"] == Output("points", "Where the points went",
                                    "Where the points went. More detail follows here.",
                                    {"type": "array"})
    assert outs["rmse"].title == "The residual" and outs["rmse"].schema == {"type": "number"}
    assert outs["count"].schema == {"type": "integer"}
    assert outs["ok"].schema == {"type": "boolean"}
    assert outs["label"].schema == {"type": "string"}
    assert outs["maybe"].schema == {"type": "number", "nullable": True}
    assert outs["maybe"].description == "" and outs["maybe"].title == "maybe"
    assert outs["undocumented_list"].title == "undocumented list"
    assert outs["undocumented_list"].schema == {"type": "array", "nullable": True}


def test_process_from_a_hand_written_function() -> None:
    """A process is one annotated function with a numpydoc docstring: its inputs, defaults,
    bounds, descriptions, outputs and references are read from it."""
    @validate_params
    def hand(n: typing.Annotated[int, Ge(1)] = 2) -> _HandResult:
        """Make points.

        Parameters
        ----------
        n : int, default 2
            How many points.

        References
        ----------
        .. [1] A. Hand, "Points", 2026.
        """
        return _HandResult(np.zeros((n, 3)), 0.0, n, True, "x")

    p = Process(id="test.hand", title="t", description="d", function=hand)
    assert p.family == "test" and not p.takes_progress and p.result is _HandResult
    assert p.reference == 'A. Hand, "Points", 2026.' and p.kinds == {}
    field = p.params.model_fields["n"]
    assert (field.default, field.description) == (2, "How many points.")
    with pytest.raises(ValidationError):
        p.params.model_validate({"n": 0})
    out = p.run(p.kwargs(p.params.model_validate({"n": 3})), progress=lambda *a: None)
    assert out["count"] == 3 and out["points"].shape == (3, 3) and out["maybe"] is None
    with pytest.raises(TypeError):
        Process(id="test.hand", title="t", description="d", function=hand,
                params=p.params)  # type: ignore[call-arg]


# -- the registry --------------------------------------------------------------------------
def test_registering_twice_raises() -> None:
    r = Registry()
    p = registry["alignment.rigid"]
    assert r.add(p) is p
    with pytest.raises(ValueError, match="alignment.rigid"):
        r.add(p)
    assert len(r) == 1 and list(r) == ["alignment.rigid"] and r["alignment.rigid"] is p


def test_global_registry_refuses_duplicates() -> None:
    before = list(registry)
    with pytest.raises(ValueError):
        registry.add(registry["assignment.nearest"])
    with pytest.raises(ValueError):
        diagnostics.add(diagnostics["diagnostics.sleep"])
    assert list(registry) == before


def test_registry_is_a_mapping() -> None:
    assert "alignment.rigid" in registry and "nope" not in registry
    assert registry.get("nope") is None
    with pytest.raises(KeyError):
        registry["nope"]


def _as_binary(value: Any) -> Any:
    """Every numeric (nested) list in an example as the typed binary array the SDK sends."""
    from morphserve._models import binary_array

    if isinstance(value, list) and value:
        try:
            arr = np.asarray(value)
        except ValueError:  # ragged
            return value
        if arr.dtype.kind in "iuf" and 1 <= arr.ndim <= 4:
            return binary_array(arr)
        return value
    if isinstance(value, dict):
        return {k: _as_binary(v) for k, v in value.items()}
    return value


@pytest.mark.parametrize("p", [p for p in ALL if p.id not in NEVER_RUN], ids=_ids)
def test_examples_give_the_same_results_from_binary_arrays(p: Process) -> None:
    from service.binary import decode_arrays

    raw = _example_inputs(p)
    if p.id in ("diagnostics.sleep", "diagnostics.nap"):
        raw = {"seconds": 0.0, "steps": 2}
    ctx = {"max_points": 1000}
    as_lists = p.run(p.kwargs(p.params.model_validate(raw, context=ctx)))
    decoded = {k: decode_arrays(_as_binary(v), k) for k, v in raw.items()}
    as_binary = p.run(p.kwargs(p.params.model_validate(decoded, context=ctx)))
    if p.id in ("diagnostics.sleep", "diagnostics.nap"):
        return  # its output is a measured time
    assert jsonio.dumps(as_binary) == jsonio.dumps(as_lists), p.id
