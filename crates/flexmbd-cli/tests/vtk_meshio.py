#!/usr/bin/env python3
"""Independent check of flexmbd's ParaView output with meshio (docs/visualisation.md).

Usage: vtk_meshio.py DIR EXPECT.json   -- or, without arguments, generate the files with
`flexmbd export ...` into a temporary directory first ($FLEXMBD names the binary; default
`cargo run --release -p flexmbd-cli`).

EXPECT.json maps a .vtu file name (relative to DIR) to
{"points": N, "cells": M, "point_data": {name: components}, "cell_data": {name: components}}.
"""
import json
import os
import subprocess
import sys
import tempfile


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


def generate(tmp):
    """Export the three example analyses; returns (dir, expectations)."""
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
    # FLEXMBD: an already built binary (.ci/run passes the one `cargo test` built)
    exe = os.environ.get("FLEXMBD")
    run = ([os.path.abspath(exe)] if exe else
           ["cargo", "run", "-q", "--release", "-p", "flexmbd-cli", "--"]) + ["export"]
    for model, analysis in [("twelve_truss", "check"), ("parallel_leaf_stroke", "static"),
                            ("strip_f01", "modes")]:
        subprocess.run(run + [f"examples/{model}.toml", "--analysis", analysis,
                              "--vtk", os.path.join(tmp, analysis)],
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
    }
    return tmp, exp


def main():
    if len(sys.argv) == 3:
        with open(sys.argv[2]) as f:
            check(sys.argv[1], json.load(f))
    else:
        with tempfile.TemporaryDirectory() as tmp:
            check(*generate(tmp))
    print("meshio check passed")


if __name__ == "__main__":
    main()
