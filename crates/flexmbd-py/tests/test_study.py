"""Design studies from Python (flexmbd.study): the local run on all cores, a real Dask
LocalCluster of two worker processes giving the same records bit for bit, the command line's
records, the output folder resumed, and the errors of a study file."""

import json
import pathlib
import pickle
import subprocess

import pytest

import flexmbd
import flexmbd.study

from conftest import ROOT, flexmbd_binary

STUDY = """
[study]
name = "strip: thickness and length"
model = "strip.toml"
analyses = ["check", "modes"]
modes = 3
sampling = "latin"
samples = 8
seed = 5
[parameters]
"sections.strip.t" = { from = 0.2e-3, to = 0.8e-3 }
"nodes.tip.x" = { from = 0.06, to = 0.12 }
"""


@pytest.fixture()
def study_file(tmp_path):
    (tmp_path / "strip.toml").write_text((ROOT / "examples" / "strip_f01.toml").read_text())
    p = tmp_path / "strip_study.toml"
    p.write_text(STUDY)
    return p


def test_local_run_gives_euler_bernoulli_frequencies(study_file):
    s = flexmbd.study.load(study_file)
    assert s.parameters == ["sections.strip.t", "nodes.tip.x"]
    res = flexmbd.study.run(s)
    assert len(res) == 8 and not res.failed
    for r in res.records:
        t, L = r["parameters"]["sections.strip.t"], r["parameters"]["nodes.tip.x"]
        # validation.md F01: f1 = (beta1 L)^2 sqrt(E t^2 / (12 rho L^4)) / (2 pi)
        exact = 1.875104**2 * (200e9 * t * t / (12 * 7800 * L**4)) ** 0.5 / (2 * 3.141592653589793)
        assert abs(r["merits"]["f1"] / exact - 1) < 1e-3
    # the Latin hypercube: one variant in each eighth of each range
    for name, (lo, hi) in {"sections.strip.t": (0.2e-3, 0.8e-3), "nodes.tip.x": (0.06, 0.12)}.items():
        strata = sorted(int((v - lo) / (hi - lo) * 8) for v in res.column(name))
        assert strata == list(range(8))


def test_a_dask_local_cluster_gives_the_same_records_bit_for_bit(study_file):
    distributed = pytest.importorskip("distributed")
    s = flexmbd.study.load(study_file)
    local = flexmbd.study.run(s, jobs=2)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        assert len(client.nthreads()) == 2
        remote = flexmbd.study.run(s, client=client, batch_size=3)
    assert remote.lines == local.lines


def test_the_command_line_writes_the_same_records(study_file, tmp_path):
    out = tmp_path / "cli_out"
    p = subprocess.run(
        [flexmbd_binary(), "--quiet", "study", str(study_file), "--out", str(out), "--no-plots"],
        capture_output=True,
        text=True,
    )
    assert p.returncode == 0, p.stderr
    cli_lines = sorted((out / "records.jsonl").read_text().splitlines())
    py_lines = sorted(flexmbd.study.run(study_file).lines)
    assert cli_lines == py_lines


def test_an_output_folder_is_written_and_resumed(study_file, tmp_path):
    s = flexmbd.study.load(study_file)
    out = tmp_path / "out"
    first = flexmbd.study.run(s, out=out, plots=False)
    assert (out / "results.csv").read_text().count("\n") == 9
    # keep the first three records only: a run stopped part-way
    lines = (out / "records.jsonl").read_text().splitlines(keepends=True)
    (out / "records.jsonl").write_text("".join(lines[:3]))
    again = flexmbd.study.run(s, out=out, plots=True)
    assert again.lines == first.lines
    assert (out / "study.html").exists()
    assert sorted((out / "records.jsonl").read_text().splitlines()) == sorted(first.lines)
    # the study pickles as its document (as it travels to a Dask worker)
    back = pickle.loads(pickle.dumps(s))
    assert back.document == s.document and back.variants() == s.variants()


def test_study_errors_name_the_file_and_line(tmp_path):
    (tmp_path / "strip.toml").write_text((ROOT / "examples" / "strip_f01.toml").read_text())
    bad = tmp_path / "bad.toml"
    bad.write_text(STUDY.replace('"nodes.tip.x"', '"nodes.top.x"'))
    with pytest.raises(flexmbd.ModelError) as e:
        flexmbd.study.load(bad)
    assert e.value.line == 12 and "nodes.top.x" in str(e.value)
    with pytest.raises(flexmbd.ReadError):
        flexmbd.study.load(tmp_path / "missing.toml")
