#!/usr/bin/python3
"""The one writer of the pages in docs/results/: every page gets the same
header (the command that regenerates it, machine, commit, date, run time and
load), is written atomically (tools/pages/output_file.py), and the index
docs/results/README.md is rewritten from the pages' headers after each write.

Each study's run script calls it with the body its tool produced:

    /usr/bin/python3 tools/pages/results_page.py --page docs/results/stress.md \\
        --title "Numerical stability stress grid" --summary "375 runs: ..." \\
        --command "bash tools/stress/run_stress.sh" --body out/stress/page_body.md \\
        --t0 "$T0" --load0 "$LOAD0"

(--t0: `date +%s.%N` at the study's start; --load0: /proc/loadavg then; the
writer reads the end values itself). From Python: `write_page(...)`.
`--index` alone rewrites docs/results/README.md.

A page's header, in this order (tests/python/test_results_page.py checks it):

    # <title>

    Regenerate: `<command>`

    - Machine: <CPU model>, <n> cores, kernel <uname -r>
    - Commit: <git rev-parse --short HEAD>[-dirty]
    - Date: <YYYY-MM-DD HH:MM> UTC
    - Run: <s> s wall; load average <1 5 15 min> at start, <...> at end

"-dirty": the work tree differs from the commit outside docs/results/ (the
pages themselves are outputs, not inputs). Nothing here edits README.md.
"""
import argparse
import contextlib
import datetime
import os
import pathlib
import platform
import re
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "pages"))
import output_file  # noqa: E402  (the package's one writer)
from results_index import INDEX_NAME, MARK, RESULTS, folder_held, index_is_ours, make_index, write_index  # noqa: E402


def cpu_model(cpuinfo="/proc/cpuinfo"):
    try:
        with open(cpuinfo) as f:
            for line in f:
                if line.lower().startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine() or "unknown CPU"


def machine():
    """'<CPU model>, <n> cores, kernel <release>'."""
    n = os.cpu_count() or 0
    return f"{cpu_model()}, {n} core{'s' if n != 1 else ''}, kernel {platform.release()}"


def commit(root=ROOT):
    """Short hash of HEAD, '-dirty' when the tree differs outside docs/results/; 'unknown' outside git."""
    def git(*args):
        return subprocess.run(["git", "-C", str(root), *args], capture_output=True, text=True)

    head = git("rev-parse", "--short", "HEAD")
    if head.returncode != 0:
        return "unknown (not a git work tree)"
    status = git("status", "--porcelain", "--", ".", ":(exclude)docs/results")
    dirty = status.returncode != 0 or status.stdout.strip() != ""
    return head.stdout.strip() + ("-dirty" if dirty else "")


def loadavg():
    try:
        return " ".join(open("/proc/loadavg").read().split()[:3])
    except OSError:
        return "unknown"


def page_arguments(doc, default_dir):
    """The options every study's page script takes: its output folder, the
    regenerate command, and the start time and load its run script noted."""
    ap = argparse.ArgumentParser(
        allow_abbrev=False, description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(ap)
    # a folder the user names is where they stand, the default the repository's (pass 43: both from the repository,
    # and a missing one a traceback); a study's run file missing in it is refused by name (run_files)
    ap.add_argument("--dir", type=_study_folder, default=str(ROOT / default_dir))
    ap.add_argument("--command", required=True)
    add_start_arguments(ap)
    return ap


def add_start_arguments(ap):
    """--t0 and --load0, as every page's writer takes them (pass 46: 'abc' a traceback at the end, 'nan' a page
    saying "nan s wall")."""
    ap.add_argument("--t0", type=_argument(start_time),
                    help="the study's start, seconds since the epoch (date +%%s.%%N)")
    ap.add_argument("--load0", type=_argument(start_load), help="/proc/loadavg at the study's start")


def _argument(check):
    def read(text):
        try:
            return check(text, where=None)  # argparse names the flag
        except output_file.Refused as e:
            raise argparse.ArgumentTypeError(str(e)) from None
    return read


def start_time(text, where="--t0"):
    """A study's start as `date +%s.%N` writes it: digits, a point and digits (no sign, no exponent), seconds
    since the epoch, not after now and not before this machine started (its study ran in this boot: pass 67,
    1e9 made a page of a 25-year run). Refused naming `where` otherwise. The page's run time is measured from it."""
    why = None
    if str(text) == "":
        why = "an empty value"
    elif not re.fullmatch(r"[1-9][0-9]*(\.[0-9]+)?", str(text)):
        why = f"{text!r} is not as date +%s.%N writes a time (digits, a point, digits)"
    else:
        x, now = float(text), time.time()
        with open("/proc/uptime") as f:
            booted = now - float(f.read().split()[0])
        if not booted - 1.0 <= x <= now:
            why = (f"{text} is no start time of a study run on this machine (date +%s.%N at its start: after the "
                   f"machine started, {booted:.0f}, and not after now)")
    if why:
        raise output_file.Refused(f"{where}: {why}" if where else why)
    return text


def start_load(text, where="--load0"):
    """/proc/loadavg as read at a study's start: its first three fields are the load averages, as the kernel
    writes them (digits, a point, two decimals: 0.52; pass 49 took 1e-400, -0, +0.5, 1e3 and 20 digits)."""
    fields = str(text).split()
    if len(fields) < 3 or not all(re.fullmatch(r"(0|[1-9][0-9]{0,5})\.[0-9]{2}", f) for f in fields[:3]):
        why = f"{text!r} is not /proc/loadavg (three load averages first, as 0.52)"
        raise output_file.Refused(f"{where}: {why}" if where else why)
    return text


def measured_start(page, results):
    """(t0, load0) of a measuring script that runs itself again inside a network namespace: noted once in the
    environment, so the exec keeps them. With `results`, its page is checked, and a start inherited from the
    environment too, before anything is measured (pass 45: refused only at the end; pass 46: never checked)."""
    if results:
        check_page(page)
    os.environ.setdefault("GIMBALSIM_RESULTS_T0", str(time.time()))
    os.environ.setdefault("GIMBALSIM_RESULTS_LOAD0", open("/proc/loadavg").read())
    t0, load0 = os.environ["GIMBALSIM_RESULTS_T0"], os.environ["GIMBALSIM_RESULTS_LOAD0"]
    if results:
        start_time(t0, "GIMBALSIM_RESULTS_T0")
        start_load(load0, "GIMBALSIM_RESULTS_LOAD0")
    return t0, load0


def _study_folder(text):
    """A --dir the user names, from where they stand, whatever its spelling (pass 44: the default's spelling was
    the repository's); absolute, so callers' ROOT / dir is it."""
    if not text:  # '' would be the current folder (pass 44): a value given must say something
        raise argparse.ArgumentTypeError("an empty value (a study's output folder)")
    path = pathlib.Path(text).absolute()
    if not path.is_dir():
        raise argparse.ArgumentTypeError(f"{text}: no such folder (a study's output folder)")
    return str(path)


def run_file(folder, name, optional=False, limit=1 << 24):
    """The text of a study's output `name` in `folder`, by output_file.read_input's rules (pass 47: a FIFO
    blocked, a device never ended); "" for an optional one that is not there; Refused (exit 2) naming it."""
    path = pathlib.Path(folder) / name
    if not os.path.lexists(path):
        if optional:
            return ""
        raise output_file.Refused(f"{path}: cannot be read (No such file or directory): run the study first")
    return output_file.read_input(str(path), "the study's output", limit)


def run_file_lines(folder, name, limit):
    """The line count of a study's output `name` by run_file's rules (counted, not held); 0 when it is not there."""
    path = pathlib.Path(folder) / name
    return output_file.count_lines(str(path), "the study's output", limit) if os.path.lexists(path) else 0


@contextlib.contextmanager
def study_files(folder, writer):
    """A page made from a study's outputs: one that is not as `writer` writes it (a key, a column or a number
    missing, JSON that does not parse) is Refused (exit 2) naming the folder, never a traceback (pass 47)."""
    try:
        yield
    except (KeyError, IndexError, TypeError, ValueError, AttributeError, ArithmeticError) as e:
        raise output_file.Refused(f"{folder}: its outputs are not as {writer} writes them "
                                  f"({type(e).__name__}: {e})") from None


def no_rows(what, page):
    """A study with no rows makes no page (pass 47: the committed page was replaced by empty tables)."""
    return output_file.Refused(f"{what}: no rows: nothing to put on the page; {page} is kept as it was")


def header(title, command, t0=None, load0=None, now=None):
    now = now or datetime.datetime.now(datetime.timezone.utc)
    lines = [MARK, f"# {title}", "", f"Regenerate: `{command}`", "",
             f"- Machine: {machine()}",
             f"- Commit: {commit()}",
             f"- Date: {now.strftime('%Y-%m-%d %H:%M')} UTC"]
    run = []
    if t0 is not None:
        run.append(f"{time.time() - float(start_time(t0)):.0f} s wall")
    if load0:
        run.append(f"load average (1, 5, 15 min) {' '.join(start_load(load0).split()[:3])} at start, {loadavg()} at end")
    else:
        run.append(f"load average (1, 5, 15 min) {loadavg()} at the end")
    lines.append("- Run: " + "; ".join(run))
    return "\n".join(lines) + "\n"


def write_text(path, text):
    """Atomic write (tools/pages/output_file.py: a temporary beside it, synced, renamed when whole); raises
    OSError, the old file untouched."""
    output_file.write_text(pathlib.Path(path), text)


def check_page(path, index=True, inputs=()):
    """The writer's rules for a page and its index (output_file.check_before_writing): Refused (exit 2) for a link,
    a folder that does not exist, one of `inputs`, or a README.md beside it that is no index of this writer. A
    study calls it before it measures: a page refused at the end would cost the run."""
    given, path = os.fspath(path), pathlib.Path(path)
    # (pass 104) a name holding a line feed forged an index row, one with ']' or ')' broke its link, a .txt page was
    # indexed once and dropped by the next --index: a page is NAME.md in letters, digits, '.', '_' and '-'; (passes
    # 106, 108) 'x.md/' or 'x.md/.' names a folder, and pathlib, dropping the '/' or '/.', wrote the file x.md
    if index and (os.path.basename(given) != path.name or path.name == INDEX_NAME or
                  not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9._-]*\.md", path.name)):
        raise output_file.Refused(f"{given!r}: a page's name is NAME.md in letters, digits, '.', '_' and '-' "
                                  f"(not {INDEX_NAME}): the index links it by that name")
    output_file.check_before_writing([path, path.parent / INDEX_NAME if index else None], inputs)
    if index:
        index_is_ours(path.parent / INDEX_NAME)


def write_page(path, title, command, body, summary="", t0=None, load0=None, index=True, inputs=()):
    """Writes header + body to path atomically, then the index beside it (when index). The writer's rules first
    (output_file.check_before_writing: Refused, exit 2, nothing written): no link, no folder that does not
    exist, none of `inputs`; and a README.md beside the page that is no results index is never replaced."""
    for what, given in (("the title", title), ("the command", command), ("the summary", summary), ("the body", body)):
        # (passes 92, 94, 96: ESC]0;..BEL, U+2028, U+202E, a title's line feed forging a summary; a summary's fold)
        lf = "" if what in ("the body", "the summary") else "\x0a"
        if bad := re.search(f"[\x00-\x08{lf}\x0b-\x1f\x7f-\x9f\u061c\u200e\u200f\u2028-\u202e\u2066-\u2069]", given):
            raise output_file.Refused(f"{what}: character U+{ord(bad.group()):04X} (a control character) at "
                                      f"position {bad.start()}: a page holds none")
        # (passes 98, 100) a comment's or the command's code span's ends in the header: the rest showed, or hid
        if bad := next((m for m in ("<!--", "-->", "--!>", "`")[:{"the body": 0, "the command": 4}.get(what, 3)]
                        if m in given), None):
            raise output_file.Refused(f"{what}: '{bad}' would end or open a comment or code span of the page")
    summary_line = f"<!-- summary: {' '.join(summary.split())} -->\n" if summary else ""
    text = header(title, command, t0, load0) + summary_line + "\n" + body.rstrip("\n") + "\n"
    check_page(path, index, inputs)
    path = pathlib.Path(path)
    with folder_held(path.parent) if index else contextlib.nullcontext():
        # The index is made (every other page read) before the page is written: a page that cannot be
        # indexed is no half-written study.
        index_text = make_index(path.parent, {path.name: text}) if index else None
        write_text(path, text)
        if index:
            write_text(path.parent / INDEX_NAME, index_text)
    return text


def main(argv=None):
    ap = argparse.ArgumentParser(
        allow_abbrev=False, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(ap)
    ap.add_argument("--page", help="the page to write (docs/results/NAME.md)")
    ap.add_argument("--title")
    ap.add_argument("--command", help="the command line that regenerates the page")
    ap.add_argument("--body", help="file with the page's body (Markdown); - for stdin")
    ap.add_argument("--summary", help="one line for the index")
    add_start_arguments(ap)
    ap.add_argument("--index", action="store_true", help="only rewrite docs/results/README.md")
    ap.add_argument("--check", action="store_true",
                    help="only check that --page and its index may be written (exit 0) or not (exit 2): a run "
                         "script asks before its study, so a refused page costs no run")
    a = ap.parse_args(argv)
    given = [f for f in ("page", "title", "command", "body", "summary", "t0", "load0") if getattr(a, f) is not None]
    if a.index and (given or a.check):
        ap.error("--index rewrites the index alone: leave out " + ", ".join(f"--{f}" for f in given or ["check"]))
    if a.check and a.page is None:
        ap.error("--check needs --page P: the page to check")
    if a.check and len(given) > 1:
        ap.error("--check takes --page alone: leave out " + ", ".join(f"--{f}" for f in given if f != "page"))
    try:
        if a.index:
            write_index(RESULTS)
            return 0
        if a.check:
            output_file.check_before_writing([a.page], names=["--page"])  # '' is "an empty value", said as such
            check_page(a.page)
            return 0
        if not (a.page and a.title and a.command and a.body):
            ap.error("--page, --title, --command and --body are required (or --index alone)")
        body = output_file.read_input(a.body, "--body", stdin=True)
        write_page(a.page, a.title, a.command, body, a.summary or "", a.t0, a.load0,
                   inputs=[] if a.body == "-" else [a.body])
    except OSError as e:  # a write that failed (the rules were checked first: output_file.Refused, exit 2)
        print(f"results_page: {e}", file=sys.stderr)
        return 4  # an output could not be written (as the C++ tools)
    print(f"results_page: wrote {a.page}")
    return 0


if __name__ == "__main__":
    sys.exit(output_file.run_script("results_page", main))
