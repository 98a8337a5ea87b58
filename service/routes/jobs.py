"""``/jobs``: job list, status, results, dismissal."""

from __future__ import annotations

from typing import Annotated, Literal
from urllib.parse import urlencode

from fastapi import APIRouter, Path, Query, Request
from pydantic import Field
from starlette.concurrency import run_in_threadpool
from starlette.responses import Response

from service.errors import ServiceError
from service.geometry_io import MEDIA_GLB, MEDIA_NPY, turned_up
from service.jobs.status import JobStatus
from service.jsonio import JSONResponse
from service.representation import REL_RESULTS, html_alternate, status_info
from service.routes import docs
from service.routes.common import (
    PageFormat,
    Wanted,
    base_url,
    failure_response,
    get_job,
    owner,
    results_response,
    state,
    with_html,
)

router = APIRouter(tags=["jobs"])

#: A process id: family and method, as in the catalog (`alignment.rigid`).
PROCESS_ID = r"^[a-z][a-z0-9_]*\.[a-z][a-z0-9_]*$"


@router.get("/jobs", operation_id="getJobs", summary="List jobs, newest first",
            responses=with_html(docs.responses(docs.JobList, 422)))
async def list_jobs(
    request: Request,
    status: Annotated[list[docs.StatusName] | None,
                      Query(description="Only jobs in these states.")] = None,
    processID: Annotated[list[Annotated[str, Field(pattern=PROCESS_ID)]] | None, Query(  # noqa: N803
        description="Only jobs of these processes.")] = None,
    limit: Annotated[int, Query(ge=1, le=1000, description="Jobs per page.")] = 10,
    offset: Annotated[int, Query(ge=0, le=10**9, description="Jobs to skip.")] = 0,
    f: PageFormat = None,
) -> JSONResponse:
    st = state(request)
    base = base_url(request)
    jobs, total = st.store.page(statuses=status or (), processes=processID or (), limit=limit,
                                offset=offset, owner=owner(st, request))

    def page(off: int) -> str:
        q: list[tuple[str, str | int]] = [("limit", limit), ("offset", off)]
        q += [("status", s) for s in status or ()] + [("processID", p) for p in processID or ()]
        return f"{base}/jobs?" + urlencode(q)

    links = [{"href": page(offset), "rel": "self", "type": "application/json"},
             html_alternate(page(offset), "this list as a web page")]
    if offset + limit < total:
        links.append({"href": page(offset + limit), "rel": "next", "type": "application/json"})
    if offset > 0:
        links.append({"href": page(max(0, offset - limit)), "rel": "prev",
                      "type": "application/json"})
    return JSONResponse({"jobs": [status_info(j, base) for j in jobs], "links": links,
                         "numberMatched": total})


@router.get("/jobs/{jobId}", operation_id="getStatus", summary="A job's status",
            responses=with_html(docs.responses(docs.StatusInfo, 404)))
async def get_status(jobId: str, request: Request,  # noqa: N803
                     f: PageFormat = None) -> JSONResponse:
    return JSONResponse(status_info(get_job(state(request), jobId, request),
                                    base_url(request)))


_BINARY = {"schema": {"type": "string", "format": "binary"}}
#: A results document is an object of outputs, but a job run with ``response: raw`` and one
#: output answers that output's value alone, of whatever type it has.
_RESULT_CONTENT = {
    "application/json": {"schema": {
        "description": "output name -> value; for a job run with response raw and one "
        "output, that output's value alone"}},
    MEDIA_GLB: _BINARY,
    MEDIA_NPY: _BINARY,
}
_OUTPUT_CONTENT = {"application/json": {"schema": {"description": "the output's value"}},
                   MEDIA_GLB: _BINARY, MEDIA_NPY: _BINARY}
_FORMAT = Query(description="Output format, instead of the Accept header: json, glb (glTF "
                "binary of the result's geometry) or npy (one array).")
_UP = Query(description="For glb: the up axis of the result's coordinates. y (the default) "
            "sends them as they are (glTF's +y up); z (scans, CAD) turns the scene so that "
            "+z points up.")


async def _results(request: Request, job_id: str, f: str | None, only: str | None,
                   up: str = "y") -> Response:
    st = state(request)
    job = get_job(st, job_id, request)
    wanted = Wanted.of(request, f)
    if job.status is JobStatus.SUCCESSFUL:
        outputs = await run_in_threadpool(st.store.result, job.id)
        # glTF and .npy encoding of large results takes a while: off the event loop
        return turned_up(await run_in_threadpool(results_response, st, job, outputs, wanted,
                                                 only=only), up)
    if job.status in (JobStatus.FAILED, JobStatus.DISMISSED):
        return failure_response(job)
    raise ServiceError("result-not-ready", f"Job {job.id} is {job.status} "
                       f"({job.progress}%); poll /jobs/{job.id} until it is successful.")


@router.get("/jobs/{jobId}/results", operation_id="getResult", summary="A job's results",
            description="The results document (JSON); the result's geometry as glTF binary "
            f"(`Accept: {MEDIA_GLB}` or `?f=glb`); a single array output as `.npy` "
            f"(`Accept: {MEDIA_NPY}` or `?f=npy`). `Prefer: arrays=binary` sends the arrays "
            "of the JSON document as typed binary arrays.",
            responses={**docs.responses(None, 404, 406, 410, 422, 500, 504),
                       200: {"description": "The results document: output name -> value.",
                             "content": _RESULT_CONTENT}})
async def get_results(
    jobId: str,  # noqa: N803
    request: Request,
    f: Annotated[Literal["json", "glb", "npy"] | None, _FORMAT] = None,
    up: Annotated[Literal["y", "z"], _UP] = "y",
) -> Response:
    return await _results(request, jobId, f, None, up)


@router.get("/jobs/{jobId}/results/{outputId}", operation_id="getResultOutput",
            summary="One output of a job's results",
            description="The value of one output: JSON, `.npy` for an array, or glTF binary of "
            "the result's geometry. Also what inputs by reference name: "
            '`{"href": "/jobs/{jobId}/results/{outputId}"}`.',
            responses={**docs.responses(None, 404, 406, 410, 422, 500, 504),
                       200: {"description": "The output's value.",
                             "content": _OUTPUT_CONTENT}})
async def get_result_output(
    jobId: str,  # noqa: N803
    outputId: Annotated[str, Path(pattern=r"^[A-Za-z_][A-Za-z0-9_]*$")],  # noqa: N803
    request: Request,
    f: Annotated[Literal["json", "glb", "npy"] | None, _FORMAT] = None,
    up: Annotated[Literal["y", "z"], _UP] = "y",
) -> Response:
    return await _results(request, jobId, f, outputId, up)


@router.delete("/jobs/{jobId}", operation_id="dismiss",
               summary="Dismiss a job: cancel it if queued or running, else remove it",
               responses=docs.responses(docs.StatusInfo, 404, 507))
async def dismiss(jobId: str, request: Request) -> JSONResponse:  # noqa: N803
    st = state(request)
    job = get_job(st, jobId, request)
    removed = True
    if job.active:
        await st.store.write(st.store.dismiss, job.id)
        await st.engine.dismiss(job.id)
        job = get_job(st, jobId, request)
        if job.status is not JobStatus.DISMISSED:  # it ended between the two reads
            await st.store.write(st.store.delete, job.id)
        else:
            removed = False
    else:
        await st.store.write(st.store.delete, job.id)
    # no results any more; a removed job has no web page either
    gone = {"results", REL_RESULTS, *(("alternate",) if removed else ())}
    info = status_info(job, base_url(request))
    info.update(status=str(JobStatus.DISMISSED),
                links=[link for link in info["links"] if link["rel"] not in gone])
    return JSONResponse(info)
