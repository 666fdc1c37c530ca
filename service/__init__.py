"""The rfesim HTTP service: FastAPI routes (``service.app``), the job manager
(``service.jobs``), the executor seam (``service.executor``: local process pool or
Dask) and the SQLite job store (``service.store``). Start it with ``rfesim serve``.

The service imports the rfesim package; the package never imports the service.
"""
