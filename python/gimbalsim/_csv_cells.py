"""The CSV convention's cells (docs/usage.md "CSV files"; the C++ side's
io/csv_format.hpp): numbers that read back as the same double, never -0,
nan for no value; text cells that numpy's genfromtxt reads as they are.
Only the standard library: tools/pages/output_file.py loads this file from
the source tree, without the built package."""
import math


def csv_number(x):
    """A number as the CSV convention writes it (io/csv_format.hpp): the
    shortest text that reads back as the same double, integers as integers,
    never -0, nan for no value."""
    x = float(x)
    if math.isnan(x):
        return "nan"
    if x == 0.0:
        return "0"
    if x.is_integer() and abs(x) < 1e15:
        return str(int(x))
    return repr(x)


def csv_text(text):
    """A text cell as the CSV convention writes it (io::csvTextCell): unquoted,
    ',' as ';', '"' as "'", '#' as "no. " (numpy reads no quotes and takes '#'
    for a comment), a line break as a space."""
    return (str(text).replace(",", ";").replace('"', "'").replace("#", "no. ")
            .replace("\r", " ").replace("\n", " "))
