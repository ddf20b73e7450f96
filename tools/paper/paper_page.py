#!/usr/bin/python3
"""docs/results/paper.md from a tools/run_paper.sh run (called by it with
--results): the paper scene's settings, the headline figures plot_paper.py
printed, and three of its figures copied small into docs/results/
(paper_pointing.png is the one README.md links).

    /usr/bin/python3 tools/paper/paper_page.py --dir out/paper --command "bash tools/run_paper.sh --results" \\
        [--t0 T0 --load0 LOAD0]
"""
import json
import math
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "pages"))
import results_page  # noqa: E402
import output_file  # noqa: E402  (the package's one writer)
import study_csv  # noqa: E402  (the writers' number rules)

# (figure of plot_paper.py, name under docs/results/, caption)
FIGURES = [
    ("fig17_pointing_error.png", "paper_pointing.png",
     "Antenna pointing error: the angle between the clearance run's boresight and the ideal run's (paper fig. 17)."),
    ("fig18_joint2_force.png", "paper_joint2_force.png",
     "Force through joint 2, clearance against ideal joint (paper fig. 18)."),
    ("fig06_eccentricity.png", "paper_eccentricity.png",
     "Journal eccentricity in the bearing (paper fig. 6): impacts, then continuous contact."),
]
DPI_FROM, DPI_TO = 110, 80  # plot_paper.py saves at 110 dpi; the committed copies are 80 dpi
MAX_PIXELS = 4000 * 4000    # far above plot_paper.py's figures (about 1300 x 800)
# The run summary's figures the page shows (gimbalsim simulate --summary), by its writer's rules
_COUNT, _STEP = study_csv.Column(0, whole=True), study_csv.Column(0.0, open_lo=True)
RUN_FIGURES = {("t_end_s",): study_csv.Column(0.0), ("impacts",): _COUNT, ("substeps",): _COUNT,
               ("wall_time_s",): study_csv.Column(0.0), ("integrator", "step_s"): _STEP,
               ("integrator", "substep_s"): _STEP}
# A figure as plot_paper.py prints it: '  name : value' (its 'wrote ...' lines are no figure)
SUMMARY_LINE = re.compile(r"^\s{2,}(\S[^:]*?)\s*: (.+)$")
NUMBER = output_file.DECIMAL_PATTERN


def small_copy(src):
    """The PNG src scaled to DPI_TO and reduced to a 64-colour palette, as PNG bytes: every copy is made before
    anything is written (pass 48: two of three committed figures were replaced, then the third was missing).
    src is read by the input rules (a FIFO, a device: refused); one that is no PNG is refused naming it."""
    import io
    from PIL import Image, UnidentifiedImageError
    data = output_file.read_input(str(src), "the run's figure", binary=True)
    try:  # (pass 49) a JPEG named .png was taken; a decompression bomb was a traceback
        im = Image.open(io.BytesIO(data))
        if im.format != "PNG" or im.width * im.height > MAX_PIXELS:
            raise OSError(f"a {im.format} image of {im.width} x {im.height} pixels; plot_paper.py writes PNG of "
                          f"at most {MAX_PIXELS} pixels")
        im = im.convert("RGB")
    except (UnidentifiedImageError, Image.DecompressionBombError, OSError) as e:
        raise output_file.Refused(f"{src}: not a figure plot_paper.py writes ({e})") from None
    w, h = im.size
    im = im.resize((round(w * DPI_TO / DPI_FROM), round(h * DPI_TO / DPI_FROM)), Image.LANCZOS)
    im = im.quantize(colors=64, method=Image.Quantize.MEDIANCUT)
    out = io.BytesIO()
    im.save(out, format="PNG", optimize=True)
    return out.getvalue()


def run_summary(folder, name):
    """gimbalsim simulate --summary's JSON, its shown figures checked (pass 49: NaN, -1, null and Infinity were put
    on the page): a status, finite numbers in range, whole counts, and a step and sub-step above 0."""
    where = f"{folder / name}"

    def refuse(const):
        raise ValueError(f"{const} is no JSON number")
    s = json.loads(results_page.run_file(folder, name), parse_constant=refuse)
    if not isinstance(s["status"], str) or not s["status"]:
        raise output_file.Refused(f"{where}: status {s['status']!r} is no run status")
    if not isinstance(s["overrides"], list) or not all(isinstance(x, str) and "=" in x for x in s["overrides"]):
        raise output_file.Refused(f"{where}: overrides {s['overrides']!r} is no list of key=value")
    for path, rule in RUN_FIGURES.items():
        x = s
        for k in path:
            x = x[k]
        rule.value(x, f"{where}: {'.'.join(path)}")
    return s


def summary_lines(text):
    """plot_paper.py's figures: [(line, name, value)] of its '  name : value' lines."""
    found = []
    for line in text.splitlines():
        m = SUMMARY_LINE.match(line)
        if m and not line.strip().startswith("wrote"):
            found.append((line, m.group(1).strip(), m.group(2)))
    return found


def check_summary(text, path):
    """plot_paper.py's figures as it prints them (pass 50: nan mm, = inf, -846.7 N, 99 rad (0.04122 deg) and
    t = -1 s were put on the page): no nan or inf; every quantity in rad, deg, N, mm or s at least 0; an
    angle at most pi rad (180 deg), its degrees those of its radians; the impacts a whole number."""
    def refuse(line, why):
        raise output_file.Refused(f"{path}: {why} in {line.strip()!r}: not as plot_paper.py writes it; "
                                  "docs/results/paper.md is kept as it was")
    for line, name, value in summary_lines(text):
        if re.search(r"(?i)\b(nan|inf|infinity)\b", value):
            refuse(line, "a figure that is no number")
        for x, unit in re.findall(rf"({NUMBER})\s*(rad|deg|N|mm|s)\b", value):
            if float(x) < 0 or (unit == "rad" and float(x) > math.pi) or (unit == "deg" and float(x) > 180):
                refuse(line, f"{x} {unit} out of range")
        for rad, deg in re.findall(rf"({NUMBER}) rad \(({NUMBER}) deg\)", value):  # both printed to 4 digits
            if not math.isclose(math.degrees(float(rad)), float(deg), rel_tol=2e-3, abs_tol=1e-300):
                refuse(line, f"{rad} rad is not {deg} deg")
        if name == "impacts" and not re.match(r"[0-9]+ \(", value):
            refuse(line, "an impact count that is no whole number")


def summary_table(text):
    """plot_paper.py's '  name : value' lines as Markdown table rows."""
    rows = [f"| {name} | {value.strip()} |" for _, name, value in summary_lines(text)]
    return "| quantity | value |\n|---|---|\n" + "\n".join(rows) + "\n"


def main():
    ap = results_page.page_arguments(__doc__, "out/paper")
    a = ap.parse_args()
    d = ROOT / a.dir
    shown = d.relative_to(ROOT) if d.is_relative_to(ROOT) else d  # the page names the repository's out/ as such
    summary = results_page.run_file(d, "plot_summary.txt")
    runs, given = [], []
    for name in ("ideal", "clearance"):
        with results_page.study_files(d / f"{name}.json", "gimbalsim simulate --summary"):
            s = run_summary(d, f"{name}.json")
            given.append(s["overrides"])
            runs.append(f"| {name} | {s['status']} | {s['t_end_s']:g} | {s['impacts']} | {s['substeps']} | "
                        f"{s['integrator']['step_s']:g} / {s['integrator']['substep_s']:g} | "
                        f"{s['wall_time_s']:.2f} |")
    out = ROOT / "docs" / "results"
    if not any(line for line in summary_table(summary).splitlines()[2:]):  # (pass 48) no page over nothing
        raise results_page.no_rows(d / "plot_summary.txt", "docs/results/paper.md")
    check_summary(summary, d / "plot_summary.txt")
    first = next((line for line in summary.splitlines() if "max pointing error" in line), "")
    peak = first.split(":", 1)[1].split()[0] if ":" in first and first.split(":", 1)[1].split() else ""
    if not first or (x := output_file.flag_decimal(peak)[0]) is None or x < 0:  # (pass 49) "x : y" made a page
        raise output_file.Refused(f"{d / 'plot_summary.txt'}: no 'max pointing error : <rad>' line with a figure "
                                  f">= 0 (got {first.strip()!r}): not as plot_paper.py writes it; "
                                  "docs/results/paper.md is kept as it was")
    figs, copies = [], {}
    for src, dst, caption in FIGURES:
        copies[out / dst] = small_copy(d / "plots" / src)
        figs.append(f"![{src.split('_')[0]}]({dst})\n\n{caption}\n")
    # what the runs were given, as their summaries say (pass 50: a --set here was any text, never compared)
    if given[0] != given[1]:
        raise output_file.Refused(f"{d}: ideal.json and clearance.json were given different overrides ({given[0]} "
                                  f"and {given[1]}): not one run of tools/run_paper.sh")
    overrides = ", ".join(f"`{x}`" for x in given[0]) if given[0] else "none (the scenes as committed)"
    body = f"""The paper's scene (You, Pan & Zhao 2010, section 4): `tools/scenes/paper_ideal.yaml` (ideal elevation
joint) and `tools/scenes/paper_clearance.yaml` (radial clearance in joint 2), the same open-loop torques, simulated
by `build/bin/gimbalsim simulate` and compared by `tools/paper/plot_paper.py` (all figures 6-18 in {shown}/plots/; the
three below are copies at {DPI_TO} dpi). Overrides given to both runs: {overrides}.

## Headline figures

{summary_table(summary)}
## Runs

| run | status | simulated to [s] | impacts | RK4 sub-steps | step / sub-step [s] | wall [s] |
|---|---|---|---|---|---|---|
{chr(10).join(runs)}

## Figures

{chr(10).join(figs)}"""
    results_page.check_page(out / "paper.md")
    output_file.check_before_writing(copies, inputs=[d / "plots" / f[0] for f in FIGURES])
    for dst, data in copies.items():  # one set with the page (run_script's whole_set): all of it or none
        output_file.write_bytes(dst, data)
    results_page.write_page(out / "paper.md", "Paper scene: ideal joint against clearance joint", a.command, body,
                            summary="max pointing error " + first.split(":", 1)[1].strip(),
                            t0=a.t0, load0=a.load0)
    print(f"paper_page: wrote {out / 'paper.md'} and {', '.join(f[1] for f in FIGURES)}")
    return 0


if __name__ == "__main__":
    sys.exit(output_file.run_script("paper_page", main, whole_set=True))
