"""The FastAPI application: ``create_app(settings)``.

The lifespan opens the job store, starts the Dask engine (embedded LocalCluster or an external
scheduler) and resubmits unfinished jobs; on shutdown it closes them in reverse order.
"""

from __future__ import annotations

import logging
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from typing import Any

from fastapi import FastAPI
from fastapi.routing import APIRoute

from service import metrics
from service.auth import AuthMiddleware, KeyRing, is_open
from service.callbacks import Notifier
from service.errors import install_handlers
from service.html import HtmlMiddleware
from service.jobs.engine import Engine
from service.jobs.status import JobStatus, Outcome
from service.jobs.store import JobRecord, JobStore
from service.representation import results_document, status_info
from service.routes import apidocs, jobs, landing, processes, ui
from service.routes.common import State
from service.settings import Settings, get_settings

__all__ = ["create_app"]

log = logging.getLogger("morphserve")


def _operation_id(route: APIRoute) -> str:
    return route.operation_id or route.name


def _wire_callbacks(engine: Engine, store: JobStore, notifier: Notifier,
                    base: str = "") -> None:
    """Send each job's subscriber its callbacks. A callback answers no request, so its
    statusInfo links start with ``base``, the configured public URL (``public_url``); when
    none is configured they are relative to the service's root (``/jobs/{id}``)."""
    def on_finish(job: JobRecord, outcome: Outcome) -> None:
        sub = job.request.subscriber
        if sub is None:
            return
        current = store.get(job.id) or job
        if outcome.status is JobStatus.SUCCESSFUL:
            if sub.success_uri is not None:
                notifier.send(sub.success_uri,
                              results_document(outcome.outputs or {}, job.request))
        elif sub.failed_uri is not None:
            notifier.send(sub.failed_uri, status_info(current, base))

    def on_start(job: JobRecord) -> None:
        sub = job.request.subscriber
        if sub is not None and sub.in_progress_uri is not None:
            notifier.send(sub.in_progress_uri, status_info(store.get(job.id) or job, base))

    engine.on_finish.append(on_finish)
    engine.on_start.append(on_start)


def create_app(settings: Settings | None = None) -> FastAPI:
    settings = settings or get_settings()
    # Read now, so that a broken keys file stops the service before it listens.
    keyring = KeyRing(settings.api_keys_file) if settings.api_keys_file else None

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        store = JobStore(settings.data_dir, fsync=settings.fsync,
                         inline_input_bytes=settings.inline_input_bytes)
        engine = Engine(settings, store)
        notifier = Notifier()
        _wire_callbacks(engine, store, notifier, (settings.public_url or "").rstrip("/"))
        app.state.morphserve = State(settings=settings, store=store, engine=engine,
                                     keyring=keyring)
        metrics.wire(engine, app.state.morphserve.metrics)
        await engine.start()
        log.info("morphserve ready: data dir %s, %s, %s", settings.data_dir.resolve(),
                 settings.scheduler or f"embedded cluster of {settings.workers} workers",
                 f"{len(keyring)} API keys" if keyring else "open (no API keys)")
        try:
            yield
        finally:
            await notifier.close()
            await engine.close()
            store.close()

    app = FastAPI(
        title="morphserve",
        version="0.1.0",
        summary="Geometry jobs over OGC API – Processes.",
        description="Send point sets, meshes or graphs with a method; get back transforms, "
        "correspondences, embeddings or deformed geometry. Every method of the catalog is "
        "one OGC process.",
        lifespan=lifespan,
        generate_unique_id_function=_operation_id,
        docs_url=None,  # FastAPI's pages load their assets from a CDN: service.routes.apidocs
        redoc_url=None,
    )
    install_handlers(app)
    app.add_middleware(AuthMiddleware, keyring=keyring)
    app.add_middleware(HtmlMiddleware)  # outside auth: renders its 401 too
    app.add_middleware(metrics.HttpMetrics)  # outermost: counts every answer
    app.include_router(landing.router)
    app.include_router(apidocs.router)
    app.include_router(processes.router)
    app.include_router(jobs.router)
    app.include_router(ui.router)
    app.openapi = lambda: _openapi(app)  # type: ignore[method-assign]
    return app


def _openapi(app: FastAPI) -> dict[str, Any]:
    """FastAPI's document, with one execute operation per process
    (:func:`service.openapi.add_process_operations`) and every error response as the
    problem+json it really is (FastAPI files error models under application/json and adds
    its own 422 model)."""
    if app.openapi_schema is None:
        from fastapi.openapi.utils import get_openapi

        doc = get_openapi(title=app.title, version=app.version, summary=app.summary,
                          description=app.description, routes=app.routes)
        from service.openapi import add_process_operations

        add_process_operations(doc)
        problem = {"application/problem+json": {"schema": {
            "$ref": "#/components/schemas/Problem"}}}
        for route, path in doc["paths"].items():
            for op in path.values():
                if not is_open(route):  # see service.auth: a key when keys are on
                    op["responses"].setdefault("401", {
                        "description": "No valid API key (when the service has keys)."})
                    op["security"] = [{}, {"bearerAuth": []}]
                # an operation with an HTML page (service.html) answers its errors as
                # pages too, to a browser
                html = op.get("responses", {}).get("200", {}).get("content", {}).get(
                    "text/html")
                for code, resp in op.get("responses", {}).items():
                    if code[0] in "45":
                        resp["content"] = {**problem, "text/html": html} if html else problem
        doc.setdefault("components", {})["securitySchemes"] = {"bearerAuth": {
            "type": "http", "scheme": "bearer",
            "description": "An API key from the service's keys file; needed when the service "
            "runs with MORPHSERVE_API_KEYS_FILE, ignored otherwise."}}
        schemas = doc["components"].setdefault("schemas", {})
        for unused in ("HTTPValidationError", "ValidationError"):
            schemas.pop(unused, None)
        from service.routes.docs import FieldError, Problem

        schemas["Problem"] = Problem.model_json_schema(
            ref_template="#/components/schemas/{model}")
        schemas["Problem"].pop("$defs", None)
        schemas["FieldError"] = FieldError.model_json_schema()
        _hoist_defs(doc, schemas)
        app.openapi_schema = doc
    return app.openapi_schema


def _hoist_defs(node: Any, schemas: dict[str, Any]) -> None:
    """Move pydantic's nested ``$defs`` (models inlined through ``openapi_extra``) into
    ``components/schemas``, where their ``#/components/schemas/...`` references point."""
    if isinstance(node, dict):
        for name, schema in node.pop("$defs", {}).items():
            schemas.setdefault(name, schema)
        for value in list(node.values()):
            _hoist_defs(value, schemas)
    elif isinstance(node, list):
        for value in node:
            _hoist_defs(value, schemas)
