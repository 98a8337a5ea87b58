"""``/jobs``: job list, status, results, dismissal."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Query, Request
from pydantic import Field
from service.jsonio import JSONResponse
from urllib.parse import urlencode

from service.errors import ServiceError
from service.representation import results_document, status_info
from service.routes import docs
from service.routes.common import failure_response, get_job, owner, state

router = APIRouter(tags=["jobs"])

#: A process id: family and method, as in the catalog (`alignment.rigid`).
PROCESS_ID = r"^[a-z][a-z0-9_]*\.[a-z][a-z0-9_]*$"

Status = Literal["accepted", "running", "successful", "failed", "dismissed"]


@router.get("/jobs", operation_id="getJobs", summary="List jobs, newest first",
            responses=docs.responses(docs.JobList, 422))
async def list_jobs(
    request: Request,
    status: Annotated[list[Status] | None, Query(description="Only jobs in these states.")]
    = None,
    processID: Annotated[list[Annotated[str, Field(pattern=PROCESS_ID)]] | None, Query(  # noqa: N803
        description="Only jobs of these processes.")] = None,
    limit: Annotated[int, Query(ge=1, le=1000, description="Jobs per page.")] = 10,
    offset: Annotated[int, Query(ge=0, le=10**9, description="Jobs to skip.")] = 0,
) -> JSONResponse:
    st = state(request)
    jobs, total = st.store.list(statuses=status or (), processes=processID or (), limit=limit,
                                offset=offset, owner=owner(st, request))

    def page(off: int) -> str:
        q = [("limit", limit), ("offset", off)]
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


def _accepts_json(accept: str) -> bool:
    for part in accept.split(","):
        media = part.split(";")[0].strip().lower()
        if media in ("", "*/*", "application/*", "application/json") or media.endswith("+json"):
            return True
    return False


@router.get("/jobs/{jobId}/results", operation_id="getResult", summary="A job's results",
            responses={**docs.responses(None, 404, 406, 410, 422, 500, 504),
                       200: {"description": "The results document: output name -> value.",
                             "content": {"application/json": {"schema": {"type": "object"}}}}})
async def get_results(
    jobId: str,  # noqa: N803
    request: Request,
    f: Annotated[Literal["json"] | None, Query(description="Output format.")] = None,
) -> JSONResponse:
    st = state(request)
    job = get_job(st, jobId, request)
    if f is None and not _accepts_json(request.headers.get("accept", "*/*")):
        raise ServiceError("not-acceptable", "The results are available as application/json "
                           f"only; the request accepts {request.headers.get('accept')!r}.")
    if job.status == "successful":
        return JSONResponse(results_document(st.store.result(job.id), job.request))
    if job.status in ("failed", "dismissed"):
        return failure_response(job)
    raise ServiceError("result-not-ready", f"Job {job.id} is {job.status} "
                       f"({job.progress}%); poll /jobs/{job.id} until it is successful.")


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
        if job.status != "dismissed":  # it ended between the two reads
            await st.store.write(st.store.delete, job.id)
    else:
        await st.store.write(st.store.delete, job.id)
    info = status_info(job)
    info.update(status="dismissed", links=[l for l in info["links"] if l["rel"] != "results"])
    return JSONResponse(info)
