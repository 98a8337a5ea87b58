"""The process description's schemas in the form the standard requires (OpenAPI 3.0 schema
objects, its schema.yaml), by hand-written cases of what pydantic writes."""

from __future__ import annotations

from typing import Any

import pytest

from service.representation import ogc_schema
from tests.service.ogc.standard import errors


@pytest.mark.parametrize(("given", "expected"), [
    # an optional bounded number: nullable, the bound as OpenAPI 3.0's flag, no null default
    ({"anyOf": [{"type": "number", "exclusiveMinimum": 0}, {"type": "null"}],
      "default": None, "examples": [1.5], "title": "Tol"},
     {"type": "number", "minimum": 0, "exclusiveMinimum": True, "nullable": True,
      "title": "Tol"}),
    # a union of two kinds: oneOf
    ({"anyOf": [{"type": "integer"}, {"type": "string", "enum": ["auto"]}], "default": "auto"},
     {"oneOf": [{"type": "integer"}, {"type": "string", "enum": ["auto"]}],
      "default": "auto"}),
    ({"const": "x"}, {"enum": ["x"]}),
    ({"type": ["string", "null"]}, {"type": "string", "nullable": True}),
    ({"type": "array", "prefixItems": [{"type": "number"}, {"type": "number"}]},
     {"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 2}),
    ({"type": "array", "prefixItems": [{"type": "number"}, {"type": "string"}]},
     {"type": "array", "items": {"oneOf": [{"type": "number"}, {"type": "string"}]},
      "minItems": 2, "maxItems": 2}),
    # a reference into $defs is inlined, the $defs dropped
    ({"$ref": "#/$defs/P", "$defs": {"P": {"type": "object", "properties": {
        "x": {"type": "number", "exclusiveMaximum": 1}}}}, "description": "d"},
     {"type": "object", "properties": {
         "x": {"type": "number", "maximum": 1, "exclusiveMaximum": True}}, "description": "d"}),
    # a definition that refers to itself is inlined once
    ({"$ref": "#/$defs/T", "$defs": {"T": {"type": "object", "properties": {
        "child": {"$ref": "#/$defs/T"}}}}},
     {"type": "object", "properties": {"child": {"type": "object"}}}),
])
def test_ogc_schema(given: dict[str, Any], expected: dict[str, Any]) -> None:
    out = ogc_schema(given)
    assert out == expected
    assert not errors("schema_or_reference", out)
