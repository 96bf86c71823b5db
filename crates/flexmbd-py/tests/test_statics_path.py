"""Statics along the whole path from Python (issue 17): the shallow two-bar (von Mises) truss
followed by arc length through both limit points, its load factor and the smallest eigenvalue
of the tangent at every state against the closed forms, the located limit points in to_dict(),
and a run that stops part-way keeps its converged steps."""

import math

import numpy as np
import pytest

import flexmbd

# half span, rise [m], axial stiffness EA [N] and the full load P [N]
A, H, EA, P = 1.0, 0.1, 1e6, 1000.0
L0 = math.hypot(A, H)


def load_at(y):
    """The vertical load that holds the apex at height y: the equilibrium of the apex with
    the bar forces N = EA (L - L0)/L0 (L = sqrt(a^2 + y^2)): P(y) = 2 EA (y/L - y/L0)."""
    L = math.hypot(A, y)
    return 2 * EA * (y / L - y / L0)


def slope_at(y):
    """dP/dy = 2 EA (a^2/L^3 - 1/L0); the tangent stiffness along y is -dP/dy."""
    L = math.hypot(A, y)
    return 2 * EA * (A * A / L**3 - 1 / L0)


def limit_height():
    """dP/dy = 0 at L = (a^2 L0)^(1/3)."""
    L = (A * A * L0) ** (1 / 3)
    return math.sqrt(L * L - A * A)


def truss(load=P):
    m = flexmbd.Model("von Mises truss")
    m.add_node("a", (-A, 0, 0))
    m.add_node("b", (A, 0, 0))
    m.add_node("c", (0, H, 0))
    m.fix("a")
    m.fix("b")
    m.fix("c", ["z"])
    m.add_truss("ac", ["a", "c"], ea=EA)
    m.add_truss("bc", ["b", "c"], ea=EA)
    m.add_load("c", force=(0, -load, 0))
    return m


def test_arc_length_follows_the_closed_form_path_through_both_limit_points():
    r = truss().static(steps=40, path="arc-length", tangent_eigenvalues=True)
    assert r.stopped is None
    lam = r.load_factors
    c = r.states.node_names.index("c")
    y = r.states.positions[:, c, 1]
    # every state is on the closed-form path: lambda P = P(y)
    for yi, li in zip(y, lam):
        assert li * P == pytest.approx(load_at(yi), abs=1e-6 * P), yi
    # it passes through both limit points: the apex ends below the supports at the full load
    ys = limit_height()
    assert y.min() < -ys and y[-1] < -ys and lam[-1] == pytest.approx(1.0, abs=1e-9)
    assert lam.max() > 0.9 * load_at(ys) / P and lam.min() < 0.9 * load_at(-ys) / P
    # the smallest eigenvalue of the tangent is -dP/dy at every state (K_xx ~ 2 EA/L0 is far
    # larger); its scale is the start value 2 EA h^2/L0^3
    kappa = r.tangent_eigenvalues
    assert kappa.shape == (len(lam), 3)
    scale = 2 * EA * H * H / L0**3
    np.testing.assert_allclose(kappa[:, 0], [-slope_at(v) for v in y], atol=1e-6 * scale)
    # two free coordinates: the third column is not there
    assert np.isnan(kappa[:, 2]).all() and not np.isnan(kappa[:, 1]).any()
    # negative between the limit points: unstable there
    between = np.abs(y) < ys * 0.99
    assert (kappa[between, 0] < 0).all() and (kappa[np.abs(y) > ys * 1.01, 0] > 0).all()


def test_the_limit_points_are_located_in_the_report():
    r = truss().static(steps=10, path="arc-length")
    events = r.to_dict()["events"]
    limits = [e for e in events if e["kind"] == "limit_point"]
    assert len(limits) == 2, events
    p_max = load_at(limit_height())
    assert limits[0]["load_factor"] * P == pytest.approx(p_max, rel=1e-4)
    assert limits[1]["load_factor"] * P == pytest.approx(-p_max, rel=1e-4)


def test_load_steps_stop_at_the_limit_load_keep_their_steps_and_point_to_arc_length():
    # under load steps to 1.37 P_max, the steps halve as they near the limit point and stop
    # there: every converged state is on the closed-form path, the last one within 1e-3 below
    # the closed-form limit load, and the error points to arc length
    p_max = load_at(limit_height())
    load = 1.37 * p_max
    with pytest.raises(flexmbd.PathStoppedError) as err:
        truss(load=load).static(steps=30)
    assert 'path="arc-length"' in str(err.value)
    r = err.value.result
    lam = r.load_factors
    y = r.states.positions[:, r.states.node_names.index("c"), 1]
    assert len(lam) == r.stopped["after_step"] + 1
    for yi, li in zip(y, lam):
        assert li * load == pytest.approx(load_at(yi), abs=1e-6 * P), yi
    assert lam[-1] == r.stopped["load_factor"]
    assert lam[-1] * load == pytest.approx(p_max, rel=1e-3) and lam[-1] * load < p_max
    assert (y > limit_height()).all()


def test_a_path_that_stops_keeps_its_converged_steps_and_says_what_to_try():
    # a bar pushed along its axis by 2 EA: its force N = EA (L - L0)/L0 cannot exceed EA in
    # compression, so the steps beyond half the load cannot converge; every converged step
    # holds L = L0 (1 - 2 t) (t the load factor)
    m = flexmbd.Model("pushed bar")
    m.add_node("a", (0, 0, 0))
    m.add_node("b", (1, 0, 0))
    m.fix("a")
    m.fix("b", ["y", "z"])
    m.add_truss("ab", ["a", "b"], ea=EA)
    m.add_load("b", force=(-2 * EA, 0, 0))
    with pytest.raises(flexmbd.PathStoppedError) as err:
        m.static(steps=10)
    r = err.value.result
    assert "arc" in str(err.value)
    stop = r.stopped
    assert stop is not None
    assert stop["reason"] and stop["what_to_try"]
    lam = r.load_factors
    assert len(lam) == stop["after_step"] + 1 >= 5 and lam[-1] == stop["load_factor"] < 0.5
    x = r.states.positions[:, r.states.node_names.index("b"), 0]
    np.testing.assert_allclose(x, 1 - 2 * lam, atol=1e-9)
    assert r.to_dict()["stopped"] == stop
