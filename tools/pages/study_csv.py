"""A study's CSV output read as its writer writes it, for the page scripts.

A page is committed and quoted: it may show only what the study's program
can have written. So each number column has the writer's rule (Column): a
plain finite decimal, or a whole number, in the column's range, whose digits
the parse kept, and 'nan' only in a column where the writer puts nan for a
figure over nothing. Anything else (' 1e-3', '-1' for an error, '1e-400'
read as 0, 'yes' for a flag) is Refused (exit 2) naming the file, line and
column, and the committed page is kept (pass 49: each was taken, and shown).
"""
import sys
import csv
import io
import math

import output_file
import results_page


class Column:
    """A number column's rule: in [lo, hi] (open_lo, open_hi: that end excluded, as (0, 1)); whole: written as a
    whole number; nan: the writer writes nan here (a figure the run has not); flag: exactly 0 or 1, read as a
    bool."""

    def __init__(self, lo=-math.inf, hi=math.inf, nan=False, whole=False, flag=False, open_lo=False, open_hi=False):
        self.lo, self.hi, self.nan, self.whole, self.flag = lo, hi, nan, whole, flag
        self.open_lo, self.open_hi = open_lo, open_hi

    def range_text(self):
        return f"{'(' if self.open_lo else '['}{self.lo:g}, {self.hi:g}{')' if self.open_hi else ']'}"

    def _outside(self, x):
        return not ((self.lo < x if self.open_lo else self.lo <= x) and (x < self.hi if self.open_hi else x <= self.hi))

    def _refuse(self, where, why):
        said = "nan where it has no figure, else " if self.nan else ""
        kind = "a whole number" if self.whole else "a number"
        raise output_file.Refused(f"{where}: {why} (its writer writes {said}{kind} in {self.range_text()})")

    def read(self, text, where):
        """The cell `text` by the rule; Refused naming `where` (file:line: column c)."""
        if self.flag:
            if text in ("0", "1"):
                return text == "1"
            raise output_file.Refused(f"{where}: {text!r} is no flag (its writer writes 0 or 1)")
        if self.nan and text == "nan":
            return math.nan
        if self.whole:
            x = output_file.plain_whole(text)
            why = None if x is not None else f"{text!r} is no whole number"
        else:
            x, why = output_file.flag_decimal(text)
        if why is None and x == 0 and text.startswith("-"):  # the project's writers never write -0 (usage.md)
            why = f"{text!r} is a negative zero"
        if why is None and self._outside(x):
            why = f"{text} is outside {self.range_text()}"
        if why:
            self._refuse(where, why)
        return x

    def value(self, x, where):
        """A number already parsed (a JSON figure, whose type says whole or not) by the same rule: finite, whole
        where the rule says, in range (pass 49: NaN, -1, null and Infinity of a run summary were shown)."""
        number = type(x) is int or (not self.whole and type(x) is float and math.isfinite(x))  # 1e400 reads as inf
        if not number:
            self._refuse(where, f"{x!r} is no {'whole number' if self.whole else 'finite number'}")
        if self._outside(x):
            self._refuse(where, f"{x!r} is outside {self.range_text()}")
        return x


def read_rows(folder, name, columns, key=None, limit=1 << 24):
    """The rows of `folder`/`name` (dicts by the header's names), each cell of `columns` (name -> Column) read by
    its rule; Refused naming the file (and line): a byte-order mark or a carriage return (the project's CSV
    writers write LF lines and no BOM), a column missing, a row longer or shorter than the header, a cell its
    rule refuses, and the same `key` cell on two rows (pass 50: a BOM was a KeyError, CRLF and a run held
    twice were taken)."""
    path = f"{folder}/{name}"
    text = results_page.run_file(folder, name, limit=limit)
    if text.startswith("\ufeff") or "\r" in text:
        cr_line = text[:text.find("\r")].count("\n") + 1
        what = "a byte-order mark" if text.startswith("\ufeff") else f"a carriage return on line {cr_line}"
        raise output_file.Refused(f"{path}: {what}: not as its study writes it (LF line ends, no byte-order mark)")
    reader = csv.DictReader(io.StringIO(text, newline=""))
    missing = [c for c in [*columns, *([key] if key else [])] if c not in (reader.fieldnames or [])]
    if missing:
        raise output_file.Refused(f"{path}: no column {', '.join(missing)} (not as its study writes it)")
    rows, seen = [], {}
    for r in reader:
        line = reader.line_num
        if None in r or None in r.values():
            raise output_file.Refused(f"{path}:{line}: {len(reader.fieldnames)} cells expected, as the header has")
        for c, rule in columns.items():
            r[c] = rule.read(r[c], f"{path}:{line}: column {c}")
        if key is not None:
            if r[key] in seen:
                raise output_file.Refused(f"{path}:{line}: {key} {r[key]!r} again (line {seen[r[key]]}): its study "
                                          "writes each once")
            seen[r[key]] = line
        rows.append(r)
    return rows


if __name__ == "__main__":  # (pass 79) run alone it took any arguments, did nothing and exited 0
    print("study_csv.py: error: a module of the page scripts (tools/*/*_page.py), not a program: "
          "run the study's page script", file=sys.stderr)
    sys.exit(2)
