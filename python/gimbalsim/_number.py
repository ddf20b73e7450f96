"""The one reading of a number given as text (a flag, --until's RELWIDTH, a
CSV cell this project wrote), as the C++ programs read theirs
(base/input/include/gimbalsim/input/plain_decimal.hpp). float() and int()
alone also take ' 1', '1_0', 'inf' and '\u0661' (an Arabic-Indic one), which
no writer of ours writes and no user means. Standard library only: the
plotting scripts load this file by its path (tools/pages/output_file.py)."""
import math
import re
import sys

DECIMAL_PATTERN = r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"  # also to find one inside a text
_DECIMAL = re.compile(DECIMAL_PATTERN)
_WHOLE = re.compile(r"[+-]?[0-9]{1,100}")  # a sign and digits (has_leading_zero and a range say the rest)


def has_leading_zero(text):
    """True when text, after an optional sign, starts with a 0 and another digit ('010', '+00.5'): C and CLI11
    read a whole 010 as octal 8; whole and real flags refuse it alike (plain_decimal.hpp hasLeadingZero)."""
    return re.match(r"[+-]?0[0-9]", text) is not None


def plain_decimal(text):
    """The float of a plain finite decimal ('5', '-2.5e-3', '+.5'); None for
    anything else (' 5', '0x1', 'inf', 'nan', '', None)."""
    if not isinstance(text, str) or not _DECIMAL.fullmatch(text):
        return None
    x = float(text)
    return x if math.isfinite(x) else None


def underflowed(text, x):
    """True when the decimal `text` names a non-zero number that its parse `x`
    lost (1e-400 reads as 0, 4e-320 as a subnormal with its digits gone): the
    rule of underflow.hpp. 0 often means "off": a value nobody wrote."""
    if x != 0.0:
        return abs(x) < sys.float_info.min
    return re.search(r"[1-9]", re.split(r"[eE]", text)[0]) is not None


def flag_decimal(text):
    """(x, None) for a number a real flag takes: a plain finite decimal whose
    value the parse kept; (None, why) otherwise, worded as the C++ programs word it."""
    if not text:
        return None, "an empty value"
    x = plain_decimal(text)
    if x is None:
        return None, f"{text!r} is not a finite decimal number"
    if underflowed(text, x):
        return None, f"{text!r} is too small for a double (it would be read as 0 or lose its digits)"
    if has_leading_zero(text):  # as a whole-number flag refuses 010 (pass 42: --duration 010 ran 10 s)
        return None, f"{text!r} is not a number written without a leading zero"
    return x, None


def plain_whole(text):
    """The int of a whole number written as one ('12', '-3', '+3'; not ' 3',
    '010', '1_0', '1e3', '0x3' or 101 digits); None otherwise."""
    if not isinstance(text, str) or not _WHOLE.fullmatch(text) or has_leading_zero(text):
        return None
    return int(text)
