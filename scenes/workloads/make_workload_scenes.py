#!/usr/bin/python3
"""Writes the workload scenes beside this script: sizes_pile.json, paddle_mixer.json, ragdolls.json
and smash_pyramid.json.

    /usr/bin/python3 scenes/workloads/make_workload_scenes.py

The canonical scenes (SCENES.md) drop bodies of one size onto open ground; these time what they
leave out, with Fx2D against Box2D and ODE on the same bodies:
- sizes_pile: 450 circles of radius 0.25 m and 50 of 0.9 m poured into a box 20 m wide with walls
  100 m tall; the small ones fall fast next to walls and large neighbours (continuous collision).
- paddle_mixer: two kinematic paddles 10 m long, side by side, turning at 3 rad/s in opposite
  senses in a walled box, with 400 circles and 200 boxes poured onto them; 300 steps (kinematic
  bodies, fast contacts). Bodies caught between a paddle and the floor are crushed: every engine's
  deepest overlap is some 0.37-0.38 m.
- ragdolls: 100 five-body figures (torso, head, two legs, an arm: four revolute joints and a
  distance joint between the feet) dropped onto the ground side by side (joints and contacts
  together, limbs that overlap their neighbours).
- smash_pyramid: a 4 m box of density 10 (160 kg against the pyramid's 1 kg boxes) thrown at 60 m/s
  into a pyramid of 325 boxes (base 25) that stands on the ground: a heap struck apart. Every
  engine lets the heavy box drive the boxes it strikes into one another: with the overlap sampled
  every step, Fx2D's deepest is 0.31 m and Box2D 2.4.1's 0.90 m.
Primary metric: penetration.
"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from scene_json import scene, write_beside  # noqa: E402 (the shared module is one folder up)

SOURCE = "(scenes/workloads/make_workload_scenes.py)"


def workload(name, description, bodies, joints=None, steps=200):
    return scene(name, f"{description} {SOURCE}", bodies, joints, steps, primary_metric="penetration")


def ground(half_width):
    return {"type": "static", "shape": {"box": [half_width, 0.5]}, "position": [0, -0.5]}


def walled_box(inner_half_width, wall_half_height):
    """The ground and two walls 1 m thick whose inner faces stand inner_half_width from the middle."""
    wall = lambda x: {"type": "static", "shape": {"box": [0.5, wall_half_height]}, "position": [x, wall_half_height]}
    return [ground(30), wall(-inner_half_width - 0.5), wall(inner_half_width + 0.5)]


def sizes_pile(count=500):
    bodies = walled_box(10, 50)
    for i in range(count):
        radius = 0.9 if i % 10 == 0 else 0.25
        bodies.append({"shape": {"circle": radius},
                       "position": [-9.0 + 2.0 * (i % 10) + 0.2 * ((i // 10) % 2), 1 + 2.0 * (i // 10)]})
    return workload("sizes_pile", "450 small and 50 large circles poured into a walled box.", bodies)


def paddle_mixer(count=600):
    bodies = walled_box(15, 40)
    # Apart, so that no two kinematic bodies overlap: the accuracy check would count that as penetration.
    for x, turn in ((-7, 3.0), (7, -3.0)):
        bodies.append({"type": "kinematic", "shape": {"box": [5, 0.3]}, "position": [x, 6], "angular_velocity": turn})
    for i in range(count):
        shape = {"circle": 0.35} if i % 3 else {"box": [0.3, 0.3]}
        bodies.append({"shape": shape, "position": [-14.4 + 1.1 * (i % 26) + 0.15 * ((i // 26) % 2), 11 + 1.1 * (i // 26)]})
    return workload("paddle_mixer", "Two kinematic paddles turning in a walled box under 600 circles and boxes.",
                 bodies, steps=300)


def ragdolls(count=100):
    bodies, joints = [ground(80)], []
    for k in range(count):
        x, y = -60 + 1.2 * k, 3.0
        torso = len(bodies)
        bodies += [{"shape": {"box": [0.2, 0.4]}, "position": [x, y]},
                   {"shape": {"circle": 0.2}, "position": [x, y + 0.65]},
                   {"shape": {"box": [0.08, 0.35]}, "position": [x - 0.12, y - 0.8]},
                   {"shape": {"box": [0.08, 0.35]}, "position": [x + 0.12, y - 0.8]},
                   {"shape": {"box": [0.3, 0.06]}, "position": [x + 0.5, y + 0.3]}]
        head, left_leg, right_leg, arm = torso + 1, torso + 2, torso + 3, torso + 4
        joints += [{"type": "revolute", "a": torso, "b": head, "anchor_a": [0, 0.45], "anchor_b": [0, -0.2]},
                   {"type": "revolute", "a": torso, "b": left_leg, "anchor_a": [-0.12, -0.4], "anchor_b": [0, 0.35]},
                   {"type": "revolute", "a": torso, "b": right_leg, "anchor_a": [0.12, -0.4], "anchor_b": [0, 0.35]},
                   {"type": "revolute", "a": torso, "b": arm, "anchor_a": [0.2, 0.3], "anchor_b": [-0.3, 0]},
                   {"type": "distance", "a": left_leg, "b": right_leg, "anchor_a": [0, -0.3], "anchor_b": [0, -0.3]}]
    return workload("ragdolls", "100 five-body figures joined by pins and a rod, dropped side by side.", bodies,
                 joints)


def smash_pyramid(base=25):
    bodies = [ground(100)]
    for row in range(base):
        for i in range(base - row):
            bodies.append({"shape": {"box": [0.5, 0.5]}, "position": [-(base - row) * 0.5 + 0.5 + i, 0.5 + row]})
    bodies.append({"shape": {"box": [2, 2]}, "position": [-60, 6], "velocity": [60, 0], "material": {"density": 10}})
    return workload("smash_pyramid", "A heavy box thrown at 60 m/s into a pyramid of 325 boxes.", bodies)


write_beside(__file__, (sizes_pile(), paddle_mixer(), ragdolls(), smash_pyramid()))
