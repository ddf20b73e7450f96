"""The first thing the package runs when a program of it starts (`python3 -m
gimbalsim.X`): a SIGINT, SIGTERM or SIGHUP from then on, before the program installs
its own handlers, is one line and 128 + N. It imports only what the
interpreter has already loaded (os, signal, sys), so the handler is in place
before any other import of the package (json in a stand-in once came first,
pass 56); what remains is the interpreter's own start."""
import os
import signal
import sys

# The signals that ask a program to stop (the C++ programs' io::installStopHandlers has the same three): SIGHUP
# is a closed terminal or ssh session, which must end as SIGTERM does, not kill the program mid-write (pass 70).
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


def report_early_signals():
    """SIGINT, SIGTERM or SIGHUP while `python3 -m gimbalsim.X` imports, before the program
    installs its own handlers: one line and 128 + N (it exited 143 saying nothing,
    pass 55). Nothing has been read or written yet, so nothing is kept. A
    library import (sys.argv[0] is not "-m" then) installs nothing."""
    if sys.argv[:1] != ["-m"]:
        return
    argv = sys.orig_argv
    at = next((i for i, a in enumerate(argv) if a.startswith("-m")), None)
    module = (argv[at][2:] or (argv[at + 1] if at + 1 < len(argv) else "")) if at is not None else ""
    program = module.rpartition(".")[2] or "gimbalsim"

    def handler(signum, frame):
        try:
            sys.stderr.write(f"{program}: interrupted ({signal.Signals(signum).name}) while starting: nothing read "
                             "or written\n")
            sys.stderr.flush()
        except (OSError, ValueError):  # a console that has gone takes no line
            pass
        os._exit(128 + signum)  # the exit-code table's 128 + N (_errors.signal_exit); no file is open yet
    for signum in STOP_SIGNALS:
        signal.signal(signum, handler)
