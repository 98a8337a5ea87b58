"""``/``, ``/conformance``, health and metrics."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import PlainTextResponse

from service.catalog import processes
from service.errors import ServiceError
from service.jsonio import JSONResponse
from service.metrics import render
from service.representation import (
    REL_CONFORMANCE,
    REL_JOB_LIST,
    REL_PROCESSES,
    html_alternate,
)
from service.routes import docs
from service.routes.common import PageFormat, base_url, state, with_html

router = APIRouter(tags=["service"])

OGC = "http://www.opengis.net/spec/ogcapi-processes-1/1.0/conf/"
CONFORMANCE = [OGC + c for c in ("core", "ogc-process-description", "json", "job-list",
                                 "dismiss", "callback", "oas30")]


@router.get("/", operation_id="getLandingPage", summary="Landing page",
            responses=with_html(docs.responses(docs.LandingPage)))
async def landing(request: Request, f: PageFormat = None) -> JSONResponse:
    base = base_url(request)

    def link(path: str, rel: str, title: str, type_: str = "application/json"
             ) -> dict[str, str]:
        return {"href": base + path, "rel": rel, "type": type_, "title": title}

    return JSONResponse({
        "title": "morphserve",
        "description": "Geometry jobs over OGC API – Processes: alignment, registration, "
                       "deformation, parameterization, embedding.",
        "links": [
            link("/", "self", "this document"),
            html_alternate(base + "/", "this document as a web page"),
            link("/openapi.json", "service-desc", "the API definition",
                 "application/vnd.oai.openapi+json;version=3.0"),
            link("/docs", "service-doc", "the API documentation", "text/html"),
            link("/conformance", REL_CONFORMANCE, "conformance classes"),
            link("/processes", REL_PROCESSES, "the processes"),
            link("/jobs", REL_JOB_LIST, "the jobs"),
        ],
    })


@router.get("/conformance", operation_id="getConformanceClasses",
            summary="Conformance classes", responses=docs.responses(docs.Conformance))
async def conformance() -> JSONResponse:
    return JSONResponse({"conformsTo": CONFORMANCE})


@router.get("/healthz", operation_id="getHealth", summary="Liveness: the process answers")
async def healthz() -> JSONResponse:
    return JSONResponse({"status": "ok"})


@router.get("/readyz", operation_id="getReadiness",
            summary="Readiness: the job store has room and at least one worker is up",
            responses=docs.responses(None, 503))
async def readyz(request: Request) -> JSONResponse:
    """Ready: a worker is connected, the data dir has more free space than the store keeps
    for the jobs accepted, and every ended job's outcome is written. The answer (the 503
    problem too) carries ``workers``, ``free_bytes``, ``reserve_bytes`` and ``held`` (ended
    jobs whose outcome waits in memory for room)."""
    st = state(request)
    workers = await st.engine.n_workers()
    space = st.store.space()
    facts = {"workers": workers, "free_bytes": space.free_bytes,
             "reserve_bytes": space.reserve_bytes, "held": space.held}
    reasons = []
    if workers == 0:
        reasons.append("No Dask worker is connected yet.")
    if space.free_bytes < space.reserve_bytes:
        reasons.append(f"The data dir has {space.free_bytes} bytes free, under the "
                       f"{space.reserve_bytes} kept for the jobs accepted: new jobs are "
                       "refused (507).")
    if space.held:
        reasons.append(f"{space.held} ended jobs wait in memory for room to write their "
                       "outcome.")
    if reasons:
        raise ServiceError("service-unavailable", " ".join(reasons),
                           headers={"Retry-After": "1"}, members=facts)
    return JSONResponse({"status": "ready", **facts})


@router.get("/metrics", operation_id="getMetrics", summary="Prometheus metrics",
            response_class=PlainTextResponse,
            responses={200: {"description": "Jobs by process and status, queue length, "
                             "workers, job latency histograms (Prometheus text format).",
                             "content": {"text/plain": {"schema": {"type": "string"}}}}})
async def metrics(request: Request) -> PlainTextResponse:
    st = state(request)
    text = render(st.metrics, jobs=st.store.count_by_process(), queue=st.engine.active,
                  workers=await st.engine.n_workers(),
                  processes=len(processes(test_processes=st.settings.test_processes)))
    return PlainTextResponse(text, media_type="text/plain; version=0.0.4; charset=utf-8")
