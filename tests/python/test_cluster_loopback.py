"""The local Dask cluster of the sweep and the tuner opens no door on the
network: every socket it listens on (scheduler, nanny, worker, their HTTP
servers) is bound to loopback."""
import psutil

from gimbalsim._cluster import dask_client

LOOPBACK = {"127.0.0.1", "::1"}


def listening(procs):
    return {(p.pid, c.laddr.ip, c.laddr.port)
            for p in procs for c in p.connections(kind="inet") if c.status == psutil.CONN_LISTEN}


def test_local_cluster_listens_on_loopback_only():
    me = psutil.Process()
    before = listening([me])
    with dask_client(workers=2) as (client, n):
        sockets = listening([me] + me.children(recursive=True)) - before
        scheduler = client.scheduler.address
        workers = list(client.scheduler_info()["workers"])
    assert n == 2 and len(workers) == 2
    # the scheduler, two nannies and two workers at least
    assert len(sockets) >= 5, sockets
    assert not [s for s in sockets if s[1] not in LOOPBACK], sockets
    assert scheduler.startswith("tcp://127.0.0.1:")
    assert all(w.startswith("tcp://127.0.0.1:") for w in workers)
