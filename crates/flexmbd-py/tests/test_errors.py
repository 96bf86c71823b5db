"""Bad input raises the exception of its kind, with the file, line and item, in Python's
words (keyword names, never a command-line flag)."""

import pytest

import flexmbd

GOOD = """
[nodes]
a = [0.0, 0.0, 0.0]
b = [1.0, 0.0, 0.0]

[fix]
a = ["x", "y", "z"]
b = ["y", "z"]

[[truss]]
id = "t1"
nodes = ["a", "b"]
EA = 1000.0
"""


def test_unknown_node_names_line_and_item():
    text = GOOD.replace('nodes = ["a", "b"]', 'nodes = ["a", "c"]')
    with pytest.raises(flexmbd.ModelError) as e:
        flexmbd.Model.from_toml(text, "guide.toml")
    err = e.value
    assert isinstance(err, ValueError)
    assert err.file == "guide.toml"
    # the line of the element's table (1-based; the text starts with an empty line)
    assert err.line == text.splitlines().index("[[truss]]") + 1
    assert err.item == "t1"
    assert "node `c` is not defined" in str(err)
    assert "guide.toml:" in str(err)


def test_syntax_error_has_line_and_column():
    text = GOOD.replace("EA = 1000.0", "EA = = 1000.0")
    with pytest.raises(flexmbd.ModelError) as e:
        flexmbd.Model.from_toml(text, "bad.toml")
    assert e.value.line == text.splitlines().index("EA = = 1000.0") + 1
    assert e.value.column is not None


def test_bad_file_from_disk(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text(GOOD.replace('b = ["y", "z"]', 'b = ["y", "w"]'))
    with pytest.raises(flexmbd.ModelError) as e:
        flexmbd.load(p)
    assert e.value.file == str(p)
    assert e.value.line == 8


def test_missing_file_is_a_read_error(tmp_path):
    with pytest.raises(flexmbd.ReadError) as e:
        flexmbd.load(tmp_path / "none.toml")
    assert isinstance(e.value, OSError)


def test_unknown_format():
    with pytest.raises(flexmbd.OptionError) as e:
        flexmbd.load("model.stl")
    assert "unknown model format" in str(e.value)


def test_options_speak_python():
    m = flexmbd.load("examples/parallel_leaf_stroke.toml")
    with pytest.raises(flexmbd.OptionError) as e:
        m.static(compliance=["nowhere"])
    assert e.value.item == "compliance" and "nowhere" in str(e.value)
    with pytest.raises(flexmbd.OptionError) as e:
        m.modes(solver="fast")
    assert e.value.item == "solver"
    with pytest.raises(flexmbd.OptionError) as e:
        m.static(tol_force=-1.0)
    assert e.value.item == "tol_force" and "tol_force" in str(e.value)
    with pytest.raises(flexmbd.OptionError) as e:
        m.modes(at_step=999, count=2)
    assert e.value.item == "at_step" and "at_step=999" in str(e.value)
    with pytest.raises(flexmbd.OptionError) as e:
        m.state_space(["nowhere:y"], ["p:y"])
    assert e.value.item == "inputs" and "nowhere" in str(e.value)
    with pytest.raises(flexmbd.OptionError) as e:
        m.state_space(["p:y"], ["p:q"])
    assert e.value.item == "outputs"
    with pytest.raises(flexmbd.OptionError) as e:
        m.check(rank_tol=-1.0)
    assert e.value.item == "rank_tol"
    with pytest.raises(flexmbd.OptionError) as e:
        flexmbd.load("examples/pendulum.toml").simulate(t_end=-1.0)
    assert "t_end=" in str(e.value)
    for exc in [e.value]:
        assert "--" not in str(exc)


def test_numerical_failure_says_what_to_try_in_python():
    # a model without mass: modes fail with a hint in keyword or TOML words
    m = flexmbd.load("examples/twelve_truss.toml")
    with pytest.raises(flexmbd.FlexmbdError) as e:
        m.modes(count=2)
    assert "--" not in str(e.value)


def test_no_constraint_rows_is_a_model_error():
    text = GOOD + "free = [1]\n"
    m = flexmbd.Model.from_toml(text)
    with pytest.raises(flexmbd.ModelError) as e:
        m.check()
    assert "constraint rows" in str(e.value)
