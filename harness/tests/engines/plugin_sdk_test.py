#!/usr/bin/python3
"""fx2d-bench and its plugin SDK as installed: `cmake --install` of this build into a scratch prefix,
moved elsewhere (so nothing can be found by the path it was installed to), its fx2d-bench loading
Chipmunk2D's plugin from the moved prefix; the template (harness/plugin/template) configured against
the moved SDK with find_package(Fx2dBench) and built out of tree, then run by the installed
fx2d-bench beside Fx2D and Chipmunk2D, the template's knob checked and swept, its stability measured on
the tests it can build (and the whole suite refused at the one it cannot), and timed by `ab`
against another build of itself; `ab` of a revision told in one line that --source names no tree.

Usage: plugin_sdk_test.py CMAKE BUILD_DIR SOURCE_DIR"""
import json
import subprocess
import sys
import tempfile
from pathlib import Path


def run(command, **options):
    done = subprocess.run(command, capture_output=True, text=True, **options)
    if done.returncode != 0:
        sys.exit(f"FAILED ({done.returncode}): {' '.join(map(str, command))}\n{done.stdout}\n{done.stderr}")
    return done


def main():
    cmake, build, source = sys.argv[1:4]
    with tempfile.TemporaryDirectory() as scratch:
        installed = Path(scratch) / "installed"
        prefix = Path(scratch) / "moved"
        plugin_build = Path(scratch) / "plugin"
        run([cmake, "--install", build, "--prefix", installed])
        installed.rename(prefix)
        assert (prefix / "include/fx2d_bench/fx2d_plugin_abi.h").is_file(), "the header was not installed"
        bench = prefix / "bin/fx2d-bench"
        listing = json.loads(run([bench, "engines", "--json"]).stdout)
        chipmunk = next(engine for engine in listing["engines"] if engine["name"] == "chipmunk")
        assert Path(chipmunk["plugin"]).is_relative_to(prefix), chipmunk
        run([cmake, "-S", Path(source) / "harness/plugin/template", "-B", plugin_build,
             "-DCMAKE_BUILD_TYPE=Release", f"-DCMAKE_PREFIX_PATH={prefix}"])
        run([cmake, "--build", plugin_build])
        plugin = plugin_build / "libmy_engine_plugin.so"
        engines = f"fx2d,plugin:{plugin}|mine"
        summary = json.loads(run([bench, "run", "stacks", "--bodies", "10", "--steps", "30", "--repeats", "1",
                                  "--engine", engines + ",chipmunk", "--json"]).stdout)
        runs = {entry["engine"]: entry for entry in summary["runs"]}
        assert set(runs) == {"fx2d", "mine", "chipmunk"}, runs.keys()
        # The template's bodies fall through each other: its top box ends far below Fx2D's stack.
        assert runs["mine"]["accuracy"]["max_displacement"] > 10 * runs["fx2d"]["accuracy"]["max_displacement"], runs
        refused = subprocess.run([bench, "run", "stacks", "--engine", engines, "--set", "/solver/my_engine/substeps=65"],
                                 capture_output=True, text=True)
        assert refused.returncode == 2, refused
        assert refused.stderr == ("fx2d-bench: --set /solver/my_engine/substeps=65: /solver/my_engine/substeps: "
                                  "expected an integer from 1 to 64, got 65\n"), refused.stderr
        sweep = json.loads(run([bench, "sweep", "stacks", "--bodies", "10", "--steps", "30", "--repeats", "1",
                                "--engine", f"plugin:{plugin}|mine", "--axis", "my_engine.substeps=2,4",
                                "--json"]).stdout)
        assert [point["settings"]["substeps"] for point in sweep["points"]] == [2, 4, 1], sweep["points"]
        # stability on the tests the template can build; the whole suite ends at the one it cannot.
        stability = json.loads(run([bench, "stability", "--quick", "--test", "card_house,thin_wall", "--engine",
                                    f"plugin:{plugin}|mine", "--json"]).stdout)
        assert [result["engine"] for result in stability["results"]] == ["mine", "mine"], stability
        refused = subprocess.run([bench, "stability", "--quick", "--engine", f"plugin:{plugin}|mine"],
                                 capture_output=True, text=True)
        assert refused.returncode == 2, refused
        assert refused.stderr == ("fx2d-bench: scene stability_chain_load: engine mine cannot build revolute "
                                  "joints\n"), refused.stderr
        # ab of an engine plugin against another build of itself: the same adapter built again.
        rebuilt = Path(scratch) / "rebuilt"
        run([cmake, "-S", Path(source) / "harness/plugin/template", "-B", rebuilt,
             "-DCMAKE_BUILD_TYPE=Release", f"-DCMAKE_PREFIX_PATH={prefix}"])
        run([cmake, "--build", rebuilt])
        ab = subprocess.run([bench, "ab", "--a", plugin, "--b", rebuilt / "libmy_engine_plugin.so", "stacks",
                             "--bodies", "10", "--steps", "30", "--rounds", "6", "--json"],
                            capture_output=True, text=True)
        assert ab.returncode in (0, 1, 3), ab  # a verdict: no regression, regression or inconclusive
        assert {row["engine"] for row in json.loads(ab.stdout)["rows"]} == {"my_engine"}, ab.stdout
        # A revision is built with the plugin project of an Fx2D tree, which --source must name.
        refused = subprocess.run([bench, "ab", "--a", "HEAD", "--b", "HEAD", "--source", scratch],
                                 capture_output=True, text=True, cwd=source)
        assert refused.returncode == 2, refused
        assert refused.stderr == (f"fx2d-bench: --a HEAD: --source {scratch}: not an Fx2D source tree "
                                  "(no harness/plugin/CMakeLists.txt)\n"), refused.stderr
    print("installed and moved: fx2d-bench ran Chipmunk2D from the prefix; the SDK's template built out of "
          "tree, run, checked, swept and timed by ab against a second build; ab refused a --source of no tree")


if __name__ == "__main__":
    main()
