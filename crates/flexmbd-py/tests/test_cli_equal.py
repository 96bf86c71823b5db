"""The Python results equal the command line's `--json` on every example (the same core
call on the same reader, two front ends), and the NumPy arrays hold the numbers of the
report. Where the command fails, Python raises the exception of that kind."""

import math

import numpy as np
import pytest

import flexmbd
from compare import assert_same
from conftest import EXAMPLES

# exit code of the command line -> the exception Python raises
RAISES = {1: flexmbd.NumericalError, 2: (flexmbd.ModelError, flexmbd.OptionError)}

NAMES = [p.name for p in EXAMPLES]


def rel(p):
    return "examples/" + p.name


def same_or_same_failure(code, doc, err, call):
    """Python's to_dict() equals the CLI's JSON, or both fail alike. (The CLI's JSON of a
    parametric model also states its parameters: Model.parameters, test_parameters.py.)"""
    if code == 0:
        doc = {k: v for k, v in doc.items() if k != "parameters"}
        return call().to_dict(), doc
    assert code in RAISES, err
    with pytest.raises(RAISES[code]) as e:
        call()
    if isinstance(e.value, flexmbd.PathStoppedError):
        # nothing lost: the converged steps are the exception's result, as in the JSON
        return e.value.result.to_dict(), doc
    assert "--" not in str(e.value), f"a CLI flag in a Python message: {e.value}"
    return None, None


@pytest.mark.parametrize("path", EXAMPLES, ids=NAMES)
def test_check_equals_cli(cli, path):
    code, doc, err = cli("check", rel(path))
    model = flexmbd.load(rel(path))
    got, want = same_or_same_failure(code, doc, err, lambda: model.check())
    if got is None:
        return
    assert_same(got, want)
    r = model.check()
    # the arrays are the report's numbers
    np.testing.assert_array_equal(r.singular_values, want["singular_values"])
    assert r.shape == (want["rows"], want["cols"])
    assert r.Dcc.shape == r.shape
    assert (r.n_motions, r.n_self_stresses, r.rank) == (
        want["n_mechanisms"],
        want["n_self_stresses"],
        want["rank"],
    )
    assert r.V.shape == (r.shape[1], r.n_motions)
    assert r.U.shape == (r.shape[0], r.n_self_stresses)
    # NumPy's SVD (an independent implementation) gives the same singular values
    if min(r.shape) > 0:
        s = np.linalg.svd(r.Dcc, compute_uv=False)
        scale = max(s[0], 1.0)
        np.testing.assert_allclose(np.sort(s)[::-1], r.singular_values[: len(s)], atol=1e-10 * scale)
        # null vectors: Dcc V = 0 and U^T Dcc = 0
        assert np.abs(r.Dcc @ r.V).max(initial=0.0) < 1e-9 * scale
        assert np.abs(r.U.T @ r.Dcc).max(initial=0.0) < 1e-9 * scale
    # motions and self-stresses by node and element: the report's entries
    for k, m in enumerate(want["mechanisms"]):
        for c in m["coordinates"]:
            i = ["x", "y", "z", "rx", "ry", "rz"].index(c["dof"])
            assert r.motions[k][c["node"]][i] == c["value"]
    for k, s in enumerate(want["self_stresses"]):
        for d in s["deformations"]:
            assert r.self_stresses[k][d["element"]][d["mode"] - 1] == d["value"]


@pytest.mark.parametrize("path", EXAMPLES, ids=NAMES)
def test_static_equals_cli(cli, path):
    code, doc, err = cli("static", rel(path))
    model = flexmbd.load(rel(path))
    got, want = same_or_same_failure(code, doc, err, lambda: model.static())
    if got is None:
        return
    assert_same(got, want, skip=("hint", "what_to_try"))
    try:
        r = model.static()
    except flexmbd.PathStoppedError as e:
        r = e.result
    st = r.states
    np.testing.assert_array_equal(r.load_factors, [s["load_factor"] for s in want["steps"]])
    last = want["steps"][-1]
    for j, n in enumerate(last["nodes"]):
        np.testing.assert_array_equal(st.positions[-1, j], n["position"])
        if n["reaction_force"] is not None:
            np.testing.assert_array_equal(st.reaction_forces[-1, j], n["reaction_force"])
    for e in last["elements"]:
        np.testing.assert_array_equal(st.stress_resultants[e["element"]][-1], e["sigma"])


@pytest.mark.parametrize("path", EXAMPLES, ids=NAMES)
def test_modes_equals_cli(cli, path):
    code, doc, err = cli("modes", rel(path), "--count", "4")
    model = flexmbd.load(rel(path))
    got, want = same_or_same_failure(code, doc, err, lambda: model.modes(count=4))
    if got is None:
        return
    assert_same(got, want, skip=("hint", "what_to_try"))
    try:
        r = model.modes(count=4)
    except flexmbd.PathStoppedError as e:
        r = e.result
    f = [m["frequency_hz"] for m in want["modes"]]
    np.testing.assert_array_equal(r.frequencies, [math.nan if v is None else v for v in f])
    for k, m in enumerate(want["modes"]):
        for j, s in enumerate(m["shape"]):
            np.testing.assert_array_equal(r.shapes[k, j], s["translation"] + s["rotation"])


STATE_SPACES = [
    ("parallel_leaf_stroke.toml", ["p:y", "p:z:moment"], ["p:y", "p:y:acc"], ["--modes", "4", "--static-correction"], dict(modes=4, static_correction=True)),
    ("paper_dynamic_5_sheets.toml", ["c:x", "c:rz"], ["c:x", "c:rz:vel"], [], {}),
]


@pytest.mark.parametrize("case", STATE_SPACES, ids=[c[0] for c in STATE_SPACES])
def test_state_space_equals_cli(cli, case):
    name, ins, outs, flags, kwargs = case
    args = ["statespace", "examples/" + name]
    for i in ins:
        args += ["--input", i]
    for o in outs:
        args += ["--output", o]
    code, want, err = cli(*args, *flags)
    assert code == 0, err
    ss = flexmbd.load("examples/" + name).state_space(ins, outs, **kwargs)
    assert_same(ss.to_dict(), want)
    np.testing.assert_array_equal(ss.A, want["A"])
    np.testing.assert_array_equal(ss.B, want["B"])
    np.testing.assert_array_equal(ss.C, want["C"])
    np.testing.assert_array_equal(ss.D, want["D"])
    assert ss.input_names == [i["name"] for i in want["inputs"]]
    assert ss.output_names == [o["name"] for o in want["outputs"]]


def test_simulate_equals_cli(cli):
    code, want, err = cli("simulate", "examples/pendulum.toml", "--t-end", "0.2")
    assert code == 0, err
    sim = flexmbd.load("examples/pendulum.toml").simulate(t_end=0.2)
    assert_same(sim.to_dict(), want)
    np.testing.assert_array_equal(sim.t, [f["t"] for f in want["frames"]])
    for k, f in enumerate(want["frames"]):
        for j, n in enumerate(f["nodes"]):
            np.testing.assert_array_equal(sim.states.positions[k, j], n["position"])
            np.testing.assert_array_equal(sim.velocities[k, j], n["velocity"])
    np.testing.assert_array_equal(sim.energies["kinetic"], [f["energy"]["kinetic"] for f in want["frames"]])


DATS = sorted((__import__("conftest").ROOT / "crates/flexmbd-io/tests/models").rglob("*.dat"))[:4]


@pytest.mark.filterwarnings("ignore::flexmbd.FlexmbdWarning")
@pytest.mark.parametrize("path", DATS, ids=[p.name for p in DATS])
def test_spacar_files_equal_cli(cli, path):
    # SPACAR .dat files go through the same readers as on the command line
    rel_path = str(path.relative_to(__import__("conftest").ROOT))
    model = flexmbd.load(rel_path)
    assert model.format == "dat"
    for args, call in [(("check",), lambda: model.check()), (("static",), lambda: model.static())]:
        code, doc, err = cli(*args, rel_path)
        got, want = same_or_same_failure(code, doc, err, call)
        if got is not None:
            assert_same(got, want, skip=("hint", "what_to_try"))


@pytest.mark.filterwarnings("ignore::flexmbd.FlexmbdWarning")
@pytest.mark.parametrize("path", DATS, ids=[p.name for p in DATS])
def test_an_edited_spacar_model_is_the_document_convert_writes(cli, path, tmp_path):
    # editing (here: reading the document of) a .dat model turns it into the TOML document
    # that `flexmbd convert` writes of the file; that document's statics equal the command
    # line's on the converted file
    import subprocess

    from conftest import flexmbd_binary

    rel_path = str(path.relative_to(__import__("conftest").ROOT))
    out = tmp_path / "converted.toml"
    p = subprocess.run([flexmbd_binary(), "--quiet", "convert", rel_path, str(out)],
                       capture_output=True, text=True)
    model = flexmbd.load(rel_path)
    if p.returncode != 0:
        with pytest.raises(flexmbd.FlexmbdError):
            model.to_dict()
        return
    assert model.to_dict() == flexmbd.load(str(out)).to_dict()
    assert model.format == "toml"
    code, cli_doc, err = cli("static", str(out))
    if code == 0:
        got = model.static().to_dict()
        assert_same(got, cli_doc, skip=("hint", "what_to_try", "file"))
    else:
        with pytest.raises(flexmbd.FlexmbdError):
            model.static()
