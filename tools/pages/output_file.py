"""How the Python tools write a file: the package's one writer,
python/gimbalsim/_output.py (the rules of the C++ io::OutputFile,
base/io/include/gimbalsim/io/output_file.hpp), loaded from the source
tree by its path, so a plotting script needs neither the built extension
nor PYTHONPATH. Everything it offers is re-exported here: open_output,
write_text, write_bytes, write_csv, savefig, check_outputs, OutputError
(an OSError naming the file), and csv_number (the CSV convention's numbers)."""
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
