"""The Dask cluster the sweep and the tuner run on: a local cluster of one
worker process per core (the default), or an existing scheduler that
dask-worker processes on any number of machines have joined. Every worker
needs this package on its PYTHONPATH."""
import contextlib
import logging
import os


@contextlib.contextmanager
def dask_client(workers=None, scheduler=None):
    """Yields (client, number of workers)."""
    from distributed import Client, LocalCluster

    if scheduler:
        client = Client(scheduler, timeout="30s")
        try:
            client.wait_for_workers(1, timeout=60)
            yield client, len(client.scheduler_info()["workers"])
        finally:
            client.close()
        return
    n = workers or os.cpu_count() or 1
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                           silence_logs=logging.ERROR)
    client = Client(cluster)
    try:
        yield client, n
    finally:
        client.close()
        cluster.close()


def add_cluster_arguments(parser):
    g = parser.add_mutually_exclusive_group()
    g.add_argument("--workers", type=int, default=None,
                   help="local cluster of N worker processes (default: one per core)")
    g.add_argument("--scheduler", default=None,
                   help="an existing Dask scheduler, tcp://HOST:PORT (dask-scheduler + dask-worker processes)")
