"""The base of every parameter model."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict

__all__ = ["Params"]


class Params(BaseModel):
    """Inputs of one process: strict types (no "3" for 3, no 1 for true), no NaN/Inf scalars,
    unknown inputs refused, arrays kept as numpy."""

    model_config = ConfigDict(
        strict=True,
        extra="forbid",
        allow_inf_nan=False,
        arbitrary_types_allowed=True,
        frozen=True,
    )
