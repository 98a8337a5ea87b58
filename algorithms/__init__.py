"""The numpy/scipy geometry algorithms behind morphserve (numba compiles one search: ICP's
nearest points, :mod:`algorithms.core.kdtree`).

Nothing here knows about HTTP, Dask or pydantic: every function takes numpy arrays and
keyword parameters and returns a small frozen dataclass. One package per family
(``alignment``, ``assignment``, ...), shared building blocks in ``core``.
"""
