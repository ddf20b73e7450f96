"""A Dask worker keeps what a sample frees for the next one: the nanny's
MALLOC_TRIM_THRESHOLD_ froze glibc's mmap threshold at 128 KiB, and every
column and array above it was mapped and page-faulted in afresh, each
sample (2.5 times a closed-loop sample's CPU on a VM). Page faults are
counted, not time: they do not depend on the machine's load."""
from gimbalsim import _cluster, sweep, tune
from gimbalsim._cluster import dask_client


def test_a_worker_reuses_freed_memory_once_a_task_has_run():
    def faults_per_mib(run_a_task):
        import os
        import resource
        from gimbalsim import sweep as worker_sweep
        if run_a_task:
            worker_sweep.run_batch(None, None, [])
        faults = lambda: resource.getrusage(resource.RUSAGE_SELF).ru_minflt  # noqa: E731
        bytearray(1 << 20)
        before = faults()
        for _ in range(50):
            bytearray(1 << 20)  # 1 MiB, zero-filled: 256 pages if mapped afresh
        return (faults() - before) / 50, os.environ.get("MALLOC_TRIM_THRESHOLD_")

    with dask_client(workers=1) as (client, _):
        fresh, trim = client.submit(faults_per_mib, False, pure=False).result()
        mended, _ = client.submit(faults_per_mib, True, pure=False).result()
    assert trim is not None, "the premise: the nanny sets glibc's trim threshold"
    assert fresh > 100, fresh
    assert mended < 10, mended


def test_every_task_of_the_sweep_and_the_tuner_mends_its_worker(monkeypatch):
    calls = []
    monkeypatch.setattr(_cluster, "keep_freed_memory", lambda: calls.append(1))
    assert sweep.run_batch(None, None, [])[0] == []
    assert tune.run_plants(None, None, None, []) == []
    assert len(calls) == 2
