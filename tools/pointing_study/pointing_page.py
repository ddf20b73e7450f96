#!/usr/bin/python3
"""docs/results/closed_loop_clearance.md from a gimbalsim_pointing_study run
(called by tools/pointing_study/run_pointing_study.sh --results): the truth
pointing error in closed loop, ideal joint against each clearance scene and
clearance, perfect, realistic and tracker sensors, and which bearing dominates, from
DIR's summary.csv, config.txt and the tool's log.

    /usr/bin/python3 tools/pointing_study/pointing_page.py --dir out/pointing_study --command CMD [--t0 T --load0 L]
"""
import math
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "pages"))
import results_page  # noqa: E402
import study_csv  # noqa: E402


RAD = study_csv.Column(0.0, math.pi, nan=True)  # an angle [rad]; nan: no figure (never tracked, no tick)
TICKS = study_csv.Column(0, 10**12, whole=True)
COLUMNS = {"clearance_m": study_csv.Column(0.0, 1.0), "peak_track_rad": RAD, "rms_track_rad": RAD,
           "peak_run_rad": RAD, "track_ticks": TICKS, "controller_limited_ticks": TICKS, "motor_limited_ticks": TICKS,
           # a count over the track window: nan where the run never reached it (track_reason says why)
           "controller_limited_track_ticks": study_csv.Column(0, 10**12, whole=True, nan=True),
           "max_tilt1_rad": RAD, "max_tilt2_rad": RAD,
           "play_onset1_s": study_csv.Column(0.0, 1e9, nan=True), "play_onset2_s": study_csv.Column(0.0, 1e9, nan=True)}
TEXT_COLUMNS = ("scene", "status")  # read as written


def _uncounted(x):
    """A count over a window the run never reached (nan in summary.csv)."""
    return isinstance(x, float) and math.isnan(x)


def _ticks(x):
    """A tick count's cell: n/a where the run never reached the window it counts over."""
    return "n/a" if _uncounted(x) else str(x)


def _ratio(a, b, digits=2):
    """A figure over the ideal's, n/a where either has none (pass 43: a bare nan)."""
    return f"{a / b:.{digits}g}" if math.isfinite(a) and math.isfinite(b) and b > 0 else "n/a"


def _rad(v, fmt=".2e"):
    """A figure [rad] as the page prints it: n/a where the run has none (its status says why)."""
    return format(v, fmt) if math.isfinite(v) else "n/a"


def read_summary(d):
    """The rows of the study's summary.csv in folder d by its writer's rules (COLUMNS, each run once, the text
    columns there, the track's figures exactly where it has tracking ticks): the page's and the plots' one reader
    (pass 70: the plot took a negative or NaN peak on an ok row, and CRLF). Refused naming file, line and column."""
    d = pathlib.Path(d)
    rows = study_csv.read_rows(d, "summary.csv", COLUMNS, key="run")
    missing = [c for c in TEXT_COLUMNS if rows and c not in rows[0]]
    if missing:
        raise results_page.output_file.Refused(f"{d / 'summary.csv'}: no column {', '.join(missing)} (not as its "
                                               "study writes it)")
    for line, r in enumerate(rows, start=2):  # the track's figures come with its ticks (pass 50: nan over 500 ticks)
        tracked = [r["track_ticks"] > 0, math.isfinite(r["peak_track_rad"]), math.isfinite(r["rms_track_rad"]),
                   not _uncounted(r["controller_limited_track_ticks"])]
        if len(set(tracked)) > 1:
            raise results_page.output_file.Refused(
                f"{d / 'summary.csv'}:{line}: track_ticks {r['track_ticks']} with peak_track_rad "
                f"{r['peak_track_rad']}, rms_track_rad {r['rms_track_rad']} and controller_limited_track_ticks "
                f"{r['controller_limited_track_ticks']}: its study writes the track's figures exactly when it has "
                "tracking ticks")
    return rows


def _page(d):
    """The page's body (Markdown lines) and its index line, from the study in d."""
    rows = read_summary(d)
    if not rows:
        raise results_page.no_rows(d / "summary.csv", "docs/results/closed_loop_clearance.md")
    if not any(r["track_ticks"] > 0 for r in rows):  # (pass 50) the page's subject: a page of n/a replaced the study's
        raise results_page.output_file.Refused(
            f"{d / 'summary.csv'}: no run has a figure while tracking (each stopped or ended before it): nothing to "
            "put on the page; docs/results/closed_loop_clearance.md is kept as it was")
    log = results_page.run_file(d, "study.log", optional=True)
    setup = next((line.lstrip("# ").strip() for line in log.splitlines() if line.startswith("# ")), "")
    config = results_page.run_file(d, "config.txt").splitlines()  # (pass 50) written by every study
    def sensors(r):
        return r.get("sensors", "perfect")

    def tilts(r):  # the tilts of the spatial joints ("-" for a joint that cannot tilt)
        kinds = r.get("joints", "").split("/")
        return " / ".join(_rad(r[f'max_tilt{j + 1}_rad'], '.3g') if j < len(kinds) and kinds[j] == "spatial"
                          else "-" for j in range(2))

    def onset(r, j):  # when axis j went onto the guard's gains [s]; NaN: never
        return r[f"play_onset{j + 1}_s"]

    ideals = {sensors(r): r for r in rows if r["clearance_m"] == 0.0}
    scenes = list(dict.fromkeys(r["scene"] for r in rows if r["clearance_m"] > 0.0))
    md = ["`build/bin/gimbalsim_pointing_study` (tools/pointing_study/): the in-process closed loop (firmware model "
          "+ pointing controller, `controllers/config/default.yaml`, the truth of the lockstep bench) on "
          "`paper_ideal` and on " + ", ".join(f"`{sc}`" for sc in scenes) + " at each clearance "
          "(`contact.clearance`, every clearance bearing of the scene), same profile and duration; the truth pointing "
          "error (boresight against the target's line of sight, inertial) every tick. Sensors: perfect (the scene's: "
          "no noise, encoders quantised) and, where listed, realistic (star tracker noise 2e-5 rad per axis, gyro "
          "bias 1e-5 rad/s: the pointing budget's upper bounds) and tracker (perfect, with the antenna's own "
          "boresight tracker and gyro, noise 0, which the controller closes its loop on: docs/MODEL.md 11.7). "
          f"{setup[0].upper() + setup[1:] if setup else ''}.", ""]
    # Which bearing dominates: RMS while tracking at the largest clearance, per scene and sensors.
    c_max = max((r["clearance_m"] for r in rows), default=0.0)
    cases = list(dict.fromkeys(sensors(r) for r in rows))
    if len(scenes) > 1 and c_max > 0.0:
        md += [f"RMS truth pointing error while tracking at c = {c_max * 1e3:g} mm (ratio to the ideal joint with "
               "the same sensors):", "",
               "| scene | " + " | ".join(f"{cs} sensors [rad]" for cs in cases) + " |",
               "|---|" + "---|" * len(cases)]
        for sc in list(dict.fromkeys(r["scene"] for r in ideals.values())) + scenes:
            cells = []
            for cs in cases:
                r = next((r for r in rows if r["scene"] == sc and sensors(r) == cs
                          and r["clearance_m"] in (0.0, c_max)), None)
                ideal = ideals.get(cs)
                if r is None:
                    cells.append("-")
                    continue
                ratio = (f" ({_ratio(r['rms_track_rad'], ideal['rms_track_rad'], 3)}x)"
                         if ideal is not None and r is not ideal and ideal["rms_track_rad"] > 0 else "")
                cells.append(f"{_rad(r['rms_track_rad'])}{ratio}")
            md.append(f"| {sc} | " + " | ".join(cells) + " |")
        md.append("")
    ticks = max(results_page.run_file_lines(d, "pointing_error.csv", limit=1 << 28) - 1, 0)  # less the header
    limited = [r for r in rows if ticks > 0 and r["controller_limited_ticks"] > 0.1 * ticks]
    if limited and all(r.get("joints", "").endswith("/spatial") for r in limited):
        md += [f"In {len(limited)} of the {len(rows)} runs a torque command sits at its limit for more than 10 % "
               f"of the {ticks} ticks (" + ", ".join(sorted({r['scene'] for r in limited})) + "): the controller, "
               "tuned for the rigid chain, limit-cycles. A spatial elevation journal's tilt lets shaft 1 turn about "
               "the azimuth axis against the antenna by up to 2c/L (backlash between the azimuth encoder and the "
               "antenna), so the azimuth loop drives the light shaft 1 alone across that play.", ""]
    tracked = [r for r in rows if r["track_ticks"] > 0 and not _uncounted(r["controller_limited_track_ticks"])]
    if tracked:  # the slew may saturate by design; the loop's own limit cycle would show while tracking
        worst = max(tracked, key=lambda r: r["controller_limited_track_ticks"] / r["track_ticks"])
        n_worst, of = worst["controller_limited_track_ticks"], worst["track_ticks"]
        md += [(f"While tracking, a torque command sat at its limit in at most {n_worst} of {of} ticks "
                f"({100 * n_worst / of:.3g} %, {worst['run']})" if n_worst else
                "While tracking, no torque command sat at its limit") +
               f" in the {len(tracked)} runs that tracked; the rest of the column's ticks came before tracking "
               "(the slew and the hold).", ""]
    guarded = [r for r in rows if any(math.isfinite(onset(r, j)) for j in range(2))]
    if guarded:
        md += [f"In {len(guarded)} of the {len(rows)} runs the controller saw a play and stepped that axis on its "
               "backlash guard's gains from the time given (docs/MODEL.md section 11.5; `-`: never): "
               + ", ".join(sorted({r['scene'] for r in guarded})) + ". Loop sensors: what the controller closes "
               "on (encoders: the joint encoders and rates; base attitude: the gyro and star tracker; antenna: its "
               "boresight tracker and gyro).", ""]
    md += ["| run | scene | sensors | loop sensors | clearance [mm] | peak while tracking [rad] "
           "| RMS while tracking [rad] | peak over the run [rad] | peak / ideal | RMS / ideal "
           "| torque at its limit, run / tracking [ticks] | largest tilt, joint 1 / 2 [rad] "
           "| guard from, az / el [s] | plant |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        c = r["clearance_m"]
        rel = ("-", "-")
        ideal = ideals.get(sensors(r))
        if ideal is not None and r is not ideal:
            rel = tuple(_ratio(r[k], ideal[k]) for k in ("peak_track_rad", "rms_track_rad"))
        status = r["status"] + (f" ({r['stop_reason']})" if r.get("stop_reason") else "")
        guard = " / ".join(f"{onset(r, j):.3f}" if math.isfinite(onset(r, j)) else "-" for j in range(2))
        md.append(f"| {r['run']} | {r['scene']} | {sensors(r)} | {r.get('loop_sensors') or '-'} | "
                  f"{'-' if c == 0 else f'{c * 1e3:g}'} | "
                  f"{_rad(r['peak_track_rad'])} | {_rad(r['rms_track_rad'])} | {_rad(r['peak_run_rad'])} | "
                  f"{rel[0]} | {rel[1]} | {r['controller_limited_ticks']} / "
                  f"{_ticks(r['controller_limited_track_ticks'])} | {tilts(r)} | {guard} | {status} |")
    # the study's folder as read (--dir), in the repository's terms where it lies there (pass 55: always the default)
    shown = d.relative_to(ROOT) if d.is_relative_to(ROOT) else d
    md += ["", f"Per tick: {shown}/pointing_error.csv; figures: {shown}/pointing_error_vs_time.png "
           "and pointing_error_vs_clearance.png (tools/pointing_study/plot_pointing_study.py).", ""]
    if config:
        md += ["Controller configuration in effect (config.txt):", "", "```", *config, "```", ""]
    # the worst clearance run with a track figure: the ideal joint's is no bound of the clearance's (pass 53)
    with_track = [r for r in rows if r["clearance_m"] > 0 and math.isfinite(r["peak_track_rad"])]
    worst = max(with_track, key=lambda r: r["peak_track_rad"]) if with_track else None
    ideal = ideals.get("perfect")
    if ideal:
        summary = (f"{len(rows)} runs; peak error while tracking {_rad(ideal['peak_track_rad'], '.3g')} rad ideal, "
                   + (f"up to {_rad(worst['peak_track_rad'], '.3g')} rad ({worst['run']})" if worst else
                      "no clearance run has a figure while tracking"))
    else:
        summary = f"{len(rows)} runs"
    return md, summary


def main():
    ap = results_page.page_arguments(__doc__, "out/pointing_study")
    a = ap.parse_args()
    d = ROOT / a.dir
    with results_page.study_files(d, "gimbalsim_pointing_study"):
        md, summary = _page(d)
    results_page.write_page(ROOT / "docs/results/closed_loop_clearance.md",
                            "Closed-loop pointing error against clearance", a.command, "\n".join(md),
                            summary=summary, t0=a.t0, load0=a.load0)
    print("pointing_page: wrote docs/results/closed_loop_clearance.md")
    return 0


if __name__ == "__main__":
    sys.exit(results_page.output_file.run_script("pointing_page", main))
