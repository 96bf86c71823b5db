"""Numbers from the paper, through the Python package."""

import numpy as np

import flexmbd


def test_twelve_truss_has_the_papers_motion_and_self_stress():
    # paper, Fig. 2 and eq. (16): Table 1 row 2, one motion and one self-stress in which all
    # twelve trusses carry +-sqrt(3)/6 (unit length: 12 * 3/36 = 1)
    r = flexmbd.load("examples/twelve_truss.toml").check()
    assert (r.table1_row, r.n_motions, r.n_self_stresses) == (2, 1, 1)
    values = np.concatenate(list(r.self_stresses[0].values()))
    values = values[values != 0]
    assert len(values) == 12
    np.testing.assert_allclose(np.abs(values), np.sqrt(3) / 6, rtol=1e-9)


def test_five_sheet_guide_is_exactly_constrained():
    # paper, Fig. 3b: five folded-sheet flexures constrain the part exactly
    r = flexmbd.load("examples/folded_sheet_guide_5.toml").check()
    assert r.exactly_constrained and r.n_motions == 0 and r.n_self_stresses == 0
