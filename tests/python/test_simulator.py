"""Simulator: step and run give simulate()'s rows; a pickled State resumes
bit for bit (mid-impact, mid-stick, both sub-step policies); numerical
trouble raises SimulationStopped naming the limit; threads stepping their own
Simulators give the results of one after the other; a long loop does not grow
the process's memory."""
import pickle
import threading

import numpy as np
import pytest

import gimbalsim
from conftest import scene_path

COL = {name: i for i, name in enumerate(gimbalsim.COLUMNS)}


def scene(name="paper_clearance", **overrides):
    return gimbalsim.load_scene(scene_path(name), {k.replace("__", "."): v for k, v in overrides.items()})


def test_run_gives_the_rows_of_simulate():
    s = scene(sim__duration=0.5, friction__law="coulomb_stick")
    expected = gimbalsim.simulate(s).rows
    sim = gimbalsim.Simulator(s)
    first = sim._output_array()
    tau = np.tile([5.0, 10.0], (len(expected) - 1, 1))
    rows = sim.run(tau)
    assert first.tobytes() == expected[0].tobytes()
    assert rows.tobytes() == expected[1:].tobytes()
    assert sim.t == pytest.approx(0.5, abs=1e-12)
    # step() with n gives the same end state as run() (same bits)
    other = gimbalsim.Simulator(s)
    other.step(5.0, 10.0, n=len(expected) - 1)
    assert other._output_array().tobytes() == expected[-1].tobytes()
    assert tuple(other.output()) == s.columns  # the CSV's columns: 42 for the paper's joint kinds
    assert len(s.columns) == 42 and s.columns == gimbalsim.COLUMNS[:42]


CHECKPOINTS = {
    # in contact and penetrating: an impact is under way
    "mid-impact": lambda st, out: any(st.in_contact) and out[COL["delta2"]] > 0.0,
    # in contact, the journal sticking (coulomb_stick friction mode 0)
    "mid-stick": lambda st, out: any(st.in_contact) and st.friction_mode == 0 and st.t > 0.1,
}


@pytest.mark.parametrize("policy", ["fixed", "adaptive"])
@pytest.mark.parametrize("where", list(CHECKPOINTS))
def test_pickled_state_resumes_bit_for_bit(policy, where):
    overrides = {"friction.law": "coulomb_stick", "sim.substep_policy": policy}
    if policy == "adaptive":
        overrides["sim.substep_tol"] = 1.0e-8
    s = gimbalsim.load_scene(scene_path("paper_clearance"), overrides)
    sim = gimbalsim.Simulator(s)
    while True:
        sim.step(5.0, 10.0)
        if CHECKPOINTS[where](sim.state, sim._output_array()):
            break
        assert sim.t < 4.0, "the checkpoint condition never held"
    saved = pickle.dumps(sim.state)
    scene_bytes = pickle.dumps(s)
    tau = np.tile([5.0, 10.0], (300, 1))
    tau[150:] = [-3.0, 20.0]  # the torques change after the checkpoint too
    original = sim.run(tau)
    resumed = gimbalsim.Simulator(pickle.loads(scene_bytes))  # another simulator, fresh workspace
    resumed.state = pickle.loads(saved)
    again = resumed.run(tau)
    assert again.tobytes() == original.tobytes()
    assert np.any(original[:, COL["fn2"]] > 0.0)
    back = pickle.loads(saved)
    assert back.variant == sim.variant and back.q.tobytes() == pickle.loads(saved).q.tobytes()


def test_a_state_of_another_variant_is_refused():
    sim = gimbalsim.Simulator(scene())
    with pytest.raises(ValueError, match="variant"):
        sim.state = gimbalsim.Simulator(scene("paper_ideal")).state


def test_numerical_trouble_raises_simulation_stopped_naming_the_limit():
    sim = gimbalsim.Simulator(scene(sim__max_substeps=3))
    with pytest.raises(gimbalsim.SimulationStopped) as e:
        sim.step(5.0, 10.0, n=5000)
    assert e.value.key == "sim.max_substeps" and 0.0 < e.value.time < 5.0
    good = sim.state
    assert np.all(np.isfinite(good.q))
    batch = gimbalsim.Simulator(scene(sim__max_substeps=3))
    with pytest.raises(gimbalsim.SimulationStopped) as e:
        batch.run(np.tile([5.0, 10.0], (5000, 1)))
    assert e.value.key == "sim.max_substeps"
    assert e.value.outputs.shape == (e.value.steps_done, len(gimbalsim.COLUMNS)) and e.value.steps_done > 0
    with pytest.raises(ValueError):
        batch.run(np.zeros((3, 3)))
    with pytest.raises(ValueError):
        batch.step(0.0, 0.0, n=-1)
    # a flag or a float is no number of steps (True ran one step, 2.0 was refused unnamed)
    for wrong in (True, 2.0, "3"):
        with pytest.raises(TypeError, match="n must be an int"):
            batch.step(0.0, 0.0, n=wrong)
    batch.step(0.0, 0.0, n=np.int64(0))  # a numpy count is one


def _work(s, n, out, i):
    sim = gimbalsim.Simulator(s)
    tau = np.tile([5.0, 10.0], (n, 1))
    rows = sim.run(tau[: n // 2])
    for _ in range(n // 4):
        sim.step(5.0, 10.0)
    sim.step(5.0, 10.0, n=n - n // 2 - n // 4)
    out[i] = (rows, sim._output_array())


def test_two_threads_give_the_results_of_one_after_the_other():
    scenes = [scene(), scene(sim__substep_policy="adaptive", friction__law="coulomb_stick")]
    n = 1500
    serial = [None, None]
    for i, s in enumerate(scenes):
        _work(s, n, serial, i)
    parallel = [None, None]
    threads = [threading.Thread(target=_work, args=(s, n, parallel, i)) for i, s in enumerate(scenes)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(serial, parallel):
        assert a[0].tobytes() == b[0].tobytes() and a[1].tobytes() == b[1].tobytes()


def _rss_kib():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise AssertionError("no VmRSS")


def test_a_long_loop_does_not_grow_memory():
    sim = gimbalsim.Simulator(scene())
    for _ in range(10_000):  # warm up: interpreter caches, allocator pools
        sim.step(5.0, 10.0)
        sim.output()
    before = _rss_kib()
    for _ in range(100_000):
        sim.step(5.0, 10.0)
        sim.output()
    grown = _rss_kib() - before
    assert grown < 1024, f"RSS grew by {grown} KiB over 10^5 steps"
    assert sim.t == pytest.approx(110.0, abs=1e-9)


@pytest.mark.parametrize("call", ["step", "run", "simulate", "closed_loop"])
def test_long_calls_release_the_gil(call):
    """While a long C++ call runs in one thread, this thread keeps taking turns
    through the whole call. With the GIL held it could take turns only in the
    few milliseconds around the call (Python's switch interval), not across it."""
    import time

    # calls of a few tenths of a second on a quiet machine (the paper's 5 s
    # with fixed sub-steps is about 200 000 sub-steps)
    s = scene(sim__duration=5.0)
    sim = gimbalsim.Simulator(s)
    ctrl = gimbalsim.Controller(scene_path("x").parents[2] / "controllers" / "config" / "default.yaml")
    work = {"step": lambda: sim.step(5.0, 10.0, n=5000),
            "run": lambda: sim.run(np.tile([5.0, 10.0], (5000, 1))),
            "simulate": lambda: gimbalsim.simulate(s),
            "closed_loop": lambda: gimbalsim.closed_loop(s, ctrl, 4.0)}
    window = {}

    def job():
        window["start"] = time.perf_counter()
        work[call]()
        window["end"] = time.perf_counter()

    t = threading.Thread(target=job)
    t.start()
    first = last = None
    while t.is_alive():
        now = time.perf_counter()
        if "start" in window and "end" not in window:
            first = first or now
            last = now
    t.join()
    duration = window["end"] - window["start"]
    assert duration > 0.05, "the call is too short to tell"
    assert first is not None and last - first > 0.5 * duration, \
        f"this thread ran only {0 if first is None else last - first:.4f} s of the call's {duration:.4f} s"
