#!/usr/bin/python3
"""Documentation that is executed: every command example and every marked error message in the
project's Markdown runs, and the test fails when the exit code or the message no longer matches.

A marker, an HTML comment that renders as nothing, says how the code after it is tested; it
applies to the next fenced or indented block, or to the next `inline code` in the same paragraph:

    <!-- doc-test: ci -->                         run in CI (the default tier)
    <!-- doc-test: nightly -->                    too slow for CI: ci/nightly runs it
    <!-- doc-test: skip: REASON -->               never run; the reason (free text) is required
    <!-- doc-test: ci; exit=0,3 -->               each command may exit with one of these
    <!-- doc-test: ci; setup: CMD; setup: CMD --> shell commands run first (they must succeed)
    <!-- doc-test: nightly; in source -->        run in the checkout itself (ab and git need it)

A marked ```python block runs as one script with /usr/bin/python3 (after its setup) and must succeed.
    <!-- doc-test: ci; stderr of: CMD; stderr of: CMD -->
        the code is not run: its lines are the one-line errors the commands print, in order
        (exit code 2 unless exit= says otherwise); `...` in a line matches any text, and the
        `fx2d-bench: ` prefix may be left out

Fields are separated by new lines, or by `;` before a field name. Without `stderr of`, each line of the code is a command
(a line ending in `\\` continues on the next), run with bash in a scratch directory that holds the
repository's `scenes/`, `ci/`, `harness/` and `reports/` (so relative paths read as in the
document), with `fx2d-bench` and `build/release/harness/fx2d-bench` both naming the binary under
test; $FX2D_SOURCE names the checkout and $FX2D_BENCH_BUILD the build directory of the binary. The commands of one block share their directory. Every `sh` block and every indented block
is a command example and must carry a marker: an example nobody classified fails the test.

Usage: doc_examples_test.py --bench FX2D_BENCH --source DIR [--tier ci|nightly] [FILE.md ...]
(without files: every document a user is sent to, DOCUMENTS below)
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field

MARKER = re.compile(r"(?<!`)<!--\s*doc-test:(.*?)-->", re.S)  # quoted in `code`, it is prose
# A new line, or a semicolon before a field name: a command may hold semicolons of its own.
FIELD_SEPARATOR = re.compile(r"\n|;(?=\s*(?:ci|nightly|in source|exit=|setup:|stderr of:))")
FENCE = re.compile(r"^(\s*)```(\w*)\s*$")
DOCUMENTS = ("README.md", "harness/README.md", "scenes/README.md", "scenes/SCENES.md", "ci/README.md", "harness/RESULTS_FORMAT.md",
             "reports/README.md")
COMMAND_LANGUAGES = {"sh", "bash", "shell", "console"}
LINKED_FROM_SOURCE = ("scenes", "ci", "harness", "reports", "fx2d")
COMMAND_SECONDS = 1800
PREFIX = "fx2d-bench: "


@dataclass
class Marker:
    tier: str = "ci"
    reason: str = ""
    exit_codes: list = field(default_factory=list)
    setup: list = field(default_factory=list)
    stderr_of: list = field(default_factory=list)
    in_source: bool = False


@dataclass
class Example:
    where: str        # file:line
    lines: list       # the code's lines
    is_command: bool  # an unmarked block of this kind is an error
    marker: Marker = None
    language: str = ""


def parse_marker(text, where):
    marker = Marker()
    if text.strip().startswith("skip:"):  # the reason is free text, semicolons included
        marker.tier, marker.reason = "skip", " ".join(text.strip()[len("skip:"):].split())
        if not marker.reason:
            raise SystemExit(f"{where}: doc-test marker: skip needs a reason")
        return marker
    for part in (p.strip() for p in FIELD_SEPARATOR.split(text)):
        if not part:
            continue
        if part in ("ci", "nightly"):
            marker.tier = part
        elif part == "in source":
            marker.in_source = True
        elif part.startswith("exit="):
            marker.exit_codes = [int(code) for code in part[len("exit="):].split(",")]
        elif part.startswith("setup:"):
            marker.setup.append(part[len("setup:"):].strip())
        elif part.startswith("stderr of:"):
            marker.stderr_of.append(part[len("stderr of:"):].strip())
        else:
            raise SystemExit(f"{where}: doc-test marker: unknown field {part!r}")
    return marker


def blocks_of(lines):
    """Each code block as (first line index, one past its end, its lines, its language)."""
    blocks, i = [], 0
    while i < len(lines):
        fence = FENCE.match(lines[i])
        if fence:
            end = next(j for j in range(i + 1, len(lines)) if lines[j].strip() == "```")
            indent = len(fence.group(1))
            blocks.append((i, end + 1, [text[indent:] for text in lines[i + 1:end]], fence.group(2)))
            i = end + 1
        elif lines[i].startswith("    ") and i > 0 and not lines[i - 1].strip():
            end = i
            while end < len(lines) and (lines[end].startswith("    ") or not lines[end].strip()):
                end += 1
            blocks.append((i, end, [text[4:] for text in lines[i:end] if text.strip()], "sh"))
            i = end
        else:
            i += 1
    return blocks


def examples_of(path):
    """The code of a Markdown file, each block or inline span with the marker before it, if any."""
    text = open(path, encoding="utf-8").read()
    lines = text.split("\n")
    blocks = blocks_of(lines)
    marked = {}
    examples = []
    for match in MARKER.finditer(text):
        line = text.count("\n", 0, match.start())
        where = f"{path}:{line + 1}"
        marker = parse_marker(match.group(1), where)
        paragraph_rest = text[match.end():].split("\n\n")[0]
        span = re.search(r"`([^`]+)`", paragraph_rest)
        if span and not paragraph_rest.startswith("\n"):
            examples.append(Example(where, [" ".join(span.group(1).split())], False, marker))  # may wrap
            continue
        after = text.count("\n", 0, match.end())
        following = [block for block in blocks if block[0] > after]
        if not following:
            raise SystemExit(f"{where}: doc-test marker with no code after it")
        marked[following[0][0]] = (where, marker)
    for first, _, body, language in blocks:
        where, marker = marked.get(first, (f"{path}:{first + 1}", None))
        examples.append(Example(where, body, language in COMMAND_LANGUAGES, marker, language))
    return examples


def scratch(source, bench):
    directory = tempfile.mkdtemp(prefix="fx2d-doc-")
    for name in LINKED_FROM_SOURCE:
        os.symlink(os.path.join(source, name), os.path.join(directory, name))
    binaries = os.path.join(directory, "build", "release", "harness")
    os.makedirs(binaries)
    os.symlink(bench, os.path.join(binaries, "fx2d-bench"))
    return directory


def commands_of(lines):
    commands, current = [], ""
    for line in lines:
        current += line.rstrip()
        if current.endswith("\\"):
            current = current[:-1] + " "
            continue
        if current.strip():
            commands.append(current.strip())
        current = ""
    return commands


def shell(command, cwd, bench, source):
    binaries = os.path.dirname(bench)
    environment = dict(os.environ, PATH=binaries + ":" + os.environ["PATH"], FX2D_SOURCE=source,
                       FX2D_BENCH_BUILD=os.path.dirname(binaries))
    return subprocess.run(["bash", "-c", command], cwd=cwd, env=environment, capture_output=True, text=True,
                          timeout=COMMAND_SECONDS)


def matches(expected, actual):
    pattern = ".*".join(re.escape(piece) for piece in expected.split("..."))
    return re.fullmatch(pattern, actual) is not None or re.fullmatch(re.escape(PREFIX) + pattern, actual) is not None


def check(example, source, bench):
    marker, directory = example.marker, scratch(source, bench)
    cwd = source if marker.in_source else directory
    problems = []
    try:
        for command in marker.setup:
            ended = shell(command, cwd, bench, source)
            if ended.returncode != 0:
                return [f"setup `{command}` exited {ended.returncode}: {ended.stderr.strip()}"]
        if marker.stderr_of:
            if len(marker.stderr_of) != len(example.lines):
                return [f"{len(marker.stderr_of)} commands for {len(example.lines)} documented lines"]
            for command, expected in zip(marker.stderr_of, example.lines):
                ended = shell(command, cwd, bench, source)
                printed = ended.stderr.rstrip("\n")
                allowed = marker.exit_codes or [2]
                if ended.returncode not in allowed or "\n" in printed or not matches(expected, printed):
                    problems.append(f"`{command}` exited {ended.returncode} printing {printed!r}; "
                                    f"the document says {expected!r} (exit {allowed})")
            return problems
        if example.language == "python":  # one script, as a reader would paste it
            ended = shell("/usr/bin/python3 - <<'DOC_EXAMPLE'\n" + "\n".join(example.lines) + "\nDOC_EXAMPLE", cwd, bench, source)
            return [] if ended.returncode == 0 else [f"the Python example failed: {(ended.stderr.strip().splitlines() or [''])[-1]}"]
        for command in commands_of(example.lines):
            ended = shell(command, cwd, bench, source)
            allowed = marker.exit_codes or [0]
            if ended.returncode not in allowed:
                problems.append(f"`{command}` exited {ended.returncode}, the document allows {allowed}: "
                                f"{ended.stderr.strip()[-300:]}")
        return problems
    finally:
        shutil.rmtree(directory, ignore_errors=True)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--bench", required=True)
    parser.add_argument("--source", required=True)
    parser.add_argument("--tier", choices=("ci", "nightly"), default="ci")
    parser.add_argument("documents", nargs="*", default=DOCUMENTS)
    arguments = parser.parse_args()
    bench, source = os.path.abspath(arguments.bench), os.path.abspath(arguments.source)
    failures = ran = 0
    for document in arguments.documents:
        for example in examples_of(os.path.join(source, document)):
            where = os.path.relpath(example.where, source)
            if example.marker is None:
                if example.is_command:
                    failures += 1
                    print(f"FAIL {where}: a command example without a doc-test marker")
                continue
            if example.marker.tier != arguments.tier:
                continue
            ran += 1
            problems = check(example, source, bench)
            failures += bool(problems)
            print(("FAIL " if problems else "ok   ") + where + "".join("\n     " + p for p in problems), flush=True)
    print(f"{ran} examples of tier {arguments.tier} run, {failures} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
