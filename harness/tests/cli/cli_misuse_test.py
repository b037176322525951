#!/usr/bin/python3
"""fx2d-bench's contract with a user who gets it wrong: every misuse below, of every subcommand,
ends in one line on stderr and exit code 2 (or the documented code), within a time bound, and none
in exit code 4, which is kept for real internal errors. Then the behaviours that used to fail after
measuring: a scene an engine cannot build, a plugin's recorded settings, sweep's default point.

Usage: cli_misuse_test.py FX2D_BENCH PLUGIN SOURCE_DIR
(ab, gate and history have misuse tests of their own beside their commands; the rows here for
gate and report are the input-size limits, which every whole-file read shares.)
"""
import functools
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass

BENCH, PLUGIN, SOURCE = (os.path.abspath(argument) for argument in sys.argv[1:4])
# A misuse is refused before anything is measured: well within this, even on a busy 2-core machine.
REFUSAL_SECONDS = 5.0
# /dev/zero, a pipe without end and a sparse file must be refused after the 16 MiB they may read.
INPUT_LIMIT_SECONDS = 1.0
# ... holding no more than this at its peak (resident; the limit is checked after the fact, since an
# address-space limit would stop a sanitizer build, which reserves terabytes, from starting at all).
PEAK_MEMORY_KIB = 100 * 1024
# ... or, where the binary alone holds nearly that (AddressSanitizer's shadow memory makes
# `fx2d-bench --version` peak at about 103 MiB, against 13 MiB in Release), no more than this above
# what it holds doing nothing: the 16 MiB read, the buffers and the refusal.
READ_GROWTH_KIB = 32 * 1024
SCRATCH = tempfile.TemporaryDirectory(prefix="fx2d-misuse-")


@dataclass
class Misuse:
    name: str
    args: list
    stderr: str                      # a fragment of the one line expected on stderr
    exit_code: int = 2
    seconds: float = REFUSAL_SECONDS
    setup: object = None  # makes the input in the scratch directory; returns a process to end after


PLUGIN_AS_FX2D = f"plugin:{PLUGIN}|fx2d"
MISSING_PLUGIN = "plugin:/nonexistent/libnothing.so"
POLYGON_BODY = '/bodies/-={"shape": {"polygon": [[0, 0], [1, 0], [0, 1]]}, "position": [0, 8]}'


def endless_fifo(cwd):
    os.mkfifo(os.path.join(cwd, "endless"))
    return subprocess.Popen(["sh", "-c", "exec yes > endless"], cwd=cwd)


CONTROL_NAME = "odd\nname\x1b[2J\r.json"  # a line break, a terminal's clear-screen, a carriage return


def control_named_scene(cwd):
    with open(os.path.join(cwd, CONTROL_NAME), "w") as scene:
        scene.write("not json")


def sparse_gigabyte(cwd):
    with open(os.path.join(cwd, "sparse.json"), "wb") as sparse:
        sparse.truncate(1 << 30)

FAST_BODY = '/bodies/-={"shape": {"circle": 0.1}, "position": [0, 50], "velocity": [1500, 0]}'
SHORT = ["--steps", "3", "--repeats", "1"]

MISUSES = [
    # run
    Misuse("run: a result file as a scene", ["run", "scenes/README.md"], "syntax error"),
    Misuse("run: a missing option value", ["run", "--bodies"], "--bodies"),
    Misuse("run: --force without --out", ["run", "--force"], "--force requires --out"),
    Misuse("run: a plugin that is not there", ["run", "--engine", MISSING_PLUGIN], "nonexistent"),
    Misuse("run: a device as a plugin", ["run", "--engine", "plugin:/dev/zero"], "plugin /dev/zero: not a regular file"),
    Misuse("run: two engines under one label", ["run", "--engine", f"{PLUGIN_AS_FX2D},fx2d"] + SHORT,
           "two engines are named fx2d"),
    Misuse("run: an engine that cannot build the scene", ["run", "pile", "scenes/tests/polygon_and_joint.json",
           "--engine", "ode", "--out", "f.h5"] + SHORT, "engine ode cannot build polygons"),
    Misuse("run: a body faster than the engine takes", ["run", "--engine", "fx2d", "--set", FAST_BODY],
           "engine fx2d cannot build bodies faster than 1000 m/s"),
    Misuse("run: no steps to measure", ["run", "pile", "--set", "/steps=0"], "/steps is 0"),
    Misuse("run: /dev/zero", ["run", "/dev/zero"], "more than 16 MiB", seconds=INPUT_LIMIT_SECONDS),
    Misuse("run: a FIFO that streams without end", ["run", "endless"], "more than 16 MiB",
           seconds=INPUT_LIMIT_SECONDS, setup=endless_fifo),
    Misuse("run: a 1 GB sparse file", ["run", "sparse.json"], "more than 16 MiB",
           seconds=INPUT_LIMIT_SECONDS, setup=sparse_gigabyte),
    Misuse("run: a file name holding control characters", ["run", CONTROL_NAME],
           "odd name?[2J .json:1:2: syntax error", setup=control_named_scene),
    # engines
    Misuse("engines: an argument it does not take", ["engines", "pile"], "pile"),
    Misuse("engines: an unknown option", ["engines", "--csv"], "--csv"),
    # compare
    Misuse("compare: a scene file as results", ["compare", "scenes/pile.json"], "not an fx2d-bench result file"),
    Misuse("compare: no file", ["compare"], "A is required"),
    Misuse("compare: two files and --baseline", ["compare", "scenes/pile.json", "scenes/stacks.json", "--baseline",
           "box2d"], "B excludes --baseline"),
    Misuse("compare: a missing option value", ["compare", "scenes/pile.json", "--noise"], "--noise"),
    # sweep
    Misuse("sweep: a text file as a scene", ["sweep", "scenes/README.md"], "syntax error"),
    Misuse("sweep: a missing option value", ["sweep", "--dt"], "--dt"),
    Misuse("sweep: --force without --out", ["sweep", "--force"], "--force requires --out"),
    Misuse("sweep: two engines under one label", ["sweep", "stacks", "--engine", f"{PLUGIN_AS_FX2D},fx2d"],
           "two engines are named fx2d"),
    Misuse("sweep: an engine that cannot build the scene",
           ["sweep", "scenes/tests/polygon_and_joint.json", "--engine", "ode"], "engine ode cannot build polygons"),
    Misuse("sweep: no steps to measure", ["sweep", "pile", "--set", "/steps=0"], "/steps is 0"),
    # stability
    Misuse("stability: --force without --out", ["stability", "--force"], "--force requires --out"),
    Misuse("stability: an unknown test", ["stability", "--test", "nosuch"], "nosuch"),
    Misuse("stability: a suite that is not there", ["stability", "--suite", "nowhere"], "nowhere"),
    Misuse("stability: a plugin that is not there", ["stability", "--engine", MISSING_PLUGIN], "nonexistent"),
    Misuse("stability: an engine that cannot build the scene",
           ["stability", "--engine", "ode", "--test", "thin_wall", "--set", POLYGON_BODY],
           "engine ode cannot build polygons"),
    # sharding and merge
    Misuse("sweep: a shard beyond the count", ["sweep", "--shard", "3/2"], "expected K/N with 1 <= K <= N"),
    Misuse("stability: a shard of zero", ["stability", "--shard", "0/2"], "expected K/N with 1 <= K <= N"),
    Misuse("run: a shard without a count", ["run", "--shard", "2"], "expected K/N with 1 <= K <= N"),
    Misuse("merge: no shard files", ["merge", "out.h5"], "IN is required"),
    Misuse("merge: a shard that is not there", ["merge", "out.h5", "nosuch.h5"], "nosuch.h5: no such file"),
    Misuse("merge: a scene file as a shard", ["merge", "out.h5", "scenes/pile.json"], "pile.json"),
    Misuse("merge: a device as a shard", ["merge", "out.h5", "/dev/zero"], "/dev/zero: not a regular file"),
    # report
    Misuse("report: a scene file as results", ["report", "scenes/pile.json", "-o", "out"], "pile.json"),
    Misuse("report: no output directory", ["report", "scenes/pile.json"], "-o"),
    Misuse("report: a device as results", ["report", "/dev/zero", "-o", "out"], "/dev/zero: not a regular file"),
    Misuse("report: --compare-json from /dev/zero", ["report", "--compare-json", "/dev/zero", "-o", "out"],
           "more than 16 MiB", seconds=INPUT_LIMIT_SECONDS),
    # gate: the policy is read whole
    Misuse("gate: a policy from /dev/zero", ["gate", "scenes/pile.json", "--policy", "/dev/zero"],
           "more than 16 MiB", seconds=INPUT_LIMIT_SECONDS),
]


def scratch_directory():
    """A directory holding the repository's scenes, so relative paths read as in the README."""
    directory = tempfile.mkdtemp(dir=SCRATCH.name)
    os.symlink(os.path.join(SOURCE, "scenes"), os.path.join(directory, "scenes"))
    return directory


@dataclass
class Ending:
    returncode: int
    stdout: str
    stderr: str
    seconds: float
    peak_kib: int


def bench(args, cwd, timeout=600):
    """Runs fx2d-bench to its end: how it ended, how long it took, its own peak resident memory."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        started = time.monotonic()
        child = subprocess.Popen([BENCH] + args, cwd=cwd, stdout=out, stderr=err)
        timer = threading.Timer(timeout, child.kill)
        timer.start()
        _, status, usage = os.wait4(child.pid, 0)
        timer.cancel()
        child.returncode = os.waitstatus_to_exitcode(status)
        seconds = time.monotonic() - started
        out.seek(0)
        err.seek(0)
        return Ending(child.returncode, out.read(), err.read(), seconds, usage.ru_maxrss)


@functools.cache
def idle_peak_kib():
    """The peak resident memory of this fx2d-bench doing nothing but print its version."""
    return bench(["--version"], SCRATCH.name).peak_kib


def check_misuse(row):
    cwd = scratch_directory()
    writer = row.setup(cwd) if row.setup else None
    ended = bench(row.args, cwd, timeout=row.seconds + 2)  # an unbounded read is stopped soon after
    if writer:
        writer.kill()
        writer.wait()
    lines = ended.stderr.splitlines()
    problems = []
    if ended.returncode == 4:
        problems.append("exit code 4, kept for internal errors")
    if ended.returncode != row.exit_code:
        problems.append(f"exit code {ended.returncode}, expected {row.exit_code}")
    if len(lines) != 1 or not lines[0].startswith("fx2d-bench: ") or row.stderr not in lines[0]:
        problems.append(f"stderr {ended.stderr!r}, expected one line 'fx2d-bench: ...{row.stderr}...'")
    if ended.seconds > row.seconds:
        problems.append(f"took {ended.seconds:.2f} s, expected under {row.seconds} s")
    peak_limit_kib = max(PEAK_MEMORY_KIB, idle_peak_kib() + READ_GROWTH_KIB)
    if ended.peak_kib > peak_limit_kib:
        problems.append(f"held {ended.peak_kib} KiB at its peak, expected under {peak_limit_kib} KiB")
    return problems


def check_unbuildable_scene_is_skipped_with_all():
    """`run scenes/tests/*.json` measures every engine that can build each scene, and says which it skipped."""
    cwd = scratch_directory()
    scenes = sorted(f"scenes/tests/{name}" for name in os.listdir(os.path.join(SOURCE, "scenes/tests")))
    ended = bench(["run"] + scenes + SHORT + ["--json"], cwd)
    if ended.returncode != 0:
        return [f"exit code {ended.returncode}: {ended.stderr.strip()}"]
    runs = json.loads(ended.stdout)["runs"]
    problems = []
    if any(run["engine"] == "ode" and run["scene"] == "polygon_and_joint" for run in runs):
        problems.append("ode measured on polygon_and_joint")
    if not any(run["engine"] == "ode" for run in runs):
        problems.append("ode measured on no scene at all")
    if "skipping ode, which cannot build polygons" not in ended.stderr:
        problems.append(f"no line saying ode was skipped: {ended.stderr!r}")
    return problems


def check_scene_from_a_generator():
    """A scene read from a pipe (`run <(cat scenes/pile.json)`) still runs."""
    cwd = scratch_directory()
    ended = subprocess.run(["bash", "-c", f"'{BENCH}' run <(cat scenes/pile.json) --engine fx2d --json "
                            + " ".join(SHORT)], cwd=cwd, capture_output=True, text=True, timeout=120)
    if ended.returncode != 0:
        return [f"exit code {ended.returncode}: {ended.stderr.strip()}"]
    return [] if json.loads(ended.stdout)["runs"][0]["bodies"] == 300 else ["not the 300-body pile"]


def check_sweep_marks_the_default_among_other_time_steps():
    """sweep --dt without the scene's own step still measures and marks the scene's own setting."""
    cwd = scratch_directory()
    ended = bench(["sweep", "stacks", "--bodies", "10", "--steps", "6", "--engine", "fx2d", "--fx2d-substeps", "2",
                      "--fx2d-passes", "1", "--dt", "0.01,0.02", "--repeats", "1", "--json"], cwd)
    if ended.returncode != 0:
        return [f"exit code {ended.returncode}: {ended.stderr.strip()}"]
    defaults = [point for point in json.loads(ended.stdout)["points"] if point["default"]]
    if len(defaults) != 1 or abs(defaults[0]["dt"] - 1 / 60) > 1e-12:
        return [f"default points {defaults}, expected one at the scene's dt 1/60"]
    return []


def check_stability_records_a_plugins_settings():
    """stability records a plugin's settings as run does: the scene's /solver entry the plugin reads."""
    cwd = scratch_directory()
    ended = bench(["stability", "--quick", "--test", "thin_wall", "--engine", f"fx2d,plugin:{PLUGIN}|p", "--json"], cwd)
    if ended.returncode != 0:
        return [f"exit code {ended.returncode}: {ended.stderr.strip()}"]
    settings = {result["engine"]: result["settings"] for result in json.loads(ended.stdout)["results"]}
    if settings.get("p") is None or settings.get("p") != settings.get("fx2d"):
        return [f"settings {settings}, expected the plugin's to be fx2d's"]
    return []


def check_stability_searches_up_to_the_engines_speed_limit():
    """stability's thin_wall on fx2d tries Fx2D's fastest body, 1000 m/s, the test's limit, and holds there.

    A lower engine limit ends the search as "engine limit at X" (unit test
    StabilitySuite.ASpeedTestStopsAtTheEnginesFastestBody)."""
    cwd = scratch_directory()
    ended = bench(["stability", "--engine", "fx2d", "--test", "thin_wall", "--json"], cwd)
    if ended.returncode != 0:
        return [f"exit code {ended.returncode}: {ended.stderr.strip()}"]
    result = json.loads(ended.stdout)["results"][0]
    found = (result["outcome"], result["limit"], result["last_pass"])
    return [] if found == ("holds_to_limit", 1000, 1000) else [f"outcome, limit, last_pass {found}"]


def check_a_broken_engine_plugin_leaves_the_others_working():
    """An installed engine plugin that does not load is refused in one line when selected; the other engines run."""
    install = scratch_directory()
    os.makedirs(os.path.join(install, "bin"))
    os.makedirs(os.path.join(install, "lib", "fx2d-bench"))
    copy = os.path.join(install, "bin", "fx2d-bench")
    shutil.copy(BENCH, copy)
    with open(os.path.join(install, "lib", "fx2d-bench", "libfx2d_bench_chipmunk.so"), "w") as broken:
        broken.write("not a shared library\n")
    problems = []
    for engines, expected_exit in (("fx2d", 0), ("chipmunk", 2), ("all", 2)):
        ended = subprocess.run([copy, "run", "stacks", "--bodies", "10", "--engine", engines] + SHORT, cwd=install,
                               capture_output=True, text=True, timeout=120)
        lines = ended.stderr.strip().splitlines()
        if ended.returncode != expected_exit:
            problems.append(f"--engine {engines}: exit {ended.returncode}, expected {expected_exit}: {ended.stderr.strip()}")
        elif expected_exit == 2 and not (len(lines) == 1 and "libfx2d_bench_chipmunk.so" in lines[0]):
            problems.append(f"--engine {engines}: expected one line naming the plugin, got {ended.stderr!r}")
    return problems


def main():
    failures = 0
    checks = [(row.name, lambda row=row: check_misuse(row)) for row in MISUSES]
    checks += [(check.__doc__.splitlines()[0], check) for check in (
        check_unbuildable_scene_is_skipped_with_all, check_scene_from_a_generator,
        check_sweep_marks_the_default_among_other_time_steps, check_stability_records_a_plugins_settings,
        check_stability_searches_up_to_the_engines_speed_limit,
        check_a_broken_engine_plugin_leaves_the_others_working)]
    for name, check in checks:
        problems = check()
        failures += bool(problems)
        print(("FAIL " if problems else "ok   ") + name + "".join("\n     " + problem for problem in problems))
    print(f"{len(checks) - failures} of {len(checks)} passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
