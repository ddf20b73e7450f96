"""`python3 -m gimbalsim` names the programs instead of Python's "cannot be
directly executed" and exit 1, which the exit-code table calls a bug (pass 40)."""
from gimbalsim._errors import not_a_program

not_a_program("")
