#!/usr/bin/env python3
"""Exudyn peer, problem cantilever_k3: flexmbd's large-deflection cantilever bench, same inputs.

Derived from the peer kit's strip_static_exudyn.py (same Exudyn model, solver and retry logic;
peercommon.py from that directory supplies the CLI, scratch dir, JSON output and the elastica).
Only the problem data differ: the shared script solves the steel strip (L = 50 mm, EI = 2.8e-3,
EA L^2/EI = 7.5e5, k = 1, 2, 5, 10, max(5, 2k) load steps); this one solves exactly the case of
crates/flexmbd-core/benches/cantilever.rs:

  L = 1, EI_y = EI_z = 1, GJ = 1, EA = 1e7, straight along x, clamped at x = 0, dead tip force
  P = k EI/L^2 = 3 perpendicular to the axis (here -z; the section is symmetric), 10 load steps.

flexmbd's beam is shear-rigid (BeamProps default shear = 0); Exudyn's ObjectBeamGeometricallyExact
is shear-deformable, so the shear stiffness is set to ks*GA = 1e7 (validation.md S01: EA L^2/EI and
GA L^2/EI >= 1e7 reproduce the table), changeable with --ga.

Model: N x ObjectBeamGeometricallyExact on NodeRigidBodyEP nodes, GenericJoint clamp, SolveStatic
with EigenSparse, numberOfLoadSteps = 10, adaptiveStep = True, Newton relativeTolerance 1e-8
(Exudyn's default) and, if that fails, 1e-6 then 1e-4 (as the shared script). "converged_default"
says whether the first attempt (Exudyn's defaults) converged; t_solve_s is the successful attempt,
t_total_s includes the failed ones.

Usage: cantilever_k3_exudyn.py --n N [N ...] [--k 3] [--rtol 1e-8 1e-6 1e-4] [--load-steps 10]
Prints one JSON line per N.
"""
import os
import sys

sys.dont_write_bytecode = True
if not os.environ.get("FLEXMBD_PEERS_DIR"):
    sys.exit("cantilever_k3_exudyn.py: set FLEXMBD_PEERS_DIR to the peer kit (bench/README.md); "
             "bench/run.sh --peers DIR does it")
sys.path.insert(0, os.environ["FLEXMBD_PEERS_DIR"])
import peercommon as pc  # noqa: E402

L, EI, GJ, EA = 1.0, 1.0, 1.0, 1e7


def solve_case(N, k, rtol, n_steps, ga):
    import numpy as np
    import exudyn as exu
    import exudyn.utilities as eu
    P = k * EI / L**2
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    tm = pc.Timer()
    sd = exu.BeamSection()
    sd.stiffnessMatrix = np.diag([EA, ga, ga, GJ, EI, EI])
    sd.massPerLength = 1.0                       # irrelevant for statics
    sd.inertia = np.diag([2e-6, 1e-6, 1e-6])
    rot0 = list(eu.eulerParameters0)
    lElem = L / N
    nodes = [mbs.AddNode(eu.NodeRigidBodyEP(referenceCoordinates=[0, 0, 0] + rot0))]
    for i in range(N):
        nodes.append(mbs.AddNode(eu.NodeRigidBodyEP(referenceCoordinates=[lElem * (i + 1), 0, 0] + rot0)))
        mbs.AddObject(eu.ObjectBeamGeometricallyExact(nodeNumbers=[nodes[-2], nodes[-1]],
                                                      length=lElem, sectionData=sd))
    nGround = mbs.AddNode(eu.NodePointGround(referenceCoordinates=[0, 0, 0]))
    mG = mbs.AddMarker(eu.MarkerNodeRigid(nodeNumber=nGround))
    m0 = mbs.AddMarker(eu.MarkerNodeRigid(nodeNumber=nodes[0]))
    mbs.AddObject(eu.GenericJoint(markerNumbers=[mG, m0]))
    mTip = mbs.AddMarker(eu.MarkerNodeRigid(nodeNumber=nodes[-1]))
    mbs.AddLoad(eu.Force(markerNumber=mTip, loadVector=[0, 0, -P]))
    mbs.Assemble()
    t_build = tm.lap()
    s = pc.exu_quiet_settings()
    s.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    s.staticSolver.numberOfLoadSteps = n_steps
    s.staticSolver.adaptiveStep = True
    s.staticSolver.newton.relativeTolerance = rtol
    try:
        ok = mbs.SolveStatic(s)
    except exu.SolverError:
        ok = False
    t_solve = tm.lap()
    it = mbs.sys['staticSolver'].it
    u = mbs.GetNodeOutput(nodes[-1], exu.OutputVariableType.Displacement)
    R = mbs.GetNodeOutput(nodes[-1], exu.OutputVariableType.RotationMatrix).reshape(3, 3)
    phi = float(np.arctan2(-R[2, 0], R[0, 0]))   # rotation of the beam axis toward -z
    return dict(ok=bool(ok), rtol=rtol, u=float(-u[0] / L), w=float(-u[2] / L), phi=phi,
                t_build=t_build, t_solve=t_solve, newton=int(it.newtonStepsCount),
                jac=int(it.newtonJacobiCount))


def main():
    p = pc.parser(__doc__.split("\n")[0])
    p.add_argument("--k", type=float, default=3.0, help="load parameter k = P L^2/EI (default 3)")
    p.add_argument("--rtol", type=float, nargs="+", default=[1e-8, 1e-6, 1e-4],
                   help="Newton relative tolerances tried in turn until a solve succeeds")
    p.add_argument("--load-steps", type=int, default=10, help="numberOfLoadSteps (default 10)")
    p.add_argument("--ga", type=float, default=1e7, help="shear stiffness ks*G*A (default 1e7)")
    args = p.parse_args()
    pc.setup_run(args)
    import exudyn as exu
    k = args.k
    ur, wr, pr = pc.elastica(k)
    for N in args.sizes:
        base = {"peer": "exudyn", "peer_version": exu.__version__, "problem": "cantilever_k3",
                "variant": "GE3D-EP", "n_elements": N, "n_dof": 7 * (N + 1), "k": k,
                "tip_load_n": k * EI / L**2, "ea": EA, "ga": args.ga, "load_steps": args.load_steps}
        try:
            attempts, t_total = [], 0.0
            for rtol in args.rtol:
                r = solve_case(N, k, rtol, args.load_steps, args.ga)
                t_total += r["t_build"] + r["t_solve"]
                attempts.append({"rtol": rtol, "ok": r["ok"], "newton": r["newton"],
                                 "t_solve_s": pc.sig(r["t_solve"], 6)})
                if r["ok"]:
                    break
            err = {"u": r["u"] - ur, "w": r["w"] - wr, "phi": r["phi"] - pr}
            rec = dict(base, status="ok" if r["ok"] else "failed",
                       converged_default=attempts[0]["ok"],
                       wall_s=r["t_build"] + r["t_solve"], t_build_s=r["t_build"], t_solve_s=r["t_solve"],
                       t_total_s=t_total, rtol=r["rtol"], newton_iterations=r["newton"], jacobians=r["jac"],
                       u_over_L=pc.sig(r["u"]), w_over_L=pc.sig(r["w"]), phi_rad=pc.sig(r["phi"]),
                       ref_u_over_L=pc.sig(ur, 7), ref_w_over_L=pc.sig(wr, 7), ref_phi_rad=pc.sig(pr, 7),
                       err_u=pc.sig(abs(err["u"]), 3), err_w=pc.sig(abs(err["w"]), 3),
                       err_phi=pc.sig(abs(err["phi"]), 3),
                       max_abs_err=pc.sig(max(abs(v) for v in err.values()), 3), attempts=attempts)
        except Exception as e:  # noqa: BLE001
            rec = dict(base, status="failed", error=f"{type(e).__name__}: {e}"[:500])
        pc.emit(rec)


if __name__ == "__main__":
    main()
