"""How the Python tools write a file: the package's one writer,
python/gimbalsim/_output.py (the rules of the C++ io::OutputFile,
base/io/include/gimbalsim/io/output_file.hpp), loaded from the source
tree by its path, so a plotting script needs neither the built extension
nor PYTHONPATH. Everything it offers is re-exported here: open_output,
write_text, write_bytes, write_csv, savefig, check_outputs, OutputError
(an OSError naming the file), and csv_number (the CSV convention's numbers).
It also says how a script ends: run_script, Refused, check_before_writing."""
import importlib.util
import pathlib
import sys

_NAME = "gimbalsim_output_writer"  # not gimbalsim._output: importing that would load the package and its extension
if _NAME not in sys.modules:
    _path = pathlib.Path(__file__).resolve().parents[2] / "python" / "gimbalsim" / "_output.py"
    _spec = importlib.util.spec_from_file_location(_NAME, _path)
    sys.modules[_NAME] = importlib.util.module_from_spec(_spec)
    _spec.loader.exec_module(sys.modules[_NAME])
_writer = sys.modules[_NAME]

OutputError = _writer.OutputError
check_outputs = _writer.check_outputs
open_output = _writer.open_output
write_text = _writer.write_text
write_bytes = _writer.write_bytes
write_csv = _writer.write_csv
savefig = _writer.savefig
csv_number = _writer.csv_number

# ---- how a script of tools/ ends: the exit-code table of docs/usage.md ----

EXIT_REFUSED, EXIT_OUTPUT = 2, 4


class Refused(Exception):
    """Bad arguments or a bad input file: the script names it and exits 2
    before it writes anything."""


def check_before_writing(outputs, inputs=()):
    """check_outputs as a refusal (exit 2): a script checks every output it
    will write, and the folder each goes in, before it reads or plots."""
    try:
        check_outputs(outputs, inputs)
    except OutputError as e:
        raise Refused(str(e)) from None


def run_script(program, main):
    """main()'s exit code (None counts as 0); Refused is one line on stderr and
    exit 2, OutputError (a write that failed, nothing left under its name)
    one line and exit 4. Anything else is a bug: a traceback and exit 1."""
    try:
        return main() or 0
    except Refused as e:
        print(f"{program}: error: {e}", file=sys.stderr)
        return EXIT_REFUSED
    except OutputError as e:
        print(f"{program}: error: {e}", file=sys.stderr)
        return EXIT_OUTPUT
