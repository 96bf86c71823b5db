#!/usr/bin/env pvpython
"""ParaView itself reads flexmbd's VTK output (docs/visualisation.md).

Run with ParaView's Python (Debian: `apt-get install paraview python3-paraview`):

    FLEXMBD=target/debug/flexmbd pvpython crates/flexmbd-cli/tests/vtk_paraview.py

It exports the same example analyses as vtk_meshio.py (its `generate`), opens every .vtu and the
.pvd collections with ParaView's own readers (`OpenDataFile`), and checks point and cell counts,
the fields and their components, and the time steps of the collections. .ci/run runs it when
`pvpython` is installed (ParaView is a 440 MB install, so CI does not install it itself; the
meshio check always runs).
"""
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from vtk_meshio import generate  # noqa: E402

from paraview.simple import OpenDataFile, UpdatePipeline, servermanager  # noqa: E402


def fetch(path):
    reader = OpenDataFile(path)
    assert reader is not None, f"ParaView has no reader for {path}"
    UpdatePipeline(proxy=reader)
    return reader, servermanager.Fetch(reader)


def arrays(data):
    return {data.GetArrayName(i): data.GetArray(i).GetNumberOfComponents()
            for i in range(data.GetNumberOfArrays())}


def check(directory, expect):
    for name, exp in expect.items():
        _, d = fetch(os.path.join(directory, name))
        assert d.GetNumberOfPoints() == exp["points"], (name, d.GetNumberOfPoints())
        assert d.GetNumberOfCells() == exp["cells"], (name, d.GetNumberOfCells())
        for kind, got in (("point_data", arrays(d.GetPointData())),
                          ("cell_data", arrays(d.GetCellData()))):
            for field, comps in exp[kind].items():
                assert got.get(field) == comps, (name, kind, field, got)
        print(f"ok {name}: {d.GetNumberOfPoints()} points, {d.GetNumberOfCells()} cells")
    # the collections: one time step per load step / mode
    for pvd, steps in (("static/static.pvd", 21), ("modes/modes.pvd", None)):
        reader, d = fetch(os.path.join(directory, pvd))
        times = list(reader.TimestepValues or [])
        assert d.GetNumberOfPoints() > 0, pvd
        if steps is not None:
            assert len(times) == steps, (pvd, times)
        else:
            assert len(times) >= 1, (pvd, times)
        print(f"ok {pvd}: {len(times)} time steps")


def main():
    with tempfile.TemporaryDirectory() as tmp:
        check(*generate(tmp))
    print("ParaView check passed")


if __name__ == "__main__":
    main()
