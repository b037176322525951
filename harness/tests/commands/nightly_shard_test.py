#!/usr/bin/python3
"""ci/nightly's smoke night whole and in two parts: the two parts (`--shard 1/2` and `--shard 2/2`)
run as two processes at once, `--collect` joins them, and the collected night must hold exactly the
unsharded night's rows with the same deterministic fields: the rows themselves, the physics and
accuracy figures of every comparison, and the exact instruction counts with their verdicts. Times are
measured again in each night, so they are not compared. Parts that are not one night's (a part
missing or given twice, another candidate, baseline or suite, another count) are refused in one
line, exit 2.

    nightly_shard_test.py --bench BUILD/harness/fx2d-bench [--source CHECKOUT] [--work DIR]

Run by ci/test (its nightly smoke stage). Exit 0 when the nights agree, 1 with each difference on
its own line.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

# The fields of a compare row that do not depend on the machine's timing.
DETERMINISTIC_FIELDS = ("repeats_a", "repeats_b", "physics", "accuracy")
# A row of the gate with an exact figure (instruction counts): p_value is null.
EXACT_FIELDS = ("a", "b", "ratio", "verdict", "regression")
ROW_KEY = ("engine", "against", "scene", "bodies", "metric")


def nightly(source, arguments, log):
    return subprocess.Popen([str(source / "ci" / "nightly"), "--smoke", *arguments],
                            stdout=log, stderr=subprocess.STDOUT)


def finish(process, name, log_path):
    if process.wait() != 0:
        sys.exit(f"nightly_shard_test: {name} exited {process.returncode}; its log: {log_path}")


def rows_of(night, bench, source):
    """Every compare row and gate row of a night, by key, with the fields that must match."""
    compares = sorted(night.glob("compare_*.json"))
    rows = {}
    for path in compares:
        for row in json.loads(path.read_text())["rows"]:
            key = (path.name,) + tuple(row.get(field) for field in ROW_KEY)
            exact = row.get("p_value") is None
            rows[key] = {field: row.get(field) for field in DETERMINISTIC_FIELDS + (EXACT_FIELDS if exact else ())}
    gate = subprocess.run([str(bench), "gate", *map(str, compares), "--policy", str(source / "ci" / "gating.json"),
                           "--json"], capture_output=True, text=True)
    if gate.returncode not in (0, 1, 3):
        sys.exit(f"nightly_shard_test: gate of {night} exited {gate.returncode}: {gate.stderr.strip()}")
    for row in json.loads(gate.stdout)["rows"]:
        key = ("gate",) + tuple(row.get(field) for field in ROW_KEY)
        exact = row.get("p_value") is None
        rows[key] = {field: row.get(field) for field in ("band", "control", "quarantined") + (EXACT_FIELDS if exact else ())}
    return rows


def timed_row(key):
    """A phase's row, which compare leaves out when a repeat timed the phase at zero (a phase that
    takes no time in most steps, such as Box2D's solve_init on pile 60): whether it is there
    depends on the timer, not on the work, so it may be in one night and not the other."""
    return str(key[-1]).startswith("phase:")


def with_manifest_line(part, copy, name, value):
    """A copy of `part` whose shard.txt says `name value`."""
    shutil.copytree(part, copy, dirs_exist_ok=True)
    manifest = copy / "shard.txt"
    lines = [f"{name} {value}" if line.startswith(name + " ") else line for line in manifest.read_text().splitlines()]
    manifest.write_text("\n".join(lines) + "\n")
    return copy


def refusals(source, parts, collected, work):
    """Parts that are not one night's: each --collect must refuse in one line, exit 2."""
    first, second = parts
    cases = [
        ([first], "part 2/2 is missing"),
        ([first, first], "part 1/2 again"),
        ([first, with_manifest_line(second, work / "other_candidate", "candidate", "0" * 40)], "(mixed revisions)"),
        ([first, with_manifest_line(second, work / "other_baseline", "baseline", "0" * 40)], "(mixed revisions)"),
        ([first, with_manifest_line(second, work / "other_suite", "work_list", "0" * 16)], "a part of another suite"),
        ([first, with_manifest_line(second, work / "of_three", "shard", "2/3")], "but " + str(first) + " is a part of 2"),
        ([first, second], "also the --out directory"),
    ]
    differences = []
    for collect, expected in cases:
        out = collect[-1] if expected == "also the --out directory" else collected.with_name("refused")
        ending = subprocess.run([str(source / "ci" / "nightly"), "--smoke", "--collect", *map(str, collect), "--out", str(out)],
                                capture_output=True, text=True)
        if ending.returncode != 2 or ending.stderr.count("\n") != 1 or expected not in ending.stderr:
            differences.append(f"--collect {' '.join(map(str, collect))}: exit {ending.returncode}, "
                               f"expected 2 and one line with '{expected}', got: {ending.stderr.strip()}")
    return differences


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bench", required=True, type=Path)
    parser.add_argument("--source", type=Path, default=Path(__file__).resolve().parents[3])
    parser.add_argument("--work", type=Path, help="where the nights go (default: a temporary directory)")
    options = parser.parse_args()
    work = options.work or Path(tempfile.mkdtemp(prefix="fx2d_nightly_shards_"))
    work.mkdir(parents=True, exist_ok=True)
    os.environ["FX2D_BENCH"] = str(options.bench.resolve())
    os.environ.setdefault("FX2D_NIGHTLY_DIR", str(work / "nightly"))
    source = options.source.resolve()

    whole = work / "whole"
    parts = [work / "part1", work / "part2"]
    collected = work / "collected"
    logs = {name: work / f"{name}.log" for name in ("whole", "part1", "part2", "collected")}
    # The whole night first: it builds ab's two plugins once, which the parts then find cached.
    with open(logs["whole"], "w") as log:
        finish(nightly(source, ["--out", str(whole)], log), "the unsharded night", logs["whole"])
    with open(logs["part1"], "w") as log1, open(logs["part2"], "w") as log2:
        first = nightly(source, ["--shard", "1/2", "--out", str(parts[0])], log1)
        second = nightly(source, ["--shard", "2/2", "--out", str(parts[1])], log2)
        finish(first, "part 1/2", logs["part1"])
        finish(second, "part 2/2", logs["part2"])
    with open(logs["collected"], "w") as log:
        finish(nightly(source, ["--collect", *map(str, parts), "--out", str(collected)], log), "--collect",
               logs["collected"])

    differences = refusals(source, parts, collected, work)
    expected = rows_of(whole, options.bench, source)
    got = rows_of(collected, options.bench, source)
    differences += [f"{key}: only in the unsharded night" for key in expected.keys() - got.keys() if not timed_row(key)]
    differences += [f"{key}: only in the collected night" for key in got.keys() - expected.keys() if not timed_row(key)]
    differences += [f"{key}: unsharded {expected[key]}, collected {got[key]}"
                    for key in expected.keys() & got.keys() if expected[key] != got[key]]
    for difference in sorted(differences):
        print(f"nightly_shard_test: {difference}")
    scenes = {key[3] for key in expected}
    print(f"nightly_shard_test: {len(expected)} rows over {len(scenes)} scenes, "
          f"{'the same' if not differences else f'{len(differences)} differences'} (collected against unsharded)")
    if not differences and not options.work:
        shutil.rmtree(work)
    return 1 if differences else 0


if __name__ == "__main__":
    sys.exit(main())
