"""Parametric TOML models from Python: ``flexmbd.load(path, set=...)``,
``Model.from_toml(text, set=...)`` and ``Model.parameters`` (docs/python.md)."""

import math

import pytest

import flexmbd
from conftest import ROOT

GUIDE = ROOT / "examples" / "folded_sheet_guide_param.toml"

# A cantilever strip of length L, width 10 mm, thickness t (Euler-Bernoulli: no shear).
STRIP = (ROOT / "crates" / "flexmbd-cli" / "tests" / "models" / "param_strip.toml").read_text()


def f1_closed_form(t, L):
    """Clamped-free Euler-Bernoulli beam: f1 = 1.8751^2/(2 pi) t/L^2 sqrt(E/(12 rho))."""
    return 1.8751040687**2 / (2 * math.pi) * t / L**2 * math.sqrt(2.1e11 / (12 * 7800))


def test_set_evaluates_a_member_of_a_strip():
    for t, L in [(0.2e-3, 0.1), (0.4e-3, 0.1), (0.1e-3, 0.2)]:
        m = flexmbd.Model.from_toml(STRIP, "strip.toml", set={"t": t, "L": L})
        assert m.parameters == {"L": L, "t": t}
        f = m.modes(count=1).frequencies[0]
        assert f == pytest.approx(f1_closed_form(t, L), rel=1e-3)
    with pytest.raises(flexmbd.ModelError, match="the parameters are: L, t"):
        flexmbd.Model.from_toml(STRIP, "strip.toml", set={"thickness": 1.0})


def test_the_parametric_guide_loads_with_set_and_writes_its_member():
    m = flexmbd.load(GUIDE)
    assert list(m.parameters)[:3] == ["t", "L", "angle"]
    assert m.parameters["angle"] == 210.0
    m2 = flexmbd.load(GUIDE, set={"angle": 200, "sections.sheet.w": 0.025})
    assert m2.parameters["th2"] == pytest.approx(200 * math.pi / 180, rel=1e-15)
    assert m2.get("sections.sheet.w") == 0.025
    # folded sheet 2 moved: f2 = (-0.1, 0.08 cos 200 deg, 0.08 sin 200 deg)
    f2 = [m2.get("nodes.f2." + k) for k in "xyz"]
    want = [-0.1, 0.08 * math.cos(math.radians(200)), 0.08 * math.sin(math.radians(200))]
    assert f2 == pytest.approx(want, rel=1e-14)
    # the written file is the evaluated member: it reads back to the same values
    back = flexmbd.Model.from_toml(m2.to_toml())
    assert back.parameters == m2.parameters
    assert back.to_dict()["nodes"] == m2.to_dict()["nodes"]


def test_the_command_line_states_the_parameters_of_the_model(cli):
    for args, set in [([], None), (["--set", "t=3e-4", "--set", "angle=200"], {"t": 3e-4, "angle": 200})]:
        code, doc, err = cli("check", "examples/folded_sheet_guide_param.toml", *args)
        assert code == 0, err
        assert doc["parameters"] == flexmbd.load(GUIDE, set=set).parameters
