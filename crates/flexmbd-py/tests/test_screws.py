"""The kinematic check in the designer's language from Python (issue 18): twists, the intended
freedom (read from the file and edited with add_freedom / remove_freedom) and the verified wire
suggestions of `check().to_dict()`.

Every number is derived by hand from the wire lines of examples/wire_guide_5.toml (the paper's
Fig. 3a; docs/kinematic-analysis.md "A worked example"): wires 1-3 are vertical through
(x, y) = (-0.05, -0.03), (-0.05, 0.03), (0.05, 0); wires 4 and 5 run along y at z = 0.01 through
x = -0.05 and x = 0.05. Without wire 5, wires 1-3 leave only a rotation w about a vertical axis
(and the translations in the plane); wire 4 (along y at x = -0.05) makes that axis meet it, so
the axis passes through x = -0.05; with c.x (the platform's x at the origin) generalised,
v_x(origin) = w * y0 = 0 puts the axis through y0 = 0: a rotation about the vertical line through
(-0.05, 0), pitch 0. A wire stops it in proportion to its moment arm about that axis: the largest
between existing nodes, 0.1 m, is wire 5 itself (a5 to g5, along y at x = 0.05).
"""

import math

import pytest

import flexmbd
from conftest import ROOT

WIRE_GUIDE = str(ROOT / "examples" / "wire_guide_5.toml")


def four_wires():
    m = flexmbd.load(WIRE_GUIDE)
    m.remove_element("w5")
    return m


def platform_twist(bodies):
    (t,) = [t for t in bodies if t["body"] == "platform"]
    return t["screw"]


def assert_vertical_axis_through(screw, x, y=None):
    assert screw["kind"] == "rotation"
    d = screw["direction"]
    assert abs(abs(d[2]) - 1.0) < 1e-9 and math.hypot(d[0], d[1]) < 1e-9, screw
    assert abs(screw["point"][0] - x) < 1e-9, screw
    if y is not None:
        assert abs(screw["point"][1] - y) < 1e-9, screw
    assert abs(screw["pitch"]) < 1e-9, screw


def test_four_wires_leave_a_rotation_and_wire_five_is_suggested():
    d = four_wires().check().to_dict()
    assert (d["n_mechanisms"], d["n_self_stresses"]) == (1, 0)
    (motion,) = d["screws"]["motions"]
    assert_vertical_axis_through(platform_twist(motion["bodies"]), -0.05, 0.0)
    # the four wires bend in this motion
    bent = {f["element"] for f in motion["flexures"]}
    assert bent == {"w1", "w2", "w3", "w4"}, motion["flexures"]

    # the intended freedom of the file (translation x): released, the guide has it and the
    # rotation about the vertical line through x = -0.05 (its y is not fixed without c.x)
    f = d["freedom"]
    assert (f["matches"], f["intended_dimension"], f["design_dimension"]) == (False, 1, 2)
    assert f["missing"] == []
    (parasitic,) = f["parasitic"]
    assert_vertical_axis_through(platform_twist(parasitic), -0.05)

    (advice,) = d["wire_suggestions"]
    best = advice["wires"][0]
    assert (best["from"], best["to"], best["body"], best["other"]) == ("a5", "g5", "platform", "ground")
    assert abs(best["reciprocal"] - 0.1) < 1e-9
    assert best["intended_change"] < 1e-9  # along y: no power in the translation x
    for w in advice["wires"]:
        assert (w["motions_after"], w["self_stresses_after"]) == (0, 0)
        # the reciprocal product of the unit line (u, p x u) with the unit twist about the
        # axis (w = (0, 0, 1), v(origin) = (0, 0.05, 0)): (p_x + 0.05) u_y - p_y u_x
        p, u = w["point"], w["direction"]
        arm = abs((p[0] + 0.05) * u[1] - p[1] * u[0])
        assert abs(w["reciprocal"] - arm) < 1e-9, w


def test_the_suggested_wire_built_gives_exact_constraint_and_the_intended_freedom():
    m = four_wires()
    best = m.check().to_dict()["wire_suggestions"][0]["wires"][0]
    m.add_beam("w5", [best["to"], best["from"]], free=[2, 3, 4, 5, 6])
    r = m.check()
    assert r.exactly_constrained
    f = r.to_dict()["freedom"]
    assert f["matches"] and f["parasitic"] == [] and f["missing"] == []


def test_add_and_remove_freedom():
    m = four_wires()
    m.remove_freedom("platform")
    assert m.check().to_dict().get("freedom") is None
    # the intended rotation about the vertical line through (-0.05, 0) is in the freedom
    # space of the four wires (released: translation x and that rotation)
    m.add_freedom("platform", axis=(0, 0, 1), point=(-0.05, 0.0, 0.0))
    m.add_freedom("a1", translation=(1, 0, 0))  # a node of the same body
    f = m.check().to_dict()["freedom"]
    assert (f["matches"], f["intended_dimension"], f["design_dimension"]) == (True, 2, 2)
    # written to TOML and read back: the same tables
    back = flexmbd.Model.from_toml(m.to_toml())
    assert back.to_dict()["freedoms"] == m.to_dict()["freedoms"]
    assert len(m.to_dict()["freedoms"]) == 2
    # a rotation about an axis the wires forbid is missing
    m.remove_freedom("a1")
    m.add_freedom("platform", axis=(1, 0, 0), point=(0.0, 0.0, 0.0))
    f = m.check().to_dict()["freedom"]
    assert not f["matches"] and len(f["missing"]) == 1


def test_freedom_errors_name_the_item():
    m = four_wires()
    with pytest.raises(flexmbd.ModelError, match="exactly one of translation and axis") as e:
        m.add_freedom("platform")
    assert e.value.item == "platform"
    with pytest.raises(flexmbd.ModelError, match="axis: expected 3 numbers"):
        m.add_freedom("platform", axis=(0, 1))
    with pytest.raises(flexmbd.ModelError, match="freedom of body `nobody`"):
        m.remove_freedom("nobody")
    m.add_freedom("nobody", translation=(1, 0, 0))
    with pytest.raises(flexmbd.ModelError, match="body `nobody` is not an element or a node"):
        m.check()
