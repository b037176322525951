#!/usr/bin/python3
"""Writes the joint scenes beside this script: joint_grid.json, chain.json and rope.json.

    /usr/bin/python3 scenes/joints/make_joint_scenes.py

The canonical scenes (SCENES.md) have no joint, so nothing in them times the joints' passes; these
two do, with Fx2D against Box2D and ODE on the same bodies:
- joint_grid: a 30 x 30 lattice of circles 1 m apart, each pinned to its right and lower
  neighbours by revolute joints (1,740 joints), the top row held by every fifth circle being static;
  it sags and sways under gravity. Primary metric: displacement.
- chain: 200 links of 0.5 x 0.1 m pinned end to end, the first to a static anchor, released level;
  the chain swings down. Deeper than any support chain the shallow schedule takes (32), so every
  step runs the full schedule.
- rope: 200 circles of radius 0.1 m, 0.5 m apart, each tied to the next by a distance joint between
  their centres, the first to a static anchor, released level: the chain's swing on distance joints.
"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from scene_json import scene, write_beside  # noqa: E402 (the shared module is one folder up)


def joint_grid(n=30):
    bodies, joints = [], []
    for r in range(n):
        for c in range(n):
            pinned = r == 0 and c % 5 == 0
            bodies.append({"type": "static" if pinned else "dynamic", "shape": {"circle": 0.4},
                           "position": [c * 1.0, 60 - r * 1.0]})
    for r in range(n):
        for c in range(n):
            k = r * n + c
            if c + 1 < n and not (bodies[k]["type"] == "static" and bodies[k + 1]["type"] == "static"):
                joints.append({"type": "revolute", "a": k, "b": k + 1, "anchor_a": [0.5, 0], "anchor_b": [-0.5, 0]})
            if r + 1 < n:
                joints.append({"type": "revolute", "a": k, "b": k + n, "anchor_a": [0, -0.5], "anchor_b": [0, 0.5]})
    return scene("joint_grid", "A 30 x 30 lattice of circles pinned to their neighbours, hanging from "
                 "every fifth circle of its top row (scenes/joints/make_joint_scenes.py).", bodies, joints)


def chain(links=200):
    bodies = [{"type": "static", "shape": {"circle": 0.1}, "position": [0, 50]}]
    joints = []
    for i in range(links):
        bodies.append({"shape": {"box": [0.25, 0.05]}, "position": [0.25 + 0.5 * i, 50]})
        joints.append({"type": "revolute", "a": i, "b": i + 1, "anchor_a": [0.25 if i else 0, 0],
                       "anchor_b": [-0.25, 0]})
    return scene("chain", "200 links pinned end to end from a static anchor, released level "
                 "(scenes/joints/make_joint_scenes.py).", bodies, joints)


def rope(links=200):
    bodies = [{"type": "static", "shape": {"circle": 0.1}, "position": [0, 50]}]
    joints = []
    for i in range(links):
        bodies.append({"shape": {"circle": 0.1}, "position": [0.5 * (i + 1), 50]})
        joints.append({"type": "distance", "a": i, "b": i + 1, "anchor_a": [0, 0], "anchor_b": [0, 0]})
    return scene("rope", "200 circles tied end to end by distance joints from a static anchor, released "
                 "level (scenes/joints/make_joint_scenes.py).", bodies, joints)


write_beside(__file__, (joint_grid(), chain(), rope()))
