"""morphserve: the Python SDK of the morphserve geometry job service.

>>> from morphserve import Client
>>> with Client("http://127.0.0.1:8000") as client:  # doctest: +SKIP
...     job = client.execute("alignment.rigid", source=a, target=b)
...     job.wait(progress=True)
...     transform = job.results()["transform"]

:class:`AsyncClient` offers the same API with ``async`` methods. ``client.map(process,
[inputs, ...])`` runs a batch of jobs; :func:`as_completed` yields jobs as they end. Errors are
the classes of :mod:`morphserve._exceptions` (all re-exported here), one per problem type of
the service, and :class:`NoSuchFile` for a path that names no file.
"""

from . import _exceptions
from ._batch import BatchItem
from ._client import (
    DEFAULT_URL,
    MAX_LISTED_JOBS,
    AsyncClient,
    AsyncJob,
    Client,
    Job,
    __version__,
    as_completed,
)
from ._exceptions import *  # noqa: F403  the exception tree; its __all__ names each class
from ._geometry import NoSuchFile
from ._models import JOB_STATES, JobStatus, ProcessDescription, ProcessSummary, Results
from ._progress import ProgressBar, ProgressDisplay

__all__ = [
    "DEFAULT_URL",
    "JOB_STATES",
    "MAX_LISTED_JOBS",
    "AsyncClient",
    "AsyncJob",
    "BatchItem",
    "Client",
    "Job",
    "JobStatus",
    "NoSuchFile",
    "ProcessDescription",
    "ProcessSummary",
    "ProgressBar",
    "ProgressDisplay",
    "Results",
    "__version__",
    "as_completed",
]
__all__ += _exceptions.__all__
