#!/usr/bin/python3
"""The git revision a build names is the one it was built from: `fx2d-bench --version` (whose
revision every result file records as fx2d_git_revision) and this tree's plugin's description (the
label `ab` and `run --engine plugin:...` give it) both equal what git says of the source tree now:
`git rev-parse --short HEAD`, with `-dirty` when tracked files differ from HEAD. A revision read
once at configure time fails this after a commit or an edit and an incremental build.

Usage: build_revision_test.py FX2D_BENCH PLUGIN SOURCE_DIR
Exit 77 (a CTest skip) when SOURCE_DIR is not a git checkout (a tarball), where both say `unknown`.
"""
import json
import subprocess
import sys

SKIP = 77
BENCH, PLUGIN, SOURCE = sys.argv[1:4]


def git(*args):
    return subprocess.run(["git", "-C", SOURCE, *args], capture_output=True, text=True)


def expected_revision():
    """What harness/git_revision.cmake should have written, or None outside a git checkout."""
    try:
        head = git("rev-parse", "--short", "HEAD")
    except FileNotFoundError:
        return None
    if head.returncode != 0:
        return None
    dirty = git("diff", "--quiet", "HEAD", "--").returncode != 0
    return head.stdout.strip() + ("-dirty" if dirty else "")


def bench(*args):
    return subprocess.run([BENCH, *args], capture_output=True, text=True, check=True).stdout.strip()


def main():
    revision = expected_revision()
    if revision is None:
        print(f"skipped: {SOURCE} is not a git checkout")
        return SKIP
    version = bench("--version")
    plugin = json.loads(bench("engines", "--engine", f"plugin:{PLUGIN}", "--json"))["engines"][0]["version"]
    failures = [f"{name} is '{said}', expected it to name {wanted}"
                for name, said, wanted in [("fx2d-bench --version", version, f"git {revision},"),
                                           ("the plugin's version", plugin, f" {revision} (this build)")]
                if wanted not in said]
    for failure in failures:
        print(failure, "(git says of the source tree now: " + revision + "; rebuild if you changed it since)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
