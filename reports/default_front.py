#!/usr/bin/python3
"""Where Fx2D's default solver settings stand on each canonical scene's speed-accuracy front.

    /usr/bin/python3 reports/default_front.py [--bench PATH] [--scenes pile:300,600 ...]
        [--substeps 2,4,8,14] [--passes 1,2,4] [--relax 1,2,4] [--steps N] [--repeats N]
        [--candidate 8x1r2 ...] [--perturbations K]

For every scene and size, runs `fx2d-bench sweep --engine fx2d --json` over substeps, velocity
passes and relaxation passes, and prints one line per cell: the default's cost and error, its
place on the front, and every point that beats it on both counts beyond noise, that is, whose
error is lower and whose 95% interval of ms/step lies wholly below the default's. A default
with no such point is on its front. Exit status: 0 when every default is on its front, 1 when
one is beaten, 2 for bad arguments or a sweep that failed. Each --candidate (substeps x passes r
relaxation passes, all within the grid) is printed beside the default, to judge a new default.

A peak error such as max penetration is chaotic: gravity changed in its sixth digit moves it by
a factor of two on the larger scenes. So each point's error is the median over K runs (default 5):
the scene as it is, and with its gravity scaled by 1 + i * 1e-6 for i = 1 .. K-1 (accuracy only,
one repeat each); the speed is the scene's own sweep's.
"""

import argparse
import json
import pathlib
import statistics
import subprocess
import sys

SCENES_DIR = pathlib.Path(__file__).resolve().parent.parent / "scenes"
GRAVITY_STEP = 1e-6  # relative change of gravity between the runs whose errors are pooled

CANONICAL_SIZES = {"stacks": [50, 200, 600], "pile": [300, 600, 1200], "settling_boxes": [200, 800, 3000]}


def parse_scenes(texts):
    """`name:n1,n2` items (a bare name takes its canonical sizes) as (scene, size) pairs."""
    cells = []
    for text in texts:
        name, _, sizes = text.partition(":")
        if name not in CANONICAL_SIZES:
            raise ValueError(f"--scenes: unknown scene '{name}', expected one of {', '.join(CANONICAL_SIZES)}")
        cells += [(name, int(size)) for size in sizes.split(",")] if sizes else [(name, n) for n in CANONICAL_SIZES[name]]
    return cells


def sweep(args, scene, bodies, repeats, extra=()):
    command = [args.bench, "sweep", scene, "--bodies", str(bodies), "--engine", "fx2d", "--json",
               "--fx2d-substeps", args.substeps, "--fx2d-passes", args.passes, "--fx2d-relax", args.relax,
               "--repeats", str(repeats), *extra]
    if args.steps:
        command += ["--steps", str(args.steps)]
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)}: exit {done.returncode}: {done.stderr.strip()}")
    return json.loads(done.stdout)["points"]


def key(point):
    s = point["settings"]
    return s["substeps"], s["velocity_passes"], s.get("relax_passes")


def pooled_sweep(args, scene, bodies):
    """The sweep's points, each with its primary error replaced by the median over the perturbed runs."""
    points = sweep(args, scene, bodies, args.repeats)
    gravity = json.loads((SCENES_DIR / f"{scene}.json").read_text())["gravity"]
    errors = {key(p): [p["primary_error"]] for p in points}
    for i in range(1, args.perturbations):
        scaled = [g * (1.0 + i * GRAVITY_STEP) for g in gravity]
        for p in sweep(args, scene, bodies, 1, ("--set", f"/gravity={json.dumps(scaled)}")):
            errors[key(p)].append(p["primary_error"])
    for p in points:
        runs = errors[key(p)]
        p["primary_error"] = None if None in runs else statistics.median(runs)
    return points


def label(point):
    s = point["settings"]
    return f"{s['substeps']}x{s['velocity_passes']} relax {s.get('relax_passes', 'default')}"


def error(point):
    return float("inf") if point["primary_error"] is None else point["primary_error"]


def beats(point, default):
    """Faster beyond both intervals and strictly more accurate."""
    return point["ms_per_step"]["ci_high"] < default["ms_per_step"]["ci_low"] and error(point) < error(default)


def settings_of(candidate):
    """`8x1r2` as (substeps, velocity passes, relaxation passes)."""
    substeps, _, rest = candidate.partition("x")
    passes, _, relax = rest.partition("r")
    try:
        return int(substeps), int(passes), int(relax)
    except ValueError:
        raise ValueError(f"--candidate: expected SUBSTEPSxPASSESrRELAX such as 8x1r2, got '{candidate}'") from None


def find(points, settings):
    for p in points:
        if key(p) == settings:
            return p
    raise ValueError(f"--candidate {settings} is not in the swept grid")


def describe(scene, bodies, points, candidates, runs):
    default = next(p for p in points if p["default"])
    better = sorted((p for p in points if beats(p, default)), key=lambda p: p["ms_per_step"]["median"])
    head = (f"{scene} {bodies}: default {label(default)} {default['ms_per_step']['median']:.4f} ms/step "
            f"[{default['ms_per_step']['ci_low']:.4f}, {default['ms_per_step']['ci_high']:.4f}], "
            f"{default['primary_metric']} {1000 * error(default):.2f} mm (median of {runs} runs)")
    lines = [head + ("; nothing beats it beyond noise" if not better else f"; beaten beyond noise by {len(better)}:")]
    for p in better:
        lines.append(f"    {label(p)}: {p['ms_per_step']['median']:.4f} ms/step "
                     f"({p['ms_per_step']['median'] / default['ms_per_step']['median']:.2f}x), "
                     f"{1000 * error(p):.2f} mm")
    for candidate in candidates:
        p = find(points, settings_of(candidate))
        beaters = [label(q) for q in points if beats(q, p)]
        lines.append(f"    candidate {label(p)}: {p['ms_per_step']['median']:.4f} ms/step "
                     f"({p['ms_per_step']['median'] / default['ms_per_step']['median']:.2f}x), "
                     f"{1000 * error(p):.2f} mm, beaten beyond noise by {len(beaters)}"
                     + (f" ({', '.join(beaters)})" if beaters else ""))
    return lines, bool(better)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bench", default="build/release/harness/fx2d-bench", help="the fx2d-bench to run")
    parser.add_argument("--scenes", nargs="+", default=list(CANONICAL_SIZES), help="name or name:n1,n2")
    parser.add_argument("--substeps", default="2,4,8,14")
    parser.add_argument("--passes", default="1,2,4")
    parser.add_argument("--relax", default="1,2,4")
    parser.add_argument("--steps", type=int, default=0, help="steps per repeat (default: the scene's)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--candidate", action="append", default=[], help="e.g. 8x1r2: printed beside the default")
    parser.add_argument("--perturbations", type=int, default=5, help="runs whose errors are pooled per point")
    args = parser.parse_args()
    try:
        cells = parse_scenes(args.scenes)
        beaten = False
        for scene, bodies in cells:
            lines, off = describe(scene, bodies, pooled_sweep(args, scene, bodies), args.candidate, args.perturbations)
            beaten |= off
            print("\n".join(lines), flush=True)
    except (ValueError, RuntimeError, OSError) as failure:
        print(f"default_front.py: {failure}", file=sys.stderr)
        return 2
    return 1 if beaten else 0


if __name__ == "__main__":
    sys.exit(main())
