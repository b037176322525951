"""The report's charts, drawn with matplotlib's Agg backend and saved as PNG (shown on the page)
and SVG (linked beside it).

Invariant: an engine has one colour everywhere (ENGINE_COLOURS; engines the harness may add later
take the next free colour of one fixed fallback list, in the order they are first seen), every
axis names its quantity and unit, and every chart function returns the base name of the files it
wrote, or None when it had nothing to draw.
"""

import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)
from matplotlib import colors as mcolors, lines, patches, ticker  # noqa: E402
import numpy as np  # noqa: E402

ENGINE_COLOURS = {"fx2d": "#1f5fbf", "box2d": "#e07b00", "ode": "#2a9d5c", "chipmunk": "#8e44ad"}
_FALLBACK_COLOURS = ["#8e44ad", "#c0392b", "#7f8c8d", "#16a085"]
# A sequential map per engine for its phases, so a phase bar still reads as that engine's.
_ENGINE_PHASE_MAPS = {"fx2d": "Blues", "box2d": "Oranges", "ode": "Greens"}
SPEED_COLOURS = {"faster": "#2a9d5c", "slower": "#c0392b", "no change": "#7f8c8d", "inconclusive": "#d4a017"}
# A row's accuracy verdict rides on its marker: same accuracy a dot, worse a down-triangle.
ACCURACY_MARKERS = {"": "o", "less accurate": "v", "more accurate": "^"}

plt.rcParams.update({
    "font.family": "DejaVu Sans",   # shipped with matplotlib: the charts need no system font
    "font.size": 11,
    "axes.titlesize": 13,
    "axes.titleweight": "bold",
    "axes.labelsize": 11,
    "legend.fontsize": 9.5,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "axes.grid": True,
    "grid.color": "#e3e3e3",
    "grid.linewidth": 0.8,
    "axes.axisbelow": True,
    "svg.fonttype": "none",         # text stays text in the SVG
    "savefig.dpi": 110,
})


def engine_colour(engine):
    if engine not in ENGINE_COLOURS:
        used = set(ENGINE_COLOURS.values())
        ENGINE_COLOURS[engine] = next((c for c in _FALLBACK_COLOURS if c not in used), "#555555")
    return ENGINE_COLOURS[engine]


def _save(figure, out_dir, name):
    for extension in ("png", "svg"):
        figure.savefig(os.path.join(out_dir, f"{name}.{extension}"), bbox_inches="tight")
    plt.close(figure)
    return name


def _slug(*parts):
    text = "_".join(str(part) for part in parts)
    return "".join(c if c.isalnum() else "_" for c in text).strip("_").lower()


# --- speed against accuracy -----------------------------------------------------------------------

def _knob_label(table, row, engine):
    """The engine's knob values of a sweep row, e.g. "14×4"; the columns are <engine>_<knob>."""
    values = [str(int(table.columns[name][row])) for name in table.columns
              if name.startswith(engine + "_") and table.columns[name][row] >= 0]
    return "×".join(values)


def _knob_names(table, engine):
    return "×".join(name[len(engine) + 1:] for name in table.columns if name.startswith(engine + "_"))


def sweep_groups(tables):
    """{(scene, bodies): [(table, [row, ...]), ...]} over every sweep table, in first-seen order."""
    groups = {}
    for table in tables:
        for row in range(len(table)):
            key = (table.columns["scene"][row], int(table.columns["bodies"][row]))
            entries = groups.setdefault(key, [])
            if not entries or entries[-1][0] is not table:
                entries.append((table, []))
            entries[-1][1].append(row)
    return groups


def _engine_line_styles(series):
    """(series, line style) for lines coloured by engine: an engine's lines take the styles in turn."""
    line_styles = ["-", "--", ":", "-."]
    per_engine = {}
    for s in series:
        yield s, line_styles[per_engine.setdefault(s["engine"], 0) % len(line_styles)]
        per_engine[s["engine"]] += 1


def _plain_log_ticks(axis):
    """Ticks at 1, 2 and 5 of each decade, written as plain numbers: a log axis a reader can read."""
    axis.set_major_locator(ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(ticker.FuncFormatter(lambda value, _: f"{value:g}"))
    axis.set_minor_formatter(ticker.NullFormatter())


def speed_accuracy(scene, bodies, entries, out_dir):
    """Cost against error for every sweep point of one scene, each engine's front as a staircase."""
    figure, axes = plt.subplots(figsize=(7.6, 5.2))
    metric_names = set()
    finite_errors, blow_ups = [], []
    for table, rows in entries:
        c = table.columns
        dt = c["dt"]
        for engine in dict.fromkeys(c["engine"][rows]):
            mine = [r for r in rows if c["engine"][r] == engine]
            colour = engine_colour(engine)
            cost = np.array([c["ms_per_simulated_s"][r] for r in mine])
            error_mm = np.array([c["primary_error"][r] for r in mine]) * 1e3
            low = np.array([c["ms_per_step_ci_low"][r] / dt[r] for r in mine])
            high = np.array([c["ms_per_step_ci_high"][r] / dt[r] for r in mine])
            metric_names.update(c["primary_metric"][r] for r in mine)
            finite = np.isfinite(error_mm)
            finite_errors.extend(error_mm[finite])
            axes.errorbar(cost[finite], error_mm[finite],
                          xerr=[np.maximum(cost - low, 0)[finite], np.maximum(high - cost, 0)[finite]],
                          fmt="o", ms=5, color=colour, alpha=0.45, elinewidth=1, capsize=0, zorder=2)
            blow_ups.extend((x, colour) for x in cost[~finite])
            front = sorted((r for r in mine if c["on_front"][r]), key=lambda r: c["front_rank"][r])
            front = [r for r in front if math.isfinite(c["primary_error"][r])]
            if front:
                xs = [c["ms_per_simulated_s"][r] for r in front]
                ys = [c["primary_error"][r] * 1e3 for r in front]
                axes.plot(xs, ys, drawstyle="steps-post", color=colour, lw=2, zorder=3,
                          label=f"{engine} front ({_knob_names(table, engine)})")
                axes.plot(xs, ys, "o", ms=6.5, color=colour, zorder=4)
                for r, x, y in zip(front, xs, ys):
                    axes.annotate(_knob_label(table, r, engine), (x, y), textcoords="offset points",
                                  xytext=(5, 4), fontsize=8, color=colour)
            for r in mine:
                if c["is_default"][r] and math.isfinite(c["primary_error"][r]):
                    axes.plot(c["ms_per_simulated_s"][r], c["primary_error"][r] * 1e3, marker="*", ms=17,
                              color=colour, markeredgecolor="black", markeredgewidth=1.1, zorder=5, linestyle="none")
    positive = [e for e in finite_errors if e > 0]
    if len(positive) < len(finite_errors):
        axes.set_yscale("symlog", linthresh=min(positive) if positive else 1e-3)
    else:
        axes.set_yscale("log")
    axes.set_xscale("log")
    _plain_log_ticks(axes.xaxis)
    if axes.get_yscale() == "log":
        _plain_log_ticks(axes.yaxis)
    if blow_ups:
        top = max(finite_errors) * 3 if finite_errors else 1.0
        for x, colour in blow_ups:
            axes.plot(x, top, marker="X", ms=10, color=colour, linestyle="none", zorder=5)
        axes.annotate("× blew up (NaN)", (0.99, top), xycoords=("axes fraction", "data"), ha="right", va="bottom",
                      fontsize=8.5, color="#444")
    axes.plot([], [], marker="*", ms=14, color="white", markeredgecolor="black", linestyle="none",
              label="default settings")
    axes.plot([], [], "o", ms=5, color="#999", alpha=0.5, label="other settings (bar: 95% CI)")
    metric = metric_names.pop() if len(metric_names) == 1 else "primary error"
    axes.set_title(f"{scene} ({bodies} bodies): speed against accuracy")
    axes.set_xlabel("cost: wall ms per simulated second (log scale; lower is faster)")
    axes.set_ylabel(f"worst {metric} (mm, log scale; lower is better)")
    axes.grid(True, which="both", color="#eeeeee")
    axes.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
    return _save(figure, out_dir, _slug("speed_accuracy", scene, bodies))


# --- phase split ----------------------------------------------------------------------------------

REMAINDER = "other (not in a phase)"


def _segments(run):
    """(name, ms) of a run's bar: its phases and what the step spent outside them, or its total."""
    if not run.phases:
        return [("total", run.ms_median)]
    segments = list(run.phases)
    remainder = run.ms_median - sum(ms for _, ms in segments)
    if remainder > 0.02 * run.ms_median:
        segments.append((REMAINDER, remainder))
    return segments


def _phase_colours(engine, names):
    cmap = plt.get_cmap(_ENGINE_PHASE_MAPS.get(engine, "Greys"))
    named = [n for n in names if n != REMAINDER]
    if len(named) == 1:
        colours = {named[0]: engine_colour(engine)}
    else:
        colours = {n: cmap(0.3 + 0.65 * i / max(len(named) - 1, 1)) for i, n in enumerate(named)}
    colours[REMAINDER] = "#d9d9d9"
    return colours


def phase_split(runs, bar_label, out_dir):
    """One panel per engine, one stacked bar per scene run: median ms per step in each phase."""
    engines = list(dict.fromkeys(run.engine for run in runs))
    if not engines:
        return None
    heights = [0.9 + 0.48 * sum(1 for r in runs if r.engine == e) for e in engines]
    figure, panels = plt.subplots(len(engines), 1, figsize=(10, 1.3 + sum(heights)),
                                  gridspec_kw={"height_ratios": heights}, squeeze=False)
    widest = max(run.ms_median for run in runs)
    for axes, engine in zip(panels[:, 0], engines):
        mine = [r for r in runs if r.engine == engine]
        names = list(dict.fromkeys(name for r in mine for name, _ in _segments(r)))
        colours = _phase_colours(engine, names)
        for y, run in enumerate(mine):
            left = 0.0
            for name, ms in _segments(run):
                axes.barh(y, ms, left=left, height=0.62, color=colours[name], edgecolor="white", linewidth=0.8,
                          hatch="//" if name == REMAINDER else None)
                if ms > 0.14 * widest and name != REMAINDER:
                    dark = sum(mcolors.to_rgb(colours[name])) < 1.6
                    axes.text(left + ms / 2, y, name, ha="center", va="center", fontsize=8.5,
                              color="white" if dark else "#1d2330")
                left += ms
            axes.text(left + widest * 0.01, y, f"{run.ms_median:.3g} ms", va="center", fontsize=9)
        axes.set_yticks(range(len(mine)), [bar_label(r) for r in mine])
        axes.invert_yaxis()
        axes.set_xlim(0, widest * 1.13)
        axes.grid(axis="y", visible=False)
        axes.set_title(engine, loc="left", color=engine_colour(engine))
        handles = [patches.Patch(facecolor=colours[n], hatch="//" if n == REMAINDER else None,
                                            edgecolor="white", label=n) for n in names]
        axes.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False,
                    title="phase", title_fontsize=9.5)
    panels[-1, 0].set_xlabel("median wall time per step (ms), split by the engine's own phases")
    figure.suptitle("Where each step's time goes", fontweight="bold", fontsize=14, x=0.02, ha="left")
    figure.tight_layout()
    return _save(figure, out_dir, "phase_split")


# --- scaling with workers -------------------------------------------------------------------------

def speedup(series, out_dir):
    """Speedup against workers, one line per engine, scene, size and setting (report_data's
    worker_scaling), with the ideal line speedup = workers."""
    if not series:
        return None
    figure, axes = plt.subplots(figsize=(7.6, 5.2))
    most = max(max(s["workers"]) for s in series)
    axes.plot([1, most], [1, most], "--", color="#999", lw=1.2, label="ideal (speedup = workers)")
    for s, style in _engine_line_styles(series):
        label = f"{s['engine']} · {s['scene']} · {s['bodies']}" + (f" · {s['setting']}" if s["setting"] else "")
        colour = engine_colour(s["engine"])
        axes.plot(s["workers"], s["speedup"], style, marker="o", ms=5, color=colour, lw=1.8, label=label)
        # Each point's 95% interval, where its rounds were paired with the 1-worker point's.
        bars = [(w, v, v - low, high - v) for w, v, low, high in
                zip(s["workers"], s["speedup"], s["speedup_low"], s["speedup_high"]) if math.isfinite(low)]
        if bars:
            workers, values, below, above = zip(*bars)
            axes.errorbar(workers, values, yerr=[below, above], fmt="none", ecolor=colour, elinewidth=1.2, capsize=3)
    axes.xaxis.set_major_locator(ticker.MaxNLocator(integer=True))
    axes.set_xlim(0.8, most + 0.2)
    axes.set_ylim(0, max(most, max((v for s in series for v in s["speedup"] if math.isfinite(v)), default=0)) * 1.08)
    axes.set_title("Speedup against workers")
    axes.set_xlabel("workers (threads a step may use)")
    axes.set_ylabel("speedup: ms/step at 1 worker / at k")
    axes.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=1, frameon=False)
    return _save(figure, out_dir, "speedup_workers")


# --- A/B comparison -------------------------------------------------------------------------------

def ab_forest(report, rows, row_label, out_dir, name):
    """Each compared metric's ratio B/A with its interval around 1 and the noise band: colour is the
    speed verdict, marker shape the accuracy verdict."""
    if not rows:
        return None
    figure, axes = plt.subplots(figsize=(9.5, 1.4 + 0.34 * len(rows)))
    noise = float(report.get("noise", 0.0))
    axes.axvspan(1 - noise, 1 + noise, color="#f1f1f1", zorder=0)
    axes.axvline(1.0, color="#555", lw=1, zorder=1)
    group_of = [(r["engine"], r["against"], r["scene"], r["bodies"]) for r in rows]
    for y in range(len(rows)):
        if y > 0 and group_of[y] != group_of[y - 1]:
            axes.axhline(y - 0.5, color="#cccccc", lw=0.8)
    for y, row in enumerate(rows):
        colour = SPEED_COLOURS.get(row["speed"], "#555")
        accuracy = row["verdict"].partition(", ")[2]
        axes.errorbar(row["ratio"], y, xerr=[[row["ratio"] - row["ci_low"]], [row["ci_high"] - row["ratio"]]],
                      fmt=ACCURACY_MARKERS.get(accuracy, "o"), color=colour, ms=7, capsize=3, lw=1.6, zorder=3)
    axes.set_yticks(range(len(rows)), [row_label(r) for r in rows], fontsize=9)
    axes.invert_yaxis()
    axes.set_xscale("log")
    bounds = [bound for r in rows for bound in (r["ci_low"], r["ci_high"]) if bound > 0]
    span = max(max((abs(math.log(b)) for b in bounds), default=0.0) * 1.15, math.log(1 + 2 * noise), 0.02)
    low, high = math.exp(-span), math.exp(span)
    axes.set_xlim(low, high)
    ticks = [t for t in ticker.MaxNLocator(7).tick_values(low, high) if low <= t <= high]
    axes.set_xticks(ticks, [f"{t:.3g}" for t in ticks])
    axes.xaxis.set_minor_locator(ticker.NullLocator())
    speeds = dict.fromkeys(row["speed"] for row in rows)
    accuracies = dict.fromkeys(row["verdict"].partition(", ")[2] for row in rows)
    handles = [patches.Patch(color="#f1f1f1", label=f"noise band ±{noise:.0%}")]
    handles += [lines.Line2D([], [], marker="o", color=SPEED_COLOURS.get(s, "#555"), ls="none", label=s) for s in speeds]
    handles += [lines.Line2D([], [], marker=ACCURACY_MARKERS.get(a, "o"), color="#555", ls="none",
                             label=a or "same accuracy") for a in accuracies if len(accuracies) > 1 or a]
    axes.grid(axis="y", visible=False)
    against = "engine / reference engine" if report.get("mode") == "cross-engine" else "B / A"
    axes.set_xlabel(f"time ratio {against} with 95% CI (log scale; < 1 is faster)")
    axes.set_title(report.get("headline", "A/B comparison"), loc="left")
    axes.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False, title="verdict")
    return _save(figure, out_dir, name)


# --- stability ------------------------------------------------------------------------------------

def stability_heatmap(rows, tests, cells, out_dir):
    """Rows are engine/setting, columns tests; cells[(row, test)] = (score 0..1, text), the score the
    boundary's place in the test's searched range (1: held to the hardest value tried)."""
    figure, axes = plt.subplots(figsize=(2.5 + 1.5 * len(tests), 2.0 + 0.75 * len(rows)))
    scores = np.full((len(rows), len(tests)), np.nan)
    for i, row in enumerate(rows):
        for j, test in enumerate(tests):
            if (row, test) in cells:
                scores[i, j] = cells[(row, test)][0]
    cmap = plt.get_cmap("RdYlGn").copy()
    cmap.set_bad("#f4f4f4")
    image = axes.imshow(np.ma.masked_invalid(scores), cmap=cmap, vmin=0.0, vmax=1.0, aspect="auto")
    for i, row in enumerate(rows):
        for j, test in enumerate(tests):
            text = cells[(row, test)][1] if (row, test) in cells else "not run"
            score = scores[i, j]
            dark = not np.isnan(score) and (score < 0.2 or score > 0.85)
            axes.text(j, i, text, ha="center", va="center", fontsize=8.5, color="white" if dark else "#222")
    axes.set_xticks(range(len(tests)), [t[1] for t in tests], fontsize=9)
    axes.set_yticks(range(len(rows)), [r[1] for r in rows], fontsize=9)
    for label, row in zip(axes.get_yticklabels(), rows):
        label.set_color(engine_colour(row[0]))
    axes.tick_params(axis="x", top=True, labeltop=True, bottom=False, labelbottom=False)
    axes.grid(False)
    for spine in axes.spines.values():
        spine.set_visible(False)
    bar = figure.colorbar(image, ax=axes, fraction=0.035, pad=0.02)
    bar.set_label("boundary in the searched range\n(0 easiest, 1 hardest value)")
    axes.set_title("Stability: where each solver first fails", loc="left", pad=34)
    return _save(figure, out_dir, "stability_heatmap")


# --- nightly history ------------------------------------------------------------------------------

def history_trend(series, metric, label, out_dir):
    """series: [{label, engine, metric, x, candidate, baseline, accepted: [night index],
    steps: [(night index, slower?)]}], one line per engine, scene and size; one metric per chart."""
    if not series:
        return None
    figure, axes = plt.subplots(figsize=(10, 4.8))
    for s, style in _engine_line_styles(series):
        colour = engine_colour(s["engine"])
        xs, ys = s["x"], s["candidate"]
        axes.plot(xs, ys, style, marker="o", ms=3.5, color=colour, lw=1.6, label=s["label"])
        axes.plot(xs, s["baseline"], color=colour, lw=1, alpha=0.5, drawstyle="steps-post")
        if s["accepted"]:
            axes.plot([xs[i] for i in s["accepted"]], [ys[i] for i in s["accepted"]], "*", ms=15, color=colour,
                      markeredgecolor="black", linestyle="none", zorder=5)
        for i, slower in s["steps"]:
            axes.plot(xs[i], ys[i], "^" if slower else "v", ms=11, color="#c0392b" if slower else "#2a9d5c",
                      markeredgecolor="black", linestyle="none", zorder=6)
    axes.plot([], [], color="#888", lw=1, alpha=0.6, label="baseline judged against")
    axes.plot([], [], "*", ms=12, color="#888", markeredgecolor="black", linestyle="none", label="accepted as baseline")
    axes.plot([], [], "^", ms=9, color="#c0392b", markeredgecolor="black", linestyle="none", label="step: slower")
    axes.plot([], [], "v", ms=9, color="#2a9d5c", markeredgecolor="black", linestyle="none", label="step: faster")
    unit = "instructions per step" if metric == "instructions_per_step" else "median wall ms per step"
    axes.set_xlabel("night (date of the gate, UTC)")
    axes.set_ylabel(f"candidate's {unit}")
    axes.set_title(f"Nightly history: {metric}", loc="left")
    axes.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    figure.autofmt_xdate()
    return _save(figure, out_dir, _slug("history", label, metric))


def lighten(colour, amount):
    """`colour` mixed with white; for table chips and row tints on the page."""
    r, g, b = mcolors.to_rgb(colour)
    return mcolors.to_hex((r + (1 - r) * amount, g + (1 - g) * amount, b + (1 - b) * amount))
