"""The sweep's files: the journal's name, the CSV text of a row, the
journal read back (every row checked against the design) and the record of
the design's size when --until grew it. Files are written by the one writer
(_output.py)."""
import csv
import io
import json
import math

from . import _provenance
from ._closed_sample import load_sample
from ._errors import OutputError, SpecError
from ._csv_cells import csv_number, csv_text
from ._sweep_spec import MAX_SAMPLES

JOURNAL = "results.partial.csv"  # the sweep's rows as they arrive (appended and synced per task)
DESIGN = "design.json"  # the design's size once --until grew it: {"samples": N}; absent, the spec's own


def record_design(out, spec, write):
    """Records the design's size in OUT/design.json before its new rows run:
    a resume or a replay then holds the same samples, no more (a capped last
    batch is not a whole one) and no fewer."""
    write(out / DESIGN, json.dumps({"samples": len(spec.design)}) + "\n")


def _drawn_beyond(spec, rows, n_columns):
    """The indices of rows beyond the design that are whole rows of their own
    draw (seed, i): results --until added. Other rows beyond it are no row the
    sweep wrote; they are dropped as outside the design."""
    beyond = [r for r in rows if r and _canonical_index(r[0]) and len(r[0]) <= 8
              and len(spec.design) <= int(r[0]) < MAX_SAMPLES]
    if not beyond or spec.grid:
        return []
    size = len(spec.design)
    spec.design.extend_to(max(int(r[0]) for r in beyond) + 1)
    try:
        return [r[0] for r in beyond if check_row(spec, r, n_columns) is None]
    finally:
        spec.design.extend_to(size)


def refuse_rows_beyond_the_record(path, spec, rows, n_columns):
    """Results of a grown sweep that the design record does not hold are never
    dropped nor used: the record is wrong (SpecError naming the file)."""
    drawn = _drawn_beyond(spec, rows, n_columns)
    if drawn:
        raise SpecError(f"{path} holds sample {drawn[0]}, beyond the sweep's {len(spec.design)} samples: "
                        f"{DESIGN}, which records the size --until grew it to, is missing or not this sweep's; "
                        "restore it, or use another --out")


def _no_repeated_key(pairs):
    keys = [k for k, _ in pairs]
    if len(set(keys)) != len(keys):
        raise ValueError("a key given twice")
    return dict(pairs)


def take_recorded_design(out, spec):
    """Extends spec's design to the size OUT/design.json records (nothing when
    there is none). A record that is unreadable, or names fewer samples than
    the spec or more than the limit, is refused naming the file (SpecError)."""
    path = out / DESIGN
    if not path.exists():
        return
    if not path.is_file():
        raise SpecError(f"{path}: not a regular file; it records the sweep's size")
    try:
        n = json.loads(path.read_text(encoding="utf-8"), object_pairs_hook=_no_repeated_key)["samples"]
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError) as e:
        raise SpecError(f"{path}: unreadable ({e}); it records the size --until grew the sweep to")
    if spec.grid or type(n) is not int or not spec.samples <= n <= MAX_SAMPLES:
        raise SpecError(f"{path}: samples {n!r} is not a size this spec grows to "
                        f"({'a grid never grows' if spec.grid else f'{spec.samples} to {MAX_SAMPLES}'})")
    spec.design.extend_to(n)


def _canonical_index(text):
    """Whether text is a sample index as the sweep writes one: its decimal,
    no sign, space or leading zero ("02" is no row the sweep wrote, and a
    replay of sample 2 would not find it)."""
    return text.isascii() and text.isdigit() and text == str(int(text))


def fmt(v):
    """A cell of the sweep's CSVs: no value empty, a float and a text as the CSV convention writes them."""
    if v is None:
        return ""
    return csv_number(v) if isinstance(v, float) else csv_text(v)


def csv_line(values):
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n", quoting=csv.QUOTE_NONE).writerow([fmt(v) for v in values])
    return buf.getvalue()


def _is_float(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


COUNTS = ("impacts", "impacts_joint1", "impacts_joint2")  # whole numbers
MAY_BE_EMPTY = ("continuous_contact_from",)  # null in a run whose last contact did not last to its end
# Every figure a sweep writes is a magnitude (a pointing error or index, a force, a tilt), a count, a time or a
# duration: none is signed, so each is >= 0 (indices.py refuses a negative pointing error).


def check_row(spec, row, n_columns):
    """Why a journal row is not to be trusted, or None: the sample index in
    range, the parameters equal to the design's draw, the status and figures
    as the sweep writes them, the fingerprints this sweep's and the applied_
    columns what the scene (and controller) apply to the draw."""
    if len(row) != n_columns:
        return "wrong number of columns"
    if not _canonical_index(row[0]) or not int(row[0]) < len(spec.design):
        return "sample index outside the design"
    i = int(row[0])
    overrides = spec.design.draw(i)
    drawn = [fmt(v) for v in spec.design.row_values(overrides)]
    if row[1:1 + len(drawn)] != drawn:  # named by its column: an edited value is found at once
        column = next(j for j, v in enumerate(drawn) if row[1 + j] != v)
        return f"{spec.csv_header()[1 + column]} differs from the design's draw"
    status = row[1 + len(drawn)]
    # after status (and a closed loop's reason), up to the provenance columns (text: applied values, hashes)
    first = 2 + len(drawn) + spec.text_columns
    figures = row[first:n_columns - len(_provenance.columns(spec))]
    if not status or not all(v == "" or _is_float(v) for v in figures) or not _is_float(figures[-1]):
        return "status or figures unreadable"
    names = spec.csv_header()
    reason = row[2 + len(drawn)] if spec.text_columns else ""
    for name, csv_name, text in zip(spec.metrics + ["wall_time"], names[first:], figures):
        why = _figure_wrong(name, text, status, reason)
        if why is not None:
            return f"{csv_name} {why}"
    why = _status_wrong(spec, status, reason, dict(zip(spec.metrics, figures)))
    if why is not None:
        return why
    return _provenance_wrong(spec, row, first + len(figures), overrides, status, reason, names)


# The stops a run ends on, as its row names them. A limit's key (dynamics/src/step_result.cpp limitKey); the
# open loop's invariants (simulate.cpp); with no key, the open loop writes the
# step's status in words (_open_sample._stop_name: non-finite_output when no step failed), the
# closed loop non_finite (python/src/controller_bindings.cpp resultDict: its stop_key is never empty when the
# run is not ok, and the one refusal it could name, control.period, _closed_sample refuses before running).
LIMIT_STOPS = ("sim.velocity_limit", "sim.penetration_limit", "sim.max_substeps", "sim.max_event_iters",
               "sim.min_substeps_per_impact")
OPEN_STOPS = LIMIT_STOPS + ("sim.momentum_tol", "sim.energy_tol", "non-finite_value_(NaN_or_Inf)_in_the_state",
                             "non-finite_output")
CLOSED_STOPS = LIMIT_STOPS + ("non_finite", "commands_rejected")
# The message a closed loop's stop begins its reason with: a limit's (dynamics/src/simulate.cpp describeStop,
# which names the key), a non-finite value's (firmware_sim closed_loop.cpp, controller_bindings guardNonFinite).
LIMIT_MESSAGE = "simulation stopped at t = "
NON_FINITE_MESSAGE = "non-finite "
NONE_ACCEPTED_MESSAGE = "the plant accepted none of "  # commands_rejected (firmware_sim closed_loop.cpp)
POINTING = ("pointing_error_max", "pointing_error_final")  # nan when the ideal twin stopped first


def _status_wrong(spec, status, reason, figures):
    """Why a row's status, with its reason (closed loop) and figures
    ({metric: text}), is none the sweep writes, or None: a refusal or a
    crash (no reason but the refusal's), ok, or one of its stops."""
    if any(part != part.strip() for part in reason.split(" | ")):  # (pass 94) "... s " was kept as the sweep's
        return "reason has white space at an end of a part: the sweep writes none"
    if status.startswith("refused:") or status == "crashed":
        return "reason is not empty in a crashed sample's row" if status == "crashed" and reason else None
    if spec.closed is None:
        return _open_status_wrong(status, figures)
    indices = spec.closed.metrics()
    parts = reason.split(" | ") if reason else []
    if status == "ok":  # its reason names only its indices that are nan, each "index_phase: why"
        if any(p.split(": ")[0] not in indices or figures[p.split(": ")[0]] != "nan" for p in parts):
            return "reason is not an ok row's (it names only the ok run's indices that are nan)"
        return None
    if status not in CLOSED_STOPS:
        return f"status is none the sweep writes (ok, {', '.join(CLOSED_STOPS)}, refused:<key>, crashed)"
    # the stop's message first (a limit's names its key), then the nan indices' reasons; every figure a number or nan
    first = parts[0] if parts else ""
    fixed = {"non_finite": NON_FINITE_MESSAGE, "commands_rejected": NONE_ACCEPTED_MESSAGE}
    if not (first.startswith(fixed[status]) if status in fixed
            else first.startswith(LIMIT_MESSAGE) and status in first):
        return f"reason is not a stopped row's: a {status} row's begins with the message of that stop"
    named = [p.split(": ")[0] for p in parts[1:]]
    if sorted(named) != sorted(m for m in indices if figures[m] == "nan"):
        return "reason is not a stopped row's: after the stop's message it names each nan index, and only those"
    if "" in figures.values():
        return "status is a stop, but a figure is empty: a stopped closed loop writes every figure"
    return None


def _open_status_wrong(status, figures):
    """Why an open-loop status is none _open_sample.run_sample writes, or
    None: `ok`, the run's stop, `ideal:<twin's stop>` (the run ok, its twin
    stopped first) or `<run's stop>|ideal:<twin's stop>`; a twin's part is
    always a stop (a twin that ran whole writes no `ideal:`), and such a row
    has no pointing error."""
    if "|ideal:" in status:
        run, _, twin = status.partition("|ideal:")
        if run not in OPEN_STOPS or twin not in OPEN_STOPS:
            return "status is none the sweep writes: in <stop>|ideal:<stop> both parts are stops (never ok)"
    elif status.startswith("ideal:"):
        twin = status[len("ideal:"):]
        if twin not in OPEN_STOPS:
            return "status is none the sweep writes: ideal:<stop> names the stop of the ideal twin (never ok)"
    elif status not in ("ok",) + OPEN_STOPS:
        return "status is none the sweep writes (ok, a stop, refused:<key>, crashed, ideal:<stop>)"
    else:
        return None
    if any(figures[m] != "nan" for m in POINTING):
        return "pointing_error is a number in an ideal:<stop> row: a twin that stopped first gives none"
    return None


def _figure_wrong(name, text, status, reason):
    """Why a figure's cell is not one the sweep writes in a row of this
    status (and a closed loop's reason), or None."""
    no_run = status == "crashed" or status.startswith("refused:")
    if no_run and (name != "wall_time" or status == "crashed"):  # no figure; a crashed sample no wall time either
        want = "nan" if name == "wall_time" else ""
        return None if text == want else f"holds {text!r} in a {status.split(':')[0]} sample's row: it has no figure"
    if text == "":
        return None if status != "ok" or name in MAY_BE_EMPTY else "is empty in an ok row"
    x = float(text)
    if csv_number(x) != text:  # the shortest text that reads back as the same double
        return f"is not a number as the sweep writes one ({text!r})"
    if math.isnan(x):
        if name == "wall_time":
            return "is nan: only a crashed sample has no wall time"
        # an ok sample's index that misses its phase is nan, and its reason says why ("ape_track: ...")
        named = any(part.startswith(f"{name}: ") for part in reason.split(" | "))
        return None if status != "ok" or named else "is nan in an ok row whose reason does not name it"
    if math.isinf(x):
        return "is infinite: the sweep never writes an infinite number"
    if x < 0.0:
        return "is negative: a magnitude, a count or a time is >= 0"
    if name in COUNTS and not x.is_integer():
        return "is not a whole number (a count)"
    return None


def _provenance_wrong(spec, row, start, overrides, status, reason, names):
    """Why a row's provenance columns (from start: applied_ values,
    applied_differs, fingerprints) are not what this sweep writes for its
    draw, or None. The scene (and controller) are loaded as a worker loads
    them: what they apply, or refuse, is compared as the sweep writes it."""
    fingerprints = _provenance.fingerprints(spec)
    n_applied = len(_provenance.columns(spec)) - len(fingerprints)
    for k, (column, value) in enumerate(fingerprints.items()):
        if row[start + n_applied + k] != value:
            return f"{column} is not this sweep's fingerprint"
    cells = row[start:start + n_applied]
    if status == "crashed":
        want = [""] * n_applied
    else:
        _, _, loaded = load_sample(spec.base, spec.closed, overrides)
        if "applied" not in loaded:  # the scene or the controller refuses the draw
            if status != loaded["status"] or (spec.text_columns and reason != fmt(loaded["reason"])):
                return "status is not the refusal the scene gives the draw"
            want = [""] * n_applied
        elif status.startswith("refused:"):
            return "status is a refusal, but the scene takes the draw"
        else:
            want = [fmt(v) for v in loaded["applied"]]
    for column, got, expected in zip(names[start:], cells, want):
        if got != expected:
            return f"{column} differs from what the draw applies when loaded"
    return None


def _parsed(line):
    """One CSV line's cells, or None when it is not CSV (a field over the csv
    module's limit, a stray quote): such a line is no row the sweep wrote."""
    try:
        return next(csv.reader([line]), [])
    except csv.Error:
        return None


def read_journal(spec, path, header):
    """The journal's trusted rows by sample, what was dropped ({reason: the
    1-based line numbers in the file}), and whether the file can be appended
    to as it is. A last line without its newline (cut by an interruption) is
    dropped; a sample written twice counts once."""
    done, dropped, appendable, _, _ = _read_rows(spec, path, header)
    return done, dropped, appendable


def _utf8(chunk):
    """A line's bytes as text, or None when they are not UTF-8."""
    try:
        return chunk.decode("utf-8")
    except UnicodeDecodeError:
        return None


def whole_lines(data):
    """A study file's bytes as its whole lines (each ended by a newline) and the bytes after the last newline:
    a last line cut by an interruption (b"" when the last write was whole). The one rule of a resume and a
    replay: a cut line is no row the sweep wrote, its sample runs again."""
    lines = data.split(b"\n")
    return lines, lines.pop()


def _read_rows(spec, path, header, journal=True):
    """read_journal's answer, the 1-based line of each trusted row ({sample: line}) and the samples the file
    holds twice, differently (trusted in no file)."""
    done, dropped, line_of, twice = {}, {}, {}, set()
    if not path.exists():
        return done, dropped, False, line_of, twice
    if not path.is_file():  # a pipe would block the resume for good, a device feed it without end
        raise SpecError(f"{path}: not a regular file (a pipe, a device or a folder): a journal is only read from a "
                        f"file; use another --out")
    try:
        data = path.read_bytes()
    except OSError as e:
        raise OutputError(f"cannot read the journal {path}: {e.strerror}")
    raw, cut = whole_lines(data)
    if cut:
        dropped["last line cut by an interruption"] = [len(raw) + 1]
    if not raw:  # killed before the header was whole: nothing was journaled
        return done, dropped, False, line_of, twice
    # Line by line: a line that is not UTF-8 is no row the sweep wrote (decoded with replacement characters,
    # one was trusted and written back with them: pass 63).
    lines = [_utf8(chunk) for chunk in raw]
    if lines[0] is None or _parsed(lines[0]) != header:
        raise SpecError(f"{path} was written by another spec (its header differs); use another --out")
    rows = []
    for number, line in enumerate(lines[1:], 2):
        row = None if line is None else _parsed(line)
        if line is None:
            dropped.setdefault("not UTF-8 text", []).append(number)
        elif row is None:
            dropped.setdefault("unreadable line", []).append(number)
        else:
            rows.append((number, row))
    refuse_rows_beyond_the_record(path, spec, [row for _, row in rows], len(header))
    # a sample held twice, differently (twice): neither row is trusted (the first stayed); each file's own words
    # (pass 40: results.csv's rows were said "journaled")
    differently, again = (("sample journaled twice, differently", "sample already journaled") if journal else
                          (f"sample held twice, differently, in {path.name}", f"sample already in {path.name}"))
    for number, row in rows:
        why = check_row(spec, row, len(header))
        sample = int(row[0]) if why is None else None
        if sample in twice:
            why = differently
        elif why is None and sample in done:
            why = again if row == done[sample] else differently
            if why == differently:
                twice.add(sample)
                del done[sample]
                dropped.setdefault(why, []).append(line_of[sample])
        if why is not None:
            dropped.setdefault(why, []).append(number)
            continue
        done[sample], line_of[sample] = row, number
    return done, dropped, not dropped, line_of, twice


def read_for_resume(spec, journal, results, header):
    """What a resume trusts: ({sample: row}, [(file, {reason: line numbers})],
    whether the journal can be appended to as it is). The journal's rows and,
    when results.csv is there too (a resume of a finished sweep, interrupted),
    its rows as well: a sample with two different rows, one in each file, is
    trusted in neither and runs again (pass 35: the journal's alone was kept),
    and so is a sample one file holds twice, differently (pass 39: the other
    file's row was kept unchecked while the message said the sample runs again)."""
    done, dropped, appendable, line_of, twice_j = _read_rows(spec, journal, header)
    if not results.exists():
        return done, [(journal, dropped)], appendable
    done_r, dropped_r, _, line_of_r, twice_r = _read_rows(spec, results, header, journal=False)
    differ = {i for i, row in done_r.items() if i in done and done[i] != row}
    untrusted_j, untrusted_r = differ | (twice_r & done.keys()), differ | (twice_j & done_r.keys())
    why = f"sample with two different rows, in {results.name} and {journal.name}"
    for rows, lines, lost, untrusted, there in ((done, line_of, dropped, untrusted_j, results),
                                                (done_r, line_of_r, dropped_r, untrusted_r, journal)):
        for i in sorted(untrusted):
            lost.setdefault(why if i in differ else f"sample held twice, differently, in {there.name}",
                            []).append(lines[i])
            del rows[i]
    added = {i: row for i, row in done_r.items() if i not in done}
    done.update(added)
    return done, [(journal, dropped), (results, dropped_r)], appendable and not added and not untrusted_j
