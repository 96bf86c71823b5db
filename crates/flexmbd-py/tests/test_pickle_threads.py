"""Pickling, threads and memory."""

import os
import pickle
import threading

import numpy as np
import pytest

import flexmbd
from compare import assert_same


def test_pickle_round_trip():
    m = flexmbd.load("examples/folded_sheet_guide_6.toml")
    back = pickle.loads(pickle.dumps(m))
    assert back.source == m.source and back.file == m.file and back.node_names == m.node_names
    assert_same(back.check().to_dict(), m.check().to_dict())
    f = flexmbd.Model.from_toml(m.source)
    assert pickle.loads(pickle.dumps(f)).element_names == m.element_names


@pytest.mark.filterwarnings("ignore::flexmbd.FlexmbdWarning")
def test_pickle_of_a_dat_model(tmp_path):
    # a model read from SPACAR text pickles as that text
    dat = sorted(__import__("pathlib").Path("crates/flexmbd-io/tests/models").rglob("*.dat"))
    if not dat:
        pytest.skip("no SPACAR fixture")
    m = flexmbd.Model.from_dat(dat[0].read_text(errors="replace"), dat[0].name)
    back = pickle.loads(pickle.dumps(m))
    assert back.format == "dat" and back.node_names == m.node_names


def test_two_threads_give_the_same_results():
    m = flexmbd.load("examples/paper_dynamic_5_sheets.toml")
    want = m.modes(count=6).frequencies
    out = {}

    def work(k):
        out[k] = [m.modes(count=6).frequencies for _ in range(3)]

    ts = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    for k in range(2):
        for f in out[k]:
            np.testing.assert_array_equal(f, want)


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


@pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="needs /proc")
def test_no_memory_growth_over_10000_analyses():
    m = flexmbd.load("examples/twelve_truss.toml")
    for _ in range(500):
        m.check().to_dict()
    before = rss_bytes()
    for _ in range(10_000):
        r = m.check()
        r.singular_values
        r.to_dict()
    grown = rss_bytes() - before
    # a leak of even 1 kB per analysis would show as 10 MB
    assert grown < 8 * 2**20, f"RSS grew by {grown / 2**20:.1f} MiB over 10,000 analyses"
