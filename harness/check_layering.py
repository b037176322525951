#!/usr/bin/python3
"""The harness's layering, checked on every build: each folder of harness/ includes only the
folders below it (harness/README.md, "The map"), and only storage/ sees HDF5, only engines/ sees
Box2D and ODE, only commands/ and main.cpp see CLI11.

The libraries already link only what they use, so a call that runs the wrong way fails to link;
this also catches what a linker cannot see: a header of types alone, an inline function, a
template. Usage: check_layering.py HARNESS_DIR. Exit 0 when every include is allowed; otherwise
one line per offending include (file:line: what it includes and what that folder may use), exit 1.
"""
import pathlib
import re
import sys

# What each folder may include besides itself; a folder not listed here (tests/, fuzz/) may use
# anything, third-party headers included. Kept in the order of harness/CMakeLists.txt, lowest first.
MAY_USE = {
    "common": set(),
    "scene": {"common"},
    "plugin": set(),
    "engines": {"common", "scene", "plugin"},
    "metrics": {"common", "scene", "engines"},
    "stats": {"common"},
    "measure": {"common", "scene", "engines", "metrics", "stats"},
    "storage": {"common"},
    "analysis": {"common", "scene", "engines", "metrics", "stats", "measure"},
    "format": {"common", "scene", "engines", "metrics", "stats", "measure", "analysis"},
    "commands": {"common", "scene", "plugin", "engines", "metrics", "stats", "measure", "storage", "analysis",
                 "format"},
}

# Third-party headers and the one folder allowed each.
ONLY_IN = {"hdf5.h": {"storage"}, "box2d/": {"engines"}, "ode/": {"engines"}, "CLI/": {"commands", "."}}

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def offences(harness, path):
    folder = path.parent.relative_to(harness).parts[0] if path.parent != harness else "."
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        match = INCLUDE.match(line)
        if not match:
            continue
        header = match.group(2)
        for prefix, allowed in ONLY_IN.items():
            if header.startswith(prefix) and (folder in MAY_USE or folder == ".") and folder not in allowed:
                yield f"{path}:{number}: includes <{header}>, which only {', '.join(sorted(allowed))}/ may use"
        target = header.split("/")[0]
        if match.group(1) == '"' and "/" in header and folder in MAY_USE and target in MAY_USE and target != folder \
                and target not in MAY_USE[folder]:
            uses = ", ".join(sorted(MAY_USE[folder])) or "nothing of the harness"
            yield f"{path}:{number}: includes {header}, but {folder}/ may use only {uses} (harness/README.md)"


def main():
    if len(sys.argv) != 2:
        print("usage: check_layering.py HARNESS_DIR", file=sys.stderr)
        return 2
    harness = pathlib.Path(sys.argv[1]).resolve()
    sources = sorted(p for p in harness.rglob("*") if p.suffix in (".h", ".cpp", ".in") and p.is_file())
    found = [line for path in sources for line in offences(harness, path)]
    for line in found:
        print(line, file=sys.stderr)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
