#!/usr/bin/env python3
"""Write the TOML model of a 3D lattice of rigid pin-jointed trusses (bench, issue 14).

    python3 bench/lattice_model.py K OUT.toml
    python3 bench/lattice_model.py --strip N OUT.toml   # N rigid beams: a 6N x 6N regular Dcc

Nodes on the (K+1)^3 grid with unit spacing, a truss on every cube edge and one diagonal per
face (from the face's lowest corner to its highest), the bottom layer (z = 0) supported; bars
between two supported nodes are left out (they would be rows of zeros). The same model as the
`lattice` test helper of flexmbd-core's kinematics tests.
"""
import sys


def lattice(k):
    def name(i, j, l):
        return f"n{i}_{j}_{l}"

    nodes = [(i, j, l) for l in range(k + 1) for j in range(k + 1) for i in range(k + 1)]
    bars = []

    def bar(p, q):
        if p[2] == 0 and q[2] == 0:
            return
        bars.append((p, q))

    r = range(k + 1)
    for (i, j, l) in nodes:
        # edges along x, y, z
        if i < k:
            bar((i, j, l), (i + 1, j, l))
        if j < k:
            bar((i, j, l), (i, j + 1, l))
        if l < k:
            bar((i, j, l), (i, j, l + 1))
        # one diagonal per face whose lowest corner is this node
        if i < k and j < k:
            bar((i, j, l), (i + 1, j + 1, l))
        if i < k and l < k:
            bar((i, j, l), (i + 1, j, l + 1))
        if j < k and l < k:
            bar((i, j, l), (i, j + 1, l + 1))
    out = [f'[model]\nname = "lattice k = {k}"\n', "[nodes]"]
    for (i, j, l) in nodes:
        out.append(f"{name(i, j, l)} = [{float(i)}, {float(j)}, {float(l)}]")
    out.append("\n[fix]")
    for (i, j, l) in nodes:
        if l == 0:
            out.append(f'{name(i, j, l)} = "all"')
    out.append("")
    for t, (p, q) in enumerate(bars):
        out.append(f'[[truss]]\nid = "b{t + 1}"\nnodes = ["{name(*p)}", "{name(*q)}"]')
    return "\n".join(out) + "\n"


def strip(n):
    """A chain of n rigid beams along x, clamped at the first node (the kinematics tests'
    `strip(n, &[], &[])`, with unit spacing)."""
    out = [f'[model]\nname = "strip of {n} rigid beams"\n', "[nodes]"]
    for i in range(n + 1):
        out.append(f"s{i} = {{ x = [{float(i)}, 0.0, 0.0], rot = true }}")
    out.append('\n[fix]\ns0 = "all"\n')
    for i in range(n):
        out.append(f'[[beam]]\nid = "beam{i}"\nnodes = ["s{i}", "s{i + 1}"]\norient = [0.0, 1.0, 0.0]')
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    args = sys.argv[1:]
    if len(args) == 3 and args[0] == "--strip":
        open(args[2], "w").write(strip(int(args[1])))
    elif len(args) == 2:
        open(args[1], "w").write(lattice(int(args[0])))
    else:
        sys.exit(__doc__)
