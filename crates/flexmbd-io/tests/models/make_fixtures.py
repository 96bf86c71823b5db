#!/usr/bin/env python3
"""Writes the two SPACAR fixtures of flexmbd's own (run from this folder; the output is committed).

Both files are written for flexmbd's tests in the layouts that SPACAR Light writes (1.29: two
SPACAR nodes per user node, tab-separated columns, a VISUALIZATION block; 0.7: the end nodes
first, then the intermediate ones, old-style BEAMPROPS / CROSSTYPE / CROSSDIM lines). The data
are flexmbd's own (not taken from any file): a thin steel strip under an end moment and an
aluminium cantilever with an initial and an incremental tip force.
"""

# --- strip_end_moment.dat (SPACAR Light 1.29 layout) ---------------------------------------
# Steel strip 30 mm x 15 mm x 0.4 mm along x, 18 beams, clamped at x = 0, a pure moment
# Mz = 1 N.m on the node at x = 15 mm (index 9). E = 210 GPa, G = 81 GPa, rho = 7800 kg/m^3.
N, L = 18, 0.030
E, G, RHO, B, T = 210e9, 81e9, 7800.0, 0.015, 0.0004
A = B * T
IY = B * T**3 / 12.0  # about the axis in the strip's plane: the thin direction
IZ = T * B**3 / 12.0
J = B * T**3 / 3.0  # thin strip
out = [
    "#Dat-file written for flexmbd's tests in the layout of SPACAR Light 1.29 output",
    "#A steel strip 30 x 15 x 0.4 mm clamped at x = 0, a pure moment at x = 15 mm",
    "#flexmbd authors, MIT OR Apache-2.0",
    "",
    "",
    "#NODES\t Nn\t\t\tX\t\t\tY\t\t\tZ",
]
for i in range(N + 1):
    out.append(f"X\t\t{2 * i + 1:3d}\t\t\t{i * L / N:.6f}\t0.000000\t0.000000\t\t#node {i + 1}")
out += ["", "", "#ELEMENTS\t Ne\t\t Xp\t Rp\t Xq\t Rq\t\tOx\t\t\tOy\t\t\tOz"]
for k in range(1, N + 1):
    out.append(f"#element {k}")
    out.append(
        f"BEAM\t\t{k:3d}\t\t{2 * k - 1:3d}\t{2 * k:3d}\t{2 * k + 1:3d}\t{2 * k + 2:3d}"
        "\t\t0.000000\t0.000000\t1.000000\t\t#beam "
    )
out += ["", "", "#DEF#\t\t Ne\t\t d1\t d2\t d3\t d4\t d5\t d6"]
for k in range(1, N + 1):
    out.append(f"DYNE\t\t{k:3d}\t\t  3\t  4")
out += ["", "", "#FIXES\t Nn", "FIX\t\t  1", "FIX\t\t  2", "", "", "END", "HALT", "", ""]
out.append("#STIFFNESS\t Ne\tEA\t\t\t\t\t\t\tGJ\t\t\t\t\t\tEIy\t\t\t\t\t\tEIz\t\t\t\t\t\tShear Y\t\t\t\t\tShear Z")
for k in range(1, N + 1):
    out.append(
        f"ESTIFF\t\t{k:3d}\t{E * A:.15f}\t{G * J:20.15f}\t{E * IY:20.15f}\t{round(E * IZ, 9):20.15f}"
        f"\t{3.1e-7:20.15f}\t{1.2e-4:20.15f}"
    )
out += ["", "", "#MASS\t\t Ne\t\t\tM/L\t\t\t\t\t\tJxx/L\t\t\t\t\tJyy/L\t\t\t\t\tJzz/L\t\t\t\t\tJyz/L"]
for k in range(1, N + 1):
    out.append(
        f"EM\t\t\t{k:3d}\t\t{RHO * A:20.15f}\t{RHO * (IY + IZ):20.15f}\t{RHO * IY:20.15f}"
        f"\t{RHO * IZ:20.15f}\t{0.0:20.15f}"
    )
out += ["", "", "#ADDITIONAL PROPERTIES", "", "ITERSTEP\t10\t  5\t0.0000005\t1\t3\t0", "", ""]
out += ["#MOMENTS\t Nn\t\tMx\t\t\tMy\t\t\tMz", "DELXF\t\t 20\t\t0.000000\t0.000000\t1.000000\t"]
out += ["", "", "END", "END", "", "", "VISUALIZATION", "", "INITIAL", "COLOR\t\t0.20\t0.20\t0.20", ""]
ids = "".join(f"\t{k:3d}" for k in range(1, N + 1))
out += [f"BEAMPROPS{ids}", "CROSSTYPE\t  RECT", f"CROSSDIM\t  {B:.6f}\t{T:.6f}", ""]
out += [f"GRAPHICS{ids}", "FACECOLOR\t  120.000000 130.000000 140.000000", ""]
with open("strip_end_moment.dat", "w", newline="\n") as f:
    f.write("\n".join(out) + "\n")

# --- cantilever_light07.dat (SPACAR Light 0.7 layout) --------------------------------------
# Aluminium cantilever 0.6 m along x, 40 x 40 mm square, three beams, all six modes flexible;
# an initial lateral tip force XF (0, 200, 0) N and an incremental one DELXF (0, 0, -500) N.
E, G, RHO, S = 70e9, 26e9, 2700.0, 0.040
A, I = S * S, S**4 / 12.0
J = 0.1406 * S**4
out = [
    "#Dat-file written for flexmbd's tests in the layout of Spacar light version 0.7 output",
    "#An aluminium cantilever, 0.6 m, 40 x 40 mm, three beams",
    "",
    "",
    "#NODES\t Nn\t\t\tX\t\t\tY\t\t\tZ",
    "X\t\t  1\t\t\t0.000000\t0.000000\t0.000000\t\t#node 1",
    "X\t\t  3\t\t\t0.600000\t0.000000\t0.000000\t\t#node 2",
    "X\t\t  5\t\t\t0.200000\t0.000000\t0.000000\t\t#intermediate node",
    "X\t\t  7\t\t\t0.400000\t0.000000\t0.000000\t\t#intermediate node",
    "",
    "",
    "#ELEMENTS\t Ne\t\t Xp\t Rp\t Xq\t Rq\t\tOx\t\t\tOy\t\t\tOz",
    "#element\t  1",
    "BEAM\t\t  1\t\t  1\t  2\t  5\t  6\t\t0.000000\t0.000000\t1.000000\t\t#beam 1",
    "BEAM\t\t  2\t\t  5\t  6\t  7\t  8\t\t0.000000\t0.000000\t1.000000\t\t#beam 2",
    "BEAM\t\t  3\t\t  7\t  8\t  3\t  4\t\t0.000000\t0.000000\t1.000000\t\t#beam 3",
    "",
    "",
    "#DEF#\t\t Ne\t\t d1\t d2\t d3\t d4\t d5\t d6",
]
for k in range(1, 4):
    out.append(f"DYNE\t\t{k:3d}\t\t  1\t  2\t  3\t  4\t  5\t  6")
out += ["", "", "#FIXES\t Nn", "FIX\t\t  1", "FIX\t\t  2", "", "", "END", "HALT", ""]
out.append("#STIFFNESS\t Ne\t\tEA\t\t\t\t\t   GJt\t\t\t   EIy\t\t\t   EIz\t\t\t\t   Shear Y\t\t   Shear Z")
for k in range(1, 4):
    out.append(
        f"ESTIFF\t\t{k:3d}\t{E * A:20.6f}\t{G * J:15.6f}\t{E * I:15.6f}\t{E * I:15.6f}"
        f"\t{0.000857:15.6f}\t{0.000857:15.6f}"
    )
out += ["", "", "#MASS\t\t Ne\t\t M/L\t\t  Jxx/L\t\t  Jyy/L\t\t  Jzz/L\t\t  Jyz/L"]
for k in range(1, 4):
    out.append(
        f"EM\t\t\t{k:3d}\t\t{RHO * A:10.6f}\t{RHO * 2 * I:10.6f}\t{RHO * I:10.6f}\t{RHO * I:10.6f}\t{0.0:10.6f}"
    )
out += ["", "", "#FORCES\t\t Nn\t\tFx\t\t\tFy\t\t\tFz"]
out += ["DELXF\t\t  3\t\t0.000000\t0.000000\t-500.000000", "XF\t\t\t  3\t\t0.000000\t200.000000\t0.000000"]
out += ["", "", "#ADDITIONAL PROPERTIES", "", "ITERSTEP\t10\t  6\t0.0000005\t1\t3\t  6", "", ""]
out += ["END", "END", "", "", "VISUALIZATION", "", "BEAMPROPS\t  1\t  2\t  3", "CROSSTYPE\t  RECT"]
out += [f"CROSSDIM\t  {S:.6f}\t{S:.6f}"]
with open("cantilever_light07.dat", "w", newline="\n") as f:
    f.write("\n".join(out) + "\n")
