"""HTML pages for browsers: the landing page, the processes, a process, the jobs and a job.

The JSON routes stay the only source of what the service says. :class:`HtmlMiddleware`
answers ``GET`` of ``/``, ``/processes``, ``/processes/{id}``, ``/jobs`` and ``/jobs/{id}``
with HTML when the client prefers ``text/html`` (a browser's ``Accept``) or asks with
``?f=html``: it asks the application for the JSON document with the same headers (so API
keys and job ownership apply unchanged) and renders it (:mod:`service.html.pages`). A
problem (4xx/5xx) becomes an HTML error page with the same status. Every other request, and
these paths for JSON clients (``Accept: application/json``, ``*/*``, none, or ``?f=json``),
pass through untouched but for ``Vary: Accept``.
"""

from service.html.middleware import HtmlMiddleware, wants_html

__all__ = ["HtmlMiddleware", "wants_html"]
