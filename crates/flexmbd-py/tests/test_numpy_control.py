"""NumPy inputs of any layout, and the conversion to python-control."""

import numpy as np
import pytest

import flexmbd


@pytest.fixture(scope="module")
def ss():
    return flexmbd.load("examples/parallel_leaf_stroke.toml").state_space(
        ["p:y"], ["p:y"], modes=4
    )


def test_frequency_response_of_any_layout(ss):
    f = np.geomspace(10.0, 1000.0, 7)
    want = ss.frequency_response(f)
    assert want.shape == (7, 1, 1) and want.dtype == np.complex128
    strided = np.zeros(14)
    strided[::2] = f
    big_endian = f.astype(">f8")
    raw = np.zeros(7 * 8 + 1, dtype=np.uint8)
    misaligned = raw[1:].view(np.float64)
    misaligned[:] = f
    for x in (strided[::2], big_endian, misaligned, list(f), f[::-1].copy()[::-1], np.asfortranarray(f[:, None])):
        np.testing.assert_array_equal(ss.frequency_response(x), want)
    # the response of the modal model, evaluated independently from A, B, C, D
    w = 2 * np.pi * f[3]
    g = ss.C @ np.linalg.solve(1j * w * np.eye(ss.A.shape[0]) - ss.A, ss.B) + ss.D
    np.testing.assert_allclose(want[3], g, rtol=1e-9)


def test_to_control(ss):
    control = pytest.importorskip("control")
    sys = ss.to_control()
    assert isinstance(sys, control.StateSpace)
    np.testing.assert_array_equal(sys.A, ss.A)
    np.testing.assert_array_equal(sys.D, ss.D)
    # python-control's own evaluation of the same model
    f = np.array([50.0, 400.0])
    resp = control.frequency_response(sys, 2 * np.pi * f)
    data = resp.frdata if hasattr(resp, "frdata") else resp.fresp
    g = np.asarray(data).reshape(1, 1, -1)[0, 0]
    np.testing.assert_allclose(g, ss.frequency_response(f)[:, 0, 0], rtol=1e-9)
    # the static gain: python-control's dcgain against flexmbd's
    np.testing.assert_allclose(np.asarray(sys.dcgain()).reshape(1, 1), ss.dc_gain, rtol=1e-9)
