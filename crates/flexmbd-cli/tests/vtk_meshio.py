#!/usr/bin/env python3
"""Independent check of flexmbd's ParaView output with meshio (docs/visualisation.md).

Usage: vtk_meshio.py DIR EXPECT.json   -- or, without arguments, generate the files with
`flexmbd export ...` and `flexmbd simulate ... --vtk` into a temporary directory first
($FLEXMBD names the binary; default `cargo run --release -p flexmbd-cli`).

EXPECT.json maps a .vtu file name (relative to DIR) to
{"points": N, "cells": M, "point_data": {name: components}, "cell_data": {name: components}}.

Without arguments it also reads the simulation's collection simulate.pvd (with the standard
library's XML parser; meshio has no .pvd reader): one data set per output time with the times
the options ask for, every file of it read by meshio, the points at t = 0 at the nodes of
examples/pendulum.toml and the bar's length kept at the last time.
"""
import json
import math
import os
import subprocess
import sys
import tempfile
import tomllib
import xml.etree.ElementTree as ET

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
# the simulation: examples/pendulum.toml to T_END with outputs every OUTPUT_STEP
T_END, OUTPUT_STEP = 0.5, 0.01


def check(directory, expect):
    import meshio

    for name, exp in expect.items():
        m = meshio.read(os.path.join(directory, name))
        assert len(m.points) == exp["points"], (name, len(m.points), exp["points"])
        lines = [c for c in m.cells if c.type == "line"]
        assert len(lines) == len(m.cells), (name, [c.type for c in m.cells])
        ncells = sum(len(c.data) for c in lines)
        assert ncells == exp["cells"], (name, ncells, exp["cells"])
        for field, comps in exp["point_data"].items():
            a = m.point_data[field]
            assert a.shape[0] == exp["points"], (name, field, a.shape)
            assert (a.shape[1] if a.ndim > 1 else 1) == comps, (name, field, a.shape)
        for field, comps in exp["cell_data"].items():
            a = m.cell_data[field][0]
            assert a.shape[0] == exp["cells"], (name, field, a.shape)
            assert (a.shape[1] if a.ndim > 1 else 1) == comps, (name, field, a.shape)
        print(f"ok {name}: {len(m.points)} points, {ncells} cells, "
              f"{len(m.point_data)} point fields, {len(m.cell_data)} cell fields")


def check_simulation(directory):
    """simulate.pvd: the output times, every file readable, the pendulum's geometry."""
    import meshio

    tree = ET.parse(os.path.join(directory, "simulate.pvd"))
    sets = tree.getroot().findall("./Collection/DataSet")
    n = round(T_END / OUTPUT_STEP) + 1
    assert len(sets) == n, (len(sets), n)
    meshes = []
    for k, d in enumerate(sets):
        t = float(d.get("timestep"))
        assert abs(t - k * OUTPUT_STEP) < 1e-12, (k, t)
        m = meshio.read(os.path.join(directory, d.get("file")))
        assert len(m.points) == 3 and sum(len(c.data) for c in m.cells) == 2, d.get("file")
        for field in ("displacement", "rotation", "velocity", "angular_velocity"):
            assert m.point_data[field].shape == (3, 3), (d.get("file"), field)
        meshes.append(m)
    with open(os.path.join(ROOT, "examples", "pendulum.toml"), "rb") as f:
        nodes = tomllib.load(f)["nodes"]
    pin, tip = nodes["pin"], nodes["tip"]
    first, last = meshes[0], meshes[-1]
    for p in (pin, tip):
        assert min(math.dist(p, q) for q in first.points) < 1e-12, ("t = 0", p)
    assert abs(first.point_data["velocity"]).max() == 0.0, "released from rest"
    length = math.dist(pin, tip)
    reach = max(math.dist(pin, q) for q in last.points)
    assert abs(reach - length) < 1e-6, ("the bar's length at the end", reach, length)
    assert max(abs(q[2] - pin[2]) for q in last.points) > 0.5 * length, "the bar has swung down"
    print(f"ok simulate.pvd: {n} output times from 0 to {T_END} s, every file read; "
          f"tip at {[round(float(v), 4) for v in last.points[[math.dist(pin, q) for q in last.points].index(reach)]]}")


def generate(tmp):
    """Export the three example analyses and simulate the pendulum; returns (dir,
    expectations)."""
    root = ROOT
    # FLEXMBD: an already built binary (.ci/run passes the one `cargo test` built)
    exe = os.environ.get("FLEXMBD")
    flexmbd = ([os.path.abspath(exe)] if exe else
               ["cargo", "run", "-q", "--release", "-p", "flexmbd-cli", "--"])
    run = flexmbd + ["export"]
    for model, analysis in [("twelve_truss", "check"), ("parallel_leaf_stroke", "static"),
                            ("strip_f01", "modes")]:
        subprocess.run(run + [f"examples/{model}.toml", "--analysis", analysis,
                              "--vtk", os.path.join(tmp, analysis)],
                       check=True, cwd=root, stdout=subprocess.DEVNULL)
    subprocess.run(flexmbd + ["simulate", "examples/pendulum.toml", "--t-end", str(T_END),
                              "--output-step", str(OUTPUT_STEP),
                              "--vtk", os.path.join(tmp, "simulate")],
                   check=True, cwd=root, stdout=subprocess.DEVNULL)
    base = {"element": 1, "element_type": 1, "section": 2}
    step_cells = dict(base, e=6, sigma=6, max_stress=1)
    step_points = {"displacement": 3, "rotation": 3}
    # twelve_truss: 8 nodes, 12 trusses, 1 motion, 1 self-stress (the paper's example)
    # parallel_leaf_stroke: 11 nodes (2 × 4 segments), 8 beams + a 3-node rigid body (2 lines)
    # strip_f01: 11 nodes, 10 beams
    exp = {
        "check/check.vtu": {"points": 8, "cells": 12,
                            "point_data": {"motion_1": 3, "motion_1_angular": 3},
                            "cell_data": dict(base, self_stress_1=1)},
        "static/static_0000.vtu": {"points": 11, "cells": 10, "point_data": step_points,
                                   "cell_data": step_cells},
        "static/static_0020.vtu": {"points": 11, "cells": 10, "point_data": step_points,
                                   "cell_data": step_cells},
        "modes/mode_001.vtu": {"points": 11, "cells": 10,
                               "point_data": dict(step_points, mode=3, mode_rotation=3),
                               "cell_data": step_cells},
        # pendulum: 3 nodes (pin, tip and the node between the 2 segments), 2 beams
        "simulate/sim_0000.vtu": {"points": 3, "cells": 2,
                                  "point_data": dict(step_points, velocity=3, angular_velocity=3),
                                  "cell_data": step_cells},
        "simulate/sim_0050.vtu": {"points": 3, "cells": 2,
                                  "point_data": dict(step_points, velocity=3, angular_velocity=3),
                                  "cell_data": step_cells},
    }
    return tmp, exp


def main():
    if len(sys.argv) == 3:
        with open(sys.argv[2]) as f:
            check(sys.argv[1], json.load(f))
    else:
        with tempfile.TemporaryDirectory() as tmp:
            check(*generate(tmp))
            check_simulation(os.path.join(tmp, "simulate"))
    print("meshio check passed")


if __name__ == "__main__":
    main()
