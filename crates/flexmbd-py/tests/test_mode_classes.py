"""Mode classes in the Python package (docs/dynamics.md "Mode classes"): the same classes and
fractions as `flexmbd modes --json`, and the paper's classes of its five-sheet guide (§5: the
intended translation first, then the rigid part moving across the guide, then the internal
modes of the folds; the example's platform also rocks in mode 4, which is support too)."""

import math

import numpy as np

import flexmbd
from conftest import ROOT


def test_classes_and_fractions_equal_the_cli(cli):
    path = "examples/paper_dynamic_5_sheets.toml"
    code, doc, err = cli("modes", path, "--count", "9")
    assert code == 0, err
    m = flexmbd.load(str(ROOT / path)).modes(count=9)
    want = doc["modes"]
    assert m.classes == [w["class"] for w in want]
    assert m.classes == ["intended"] + ["support"] * 3 + ["internal"] * 5
    np.testing.assert_array_equal(m.body_fractions, [w["body_fraction"] for w in want])
    np.testing.assert_array_equal(m.released_fractions, [w["released_fraction"] for w in want])
    got = m.to_dict()["modes"]
    for g, w in zip(got, want):
        for key in ("class", "body_fraction", "released_fraction"):
            assert g[key] == w[key]


def test_a_model_without_bodies_has_only_internal_modes():
    m = flexmbd.load(str(ROOT / "examples/strip_f01.toml")).modes(count=3)
    assert m.classes == ["internal"] * 3
    np.testing.assert_array_equal(m.body_fractions, [0.0, 0.0, 0.0])
    assert all(0.0 <= r <= 1.0 and not math.isnan(r) for r in m.released_fractions)
