"""Set-up of the embedded local cluster's worker processes (a Dask preload module).

Ctrl-C in a terminal reaches every process of the command; the workers leave it to the batch's driver,
which cancels the tasks, removes half-written files and closes the cluster, so that a Ctrl-C prints one
line instead of a traceback from each worker. The workers' own logs are silenced as the cluster's are
(``silence_logs``): a heartbeat in flight as the cluster closes printed a traceback ("Failed to communicate
with scheduler during heartbeat") after a batch that had finished well; what fails in a task reaches the
driver through its future.
"""
from __future__ import annotations

import logging
import signal

__all__ = ["dask_setup"]


def dask_setup(worker) -> None:
    """Called by Dask in each worker process as it starts."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    logging.getLogger("distributed").setLevel(logging.CRITICAL)
