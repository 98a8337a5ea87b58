"""``/jobs``: job list, status, results, dismissal."""

from __future__ import annotations

from typing import Annotated, Literal
from urllib.parse import urlencode

from fastapi import APIRouter, Path, Query, Request
from pydantic import Field
from starlette.concurrency import run_in_threadpool
from starlette.responses import Response

from service.errors import ServiceError
from service.geometry_io import MEDIA_GLB, MEDIA_NPY
from service.jobs.status import JobStatus
from service.jsonio import JSONResponse
from service.representation import status_info
from service.routes import docs
from service.routes.common import (
    Wanted,
    failure_response,
    get_job,
    owner,
    results_response,
    state,
)

router = APIRouter(tags=["jobs"])

#: A process id: family and method, as in the catalog (`alignment.rigid`).
PROCESS_ID = r"^[a-z][a-z0-9_]*\.[a-z][a-z0-9_]*$"


@router.get("/jobs", operation_id="getJobs", summary="List jobs, newest first",
            responses=docs.responses(docs.JobList, 422))
async def list_jobs(
    request: Request,
    status: Annotated[list[docs.StatusName] | None,
                      Query(description="Only jobs in these states.")] = None,
    processID: Annotated[list[Annotated[str, Field(pattern=PROCESS_ID)]] | None, Query(  # noqa: N803
        description="Only jobs of these processes.")] = None,
    limit: Annotated[int, Query(ge=1, le=1000, description="Jobs per page.")] = 10,
    offset: Annotated[int, Query(ge=0, le=10**9, description="Jobs to skip.")] = 0,
) -> JSONResponse:
    st = state(request)
    jobs, total = st.store.page(statuses=status or (), processes=processID or (), limit=limit,
                                offset=offset, owner=owner(st, request))

    def page(off: int) -> str:
        q: list[tuple[str, str | int]] = [("limit", limit), ("offset", off)]
        q += [("status", s) for s in status or ()] + [("processID", p) for p in processID or ()]
        return "/jobs?" + urlencode(q)

    links = [{"href": page(offset), "rel": "self", "type": "application/json"}]
    if offset + limit < total:
        links.append({"href": page(offset + limit), "rel": "next", "type": "application/json"})
    if offset > 0:
        links.append({"href": page(max(0, offset - limit)), "rel": "prev",
                      "type": "application/json"})
    return JSONResponse({"jobs": [status_info(j) for j in jobs], "links": links,
                         "numberMatched": total})


@router.get("/jobs/{jobId}", operation_id="getStatus", summary="A job's status",
            responses=docs.responses(docs.StatusInfo, 404))
async def get_status(jobId: str, request: Request) -> JSONResponse:  # noqa: N803
    return JSONResponse(status_info(get_job(state(request), jobId, request)))


_RESULT_CONTENT = {
    "application/json": {"schema": {"type": "object"}},
    MEDIA_GLB: {"schema": {"type": "string", "format": "binary"}},
    MEDIA_NPY: {"schema": {"type": "string", "format": "binary"}},
}
_FORMAT = Query(description="Output format, instead of the Accept header: json, glb (glTF "
                "binary of the result's geometry) or npy (one array).")


async def _results(request: Request, job_id: str, f: str | None, only: str | None
                   ) -> Response:
    st = state(request)
    job = get_job(st, job_id, request)
    wanted = Wanted.of(request, f)
    if job.status is JobStatus.SUCCESSFUL:
        outputs = await run_in_threadpool(st.store.result, job.id)
        # glTF and .npy encoding of large results takes a while: off the event loop
        return await run_in_threadpool(results_response, st, job, outputs, wanted,
                                       only=only)
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
) -> Response:
    return await _results(request, jobId, f, None)


@router.get("/jobs/{jobId}/results/{outputId}", operation_id="getResultOutput",
            summary="One output of a job's results",
            description="The value of one output: JSON, `.npy` for an array, or glTF binary of "
            "the result's geometry. Also what inputs by reference name: "
            '`{"href": "/jobs/{jobId}/results/{outputId}"}`.',
            responses={**docs.responses(None, 404, 406, 410, 422, 500, 504),
                       200: {"description": "The output's value.",
                             "content": _RESULT_CONTENT}})
async def get_result_output(
    jobId: str,  # noqa: N803
    outputId: Annotated[str, Path(pattern=r"^[A-Za-z_][A-Za-z0-9_]*$")],  # noqa: N803
    request: Request,
    f: Annotated[Literal["json", "glb", "npy"] | None, _FORMAT] = None,
) -> Response:
    return await _results(request, jobId, f, outputId)


@router.delete("/jobs/{jobId}", operation_id="dismiss",
               summary="Dismiss a job: cancel it if queued or running, else remove it",
               responses=docs.responses(docs.StatusInfo, 404))
async def dismiss(jobId: str, request: Request) -> JSONResponse:  # noqa: N803
    st = state(request)
    job = get_job(st, jobId, request)
    if job.active:
        await st.store.write(st.store.dismiss, job.id)
        await st.engine.dismiss(job.id)
        job = get_job(st, jobId, request)
        if job.status is not JobStatus.DISMISSED:  # it ended between the two reads
            await st.store.write(st.store.delete, job.id)
    else:
        await st.store.write(st.store.delete, job.id)
    info = status_info(job)
    info.update(status=str(JobStatus.DISMISSED),
                links=[link for link in info["links"] if link["rel"] != "results"])
    return JSONResponse(info)
