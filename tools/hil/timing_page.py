"""The page docs/results/bench_timing.md of tools/hil/hil_speed.py: what it
printed, kept as it ran (Tee), made Markdown (tables kept, the long run's
lines in a code block) and written by tools/pages/results_page.py."""
import io
import shlex
import sys


class Tee(io.TextIOBase):
    """Writes to the terminal and keeps a copy (the page's body)."""

    def __init__(self, out):
        self.out, self.copy = out, io.StringIO()

    def write(self, s):
        self.copy.write(s)
        return self.out.write(s)

    def flush(self):
        self.out.flush()


PREAMBLE = """`tools/hil/hil_speed.py`: firmware_sim + pointing_controller over LCM udpm (ttl=0) in a private network
namespace, paper_clearance with the controller; figures parsed from firmware_sim's exit summary. Real-time runs:
both processes under `chrt -f 60`, firmware_sim's loop thread SCHED_FIFO 80 pinned to `--cpu`, the controller
and firmware_sim's communication thread on the other CPUs. The machine's floor:
cyclictest (Debian's rt-tests) at the same period, priority and CPU, half of its time just before and half just
after each firmware_sim run; ratio = firmware_sim / cyclictest (1 = the machine's own floor). Lateness = wake-up
lateness of the loop thread; "sustains" = zero overruns and lateness p99 below 10 % of the period. The kernel is
not PREEMPT_RT and the 2 cores are shared (load average in the header): single multi-millisecond stalls of the VM
land in one run or another, so p99.9 and max swing between runs; quote medians and ratios, not tails.
"""


def page_body(text):
    """The printed report as Markdown: tables kept, the long run's indented lines in a code block."""
    out, mode = [PREAMBLE], None
    for line in text.splitlines():
        kind = "table" if line.startswith("|") else "code" if line.startswith("  ") or line.startswith(
            "firmware_sim:") else "text" if line.strip() else None
        if kind is None:
            continue
        if kind != mode:
            if mode == "code":
                out.append("```")
            out.append("")
            if kind == "code":
                out.append("```")
        if kind == "text" and line.startswith("("):  # (i), (ii), (iii): a section each
            out += ["", "### " + line.strip()]
            mode = "heading"
            continue
        out.append(line if kind != "text" else line.strip())
        mode = kind
    if mode == "code":
        out.append("```")
    return "\n".join(out) + "\n"


def write(page, argv, text, t0, load0):
    """The page of a run whose printed report is `text` (argv: the script's arguments, for its command)."""
    import results_page  # (tools/pages on the path: hil_speed.py set it)
    command = "/usr/bin/python3 tools/hil/hil_speed.py " + " ".join(shlex.quote(x) for x in argv)
    ratio = next((line.split("=", 1)[1].strip() for line in text.splitlines() if "firmware_sim / cyclictest" in line),
                 "")
    best = next((line.split("):", 1)[1].split("[")[0].strip() for line in text.splitlines()
                 if line.startswith("highest rate sustained (plain")), "")
    best = best if best[:1].isdigit() else best.removesuffix(" Hz")
    summary = "; ".join(x for x in (f"highest rate sustained: {best}" if best else "",
                                    f"1 kHz run, firmware_sim / cyclictest lateness p50 / p99 / p99.9 / max = {ratio}"
                                    if ratio else "") if x)
    results_page.write_page(page, "HIL bench timing against cyclictest", command, page_body(text), summary=summary,
                            t0=t0, load0=load0)


if __name__ == "__main__":
    print("timing_page.py: error: a module of tools/hil/hil_speed.py, not a program: run hil_speed.py --results",
          file=sys.stderr)
    sys.exit(2)
