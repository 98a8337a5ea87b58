"""THE registry of methods: process id -> family, parameter model, algorithm function, result
type, summary and reference. Importing this package registers every family's entries.

Adding a method = one function in its ``algorithms`` family module + one entry in the family's
module here + tests. Routes, OpenAPI, the SDK's process list and the docs derive from it.
"""

from __future__ import annotations

import importlib

from service.catalog.registry import Output, Process, Registry, registry

#: The families, in the order their processes are listed (importing one registers them).
FAMILIES = ("alignment", "assignment", "classification", "layout", "clustering",
            "deformation", "embedding", "interpolation", "parameterization", "registration")
for _family in FAMILIES:
    importlib.import_module(f"service.catalog.{_family}")

__all__ = ["Output", "Process", "Registry", "registry", "lookup", "processes"]


def lookup(process_id: str, *, test_processes: bool = False) -> Process | None:
    """The process with this id, diagnostics included when ``test_processes`` is on."""
    process = registry.get(process_id)
    if process is None and test_processes:
        from service.diagnostics import diagnostics

        process = diagnostics.get(process_id)
    return process


def processes(*, test_processes: bool = False) -> list[Process]:
    """Every offered process, in catalog order."""
    out = list(registry.values())
    if test_processes:
        from service.diagnostics import diagnostics

        out += list(diagnostics.values())
    return out
