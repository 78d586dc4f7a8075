"""Set-up of the embedded local cluster's worker processes (a Dask preload module).

Ctrl-C in a terminal reaches every process of the command; the workers leave it to the batch's driver,
which cancels the tasks, removes half-written files and closes the cluster, so that a Ctrl-C prints one
line instead of a traceback from each worker.
"""
from __future__ import annotations

import signal

__all__ = ["dask_setup"]


def dask_setup(worker) -> None:
    """Called by Dask in each worker process as it starts."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
