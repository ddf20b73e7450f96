"""How the package's programs and the tools/ scripts read a flag that takes
one value: given once and never empty, as the C++ programs (CLI11) do.
argparse keeps the last of two silently (pass 76: `--out a --out b`) and
takes `--filter=` as an empty value (pass 78: it ran every benchmark).
Standalone (argparse only): tools/pages/output_file.py loads it by path."""
import argparse


class StoreOnce(argparse._StoreAction):
    """A flag of one value, refused when given twice or given nothing."""

    def __call__(self, parser, namespace, values, option_string=None):
        if option_string is not None:
            given = namespace.__dict__.setdefault("_given_once", set())
            if self.dest in given:
                parser.error(f"{'/'.join(self.option_strings)}: given twice; it takes one value")
            given.add(self.dest)
            if values == "":
                parser.error(f"{option_string}: an empty value; it takes one value")
        super().__call__(parser, namespace, values, option_string)


def one_value_each(parser):
    """Every flag of one value added to parser from now on keeps StoreOnce's rules."""
    parser.register("action", None, StoreOnce)
    parser.register("action", "store", StoreOnce)
