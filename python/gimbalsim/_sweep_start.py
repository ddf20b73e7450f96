"""What a sweep refuses before it writes a byte (exit 2): the one path of
the run and of --check (which then writes nothing); and its first writes,
taken back whole when they fail. The sweep's output names live here too, as
what is checked is what is written."""
import contextlib

from . import _budget_report, _provenance
from ._errors import SpecError
from ._journal import DESIGN, JOURNAL, csv_line, take_recorded_design
from ._output_names import check_output_names
from ._spec import check_outputs_not_inputs
from ._summary import plot_names
from ._sweep_spec import MAX_SAMPLES
from ._until import Until

# The sweep's files in --out, by the names its writers take them from; output_paths lists them all.
RESULTS, SUMMARY, REPORT, PLOTS, FINGERPRINT = "results.csv", "summary.json", "report.md", "plots", "spec.json"


def output_paths(spec, out):
    """(files, folders): every path the sweep may write in out, out first
    among the folders. Each is checked (check_output_folder) before a sample
    runs, as found at the end the samples' work would be lost."""
    plots = _budget_report.cdf_names(spec) if spec.closed else plot_names(spec)
    names = [FINGERPRINT, _provenance.SPEC_COPY, _provenance.INPUTS, JOURNAL, RESULTS, DESIGN, SUMMARY, REPORT]
    return [out / n for n in names] + [out / PLOTS / n for n in plots], [out, out / PLOTS]


def check_output_folder(spec, out, inputs):
    """Refuses out (exit 2) when it holds another tool's outputs, or a link,
    something of another kind or an input under a name the sweep writes."""
    files, folders = output_paths(spec, out)
    check_output_names(out, "sweep", files, folders, refuse=SpecError)
    check_outputs_not_inputs(files + folders[1:], inputs)


def until_of(text, max_samples, spec):
    """--until TEXT [--max-samples N] of the command line as an Until, or None."""
    if text is None:
        return None
    return Until(text, spec, max_samples or min(MAX_SAMPLES, 20 * spec.samples))


def check_start(spec, out, resume, inputs):
    """Refuses (SpecError) a sweep of spec into out: out's names
    (check_output_folder), a --resume of another spec's sweep, a sweep held
    there without --resume. Reads, writes nothing."""
    check_output_folder(spec, out, inputs)
    fingerprint = out / FINGERPRINT
    if resume:
        try:
            same = not fingerprint.exists() or fingerprint.read_text() == spec.fingerprint
        except (OSError, UnicodeDecodeError) as e:
            raise SpecError(f"{fingerprint}: cannot read it ({e}); --resume needs the spec it names")
        if not same:
            raise SpecError(f"{out} holds a sweep of another spec; --resume needs the same spec")
    elif (out / JOURNAL).exists() or (out / RESULTS).exists() or (out / DESIGN).exists():
        raise SpecError(f"{out} already holds a sweep: give --resume to finish it, or another --out")


def take_design(spec, out, until):
    """spec's design extended to the size OUT/design.json records (--until
    grew it); refused (SpecError) when the record is unreadable or above
    --max-samples (it would say "stopped by the cap at" the rows held)."""
    take_recorded_design(out, spec)
    if until is not None and until.max_samples < len(spec.design):
        raise SpecError(f"--max-samples {until.max_samples} is below the {len(spec.design)} samples this sweep "
                        f"already grew to ({out / DESIGN}): give at least {len(spec.design)}")


def write_start(spec, out, write, trusted_rows, appendable, made):
    """The start's files: the fingerprint, the provenance and (unless the
    journal can be appended to) a journal of the trusted rows, written whole
    to a new file that replaces it. A start that fails before its journal
    exists keeps nothing, as it says: what it wrote new goes, and the folder
    if it made it (pass 66: a full disk left spec.json and spec.yaml behind)."""
    journal = out / JOURNAL
    started = [p for p in (out / FINGERPRINT, out / _provenance.SPEC_COPY, out / _provenance.INPUTS)
               if not p.exists()]
    try:
        write(out / FINGERPRINT, spec.fingerprint)
        _provenance.record_inputs(spec, out, write)
        if not appendable:
            write(journal, "".join(csv_line(r) for r in [spec.csv_header()] + trusted_rows))
    except BaseException:
        if not journal.exists():
            for p in started:
                with contextlib.suppress(OSError):
                    p.unlink()
            if made:
                remove_empty_folder(out)
        raise


def remove_empty_folder(folder):
    """folder removed if it is empty (a set that failed left nothing in it)."""
    with contextlib.suppress(OSError):
        folder.rmdir()
