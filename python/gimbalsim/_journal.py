"""The sweep's files: the journal's name, the CSV text of a row and the
journal read back (every row checked against the design). Files are
written by the one writer (_output.py)."""
import csv
import io

from . import _provenance
from ._errors import OutputError, SpecError
from ._output import csv_number, csv_text

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


def read_journal(spec, path, header):
    """The journal's trusted rows by sample, what was dropped ({reason:
    count}), and whether the file can be appended to as it is. A last line
    without its newline (cut by an interruption) is dropped; a sample written
    twice counts once."""
    done, dropped = {}, {}
    if not path.exists():
        return done, dropped, False
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
    if next(csv.reader(lines[:1]), None) != header:
        raise SpecError(f"{path} was written by another spec (its header differs); use another --out")
    for row in csv.reader(lines[1:]):
        why = check_row(spec, row, len(header))
        if why is None and int(row[0]) in done:
            why = "sample already journaled" if row == done[int(row[0])] else "sample journaled twice, differently"
        if why is not None:
            dropped[why] = dropped.get(why, 0) + 1
            continue
        done[int(row[0])] = row
    return done, dropped, not dropped
