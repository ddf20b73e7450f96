"""The budget's cells (gimbalsim._budget) when units have no figure: one
stopped unit of 60 counts as worst, and every cell still shows the empirical
value, or says that it falls on the units without a figure and gives the
worst figure there is: never a bare n/a."""
from types import SimpleNamespace

from gimbalsim import _budget


class Spec:
    def header(self):
        return ["sample", "status", "ape_track"]


def rows(n_ok, n_stopped):
    ok = [[str(i), "ok", repr(1e-5 * (1 + i / 100))] for i in range(n_ok)]
    return ok + [[str(n_ok + i), "stopped: sim.penetration_limit", "nan"] for i in range(n_stopped)]


def index(level, confidence=0.95):
    return SimpleNamespace(name="ape", level=level, confidence=confidence, requirement=None)


def test_one_stopped_unit_of_60_leaves_no_cell_bare():
    e = _budget.entry(Spec(), rows(59, 1), index(0.9973), "track")
    assert not e["supported"] and e["n"] == 60 and e["n_missing"] == 1
    text = _budget.cell(e)
    assert "n/a" not in text, text
    assert "falls on the 1 of 60 units without one" in text
    assert f"the worst unit with a figure: {1e-5 * 1.58:.3g} rad" in text, text
    assert e["worst_with_figure_rad"] == 1e-5 * (1 + 58 / 100)


def test_a_supported_quantile_below_the_missing_units_keeps_its_number():
    # level 0.5 over 60 units, one stopped: the median is a figure, the interval too.
    e = _budget.entry(Spec(), rows(59, 1), index(0.5), "track")
    assert e["supported"] and e["estimate_rad"] is not None
    assert "estimate_note" not in e
    text = _budget.cell(e)
    assert "n/a" not in text and "beyond" not in text, text


def test_a_supported_quantile_on_the_missing_units_says_so():
    # level 0.9 over 100 units of which 20 stopped: the quantile and its upper bound fall on them.
    e = _budget.entry(Spec(), rows(80, 20), index(0.9), "track")
    assert e["supported"] and e["estimate_rad"] is None
    text = _budget.cell(e)
    assert "n/a" not in text, text
    assert "beyond every figure" in text and "20 of 100 units without one" in text


def test_every_unit_drawn_counts_crashed_and_refused_as_worst():
    # 59 good units, one that crashed its worker, one the scene refused: n is the 61 drawn,
    # and a requirement every good unit meets cannot PASS over the units without a figure.
    drawn = rows(59, 0) + [["59", "crashed", ""], ["60", "refused:contact.clearance", ""]]
    idx = SimpleNamespace(name="ape", level=0.9, confidence=0.5, requirement=1.0)
    e = _budget.entry(Spec(), drawn, idx, "track")
    assert e["n"] == 61 and e["n_missing"] == 2
    assert e["requirement"]["n_meeting"] == 59
    assert e["requirement"]["fraction_meeting"] == 59 / 61
    strict = SimpleNamespace(name="ape", level=0.98, confidence=0.5, requirement=1.0)  # PASS over the 59 alone
    assert _budget.entry(Spec(), drawn, strict, "track")["requirement"]["verdict"].startswith("FAIL")


def test_a_bound_beyond_every_figure_is_null_with_its_reason():
    # (pass 44) one crashed unit of 4: the interval's upper end fell on it and summary.json said [0.57, null]
    # with an empty note
    e = _budget.entry(Spec(), rows(3, 1), index(0.5, 0.5), "track")
    assert e["interval_rad"][0] is not None and e["interval_rad"][1] is None and e["n_missing"] == 1, e
    assert "the interval's upper end beyond every figure: on the 1 of 4 units without one" in e["bound_note"], e
    assert "bound_note" not in _budget.entry(Spec(), rows(59, 1), index(0.5), "track")  # every end a figure


def test_stopped_units_with_a_figure_before_the_stop_are_said_to_have_one():
    # (pass 54) three units stopped after the phase: their rows hold its figure (0.0), and the note said
    # "no unit has a figure (all 3 without one)" beside them. They still count as worst; the note says so.
    drawn = [[str(i), "sim.velocity_limit", "0.0"] for i in range(3)]
    e = _budget.entry(Spec(), drawn, index(0.9973), "track")
    assert e["n"] == 3 and e["n_missing"] == 3 and e["estimate_rad"] is None
    assert e["note"] == ("no unit has a figure the budget takes (all 3 count as worst): 3 stopped "
                         "(sim.velocity_limit), 3 of them with a figure over this phase before the stop, not used: "
                         "a unit that stopped counts as worst"), e["note"]
    assert _budget.cell(e) == e["note"]
    # a stop inside the phase leaves no figure in the row: nothing more is said
    inside = [[str(i), "sim.velocity_limit", "nan"] for i in range(3)]
    assert _budget.entry(Spec(), inside, index(0.9973), "track")["note"].endswith("3 stopped (sim.velocity_limit)")


def test_a_verdict_over_figures_all_exactly_0_says_so():
    # (pass 70) no motion and no noise: every unit's figure 0, and the budget said PASS with nothing beside it
    zeros = [[str(i), "ok", "0"] for i in range(20)]
    question = SimpleNamespace(name="ape", level=0.5, confidence=0.5, requirement=1e-4)
    e = _budget.entry(Spec(), zeros, question, "track")
    assert e["requirement"]["verdict"].startswith("PASS")
    assert "every unit's figure is exactly 0 rad" in _budget.verdict_text(e), _budget.verdict_text(e)
    # one unit with a figure above 0: no such note
    e = _budget.entry(Spec(), zeros[:19] + [["19", "ok", "1e-9"]], question, "track")
    assert "exactly 0" not in _budget.verdict_text(e), _budget.verdict_text(e)
    # (pass 73) one without a figure: the PASS still rests on zeros only, and says so
    e = _budget.entry(Spec(), zeros[:19] + [["19", "stopped: sim.penetration_limit", "nan"]], question, "track")
    assert e["requirement"]["verdict"].startswith("PASS")
    assert ("every figure is exactly 0 rad (19 of 20 units have one, the others count as worst)"
            in _budget.verdict_text(e)), _budget.verdict_text(e)
