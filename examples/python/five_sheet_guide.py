"""The paper's straight guide on five folded sheets (§5, Fig. 6a-b), built in Python.

The same model as examples/paper_dynamic_5_sheets.toml (read its header for the geometry and
the data): a rigid cylinder (0.312 kg, centre node c) on the x axis, held by five folded
sheets of steel 50 x 20 x 0.2 mm, three at x = -0.1 and two at x = +0.1. Each folded sheet
is a base sheet b -> f (clamped at b) and a radial sheet f -> a (a on the cylinder's rim),
folded along the line through f tangent to the circle of radius 80 mm.

Run from anywhere: ``python five_sheet_guide.py [OUTPUT_DIR]``. It prints the check (the
x translation and the folds' five internal modes are the motions) and the first modes (paper:
8.2 Hz, then about 20 times higher), then sweeps the sheet thickness and saves a plot of the
first two natural frequencies, five_sheet_guide_sweep.png, in OUTPUT_DIR (default: here).
"""

import math
import pathlib
import sys

import numpy as np

import flexmbd

NAME = "Straight guide, five folded sheets: dynamics (paper §5, Fig. 6a-b)"
R_FOLD, R_PART, L_SHEET = 0.08, 0.03, 0.05  # m
# (end of the part along x, angle of the fold's place about the x axis [deg])
SHEETS = [(-0.1, 90), (-0.1, 210), (-0.1, 330), (0.1, 90), (0.1, 210)]


def build(t=0.2e-3):
    """The guide with sheets of thickness ``t`` [m]."""
    m = flexmbd.Model(NAME)
    m.add_node("c", (0.0, 0.0, 0.0), rot=True)  # centre of the moving part
    for k, (x_end, theta) in enumerate(SHEETS, start=1):
        cos, sin = math.cos(math.radians(theta)), math.sin(math.radians(theta))
        outward = math.copysign(L_SHEET, x_end)
        m.add_node(f"b{k}", (x_end + outward, R_FOLD * cos, R_FOLD * sin))
        m.add_node(f"f{k}", (x_end, R_FOLD * cos, R_FOLD * sin))
        m.add_node(f"a{k}", (x_end, R_PART * cos, R_PART * sin))
    for k in range(1, len(SHEETS) + 1):
        m.fix(f"b{k}")  # clamped: every degree of freedom
    m.add_material("steel", E=210e9, nu=0.3, rho=7800.0)
    m.add_section("sheet", "rectangle", w=0.02, t=t, shear=False)  # Euler-Bernoulli
    m.add_mass("c", 0.312)
    # an aluminium tube of 0.312 kg, outer radius 30 mm, length 200 mm, about c
    m.add_inertia("c", [2.5211e-4, 0.0, 0.0, 1.1661e-3, 0.0, 1.1661e-3])
    for k, (_, theta) in enumerate(SHEETS, start=1):
        # the fold line's direction: the sheets' local y axis
        w = (0.0, -math.sin(math.radians(theta)), math.cos(math.radians(theta)))
        for part, nodes in (("a", (f"b{k}", f"f{k}")), ("b", (f"f{k}", f"a{k}"))):
            m.add_beam(
                f"s{k}{part}", nodes, section="sheet", material="steel", orient=w, free=[2, 3, 4]
            )
    m.add_rigid("platform", ["c"] + [f"a{k}" for k in range(1, len(SHEETS) + 1)])
    return m


def main(out_dir="."):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    model = build()
    c = model.check()
    print(f"check: {c.classification}; {c.n_motions} motions, {c.n_self_stresses} self-stresses")
    modes = model.modes(count=4)
    print("modes [Hz]:", np.array2string(modes.frequencies, precision=1))

    thickness = np.linspace(0.1e-3, 0.4e-3, 7)
    f = []
    for t in thickness:
        model.set("sections.sheet.t", t)  # edit the document; the next analysis rebuilds
        f.append(model.modes(count=2).frequencies)
    f = np.array(f)
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(thickness * 1e3, f[:, 0], "o-", label="mode 1 (the guided x translation)")
    ax.plot(thickness * 1e3, f[:, 1], "s-", label="mode 2")
    ax.set_xlabel("sheet thickness t [mm]")
    ax.set_ylabel("natural frequency [Hz]")
    ax.set_yscale("log")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    ax.set_title("Five folded sheets: first two frequencies")
    out = pathlib.Path(out_dir) / "five_sheet_guide_sweep.png"
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print("saved", out)
    return thickness, f


if __name__ == "__main__":
    main(*sys.argv[1:2])
