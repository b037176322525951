"""What the scene generators under scenes/ share: a scene file's fields (README.md in this folder
says what each means) and writing the files beside the generator that made them."""
import json
import pathlib


def scene(name, description, bodies, joints=None, steps=200, primary_metric="displacement"):
    """A scene at 60 Hz under standard gravity, with Fx2D's default schedule and Box2D's default
    iterations pinned, sleeping off; `joints` written when given."""
    made = {
        "schema": "fx2d.scene/1",
        "name": name,
        "description": description,
        "steps": steps,
        "dt": 1 / 60,
        "gravity": [0, -10],
        "material": {"density": 1, "friction": 0.6, "restitution": 0},
        "primary_metric": primary_metric,
        "bounds": {"lower": [-200, -50], "upper": [200, 300]},
        "solver": {
            "fx2d": {"substeps": 8, "velocity_passes": 1, "relax_passes": 3, "sleeping": False},
            "box2d": {"velocity_iterations": 8, "position_iterations": 3, "sleeping": False},
        },
        "bodies": bodies,
    }
    if joints is not None:
        made["joints"] = joints
    return made


def write_beside(generator_file, scenes):
    """Writes each scene as NAME.json, compact, in the folder of `generator_file`."""
    folder = pathlib.Path(generator_file).resolve().parent
    for made in scenes:
        (folder / f"{made['name']}.json").write_text(json.dumps(made, separators=(",", ":")) + "\n")
