"""morphserve: the Python SDK of the morphserve geometry job service.

>>> from morphserve import Client
>>> with Client("http://127.0.0.1:8000") as client:  # doctest: +SKIP
...     job = client.execute("alignment.rigid", source=a, target=b)
...     job.wait(progress=True)
...     transform = job.results()["transform"]

:class:`AsyncClient` offers the same API with ``async`` methods. Errors are the classes of
:mod:`morphserve._exceptions` (all re-exported here), one per problem type of the service.
"""

from . import _exceptions
from ._client import DEFAULT_URL, MAX_LISTED_JOBS, AsyncClient, AsyncJob, Client, Job, __version__
from ._exceptions import *  # noqa: F403  the exception tree; its __all__ names each class
from ._models import JOB_STATES, JobStatus, ProcessDescription, ProcessSummary, Results
from ._progress import ProgressBar

__all__ = [
    "DEFAULT_URL",
    "JOB_STATES",
    "MAX_LISTED_JOBS",
    "AsyncClient",
    "AsyncJob",
    "Client",
    "Job",
    "JobStatus",
    "ProcessDescription",
    "ProcessSummary",
    "ProgressBar",
    "Results",
    "__version__",
]
__all__ += _exceptions.__all__
