#!/usr/bin/python3
"""Renders fx2d-bench's files into one HTML report: `DIR/index.html` with its charts beside it.

    /usr/bin/python3 reports/render_report.py FILE.h5 [FILE.h5 ...] [--compare-json FILE] -o DIR

`fx2d-bench report` runs this; it may also be run by hand. Reads run, sweep, stability and nightly
history files (harness/RESULTS_FORMAT.md) and the JSON of `fx2d-bench compare --json`.

Invariant: the page is self-contained and viewable offline: inline CSS, no scripts but the one
inline check that records whether every image loaded (body data-images-loaded/-total, read by
harness/tests/report_test.cpp), images by relative path. Every section is always present; one
without data says what input would fill it. Exit status: 0 done, 2 an input it cannot read,
3 a Python package missing, 1 anything else; every failure is one line on stderr.
"""

import sys

try:
    import h5py  # noqa: F401  (checked here so a missing package is named before anything runs)
    import matplotlib  # noqa: F401
    import numpy  # noqa: F401
except ImportError as missing:
    print(f"render_report.py: Python module '{missing.name}' is missing; install Debian's "
          "python3-h5py and python3-matplotlib (apt-get install python3-h5py python3-matplotlib)", file=sys.stderr)
    sys.exit(3)

import argparse  # noqa: E402
import datetime  # noqa: E402
import html  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import os  # noqa: E402
import textwrap  # noqa: E402

import charts  # noqa: E402
import report_data  # noqa: E402
from report_data import InputProblem  # noqa: E402

SECTIONS = [
    ("runs", "Runs"),
    ("phases", "Phase split"),
    ("speed-accuracy", "Speed against accuracy"),
    ("scaling", "Scaling with workers"),
    ("ab", "A/B comparison"),
    ("stability", "Stability"),
    ("history", "Nightly history"),
    ("provenance", "Provenance"),
]

ACCURACY_NOTE = ("Accuracy is the worst over the sampled steps of the first repeat (kinetic energy: the last "
                 "sample); the scene's primary metric is in bold.")

esc = html.escape


# --- small HTML pieces ----------------------------------------------------------------------------

def chip(engine):
    colour = charts.engine_colour(engine)
    return (f'<span class="chip" style="background:{charts.lighten(colour, 0.82)};color:{colour};'
            f'border-color:{colour}">{esc(engine)}</span>')


def figure(name, caption):
    return (f'<figure><img src="{name}.png" alt="{esc(caption)}">'
            f'<figcaption>{esc(caption)} <a href="{name}.svg">SVG</a></figcaption></figure>')


def note(text):
    return f'<p class="note">{text}</p>'


def table(header, rows, classes=""):
    """Rows are lists of cells, or a string: a heading row across the whole table."""
    head = "".join(f"<th>{h}</th>" for h in header)
    body = "".join(f'<tr class="group"><td colspan="{len(header)}">{row}</td></tr>' if isinstance(row, str) else
                   "<tr>" + "".join(f"<td>{cell}</td>" for cell in row) + "</tr>" for row in rows)
    return f'<div class="scroll"><table class="{classes}"><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table></div>'


def number(value, digits=3):
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "–"
    return f"{value:.{digits}g}"


# --- sections -------------------------------------------------------------------------------------

def runs_section(files):
    runs = [run for f in files for run in f.runs]
    if not runs:
        return note("No run file among the inputs: <code>fx2d-bench run SCENE --out run.h5</code> makes one.")
    rows = []
    for f in files:
        if f.runs:
            rows.append(file_heading(f))
        rows.extend(run_row(run) for run in f.runs)
    header = ["engine", "version", "scene", "bodies", "steps × repeats", "ms/step median [min–max]",
              "max pen. mm", "max disp. m", "lateral drift m", "final KE J", "escaped", "NaN", "state hash"]
    return table(header, rows, "runs") + note(
        ACCURACY_NOTE + " Timing: a repeat's figure is its mean per step; median, min and max are across repeats. "
        "Hover an engine version for its solver settings.")


def file_heading(f):
    p = f.provenance
    return (f"<b>{esc(f.label)}</b> · {esc(p.get('hostname', ''))} ({esc(p.get('cpu_model', ''))}) · "
            f"{esc(p.get('compiler', ''))} {esc(p.get('build_type', ''))} <code>{esc(p.get('build_flags', ''))}</code>"
            f" · {esc(p.get('date_utc', ''))}")


def run_row(run):
    worst = run.worst
    primary = {"penetration": "max_penetration", "displacement": "max_displacement"}.get(run.primary_metric)

    def figure_of(name, scale, digits=3):
        text = number(worst.get(name, math.nan) * scale, digits)
        return f"<b>{text}</b>" if name == primary else text

    hash_cell = f'<code title="{esc(run.state_hash)}">{esc(run.state_hash[:8])}</code>'
    if not run.deterministic:
        hash_cell += ' <span class="warn" title="repeats ended in different states">varies</span>'
    return [
        chip(run.engine), f'<span title="{esc(run.settings)}">{esc(run.engine_version)}</span>',
        esc(run.scene), str(run.bodies), f"{run.steps} × {run.repeats}",
        f'<span class="num">{run.ms_median:.3f}</span> <span class="range">[{run.ms_min:.3f}–{run.ms_max:.3f}]</span>',
        figure_of("max_penetration", 1e3), figure_of("max_displacement", 1.0),
        figure_of("max_lateral_drift", 1.0), number(worst.get("kinetic_energy", math.nan)),
        str(int(worst.get("escaped", 0))), str(int(worst.get("nan", 0))), hash_cell,
    ]


def phases_section(files, out_dir):
    runs = [run for f in files for run in f.runs]
    if not runs:
        return note("No run file among the inputs, so no phase split.")
    seen = {}
    for run in runs:
        seen.setdefault((run.engine, run.scene, run.bodies), set()).add(run.source)

    def bar_label(run):
        label = f"{run.scene} · {run.bodies}"
        return label + f"\n{run.source}" if len(seen[(run.engine, run.scene, run.bodies)]) > 1 else label

    name = charts.phase_split(runs, bar_label, out_dir)
    return figure(name, "Median wall time per step in each of the engine's own phases, per scene "
                        "(scene · bodies). An engine that reports no phases (ODE) shows its total; "
                        "time a step spends outside every phase is shown hatched grey.")


def speed_accuracy_section(files, out_dir):
    tables = [f.sweep for f in files if f.sweep is not None and len(f.sweep)]
    if not tables:
        return note("No sweep file among the inputs: <code>fx2d-bench sweep SCENE --out sweep.h5</code> makes one.")
    parts = []
    standing = []
    for (scene, bodies), entries in charts.sweep_groups(tables).items():
        name = charts.speed_accuracy(scene, bodies, entries, out_dir)
        parts.append(figure(name, f"{scene}, {bodies} bodies: every setting tried; lines are each engine's Pareto "
                                  "front (fastest setting for each accuracy level), stars the scene's default settings."))
        for table_, rows in entries:
            standing.extend(default_standing(table_, rows))
    text = '<div class="grid">' + "".join(parts) + "</div>"
    if standing:
        text += "<h3>Where each default stands</h3>" + table(
            ["scene", "bodies", "engine", "default settings", "ms/step", "error mm", "on its front?"], standing)
    return text


def default_standing(sweep, rows):
    c = sweep.columns
    result = []
    for r in rows:
        if not c["is_default"][r]:
            continue
        if c["on_front"][r]:
            where = f'<span class="good">on it, #{int(c["front_rank"][r]) + 1} from the fastest</span>'
        else:
            better = int(c["dominated_by"][r])
            where = (f'<span class="warn">off it</span>: {esc(c["settings"][better])} is at least as accurate at '
                     f'{100 * c["ms_per_simulated_s"][better] / c["ms_per_simulated_s"][r]:.0f}% of the cost')
        result.append([esc(c["scene"][r]), str(int(c["bodies"][r])), chip(c["engine"][r]), esc(c["settings"][r]),
                       f'{c["ms_per_step"][r]:.3f}', number(c["primary_error"][r] * 1e3), where])
    return result


def scaling_section(files, out_dir):
    scaled = [(f, report_data.worker_scaling(f.sweep, f.sweep_runs)) for f in files
              if f.sweep is not None and len(f.sweep)]
    series = [s for _, file_series in scaled for s in file_series]
    if not series:
        return note("No sweep over an engine's thread count among the inputs: <code>fx2d-bench sweep SCENE "
                    "--engine fx2d --axis fx2d.workers=1,2,3,4 --out sweep.h5</code> makes one.")
    parts = [figure(charts.speedup(series, out_dir),
                    "Speedup (ms/step at 1 worker over that at k: the median of the rounds' ratios, each round of "
                    "the two run in the same pass, with its 95% interval; in a merged file the ratio of the medians) "
                    "against workers, per engine, scene, size and setting of the other knobs; the dashed line is the "
                    "ideal, speedup = workers.")]
    # Threads that hand work to each other pay a cache line's trip between cores at each hand-over.
    for f, file_series in scaled:
        if file_series and f.core_round_trip_ns:
            start, end = f.core_round_trip_ns
            parts.append(note(f"{esc(f.label)}: a cache line went from one core to another and back in "
                              f"{start:.0f} ns as the sweep began, {end:.0f} ns as it ended; the speedups "
                              "move with it."))
    for engine in dict.fromkeys(s["engine"] for s in series):
        mine = [s for s in series if s["engine"] == engine]
        names = list(dict.fromkeys(name for s in mine for phases in s["phases"] for name, _ in phases))
        rows = []
        for s in mine:
            rows.append(f"{esc(s['scene'])} · {s['bodies']} bodies" + (f" · {esc(s['setting'])}" if s["setting"] else ""))
            for workers, ms, speed, low, high, phases in zip(s["workers"], s["ms"], s["speedup"], s["speedup_low"],
                                                              s["speedup_high"], s["phases"]):
                split = dict(phases)
                interval = f"{number(low)}–{number(high)}" if math.isfinite(low) else number(low)
                rows.append([str(workers), f"{ms:.4g}", number(speed), interval] + [number(split.get(n)) for n in names])
        parts.append(f"<h3>{chip(engine)} phase split per {esc(mine[0]['knob'])} count</h3>")
        parts.append(table([esc(mine[0]["knob"]), "ms/step", "speedup", "95% CI"] + [f"{esc(n)} ms" for n in names],
                           rows))
    return "".join(parts)


def ab_file_section(files, out_dir):
    """The A/B comparison inside each run file written by `fx2d-bench ab --out` (engines X@A, X@B)."""
    parts = []
    for index, f in enumerate(files):
        rows = report_data.ab_rows(f.runs)
        if not rows:
            continue
        headline = f"{f.label}: B against A, by interval"
        name = charts.ab_forest({"noise": report_data.AB_NOISE, "headline": headline, "mode": "ab"}, rows,
                                lambda row: f"{row['engine']} · {row['scene']} · {row['bodies']} · "
                                            f"{row['metric'].removeprefix('phase:')}",
                                out_dir, f"ab_file_{index}")
        parts.append(f"<h3>{esc(f.label)} (fx2d-bench ab)</h3>")
        parts.append(figure(name, "Ratio B/A of the median per-repeat step time and of each phase, with a 95% "
                                  "percentile bootstrap interval over repeats, around the ±2% noise band. The colour "
                                  "judges the interval alone; <code>fx2d-bench compare</code> adds the rank test."))
        parts.append(table(["engine", "scene", "bodies", "metric", "A (ms)", "B (ms)", "ratio [95% CI]", "by interval"],
                           [[chip(r["engine"]), esc(r["scene"]), str(r["bodies"]), esc(r["metric"]), number(r["a"], 4),
                             number(r["b"], 4), f'{r["ratio"]:.3f} [{r["ci_low"]:.3f}–{r["ci_high"]:.3f}]',
                             f'<span class="verdict {esc(r["speed"].replace(" ", "-"))}">{esc(r["speed"])}</span>']
                            for r in rows]))
    return "".join(parts)


def ab_section(compare_reports, files, out_dir):
    from_files = ab_file_section(files, out_dir)
    if not compare_reports:
        return from_files or note("No comparison given: pass <code>--compare-json FILE</code> with the output of "
                                  "<code>fx2d-bench compare A.h5 B.h5 --json</code>, or an <code>fx2d-bench ab "
                                  "--out</code> file.")
    parts = [from_files]
    for index, (path, report) in enumerate(compare_reports):
        rows = [row for row in report["rows"] if row["metric"] != "cycles_per_step"]
        cross = report.get("mode") == "cross-engine"

        def row_label(row, cross=cross):
            who = f"{row['engine']} / {row['against']}" if cross else row["engine"]
            return f"{who} · {row['scene']} · {row['bodies']} · {row['metric'].removeprefix('phase:')}"

        name = charts.ab_forest(report, rows, row_label, out_dir, f"ab_{index}")
        parts.append(f"<h3>{esc(os.path.basename(path))}</h3>")
        if name:
            parts.append(figure(name, "Ratio of medians with its 95% bootstrap interval for the step time and each "
                                      "phase (cycles per step, which mirrors the step time, is left out)."))
        parts.append(table(["engine", "scene", "bodies", "metric", "A", "B", "ratio [95% CI]", "p", "verdict"],
                           [[chip(r["engine"]), esc(r["scene"]), str(r["bodies"]), esc(r["metric"]), number(r["a"], 4),
                             number(r["b"], 4), f'{r["ratio"]:.3f} [{r["ci_low"]:.3f}–{r["ci_high"]:.3f}]',
                             number(r["p_value"], 2),
                             f'<span class="verdict {esc(r["speed"].replace(" ", "-"))}">{esc(r["verdict"])}</span>'] for r in rows]))
    return "".join(parts)


def settings_text(settings_json):
    try:
        settings = json.loads(settings_json)
    except ValueError:
        return settings_json
    return ", ".join(f"{key} {value}" for key, value in settings.items()) if isinstance(settings, dict) else settings_json


def _search_score(boundary, start, limit, geometric):
    """Where the boundary lies in the searched range, 0 at the easiest value, 1 at the hardest; on
    a log scale for a geometric search. The same number whichever way the test gets harder."""
    position = (lambda v: math.log(v)) if geometric and min(boundary, start, limit) > 0 else (lambda v: v)
    if position(limit) == position(start):
        return 1.0
    return min(max((position(boundary) - position(start)) / (position(limit) - position(start)), 0.0), 1.0)


def stability_cells(tables):
    """Heat-map rows (engine, settings), columns (tests) and cells (score, text): each boundary, the
    hardest value that passed, scored by where it lies in its test's searched range."""
    rows, tests, cells = [], [], {}
    for t in tables:
        c = t.columns
        for i in range(len(t)):
            row = (c["engine"][i], f'{c["engine"][i]}\n' + textwrap.fill(settings_text(c["settings"][i]), 40))
            units = f' ({c["units"][i]})' if c["units"][i] else ""
            better = "higher" if c["harder"][i] == "increasing" else "lower"
            test = (c["test"][i], c["test"][i] + "\n" + textwrap.fill(f"{c['parameter'][i]}{units}", 18)
                    + f"\n{better} is better")
            if row not in rows:
                rows.append(row)
            if test not in tests:
                tests.append(test)
            boundary = float(c["last_pass"][i])
            if c["outcome"][i] == "fails_at_start" or not math.isfinite(boundary):
                cells[(row, test)] = (0.0, "fails at start")
                continue
            score = _search_score(boundary, float(c["start"][i]), float(c["limit"][i]), c["scale"][i] == "geometric")
            prefix = "≥ " if c["outcome"][i] in ("holds_to_limit", "engine_limit") else ""
            suffix = " (engine limit)" if c["outcome"][i] == "engine_limit" else ""
            text = f"{prefix}{boundary:.3g}{suffix}"
            cells[(row, test)] = (score, text)
    return rows, tests, cells


def stability_section(files, out_dir):
    tables = [f.stability[""] for f in files if "" in f.stability]
    if not tables:
        return note("No stability file among the inputs: <code>fx2d-bench stability --out stability.h5</code> "
                    "makes one.")
    rows, tests, cells = stability_cells(tables)
    name = charts.stability_heatmap(rows, tests, cells, out_dir)
    failures = []
    for t in tables:
        c = t.columns
        for i in range(len(t)):
            # Files written before the criterion and step were recorded have neither column.
            criterion = c["failed_criterion"][i] if "failed_criterion" in c else ""
            step = int(c["failed_step"][i]) if "failed_step" in c else -1
            failures.append([chip(c["engine"][i]), esc(c["test"][i]), esc(c["outcome"][i].replace("_", " ")),
                             number(float(c["last_pass"][i])), number(float(c["first_fail"][i])),
                             esc(criterion), str(step) if step >= 0 else "", esc(c["failure"][i])])
    quick = any(int(t.attributes.get("quick", 0)) for t in tables)
    return (figure(name, "Each cell is the hardest stress value that still passed (≥: held up to the search "
                         "limit); its colour is where that lies in the test's searched range, from the easiest "
                         "value (0) to the hardest (1), on a log scale for a geometric search.")
            + (note("Searched with <code>--quick</code>: limits are lower than the full suite's.") if quick else "")
            + "<details open><summary>What failed first, for each engine and test</summary>"
            + table(["engine", "test", "outcome", "last pass", "first fail", "criterion", "at step", "failure"],
                    failures) + "</details>")


def history_section(files, out_dir):
    histories = [f for f in files if f.history is not None]
    if not histories:
        return note("No nightly history file among the inputs (a file with a <code>/history</code> group); "
                    "this section is left empty.")
    parts = []
    for f in histories:
        series = history_series(f.history)
        if not series:
            parts.append(note(f"{esc(f.label)}: the history has no nights yet."))
            continue
        for metric in dict.fromkeys(s["metric"] for s in series):
            mine = [s for s in series if s["metric"] == metric]
            name = charts.history_trend(mine, metric, f.label, out_dir)
            parts.append(figure(name, f"{esc(f.label)}: the candidate's median {esc(metric)} night by night per "
                                      "engine, scene and size; the thin line is the baseline it was judged against, "
                                      "a star marks a night whose candidate was accepted as the new baseline, a "
                                      "triangle a change the gate detected (up: slower, down: faster)."))
        parts.append(history_nights_table(f.history))
    return "".join(parts)


def _history_x(values):
    try:
        return [datetime.datetime.fromisoformat(str(v).replace("Z", "+00:00")) for v in values]
    except ValueError:
        return list(range(len(values)))


def history_series(history):
    """One series per (engine, scene, bodies, metric) of a /history table, nights in file order:
    x the night's date, y the candidate's median (b), the baseline's (a), and the nights that were
    accepted or where the gate detected a step (with its direction, from the ratio)."""
    c = history.columns
    keys = [(str(c["engine"][i]).partition("@")[0], str(c["scene"][i]), int(c["bodies"][i]), str(c["metric"][i]))
            for i in range(len(history))]
    series = []
    for key in dict.fromkeys(keys):
        rows = [i for i in range(len(history)) if keys[i] == key]
        series.append({
            "label": f"{key[0]} · {key[1]} · {key[2]}", "engine": key[0], "metric": key[3],
            "x": _history_x([c["date_utc"][i] for i in rows]),
            "candidate": [float(c["b"][i]) for i in rows],
            "baseline": [float(c["a"][i]) for i in rows],
            "accepted": [n for n, i in enumerate(rows) if c["accepted"][i]],
            "steps": [(n, float(c["ratio"][i]) > 1.0) for n, i in enumerate(rows) if c["step_detected"][i]],
        })
    return series


def history_nights_table(history):
    """The last night's gating rows: what the gate said, and what was quarantined or accepted."""
    c = history.columns
    last = c["date_utc"][len(history) - 1]
    rows = [i for i in range(len(history)) if c["date_utc"][i] == last]
    return (f"<h3>Last night ({esc(str(last))}): {esc(str(c['candidate'][rows[0]]))} against "
            f"{esc(str(c['baseline'][rows[0]]))}</h3>"
            + table(["engine", "scene", "bodies", "metric", "ratio [95% CI]", "verdict", "step", "accepted"],
                    [[chip(str(c["engine"][i]).partition("@")[0]), esc(str(c["scene"][i])), str(int(c["bodies"][i])),
                      esc(str(c["metric"][i])),
                      f'{c["ratio"][i]:.3f} [{c["ci_low"][i]:.3f}–{c["ci_high"][i]:.3f}]',
                      esc(str(c["verdict"][i])), "step" if c["step_detected"][i] else "",
                      "yes" if c["accepted"][i] else ""] for i in rows]))


def provenance_section(files):
    rows = []
    for f in files:
        kind = ("sweep" if f.sweep is not None else "stability" if f.stability else
                "history" if f.history is not None else "run")
        p = f.provenance
        rows.append([esc(f.label), kind, esc(f"{p.get('fx2d_version', '')} ({p.get('fx2d_git_revision', '')})"),
                     esc(p.get("build_type", "")), esc(p.get("compiler", "")), f"<code>{esc(p.get('build_flags', ''))}</code>",
                     esc(p.get("cpu_model", "")), esc(p.get("kernel", "")), esc(p.get("hostname", "")),
                     esc(p.get("date_utc", "")), f"<code>{esc(p.get('command_line', ''))}</code>"])
    return table(["file", "kind", "fx2d", "build", "compiler", "flags", "CPU", "kernel", "machine", "date (UTC)",
                  "command"], rows, "provenance")


# --- the page -------------------------------------------------------------------------------------

HERE = os.path.dirname(os.path.abspath(__file__))


def asset(name):
    """A file beside this script (the page's style and its image check), inlined into the page."""
    with open(os.path.join(HERE, name), encoding="utf-8") as text:
        return text.read()



def page(files, compare_paths, bodies):
    inputs = ", ".join(f"<code>{esc(f.label)}</code>" for f in files)
    inputs += "".join(f", <code>{esc(os.path.basename(p))}</code>" for p in compare_paths)
    generated = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    nav = "".join(f'<a href="#{key}">{title}</a>' for key, title in SECTIONS)
    sections = "".join(f'<section id="{key}"><h2>{title}</h2>{bodies[key]}</section>' for key, title in SECTIONS)
    legend = " ".join(chip(engine) for engine in ("fx2d", "box2d", "ode", "chipmunk"))
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>fx2d-bench report</title>
<style>{asset("report.css")}</style>
</head><body>
<header><h1>fx2d-bench report</h1>
<p>Fx2D against Box2D, ODE and Chipmunk2D: speed, accuracy and stability. Generated {generated} from {inputs}.</p>
<p>Engines: {legend}</p></header>
<nav>{nav}</nav>
<main>{sections}</main>
<script>{asset("report_check.js")}</script>
</body></html>
"""


def render(arguments):
    labels = report_data.unique_labels(arguments.files)
    files = [report_data.read_h5(path, label) for path, label in zip(arguments.files, labels)]
    compare_reports = [(path, report_data.read_compare_json(path)) for path in arguments.compare_json]
    out_dir = arguments.output
    os.makedirs(out_dir, exist_ok=True)
    bodies = {
        "runs": runs_section(files),
        "phases": phases_section(files, out_dir),
        "speed-accuracy": speed_accuracy_section(files, out_dir),
        "scaling": scaling_section(files, out_dir),
        "ab": ab_section(compare_reports, files, out_dir),
        "stability": stability_section(files, out_dir),
        "history": history_section(files, out_dir),
        "provenance": provenance_section(files),
    }
    with open(os.path.join(out_dir, "index.html"), "w", encoding="utf-8") as stream:
        stream.write(page(files, arguments.compare_json, bodies))


def main():
    parser = argparse.ArgumentParser(description="Render fx2d-bench files into an HTML report")
    parser.add_argument("files", nargs="*", help="run, sweep, stability or history HDF5 files")
    parser.add_argument("--compare-json", action="append", default=[], help="fx2d-bench compare --json output")
    parser.add_argument("-o", "--output", required=True, help="directory to write index.html and charts into")
    arguments = parser.parse_args()
    if not arguments.files and not arguments.compare_json:
        parser.error("nothing to report: give at least one HDF5 file or --compare-json")
    try:
        render(arguments)
    except InputProblem as problem:
        print(f"render_report.py: {problem}", file=sys.stderr)
        return 2
    except Exception as error:  # one line for the CLI, whatever broke
        print(f"render_report.py: internal error: {type(error).__name__}: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
