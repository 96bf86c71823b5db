"""The five-folded-sheet guide's state space in python-control, and its Bode plot.

The input is a force on the moving part along the guided direction x (``c:x``), the output its
displacement along x. The state space keeps the lowest six modes (1 % modal damping each) with
the static flexibility of the dropped ones added to D. At low frequency the compliance is that
of the guide's x stiffness (about 1/840 m/N, see examples/paper_dynamic_5_sheets.toml); the
first resonance is the 8.2 Hz mode.

Run from anywhere: ``python bode.py [OUTPUT_DIR]``; it saves five_sheet_guide_bode.png there.
Needs python-control and matplotlib (``pip install control matplotlib``).
"""

import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from five_sheet_guide import build  # noqa: E402 (the guide, built in Python)


def main(out_dir="."):
    import matplotlib

    matplotlib.use("Agg")
    import control
    import matplotlib.pyplot as plt

    ss = build().state_space(
        inputs=["c:x"], outputs=["c:x"], modes=6, damping=0.01, static_correction=True
    )
    sys_ = ss.to_control()
    print(sys_)
    print("DC gain [m/N]:", control.dcgain(sys_))
    omega = 2 * np.pi * np.geomspace(0.5, 2000.0, 600)
    plt.figure(figsize=(6, 5))
    control.bode_plot(sys_, omega, Hz=True, dB=True)
    out = pathlib.Path(out_dir) / "five_sheet_guide_bode.png"
    plt.savefig(out, dpi=120)
    print("saved", out)
    return sys_


if __name__ == "__main__":
    main(*sys.argv[1:2])
