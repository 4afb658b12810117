"""Scene files for the batch tests: shapes and STEP parts, every kind of motion (still, twist,
keyframes, pose table), a threshold, several pairs, a file of two solids."""

import os
import shutil

from conftest import write_scene

STILL = {"type": "static"}


def sphere(name, r, position=(0, 0, 0), motion=STILL):
    return {"name": name, "shape": {"type": "sphere", "radius": r},
            "pose": {"position": list(position)}, "motion": motion}


def twist(v=(0, 0, 0), w=(0, 0, 0)):
    return {"type": "twist", "velocity": list(v), "angular_velocity": list(w)}


def write_scenes(folder, shared_data, copy_parts=False):
    """Writes eight scenes into `folder` (and poses.csv); returns their paths. With copy_parts
    the STEP parts are copied beside them (named relatively), else named where they are."""
    folder.mkdir(parents=True, exist_ok=True)
    box = shared_data / "step" / "pr2ct.stp"
    balls = shared_data / "step" / "bug24283_spheres.stp"
    if copy_parts:
        (folder / "parts").mkdir(exist_ok=True)
        box = shutil.copy(box, folder / "parts" / "pr2ct.stp")
        balls = shutil.copy(balls, folder / "parts" / "bug24283_spheres.stp")
    (folder / "poses.csv").write_text(
        "# a ball over a plate\nt,x,y,z,qw,qx,qy,qz\n" +
        "".join(f"{0.1 * k:.1f},{-4 + 0.8 * k:.2f},0.5,{1.5 - 0.1 * k:.2f},1,0,0,0\n"
                for k in range(11)))
    scenes = {
        "spheres": {"time": {"start": 0, "end": 2, "step": 0.01},
                    "bodies": [sphere("A", 1), sphere("B", 0.5, (4, 1, 0), twist((-2, 0, 0), (0, 0, 1)))]},
        "ellipsoids": {
            "time": {"start": 0, "end": 3, "step": 0.02},
            "bodies": [
                {"name": "A", "shape": {"type": "ellipsoid", "axes": [3, 2, 1.5]},
                 "pose": {"position": [0, 0, 0], "quaternion": [0.9233805169, 0.1025978352, 0.3077935056, 0.2051956704]},
                 "motion": twist((0, 0, 0), (0.2, -0.1, 0.3))},
                {"name": "B", "shape": {"type": "ellipsoid", "axes": [2, 1.2, 1]},
                 "pose": {"position": [7.5, 1, 0.5], "quaternion": [0.8677218313, -0.2169304578, 0.1084652289, 0.4338609156]},
                 "motion": twist((-0.35, 0.1, 0.05), (-0.1, 0.3, 0.2))}],
            "tracker": {"gain": 100, "audit_every": 10}},
        "box_ball": {"time": {"start": 0, "end": 2, "step": 0.02},
                     "bodies": [{"name": "box", "file": os.path.relpath(box, folder)},
                                sphere("ball", 10, (250, -50, 120), twist((0, 150, 0)))],
                     "pairs": [["box", "ball"]]},
        "table": {"time": {"start": 0, "end": 1, "step": 0.01},
                  "bodies": [{"name": "plate", "shape": {"type": "plane", "size": [10, 10]}},
                             {"name": "ball", "shape": {"type": "sphere", "radius": 0.5},
                              "motion": {"type": "table", "file": "poses.csv"}}]},
        "farther": {"time": {"start": 0, "end": 2, "step": 0.02},
                    "bodies": [sphere("A", 1), sphere("B", 0.5, (-6, 1.8, 0), twist((6, 0, 0)))],
                    "threshold": 2},
        "three": {"time": {"start": 0, "end": 1, "step": 0.02},
                  "bodies": [{"name": "ring", "shape": {"type": "torus", "major": 3, "minor": 0.5}},
                             {"name": "rod", "shape": {"type": "cylinder", "radius": 0.3, "height": 4},
                              "pose": {"position": [-2, 0, -2]}, "motion": twist((4, 0, 0), (0, 0.5, 0))},
                             sphere("ball", 0.4, (0, 0, 2), twist((0, 0, -1)))],
                  "pairs": "all"},
        "keyframes": {"time": {"start": 0, "end": 2, "step": 0.02},
                      "bodies": [{"name": "post", "shape": {"type": "cylinder", "radius": 1, "height": 3}},
                                 {"name": "ball", "shape": {"type": "sphere", "radius": 0.5},
                                  "motion": {"type": "keyframes", "keyframes": [
                                      {"t": 0, "position": [-3, 1.2, 1], "quaternion": [1, 0, 0, 0]},
                                      {"t": 1, "position": [0, 1.8, 2], "quaternion": [0.7071067811865476, 0, 0, 0.7071067811865476]},
                                      {"t": 2, "position": [3, 1.2, 3.5], "quaternion": [0, 0, 0, 1]}]}}]},
        "two_solids": {"time": {"start": 0, "end": 1, "step": 0.02},
                       "units": "mm",
                       "bodies": [{"name": "balls", "file": str(balls)},
                                  {"name": "probe", "shape": {"type": "point"},
                                   "pose": {"position": [3, -2, 0]}, "motion": twist((-5, 4, 0))}],
                       "pairs": [["balls", "probe"]]},
    }
    return [write_scene(folder / f"{name}.json", scene) for name, scene in scenes.items()]


def write_small(path, offset):
    """A small scene of its own (for stems that clash)."""
    return write_scene(path, {"time": {"start": 0, "end": 0.5, "step": 0.01},
                              "bodies": [sphere("A", 1), sphere("B", 0.25, (offset, 0, 0), twist((-1, 0.5, 0)))]})
