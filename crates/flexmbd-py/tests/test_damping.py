"""Material damping from Python (issue 13: "per-element material damping"): a truss spring
with a point mass, its Kelvin-Voigt retardation time tau set on the element, against the
closed form of the damped oscillator; the same tau on a material reaches the beams made of it
and is written to TOML."""

import math

import numpy as np
import pytest

import flexmbd

M, K, TAU, V0 = 2.0, 800.0, 2e-3, 0.1


def oscillator(damping):
    m = flexmbd.Model("oscillator")
    m.add_node("a", (0, 0, 0))
    m.add_node("p", (1, 0, 0))
    m.fix("a")
    m.fix("p", ["y", "z"])
    m.add_truss("s", ["a", "p"], ea=K * 1.0, damping=damping)
    m.add_mass("p", M)
    m.set_velocity("p", v=(V0, 0, 0))
    return m


def test_a_damped_truss_spring_decays_as_the_closed_form():
    # x(t) = v0/wd exp(-zeta w t) sin(wd t), w = sqrt(k/m), zeta = tau w / 2; the trapezoidal
    # rule (rho_inf = 1) with h = 0.5 ms over 2 s: within 2e-3 of the amplitude
    r = oscillator(TAU).simulate(t_end=2.0, dt=5e-4, fixed_step=True, rho_inf=1.0, output_step=0.01)
    w = math.sqrt(K / M)
    zeta = TAU * w / 2
    wd = w * math.sqrt(1 - zeta**2)
    t = r.t
    x = r.states.positions[:, r.states.node_names.index("p"), 0] - 1.0
    want = V0 / wd * np.exp(-zeta * w * t) * np.sin(wd * t)
    np.testing.assert_allclose(x, want, atol=2e-3 * V0 / w)
    # the energy dissipated: from 1/2 m v0^2 to what is left (e^(-2 zeta w t) of it, about)
    e = r.energies
    left = e["kinetic"][-1] + e["strain"][-1]
    assert e["dissipated"][-1] == pytest.approx(0.5 * M * V0**2 - left, rel=1e-2)
    # undamped: the amplitude stays
    r0 = oscillator(None).simulate(t_end=2.0, dt=5e-4, fixed_step=True, rho_inf=1.0, output_step=0.01)
    x0 = r0.states.positions[:, 1, 0] - 1.0
    np.testing.assert_allclose(x0, V0 / w * np.sin(w * r0.t), atol=2e-3 * V0 / w)
    assert r0.energies["dissipated"][-1] == pytest.approx(0.0, abs=1e-12)


def test_material_damping_reaches_its_beams_and_the_toml():
    m = flexmbd.Model("leaf")
    m.add_node("a", (0, 0, 0), rot=True)
    m.add_node("b", (0.05, 0, 0), rot=True)
    m.fix("a")
    m.add_material("steel", E=210e9, nu=0.3, rho=7800.0, damping=1e-4)
    m.add_section("sheet", "rectangle", w=0.02, t=0.2e-3)
    m.add_beam("leaf", ["a", "b"], section="sheet", material="steel", segments=2)
    assert m.get("materials.steel.damping") == 1e-4
    text = m.to_toml()
    assert "damping = 0.0001" in text
    back = flexmbd.Model.from_toml(text)
    assert back.to_dict() == m.to_dict()
    m.set("materials.steel.damping", -1.0)
    with pytest.raises(flexmbd.ModelError, match="damping"):
        m.check()
