"""One sample of a finished (or interrupted) sweep, run again alone:

    python3 -m gimbalsim.sweep DIR --replay I --out run.csv [--plot run.png]

reads DIR's copy of its spec (spec.yaml, its paths against the original's
folder, inputs.json) and its row of sample I (results.csv, else the journal),
refuses (exit 2, naming what changed) when the base scene's or controller's
fingerprint is no longer the sweep's, runs the sample in this process through
the sweep's own seam (_sample.sample_alone, what the sweep's tasks run),
compares every column of the row as text (wall_time_s aside: a duration), and
writes the sample's full time series (run.csv, the project's CSV convention)
and a plot beside it.
Exit codes (the project's table, docs/usage.md "Exit codes", mirrored in _errors.py): 0
reproduced, 2 refused, 3 reproduced, but the sample's run stopped (its status
names why), 4 an output not written, 8 the row did not reproduce (the columns
named; the time series is written all the same) (docs/python.md "Replay")."""
import csv
import io
import json
import pathlib
import re
import sys

from . import _provenance
from ._errors import (EXIT_INTERNAL, EXIT_OK, EXIT_REFUSED, EXIT_STOPPED, NotReproduced, OutputError, SpecError,
                      guarded_main)
from ._journal import JOURNAL, refuse_rows_beyond_the_record, take_recorded_design, whole_lines
from ._output import check_outputs, figure_bytes, write_bytes
from ._sample import sample_alone
from ._spec import refuse_inside_tool_folder
from ._sweep_spec import SweepSpec

NOT_COMPARED = ("wall_time_s",)  # how long it took, not what it computed


def _refuse(message):
    raise SpecError(message)


_NOT_UTF8 = re.compile("[\udc80-\udcff]")  # the bytes that were not UTF-8, as surrogateescape reads them


def _read_rows(folder):
    """(file, header, {sample: row}, {sample: "file:line" of its row}) of
    results.csv and the journal together: a resume with --until journals
    rows that an earlier results.csv lacks. A last line cut by an
    interruption is read by the resume's rule (_journal.whole_lines): no row,
    its sample "cut" when no file holds a whole row of it."""
    found, cuts = [], []
    for name in ("results.csv", JOURNAL):
        path = folder / name
        if path.is_file():
            try:
                whole, cut = whole_lines(path.read_bytes())
                # surrogateescape: a row that is not UTF-8 is refused on its own line (below), the others read
                text = b"".join(line + b"\n" for line in whole).decode("utf-8", errors="surrogateescape")
                reader = csv.reader(io.StringIO(text, newline=""))
                lines, ends = [], []
                for r in reader:
                    lines.append(r)
                    ends.append(reader.line_num)
            except (OSError, UnicodeDecodeError, csv.Error) as e:  # csv.Error: a line over the field limit
                _refuse(f"{path}: cannot read it ({e})")
            if not lines:
                _refuse(f"{path} is empty: the sweep wrote nothing yet")
            found.append((path, lines, ends))
            sample = re.match(rb"([0-9]{1,18}),", cut)  # the cut row's sample, when its first cell is whole
            if sample:
                cuts.append((int(sample[1]), f"{path}:{len(whole) + 1}"))
    if not found:
        _refuse(f"{folder} holds neither results.csv nor the journal {JOURNAL}: no sample to replay")
    source, header = found[0][0], found[0][1][0]
    rows, where = {}, {}
    if any(_NOT_UTF8.search(cell) for cell in header):
        _refuse(f"{source}:1: its header is not UTF-8 text: not a file the sweep wrote")
    for path, lines, ends in found:
        if lines[0] != header:
            _refuse(f"{path}: its columns are not those of {source}")
        for r, line in zip(lines[1:], ends[1:]):
            if any(_NOT_UTF8.search(cell) for cell in r):  # no row the sweep wrote
                if r and r[0].isdigit():
                    where[int(r[0])] = f"{path}:{line}"
                    rows[int(r[0])] = "not UTF-8"
                continue
            if r and r[0].isdigit() and int(r[0]) not in rows:
                rows[int(r[0])], where[int(r[0])] = r, f"{path}:{line}"
            elif r and r[0].isdigit() and r != rows[int(r[0])]:  # two different rows: which is the sweep's?
                where[int(r[0])] += f" and {path}:{line}"
                rows[int(r[0])] = None
    for sample, line in cuts:  # a whole row of the sample elsewhere is the one a resume keeps
        if sample not in rows:
            rows[sample], where[sample] = "cut", line
    return source, header, rows, where


def _check_output(path, folder, what):
    """An output of the replay: not a folder, not one of the sweep's own
    files, in a folder that exists (docs/usage.md "Output files")."""
    p = pathlib.Path(path)
    if p.is_dir():
        _refuse(f"{what} {path}: is a folder; give a file name")
    if p.resolve().parent == folder.resolve() or folder.resolve() in p.resolve().parents:
        _refuse(f"{what} {path}: inside the sweep's folder {folder}; its files are the sweep's, write elsewhere")
    if not p.absolute().parent.is_dir():
        _refuse(f"{what} {path}: the folder it goes in, {p.absolute().parent}, does not exist (create it first)")
    # another sweep's, an allocation's or a tuning study's files: never written over by a replay
    refuse_inside_tool_folder(what, path)
    return p


def _changed_keys(old, new):
    """'key old -> new' for each key whose value differs."""
    keys = sorted(set(old) | set(new))
    return [f"{k} {old.get(k, '(none)')} -> {new.get(k, '(none)')}" for k in keys if old.get(k) != new.get(k)]


def load(folder):
    """The sweep spec of DIR (its copy, paths against the original's folder),
    checked against the fingerprints the sweep recorded."""
    folder = pathlib.Path(folder)
    if not folder.is_dir():
        _refuse(f"{folder}: no such sweep folder")
    copy, inputs_path = folder / _provenance.SPEC_COPY, folder / _provenance.INPUTS
    if not copy.is_file() or not inputs_path.is_file():
        _refuse(f"{folder} has no {_provenance.SPEC_COPY} and {_provenance.INPUTS}: not a sweep folder, or one "
                f"made before sweeps recorded their inputs")
    try:
        inputs = json.loads(inputs_path.read_text(encoding="utf-8"))
        spec_folder, recorded = inputs["spec_folder"], inputs["fingerprints"]
        workdir = inputs.get("workdir")  # absent in a sweep made before it was recorded
        if workdir is not None and not isinstance(workdir, str):
            raise TypeError(f"workdir is {type(workdir).__name__}, not a path")
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError) as e:
        _refuse(f"{inputs_path}: unreadable ({e})")
    spec = SweepSpec(copy, folder=spec_folder, workdir=workdir)
    now = _provenance.fingerprints(spec)
    if now != recorded:
        what = [k for k in sorted(set(now) | set(recorded)) if now.get(k) != recorded.get(k)]
        detail = ""
        try:  # the sweep's base values are in its spec.json (the resume fingerprint)
            old = json.loads((folder / "spec.json").read_text(encoding="utf-8"))["scene"]
            detail = "; changed: " + ", ".join(_changed_keys(old, spec.base.values()))
        except (OSError, ValueError, KeyError, TypeError):
            pass
        # the set and controller_set are the copy's, the file read: an edit there is named, not the original
        if _provenance.SCENE_FINGERPRINT in what:
            _refuse(f"{', '.join(what)} differs from the sweep's: {spec.scene_path} (with the set of {copy}) is "
                    f"not the scene the sweep ran{detail}")
        closed = getattr(spec, "closed", None)
        source = (closed.controller_path or "the built-in default") if closed is not None else "?"
        _refuse(f"{', '.join(what)} differs from the sweep's: the controller configuration {source} (with the "
                f"controller_set of {copy}) is not the one the sweep ran")
    original = pathlib.Path(inputs.get("spec", ""))
    spec.original_spec = original if str(original) not in ("", ".") else None  # an input of the replay too
    try:
        ran = (folder / "spec.json").read_text(encoding="utf-8")  # the fingerprint of the spec the sweep ran
    except (OSError, UnicodeDecodeError):
        ran = None
    try:
        if ran is not None and ran != spec.fingerprint:  # the copy was edited: it, not the original, is named
            print(f"replay: {copy} differs from the spec the sweep ran (its fingerprint {folder / 'spec.json'}): "
                  f"edited since the sweep; replaying from it as it is", file=sys.stderr)
        elif inputs.get("spec_sha256") is not None:  # the file as the sweep read it, recorded
            if original.is_file() and _provenance.file_sha256(original) != inputs["spec_sha256"]:
                print(f"replay: {original} was edited since the sweep; replaying from the sweep's copy {copy}",
                      file=sys.stderr)
        elif original.is_file() and original.read_text(encoding="utf-8") != spec.spec_text:
            # a comment edited in the copy leaves its fingerprint: which of the two changed is unknown
            print(f"replay: {original} differs from the sweep's copy {copy} (one of them was edited since the "
                  f"sweep); replaying from the copy", file=sys.stderr)
    except (OSError, UnicodeDecodeError):
        pass
    return spec


def replay(folder, i, out, plot_path=None):
    """Replays sample i of the sweep in folder; returns the exit code (a row
    that does not reproduce raises NotReproduced, after the outputs are written)."""
    folder = pathlib.Path(folder)
    spec = load(folder)
    out = _check_output(out, folder, "--out")
    plot_path = _check_output(plot_path or out.with_suffix(".png"), folder, "--plot")
    if plot_path.resolve() == out.resolve():
        _refuse(f"--plot {plot_path}: the same file as --out")
    plot_format = _figure_format(plot_path)
    inputs = spec.input_files() + [spec.original_spec]  # the spec the sweep ran from is an input, never an output
    # and every file of the sweep's folder, whatever its name outside it (pass 69: a hard link of results.csv)
    inputs += sorted(p for p in folder.iterdir() if p.is_file())
    try:  # before anything runs, as the command line: refused (exit 2)
        check_outputs([out, plot_path], inputs)
    except OutputError as e:
        _refuse(str(e))
    source, header, rows, where = _read_rows(folder)
    take_recorded_design(folder, spec)  # the samples --until added: their draws are (seed, i) as any other's
    whole = [r for r in rows.values() if isinstance(r, list)]
    refuse_rows_beyond_the_record(source, spec, whole, len(header))  # as a resume does
    if not 0 <= i < len(spec.design):
        _refuse(f"--replay {i}: outside the sweep's samples 0..{len(spec.design) - 1}")
    if header != spec.csv_header():
        _refuse(f"{source}: its columns are not those of the spec copy {folder / _provenance.SPEC_COPY}")
    if i not in rows:
        _refuse(f"--replay {i}: sample {i} has no row in {folder} (results.csv, {JOURNAL}): not run yet, finish "
                "the sweep with --resume")
    recorded = rows[i]
    if recorded == "not UTF-8":
        _refuse(f"{where[i]}: sample {i}'s row is not UTF-8 text: not a row the sweep wrote; --resume the sweep, "
                "which drops such a row and runs its sample again")
    if recorded == "cut":  # compared, it blamed the simulation (exit 8) for the interruption's cut
        _refuse(f"{where[i]}: sample {i}'s row is not whole (its last line, cut by an interruption): not a row the "
                f"sweep wrote; --resume the sweep, which drops it and runs the sample again")
    if recorded is None:  # (pass 34) the first of two was compared, and the study's two rows never said
        _refuse(f"{where[i]}: two different rows of sample {i}: no file the sweep writes; --resume the sweep, which "
                "drops both and runs the sample again")
    if len(recorded) != len(header):  # cut or edited: no row the sweep wrote, and nothing to compare column by column
        _refuse(f"{where[i]}: sample {i}'s row has {len(recorded)} columns, not the header's {len(header)}: not a "
                f"row the sweep wrote; --resume the sweep, which drops such a row and runs its sample again")
    status = recorded[header.index("status")]
    if status == "crashed":
        print(f"replay: sample {i} was recorded crashed (it killed its worker twice); running it alone in this "
              f"process, which it may kill too", file=sys.stderr)
    row, run = sample_alone(spec, i)
    # a crashed row holds the parameters and fingerprints only: those are compared
    compared = [k for k, name in enumerate(header) if name not in NOT_COMPARED
                and (status != "crashed" or (recorded[k] and name != "status"))]
    differ = [header[k] for k in compared if row[k] != recorded[k]]
    replay_status = row[header.index("status")]
    if run is None:
        print(f"replay: the scene refuses sample {i} ({replay_status}): nothing ran, nothing written", file=sys.stderr)
        if differ:
            _report(differ, header, recorded, row, i, source)
        return EXIT_REFUSED
    if not hasattr(run, "to_csv"):  # the seam's contract: a run writes its own series by the CSV convention
        print(f"error: sample {i}'s run ({type(run).__name__}) cannot write its time series (no to_csv)",
              file=sys.stderr)
        return EXIT_INTERNAL
    figure = _plot(run, spec, i, replay_status, plot_format)  # drawn before any file is written
    try:
        run.to_csv(out)  # an open loop's Run writes through the C++ writer, which raises OSError
    except OutputError:
        raise
    except OSError as e:
        raise OutputError(str(e)) from None
    try:
        write_bytes(plot_path, figure, inputs)
    except OutputError:
        out.unlink(missing_ok=True)  # the two outputs come together or not at all
        raise
    print(f"replay: sample {i}: {len(run.rows)} rows in {out}, plot {plot_path}", file=sys.stderr)
    if differ:
        _report(differ, header, recorded, row, i, source)
    if status == "crashed":
        print(f"replay: sample {i} ran alone to status {replay_status}; its parameters and fingerprints are the "
              f"row's", file=sys.stderr)
    else:
        print(f"replay: sample {i} reproduces its row of {source}, every column but "
              f"{', '.join(NOT_COMPARED)}, bit for bit", file=sys.stderr)
    if replay_status != "ok":
        print(f"replay: {_stop_text(run.summary, replay_status)}", file=sys.stderr)
        return EXIT_STOPPED
    return EXIT_OK


def _stop_text(summary, status):
    """Why a replayed sample is not ok, in the run's own words: an open loop's
    stop (its time and step status), a closed loop's error, or (open loop) the
    ideal-joint twin that stopped, leaving no pointing error."""
    if "stop" in summary and summary["stop"]:  # open loop
        stop = summary["stop"]
        run = f"the run stopped at t = {stop['time_s']:g} s: {stop['step_status']}" if stop.get("key") else "the run ended"
    else:
        run = summary.get("error") or "the run ended"
    twin = status.split("ideal:", 1)[1] if "ideal:" in status else None
    return f"status {status}: " + (run if twin is None or "|" in status else "") + \
        (("; " if "|" in status else "") + f"the ideal-joint twin (the pointing error's reference) stopped on {twin}, "
         "so the sample has no pointing error" if twin else "")


def _report(differ, header, recorded, row, i, source):
    """Raises NotReproduced naming the columns that differ and their two values."""
    detail = "; ".join(f"{c}: {recorded[header.index(c)]!r} in the sweep, {row[header.index(c)]!r} now"
                       for c in differ)
    raise NotReproduced(f"sample {i} does not reproduce its row of {source}: {len(differ)} column"
                        f"{'s' * (len(differ) != 1)} differ: {detail}")


# The plot's panels: (y label, columns), each drawn when the run has its columns
# (an open-loop Run, or a closed loop's ticks).
PANELS = [("joint angle [rad]", ("theta1", "theta2")), ("joint angle [rad]", ("theta1_true", "theta2_true")),
          ("applied torque [N m]", ("tau1_applied", "tau2_applied")), ("joint-2 eccentricity [m]", ("ecc2",)),
          ("joint-2 force [N]", ("joint2_force",)), ("truth pointing error [rad]", ("truth_error",))]


def _figure_format(path):
    """The figure format path's suffix names; refused (before anything runs)
    when matplotlib cannot write it."""
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.backend_bases import FigureCanvasBase
    fmt = path.suffix.lstrip(".").lower()
    # pgf needs a LaTeX installation the project does not install (xelatex): not offered.
    supported = {k: v for k, v in FigureCanvasBase.get_supported_filetypes().items() if k != "pgf"}
    if fmt not in supported:
        _refuse(f"--plot {path}: a figure is written as one of {', '.join(sorted(supported))} (its suffix), "
                f"not {fmt or 'a file without a suffix'!r}")
    return fmt


def _panels(run):
    """[(label, column names)] of the panels the run has columns for."""
    return [(label, names) for label, names in PANELS if all(n in run.columns for n in names)]


def _plot(run, spec, i, status, fmt):
    """The run's panels as the bytes of a figure in format fmt."""
    import matplotlib.pyplot as plt

    c = run.columns
    panels = _panels(run)
    fig, axes = plt.subplots(len(panels), 1, figsize=(8, 2.7 * len(panels)), sharex=True, squeeze=False)
    for ax, (label, names) in zip(axes[:, 0], panels):
        for n in names:
            ax.plot(c["t"], c[n], label=n)
        if names == ("ecc2",) and getattr(run, "scene", None) is not None:
            v = run.scene.values()
            radius = {n: float(v.get("joint2.contact." + n, v["contact." + n])) for n in ("bearing_radius", "journal_radius")}
            ax.axhline(radius["bearing_radius"] - radius["journal_radius"], ls=":", c="gray",
                       label="clearance")
        ax.set_ylabel(label)
        ax.legend()
    axes[-1, 0].set_xlabel("t [s]")
    fig.suptitle(f"sample {i} of the sweep in {spec.spec_path.parent.name}/ ({status})")
    fig.tight_layout()
    try:
        return figure_bytes(fig, fmt, dpi=110)
    except (OSError, RuntimeError, ValueError, AttributeError) as e:  # a backend that cannot draw: nothing written
        raise OutputError(f"the plot ({fmt}) could not be drawn: {e}") from None
    finally:
        plt.close(fig)


def main(folder, i, out, plot_path):
    """--replay's exit code, by the project's table (_errors.guarded_main)."""
    return guarded_main("replay", lambda: replay(folder, i, out, plot_path))


if __name__ == "__main__":
    from gimbalsim._errors import not_a_program
    not_a_program("replay")
