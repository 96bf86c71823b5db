#!/usr/bin/env python3
"""Exudyn peer, problem williams_toggle: flexmbd's examples/williams_toggle.toml (validation S05).

The half model of the Williams toggle frame in SI units: one member from the apex (0, 9.8044 mm)
to the clamped support (328.752 mm, 0); rectangular section b = 19.1262 mm (out of plane, z) x
h = 6.1722 mm (in plane); E = 71.016 GPa, nu = 0.3. The apex holds the symmetry conditions (x,
z and all rotations held, y free); half the apex load, P/2, acts downward (-y).

Model: N x ObjectBeamGeometricallyExact on NodeRigidBodyEP nodes (Euler parameters), the first
node at the apex, the last at the clamp; the nodes' reference frames have their x axis along
the member (a rotation about z). Clamp: a GenericJoint to ground, all six axes; apex: a
GenericJoint to ground with the translations x, z and the three rotations constrained (the
joints' node-side frames are the global axes, MarkerNodeRigid localHT). Exudyn's beam is
shear-deformable (Simo-Reissner); flexmbd's example is Euler-Bernoulli, so the shear stiffness
ks*GA is set large, --ga (default 100 x EA = 8.4e8 N: GA L^2/EI = 3.4e6 with the member length
L; the physical ks*GA is 2.7e6 N). Between 8.4e7 and 2.5e9 N the path changes by less than
1e-4 relative. Torsion GJ = G J of the rectangle (irrelevant in the plane).

Modes (--mode):
  load  load control: the dead apex force P/2 (--load P, total, N) scaled by Exudyn's load
        factor, SolveStatic with numberOfLoadSteps = --steps and adaptiveStep = True (Exudyn's
        automatic step reduction after a failed Newton solve; adaptiveStepIncrease 2). Load
        control cannot follow the descending branch: past the limit load Newton either jumps
        to the far branch or fails.
  disp  displacement control: the apex y is prescribed too (the apex GenericJoint constrains
        all six axes), its offset stepped by the joint's offsetUserFunction, y = -stroke * t
        over Exudyn's static quasi-time t in [0, 1] (--stroke, m); the reaction of the joint's
        y axis is P/2. Same SolveStatic settings.

Every accepted step (PostStepUserFunction) records (load factor, apex deflection delta [m],
total load P = 2 x (half-model apex force) [N]); step 0 is the unloaded state. Newton:
Exudyn's defaults (relativeTolerance 1e-8, absoluteTolerance 1e-10, maxIterations 25); when a
solve fails it is repeated with 1e-6 and then 1e-4 (--rtol; the peer kit's static scripts do the
same). With the stiff shear the residual stalls at a round-off floor of a few 1e-6 N, above
1e-8 of the first step's residual under load control, so that attempt fails in the first step
(under a stroke the first residual is large and 1e-8 of it is reached). t_solve_s is
SolveStatic of the successful attempt alone (model built, in process); t_total_s adds the
model building and the failed attempts, whose paths are summarised in "attempts".
TOGGLE_VERBOSE=2 in the environment shows Exudyn's Newton iterations on stderr.

Peer kit: peercommon.py is imported from --peers DIR or $FLEXMBD_PEERS_DIR (bench/README.md).

Usage: toggle_exudyn.py --peers DIR [--n 20] [--mode load|disp] [--load P] [--stroke S] [--steps K]
       [--rtol 1e-8 1e-6 1e-4] [--ga GA]
Prints one JSON line per N.
"""
import math
import os
import sys

sys.dont_write_bytecode = True


def _peers_dir():
    """--peers DIR (taken out of argv before peercommon's parser sees it) or $FLEXMBD_PEERS_DIR."""
    d = os.environ.get("FLEXMBD_PEERS_DIR")
    for i, a in enumerate(sys.argv):
        if a == "--peers" and i + 1 < len(sys.argv):
            d = sys.argv[i + 1]
            del sys.argv[i:i + 2]
            break
        if a.startswith("--peers="):
            d = a.split("=", 1)[1]
            del sys.argv[i]
            break
    if not d:
        sys.exit("toggle_exudyn.py: give the peer kit as --peers DIR or $FLEXMBD_PEERS_DIR "
                 "(bench/README.md)")
    return d


sys.path.insert(0, _peers_dir())
import peercommon as pc  # noqa: E402

# Problem data (SI): examples/williams_toggle.toml
HALF_SPAN, RISE = 0.328752, 0.0098044
B, H = 0.0191262, 0.0061722           # out of plane (z), in plane
E, NU = 71.016e9, 0.3
G = E / (2 * (1 + NU))
AREA = B * H
I_IN = B * H**3 / 12                  # bending in the plane of the frame (about z)
I_OUT = H * B**3 / 12                 # out of plane (about the local y)
J_RECT = B * H**3 / 3 * (1 - 0.630 * H / B)
GA_DEFAULT = 100 * E * AREA           # shear-rigid: GA L^2/EI = 3.4e6 with the member length
P_07 = 88.184 * 4.4482216152605      # total load at delta = 0.7 in (validation.md S05) [N]


def build(mbs, N, ga, mode, load_half, stroke):
    import numpy as np
    import exudyn as exu
    import exudyn.utilities as eu
    L = math.hypot(HALF_SPAN, RISE)
    alpha = math.atan2(-RISE, HALF_SPAN)          # member direction apex -> clamp
    Rz = eu.RotationMatrixZ(alpha)
    ep0 = list(eu.RotationMatrix2EulerParameters(Rz))
    sd = exu.BeamSection()
    sd.stiffnessMatrix = np.diag([E * AREA, ga, ga, G * J_RECT, E * I_OUT, E * I_IN])
    sd.massPerLength = 2700.0 * AREA               # irrelevant for statics
    sd.inertia = 2700.0 * np.diag([I_IN + I_OUT, I_OUT, I_IN])
    apex = np.array([0.0, RISE, 0.0])
    d = np.array([HALF_SPAN, -RISE, 0.0]) / L
    nodes = []
    for k in range(N + 1):
        p = apex + d * (L * k / N)
        nodes.append(mbs.AddNode(eu.NodeRigidBodyEP(referenceCoordinates=list(p) + ep0)))
        if k:
            mbs.AddObject(eu.ObjectBeamGeometricallyExact(nodeNumbers=[nodes[-2], nodes[-1]],
                                                          length=L / N, sectionData=sd))
    # joint frames on the node side: the global axes (node frame turned back by Rz^T)
    ht_back = exu.HT(rotation=Rz.T, translation=[0.0, 0.0, 0.0])

    def ground_joint(node, pos, axes, offset_fn=None):
        ng = mbs.AddNode(eu.NodePointGround(referenceCoordinates=list(pos)))
        mg = mbs.AddMarker(eu.MarkerNodeRigid(nodeNumber=ng))
        mn = mbs.AddMarker(eu.MarkerNodeRigid(nodeNumber=node, localHT=ht_back))
        kw = {"offsetUserFunction": offset_fn} if offset_fn else {}
        return mbs.AddObject(eu.GenericJoint(markerNumbers=[mg, mn], constrainedAxes=axes, **kw))

    ground_joint(nodes[-1], apex + d * L, [1, 1, 1, 1, 1, 1])
    if mode == "load":
        j_apex = ground_joint(nodes[0], apex, [1, 0, 1, 1, 1, 1])
        m_apex = mbs.AddMarker(eu.MarkerNodeRigid(nodeNumber=nodes[0]))
        mbs.AddLoad(eu.Force(markerNumber=m_apex, loadVector=[0.0, -load_half, 0.0]))
    else:
        def offset(mbs_, t, item, par):
            return [0.0, -stroke * t, 0.0, 0.0, 0.0, 0.0]
        j_apex = ground_joint(nodes[0], apex, [1, 1, 1, 1, 1, 1], offset)
    return nodes, j_apex


def solve_case(N, a, rtol):
    import exudyn as exu
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    tm = pc.Timer()
    load_half = a.load / 2
    nodes, j_apex = build(mbs, N, a.ga, a.mode, load_half, a.stroke)
    mbs.Assemble()
    t_build = tm.lap()
    path = [[0.0, 0.0, 0.0]]          # (load factor or stroke fraction, delta [m], P total [N])
    attempts = [0]

    def pre_step(mbs_, t):
        attempts[0] += 1
        return True

    def post_step(mbs_, t):
        if t <= 0.0:      # Exudyn calls it once for the initial state, before step 1
            return True
        uy = mbs_.GetNodeOutput(nodes[0], exu.OutputVariableType.Displacement)[1]
        if a.mode == "load":
            P = t * a.load
        else:   # the joint's force on the node side acts on marker 1; the apex force is its negative
            f = mbs_.GetObjectOutput(j_apex, exu.OutputVariableType.ForceLocal)
            P = 2 * abs(f[1])
        path.append([t, -uy, P])
        return True

    mbs.SetPreStepUserFunction(pre_step)
    mbs.SetPostStepUserFunction(post_step)
    s = pc.exu_quiet_settings()
    s.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    s.staticSolver.numberOfLoadSteps = a.steps
    s.staticSolver.adaptiveStep = True
    s.staticSolver.newton.relativeTolerance = rtol
    if os.environ.get("TOGGLE_VERBOSE"):
        s.staticSolver.verboseMode = int(os.environ["TOGGLE_VERBOSE"])
    tm.lap()
    try:
        ok = mbs.SolveStatic(s)
    except (exu.SolverError, SystemError, RuntimeError):
        ok = False
    t_solve = tm.lap()
    it = mbs.sys["staticSolver"].it
    return dict(ok=bool(ok), rtol=rtol, t_build=t_build, t_solve=t_solve, newton=int(it.newtonStepsCount),
                jac=int(it.newtonJacobiCount), attempts=attempts[0], path=path)


def main():
    p = pc.parser(__doc__.split("\n")[0], default_sizes=[20])
    p.add_argument("--mode", choices=["load", "disp"], default="load")
    p.add_argument("--load", type=float, default=P_07,
                   help="total apex load P [N] (the half model carries P/2); default: the "
                        "reference load at delta = 0.7 in, 88.184 lbf = %.2f N" % P_07)
    p.add_argument("--stroke", type=float, default=0.7 * 0.0254,
                   help="apex stroke [m] in --mode disp (default 0.7 in)")
    p.add_argument("--steps", type=int, default=20, help="numberOfLoadSteps (default 20)")
    p.add_argument("--rtol", type=float, nargs="+", default=[1e-8, 1e-6, 1e-4],
                   help="Newton relative tolerances tried in turn until a solve succeeds "
                        "(default 1e-8 1e-6 1e-4, as the peer kit's static scripts)")
    p.add_argument("--ga", type=float, default=GA_DEFAULT,
                   help="shear stiffness ks*G*A [N] (default 100 x EA = %.3g)" % GA_DEFAULT)
    a = p.parse_args()
    pc.setup_run(a)
    import exudyn as exu
    for N in a.sizes:
        base = {"peer": "exudyn", "peer_version": exu.__version__, "problem": "williams_toggle",
                "variant": "GE3D-EP-" + a.mode, "n_elements": N, "n_dof": 7 * (N + 1),
                "mode": a.mode, "load_n": a.load if a.mode == "load" else None,
                "stroke_m": a.stroke if a.mode == "disp" else None, "load_steps": a.steps,
                "ga": a.ga}
        try:
            attempts, t_total = [], 0.0
            for rtol in a.rtol:
                r = solve_case(N, a, rtol)
                t_total += r["t_build"] + r["t_solve"]
                last = r["path"][-1]
                attempts.append({"rtol": rtol, "ok": r["ok"], "steps": len(r["path"]) - 1,
                                 "newton": r["newton"], "last_delta_m": pc.sig(last[1], 9),
                                 "last_load_n": pc.sig(last[2], 9),
                                 "t_solve_s": pc.sig(r["t_solve"], 6)})
                if r["ok"]:
                    break
            rec = dict(base, status="ok" if r["ok"] else "failed",
                       converged_default=attempts[0]["ok"], rtol=r["rtol"],
                       wall_s=r["t_build"] + r["t_solve"], t_build_s=r["t_build"],
                       t_solve_s=r["t_solve"], t_total_s=t_total, attempts=attempts,
                       steps=len(r["path"]) - 1,
                       step_attempts=r["attempts"], newton_iterations=r["newton"],
                       jacobians=r["jac"], last_factor=last[0], last_delta_m=last[1],
                       last_load_n=last[2],
                       path=[[pc.sig(t, 9), pc.sig(dl, 9), pc.sig(P, 9)] for t, dl, P in r["path"]])
        except Exception as e:  # noqa: BLE001
            rec = dict(base, status="failed", error=f"{type(e).__name__}: {e}"[:500])
        pc.emit(rec)


if __name__ == "__main__":
    main()
