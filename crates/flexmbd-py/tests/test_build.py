"""Building and editing a model in Python (issue 16 phase 2): the same document as the TOML
reader, edits by path, pickling, errors naming the item."""

import importlib.util
import math
import pickle

import numpy as np
import pytest

import flexmbd
from compare import assert_same
from conftest import ROOT


def example(name):
    """A module of examples/python."""
    spec = importlib.util.spec_from_file_location(name, ROOT / "examples" / "python" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def without_comments(doc):
    if isinstance(doc, dict):
        return {
            k: without_comments(v)
            for k, v in doc.items()
            if k not in ("header", "footer", "comments", "comment")
        }
    if isinstance(doc, list):
        return [without_comments(v) for v in doc]
    return doc


def test_five_sheet_guide_built_in_python_equals_the_toml_file():
    built = example("five_sheet_guide").build()
    read = flexmbd.load("examples/paper_dynamic_5_sheets.toml")
    # the documents: the file's coordinates are written to 15 digits, Python computes them
    assert_same(without_comments(built.to_dict()), without_comments(read.to_dict()), rtol=1e-13)
    c_built, c_read = built.check(), read.check()
    assert (c_built.n_motions, c_built.n_self_stresses) == (c_read.n_motions, c_read.n_self_stresses)
    s = c_read.singular_values
    np.testing.assert_allclose(c_built.singular_values, s, rtol=1e-9, atol=1e-12 * s[0])
    np.testing.assert_allclose(
        built.modes(count=6).frequencies, read.modes(count=6).frequencies, rtol=1e-9
    )


def test_a_document_written_as_toml_reads_back_the_same():
    m = example("five_sheet_guide").build()
    back = flexmbd.Model.from_toml(m.to_toml())
    assert back.to_dict() == m.to_dict()


def cantilever(t, L=0.05, w=0.02, segments=20):
    m = flexmbd.Model("cantilever")
    m.add_node("a", (0, 0, 0), rot=True)
    m.add_node("b", (L, 0, 0), rot=True)
    m.fix("a")
    m.add_material("steel", E=210e9, nu=0.3, rho=7800.0)
    m.add_section("sheet", "rectangle", w=w, t=t, shear=False)
    m.add_beam("leaf", ["a", "b"], section="sheet", material="steel", orient=(0, 1, 0), segments=segments)
    return m


def euler_bernoulli_f1(t, L=0.05, E=210e9, rho=7800.0):
    # f1 = (beta1 L)^2 / (2 pi L^2) sqrt(EI / (rho A)), EI/(rho A) = E t^2 / (12 rho)
    # (beta1 L = 1.875104069, the first root of cos x cosh x = -1)
    return 1.875104069**2 / (2 * math.pi * L**2) * math.sqrt(E * t**2 / (12 * rho))


def test_editing_the_thickness_by_path_scales_the_first_frequency_as_euler_bernoulli():
    m = cantilever(0.2e-3)
    f_thin = m.modes(count=1).frequencies[0]
    m.set("sections.sheet.t", 0.3e-3)
    assert m.get("sections.sheet.t") == 0.3e-3
    f_thick = m.modes(count=1).frequencies[0]
    # f is proportional to t (the bending of the thickness); 20 segments: 1e-4 of the closed form
    assert f_thick / f_thin == pytest.approx(1.5, rel=1e-5)
    assert f_thin == pytest.approx(euler_bernoulli_f1(0.2e-3), rel=1e-4)
    assert f_thick == pytest.approx(euler_bernoulli_f1(0.3e-3), rel=1e-4)


def test_pickling_an_edited_model_keeps_the_edit():
    m = cantilever(0.2e-3)
    m.set("sections.sheet.t", 0.25e-3)
    m.add_mass("b", 0.01)
    back = pickle.loads(pickle.dumps(m))
    assert back.to_toml() == m.to_toml() and back.to_dict() == m.to_dict()
    assert back.get("masses.b.m") == 0.01
    np.testing.assert_array_equal(back.modes(count=3).frequencies, m.modes(count=3).frequencies)


def test_a_copy_is_independent():
    m = cantilever(0.2e-3)
    c = m.copy()
    c.set("sections.sheet.t", 0.4e-3)
    assert m.get("sections.sheet.t") == 0.2e-3
    assert c.modes(count=1).frequencies[0] == pytest.approx(2 * m.modes(count=1).frequencies[0], rel=1e-5)


def test_edits_remove_and_replace():
    m = cantilever(0.2e-3)
    m.add_load("b", force=(0.0, 0.0, -1.0))
    m.remove_loads("b")
    assert m.to_dict()["loads"] == []
    m.add_input("b", ["x"])
    m.set_stroke("b", "x", 1e-4)
    assert m.get("prescribed.b.value") == 1e-4
    m.remove_stroke("b", "x")
    m.remove_input("b")
    m.add_node("b", (0.1, 0, 0), rot=True, replace=True)
    assert m.get("nodes.b.x") == 0.1
    m.remove_element("leaf")
    m.remove_section("sheet")
    assert [e["id"] for e in m.to_dict()["elements"]] == []


def test_errors_name_the_item():
    m = cantilever(0.2e-3)
    with pytest.raises(flexmbd.ModelError) as e:
        m.add_node("a", (1, 0, 0))
    assert e.value.item == "a" and "defined already" in str(e.value)
    with pytest.raises(flexmbd.ModelError) as e:
        m.set("sections.sheet.thickness", 1e-3)
    assert e.value.item == "sections.sheet.thickness" and "no key `thickness`" in str(e.value)
    with pytest.raises(flexmbd.ModelError) as e:
        m.add_section("s2", "rectangle", w=0.01, d=0.002)
    assert e.value.item == "s2"
    with pytest.raises(flexmbd.ModelError) as e:
        m.fix("b", ["x", "q"])
    assert e.value.item == "b"
    with pytest.raises(flexmbd.ModelError) as e:
        m.remove_material("aluminium")
    assert e.value.item == "aluminium"
    # references are checked when the model is built: at the next analysis
    m.add_truss("t1", ["a", "n9"], ea=1e3)
    with pytest.raises(flexmbd.ModelError) as e:
        m.check()
    assert e.value.item == "t1" and "n9" in str(e.value)
    assert e.value.file == "<python>"
    m.remove_element("t1")
    m.check()


def test_an_empty_model_has_no_elements_to_analyse():
    m = flexmbd.Model("empty")
    assert m.name == "empty" and "0 nodes" in repr(m)
    with pytest.raises(flexmbd.ModelError):
        m.check()


def test_the_built_guides_static_compliance_is_that_of_five_folded_sheets():
    # each folded sheet resists x with 7.5 EI/L^3 (a guided sheet whose fold end is held by the
    # rotational stiffness 4EI/L of the base sheet); five in parallel
    ei = 210e9 * 0.02 * 0.2e-3**3 / 12
    k = 5 * 7.5 * ei / 0.05**3
    ss = example("five_sheet_guide").build().state_space(["c:x"], ["c:x"], static_correction=True)
    g = ss.frequency_response([1e-3])
    assert abs(g.ravel()[0]) == pytest.approx(1 / k, rel=1e-3)
