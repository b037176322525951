"""Reads every file fx2d-bench writes into plain Python records for the report.

Invariant: the aggregates here follow the harness's own rules (harness/analysis/summary.h), so a number on
the page is the number `fx2d-bench run` prints: a repeat's figure is its mean per step, medians
and extremes are across repeats, accuracy is the worst over the sampled steps of the first repeat
(kinetic energy: the last sample). A file's runs are "runs" in the report only when the file is a
plain run file; the runs inside a sweep or stability file are the raw material of those tables
and are shown through them. Nothing here draws or writes.
"""

from dataclasses import dataclass, field
import json

import h5py
import numpy as np

RESULTS_SCHEMA = "fx2d-bench.results/1"
COMPARE_SCHEMA = "fx2d-bench.compare/1"
HISTORY_SCHEMA_PREFIX = "fx2d-bench.history/"

PROVENANCE_FIELDS = ("fx2d_version", "fx2d_git_revision", "build_type", "build_flags", "compiler",
                     "cpu_model", "kernel", "hostname", "date_utc", "command_line")


ROUND_TRIP_FIELDS = ("core_round_trip_ns_start", "core_round_trip_ns_end")


class InputProblem(Exception):
    """A file the report cannot take; the message is one line, fit to print as is."""


@dataclass
class Run:
    source: str            # the file's label on the page
    engine: str
    engine_version: str
    settings: str
    scene: str
    bodies: int
    steps: int
    repeats: int
    ms_median: float
    ms_min: float
    ms_max: float
    phases: list           # [(name, median ms per step)], the engine's order; empty for none
    worst: dict            # accuracy field -> worst value
    primary_metric: str
    state_hash: str
    deterministic: bool
    repeat_ms: list = field(default_factory=list)        # each repeat's mean wall ms per step
    phase_repeat_ms: dict = field(default_factory=dict)  # phase -> each repeat's mean ms per step


@dataclass
class Table:
    """A group of equal-length column datasets, as harness/storage/h5_tables.h writes them."""
    attributes: dict
    columns: dict          # name -> numpy array (strings decoded)
    units: dict            # name -> units string

    def __len__(self):
        return len(next(iter(self.columns.values()))) if self.columns else 0

    def get(self, *names, default=None):
        """The first column present among `names`, else `default`."""
        for name in names:
            if name in self.columns:
                return self.columns[name]
        return default


@dataclass
class InputFile:
    path: str
    label: str
    schema: str
    provenance: dict
    runs: list = field(default_factory=list)
    sweep: Table = None
    sweep_runs: list = field(default_factory=list)  # a sweep's /runs/k by k: each point's phases
    stability: dict = field(default_factory=dict)   # table name -> Table, "" for /stability itself
    history: Table = None  # the nightly history (/history), read by its documented columns
    # The cross-core round trip as the measurement began and ended, ns (RESULTS_FORMAT.md); None when
    # the file does not say (written before it was recorded, or on one hardware thread).
    core_round_trip_ns: tuple = None


def _text(value):
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.ndarray) and value.shape == ():
        return _text(value[()])
    return str(value)


def _per_repeat_means(samples, repeats, steps):
    """Each repeat's mean per step of an [R x S] (or flat R*S) array."""
    return np.asarray(samples, dtype=float).reshape(repeats, steps).mean(axis=1)


def _worst(accuracy):
    if accuracy is None or len(accuracy) == 0:
        return {}
    worst = {name: float(np.max(accuracy[name])) for name in accuracy.dtype.names if name != "step"}
    worst["kinetic_energy"] = float(accuracy["kinetic_energy"][-1])
    return worst


def _read_run(group, label, primary_metrics):
    attrs = group.attrs
    repeats, steps = int(attrs["repeats"]), int(attrs["steps"])
    repeat_ms = _per_repeat_means(group["wall_ms"][()], repeats, steps)
    phases, phase_repeat_ms = [], {}
    if "phase_ms" in group:
        names = [_text(name) for name in group["phase_ms"].attrs["phase_names"]]
        phase_ms = np.asarray(group["phase_ms"][()], dtype=float).reshape(repeats, steps, len(names))
        phase_repeat_ms = {name: phase_ms[:, :, p].mean(axis=1) for p, name in enumerate(names)}
        phases = [(name, float(np.median(means))) for name, means in phase_repeat_ms.items()]
    scene_hash = _text(attrs["scene_hash"])
    return Run(
        source=label,
        engine=_text(attrs["engine"]),
        engine_version=_text(attrs["engine_version"]),
        settings=_text(attrs["engine_settings"]),
        scene=_text(attrs["scene"]),
        bodies=int(attrs["bodies"]),
        steps=steps,
        repeats=repeats,
        ms_median=float(np.median(repeat_ms)),
        ms_min=float(np.min(repeat_ms)),
        ms_max=float(np.max(repeat_ms)),
        phases=phases,
        worst=_worst(group["accuracy"][()] if "accuracy" in group else None),
        primary_metric=primary_metrics.get(scene_hash, ""),
        state_hash=_text(attrs["final_state_hash"]),
        deterministic=bool(attrs["deterministic"]),
        repeat_ms=repeat_ms,
        phase_repeat_ms=phase_repeat_ms,
    )


def _numbered(group):
    """The members of a numbered group (/runs, /scenes) in their order."""
    return [group[key] for key in sorted(group.keys(), key=int)]


def _read_table(group):
    columns, units = {}, {}
    for name, dataset in group.items():
        if not isinstance(dataset, h5py.Dataset) or dataset.ndim != 1:
            continue
        if h5py.check_string_dtype(dataset.dtype) is not None:
            columns[name] = np.array(dataset.asstr()[()], dtype=object)
        else:
            columns[name] = dataset[()]
        units[name] = _text(dataset.attrs.get("units", ""))
    lengths = {len(values) for values in columns.values()}
    if len(lengths) > 1:
        raise InputProblem(f"{group.file.filename}: {group.name}: columns differ in length")
    return Table({key: _text(value) if not np.isscalar(value) or isinstance(value, (bytes, str)) else value
                  for key, value in group.attrs.items()}, columns, units)


def _read_tables(group):
    """The table at `group` itself (key "") and at each subgroup (key: its name)."""
    tables = {}
    if any(isinstance(member, h5py.Dataset) for member in group.values()):
        tables[""] = _read_table(group)
    for name, member in group.items():
        if isinstance(member, h5py.Group):
            tables[name] = _read_table(member)
    return tables


# The /history columns (harness/RESULTS_FORMAT.md, "The nightly history file"), each one row per
# gating metric per night.
HISTORY_COLUMNS = ("date_utc", "candidate", "baseline", "engine", "scene", "bodies", "metric", "a", "b", "ratio",
                   "ci_low", "ci_high", "p_value", "verdict", "step_detected", "accepted")


def _read_history(group):
    table = _read_table(group)
    missing = [name for name in HISTORY_COLUMNS if name not in table.columns]
    if missing:
        raise InputProblem(f"{group.file.filename}: /history: missing columns {', '.join(missing)} "
                           "(expected the fx2d-bench.history/1 layout)")
    return table


def read_h5(path, label):
    """One file of any kind fx2d-bench writes. Raises InputProblem."""
    try:
        with h5py.File(path, "r") as f:
            schema = _text(f.attrs.get("schema", ""))
            if schema != RESULTS_SCHEMA and not schema.startswith(HISTORY_SCHEMA_PREFIX):
                raise InputProblem(f"{path}: schema '{schema}' is not one the report reads "
                                   f"(expected {RESULTS_SCHEMA} or {HISTORY_SCHEMA_PREFIX}N)")
            provenance = {name: _text(f.attrs[name]) for name in PROVENANCE_FIELDS if name in f.attrs}
            loaded = InputFile(path, label, schema, provenance)
            round_trip = tuple(float(f.attrs.get(name, 0.0)) for name in ROUND_TRIP_FIELDS)
            loaded.core_round_trip_ns = round_trip if min(round_trip) > 0 else None
            if "sweep" in f:
                loaded.sweep = _read_table(f["sweep"])
            if "stability" in f:
                loaded.stability = _read_tables(f["stability"])
            if "history" in f:
                loaded.history = _read_history(f["history"])
            plain_run_file = loaded.sweep is None and not loaded.stability and loaded.history is None
            if (plain_run_file or loaded.sweep is not None) and "runs" in f:
                primary = {_text(s.attrs["hash"]): _text(s.attrs["primary_metric"]) for s in _numbered(f["scenes"])}
                runs = [_read_run(run, label, primary) for run in _numbered(f["runs"])]
                if plain_run_file:
                    loaded.runs = runs
                else:
                    loaded.sweep_runs = runs
            return loaded
    except OSError as error:
        raise InputProblem(f"{path}: cannot read as HDF5: {error}") from None
    except KeyError as error:
        raise InputProblem(f"{path}: missing member {error}") from None


# The bootstrap intervals the report works out: compare's resample count and seed, so a re-render
# draws the same resamples.
BOOTSTRAP_RESAMPLES = 2000
BOOTSTRAP_SEED = 0x6678326462656E63


# --- scaling with workers (a sweep over an engine's thread count) ----------------------------------

# The knob names that count an engine's threads: Fx2D's `workers`, Chipmunk2D's `threads`.
WORKER_KNOBS = ("workers", "threads")


def _worker_column(sweep, engine, rows):
    """The engine's thread-count column when the sweep varied it over these rows, else None."""
    for knob in WORKER_KNOBS:
        name = f"{engine}_{knob}"
        if name in sweep.columns and len({int(sweep.columns[name][r]) for r in rows}) > 1:
            return name
    return None


def _paired_speedup(one_worker, k_workers, rng):
    """The median over rounds r of one_worker[r] / k_workers[r], with a 95% percentile bootstrap
    interval that resamples the rounds (the sweep's cost_vs_default, sweep_grid.h, turned over)."""
    ratios = np.asarray(one_worker, dtype=float) / np.asarray(k_workers, dtype=float)
    resampled = np.median(rng.choice(ratios, size=(BOOTSTRAP_RESAMPLES, len(ratios))), axis=1)
    return float(np.median(ratios)), float(np.percentile(resampled, 2.5)), float(np.percentile(resampled, 97.5))


def worker_scaling(sweep, sweep_runs):
    """One series per engine, scene, size and setting of the other knobs of a sweep whose points
    differ in a thread-count knob: workers ascending, each point's median ms/step, its speedup over
    the series' 1-worker point with a 95% interval, and its phase split (the point's run's
    [(phase, median ms)], empty for an engine that reports none).
    The points of one engine on one scene take their repeats in rounds, one repeat of each per pass,
    so round r of the 1-worker point and of the k-worker point ran in the same pass: the speedup is
    the median of the rounds' ratios, as `sweep`'s cost against its default, and the drift of the
    machine cancels in each. A merged file's points may come from shards that ran apart, so there
    (and for points with other round counts) it is the ratio of the medians, with no interval.
    NaN without a 1-worker point."""
    c = sweep.columns
    paired = "merged_shards" not in sweep.attributes
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    series = {}
    for engine in dict.fromkeys(c["engine"]):
        mine = [r for r in range(len(sweep)) if c["engine"][r] == engine]
        column = _worker_column(sweep, engine, mine)
        if column is None:
            continue
        others = [name for name in c if name.startswith(engine + "_") and name != column]
        for r in mine:
            setting = ", ".join(f"{name[len(engine) + 1:]} {int(c[name][r])}" for name in others if c[name][r] >= 0)
            key = (engine, c["scene"][r], int(c["bodies"][r]), setting, float(c["dt"][r]))
            entry = series.setdefault(key, {"engine": engine, "scene": c["scene"][r], "bodies": int(c["bodies"][r]),
                                            "setting": setting, "knob": column[len(engine) + 1:], "points": []})
            run = sweep_runs[int(c["run"][r])] if int(c["run"][r]) < len(sweep_runs) else None
            entry["points"].append((int(c[column][r]), float(c["ms_per_step"][r]), run))
    for entry in series.values():
        entry["points"].sort(key=lambda point: point[0])
        one = [(ms, run) for workers, ms, run in entry["points"] if workers == 1]
        entry["workers"] = [workers for workers, _, _ in entry["points"]]
        entry["ms"] = [ms for _, ms, _ in entry["points"]]
        entry["speedup"], entry["speedup_low"], entry["speedup_high"] = [], [], []
        for _, ms, run in entry["points"]:
            if not one or ms <= 0:
                speedup = (float("nan"),) * 3
            elif paired and run and one[0][1] and len(run.repeat_ms) == len(one[0][1].repeat_ms) > 0:
                speedup = _paired_speedup(one[0][1].repeat_ms, run.repeat_ms, rng)
            else:
                speedup = (one[0][0] / ms, float("nan"), float("nan"))
            for name, value in zip(("speedup", "speedup_low", "speedup_high"), speedup):
                entry[name].append(value)
        entry["phases"] = [run.phases if run else [] for _, _, run in entry.pop("points")]
    # The scene's default setting, measured at its own worker count alone, is no series.
    return [entry for entry in series.values() if len(entry["workers"]) > 1]


# --- A/B inside one run file (`fx2d-bench ab --out`: engines X@A and X@B) ----------------------------

AB_NOISE = 0.02            # compare's default band: ratios within 1 +- 2% are no change


def _bootstrap_ratio(a, b, rng):
    """Ratio of medians b/a with a 95% percentile bootstrap interval (compare's method, numpy's
    generator: the interval is close to compare's, not identical)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    resampled_a = np.median(rng.choice(a, size=(BOOTSTRAP_RESAMPLES, len(a))), axis=1)
    resampled_b = np.median(rng.choice(b, size=(BOOTSTRAP_RESAMPLES, len(b))), axis=1)
    ratios = resampled_b / resampled_a
    return float(np.median(b) / np.median(a)), float(np.percentile(ratios, 2.5)), float(np.percentile(ratios, 97.5))


def _interval_speed(low, high):
    """The interval half of compare's two-stage verdict; the report has no rank test."""
    if 1 - AB_NOISE <= low and high <= 1 + AB_NOISE:
        return "no change"
    if low > 1 + AB_NOISE:
        return "slower"
    if high < 1 - AB_NOISE:
        return "faster"
    return "inconclusive"


def ab_rows(runs):
    """Rows shaped like compare's (engine, against, scene, bodies, metric, a, b, ratio, ci_low,
    ci_high, speed, verdict) for every (engine, scene, bodies) run as both X@A and X@B in one file:
    the step time and each phase, B against A."""
    by_key = {(r.source, r.engine, r.scene, r.bodies): r for r in runs}
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    rows = []
    for (source, engine, scene, bodies), run_a in by_key.items():
        base, _, side = engine.rpartition("@")
        run_b = by_key.get((source, f"{base}@B", scene, bodies))
        if side != "A" or run_b is None or len(run_a.repeat_ms) == 0 or len(run_b.repeat_ms) == 0:
            continue
        metrics = [("ms_per_step", run_a.repeat_ms, run_b.repeat_ms)]
        metrics += [(f"phase:{name}", means, run_b.phase_repeat_ms[name])
                    for name, means in run_a.phase_repeat_ms.items() if name in run_b.phase_repeat_ms]
        for metric, a, b in metrics:
            if np.min(a) <= 0 or np.min(b) <= 0:
                continue  # a phase that measured nothing has no ratio
            ratio, low, high = _bootstrap_ratio(a, b, rng)
            speed = _interval_speed(low, high)
            rows.append({"source": source, "engine": base, "against": base, "scene": scene, "bodies": bodies,
                         "metric": metric, "a": float(np.median(a)), "b": float(np.median(b)), "ratio": ratio,
                         "ci_low": low, "ci_high": high, "speed": speed, "verdict": speed})
    return rows


def read_compare_json(path):
    """The JSON `fx2d-bench compare --json` prints. Raises InputProblem."""
    try:
        with open(path, encoding="utf-8") as stream:
            report = json.load(stream)
    except (OSError, ValueError) as error:
        raise InputProblem(f"{path}: cannot read compare JSON: {error}") from None
    if not isinstance(report, dict) or report.get("schema") != COMPARE_SCHEMA:
        raise InputProblem(f"{path}: expected a {COMPARE_SCHEMA} object (fx2d-bench compare --json)")
    return report


def unique_labels(paths):
    """Short names for the files: the base name, or as much of the path as tells them apart."""
    parts = [path.split("/") for path in paths]
    depth = 1
    while depth < max(len(p) for p in parts):
        labels = ["/".join(p[-depth:]) for p in parts]
        if len(set(labels)) == len(labels):
            return labels
        depth += 1
    return ["/".join(p) for p in parts]
