"""The sweep's files: the journal's name, the CSV text of a row and the
journal read back (every row checked against the design). Files are
written by the one writer (_output.py)."""
import csv
import io

from . import _provenance
from ._errors import OutputError, SpecError
from ._output import csv_number, csv_text
from ._sweep_spec import MAX_SAMPLES

JOURNAL = "results.partial.csv"  # the sweep's rows as they arrive (appended and synced per task)


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


def check_row(spec, row, n_columns):
    """Why a journal row is not to be trusted, or None: the sample index in
    range, the parameters equal to the design's draw, the figures numbers."""
    if len(row) != n_columns:
        return "wrong number of columns"
    if not row[0].isdigit() or not int(row[0]) < len(spec.design):
        return "sample index outside the design"
    i = int(row[0])
    drawn = [fmt(v) for v in spec.design.row_values(spec.design.draw(i))]
    if row[1:1 + len(drawn)] != drawn:
        return "parameters differ from the design's draw"
    # after status (and a closed loop's reason), up to the provenance columns (text: applied values, hashes)
    figures = row[2 + len(drawn) + spec.text_columns:n_columns - len(_provenance.columns(spec))]
    if not row[1 + len(drawn)] or not all(v == "" or _is_float(v) for v in figures) or not _is_float(figures[-1]):
        return "status or figures unreadable"
    return None


def _parsed(line):
    """One CSV line's cells, or None when it is not CSV (a field over the csv
    module's limit, a stray quote): such a line is no row the sweep wrote."""
    try:
        return next(csv.reader([line]), [])
    except csv.Error:
        return None


def read_journal(spec, path, header):
    """The journal's trusted rows by sample, what was dropped ({reason:
    count}), and whether the file can be appended to as it is. A last line
    without its newline (cut by an interruption) is dropped; a sample written
    twice counts once."""
    done, dropped = {}, {}
    if not path.exists():
        return done, dropped, False
    if not path.is_file():  # a pipe would block the resume for good, a device feed it without end
        raise SpecError(f"{path}: not a regular file (a pipe, a device or a folder): a journal is only read from a "
                        f"file; use another --out")
    try:
        data = path.read_bytes()
    except OSError as e:
        raise OutputError(f"cannot read the journal {path}: {e.strerror}")
    lines = data.decode("utf-8", errors="replace").split("\n")
    torn = lines.pop() != ""  # the text after the last newline: empty when the last write was whole
    if torn:
        dropped["last line cut by an interruption"] = 1
    if not lines:  # killed before the header was whole: nothing was journaled
        return done, dropped, False
    if _parsed(lines[0]) != header:
        raise SpecError(f"{path} was written by another spec (its header differs); use another --out")
    rows = []
    for line in lines[1:]:
        row = _parsed(line)
        if row is None:
            dropped["unreadable line"] = dropped.get("unreadable line", 0) + 1
        else:
            rows.append(row)
    spoken_for = _extend_over(spec, rows)  # the spec's own size
    for row in rows:
        why = check_row(spec, row, len(header))
        if why is not None and row and row[0].isdigit() and int(row[0]) >= spoken_for:
            why = "sample index outside the design"  # beyond the spec's samples and no extension's draw
        if why is None and int(row[0]) in done:
            why = "sample already journaled" if row == done[int(row[0])] else "sample journaled twice, differently"
        if why is not None:
            dropped[why] = dropped.get(why, 0) + 1
            continue
        done[int(row[0])] = row
    # The design is the spec's and every extension its rows show (--until grows it by whole batches of
    # the spec's samples): a row beyond the spec's samples that matches its draw is kept, and the rest
    # of its batch runs; nothing beyond the last kept row is drawn.
    beyond = [i for i in done if i >= spoken_for]
    if beyond:
        batch = spec.samples
        spec.design.extend_to(min(MAX_SAMPLES, -(-(max(beyond) + 1) // batch) * batch))
    elif len(spec.design) != spoken_for:
        spec.design.extend_to(spoken_for)
    return done, dropped, not dropped



def _extend_over(spec, rows):
    """Extends a grid-less design over the largest sample index the rows name
    (below MAX_SAMPLES), so that their draws can be checked; returns the
    design's size before, to which read_journal shrinks it back unless a row
    beyond was kept."""
    size = len(spec.design)
    if spec.grid:
        return size
    named = [int(r[0]) for r in rows if r and r[0].isdigit() and len(r[0]) <= 8]
    top = max([i for i in named if i < MAX_SAMPLES], default=-1)
    if top >= size:
        spec.design.extend_to(top + 1)
    return size
