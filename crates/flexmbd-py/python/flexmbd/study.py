"""Design studies: the variants of a parametric model, on all cores or on a Dask cluster.

A study file names a model, its parameters and how they vary, and the analyses whose figures
of merit each variant reports (docs/studies.md). ``flexmbd study STUDY.toml`` runs it from the
command line; from Python::

    import flexmbd.study
    s = flexmbd.study.load("examples/studies/folded_sheet_guide.toml")
    res = flexmbd.study.run(s)                       # all cores of this machine (rayon)
    res = flexmbd.study.run(s, client=dask_client)   # the workers of a Dask cluster
    res.records[0]["merits"]["f_support"]

Every variant runs on one thread, locally or on a worker, so the records of a Dask run are the
same, bit for bit, as those of the local run. With ``out=DIR`` the records are written as they
arrive (``records.jsonl``, ``results.csv``), then the plots and ``study.html``; a folder that
holds an unfinished run of the same study is resumed.
"""

import json as _json
import math as _math
import os as _os

from . import _flexmbd

__all__ = ["Study", "StudyResult", "load", "run"]


class Study:
    """A study read from its file, with the model's text inside (it pickles, and it travels
    to the workers of a cluster as one document)."""

    def __init__(self, document):
        self._doc = document
        d = _json.loads(document)
        self.name = d["name"]
        self.file = d["file"]
        self.model_file = d["model_file"]
        self.parameters = [p["name"] for p in d["parameters"]]

    @classmethod
    def read(cls, path):
        """Read a study file and the model file it names."""
        return cls(_flexmbd.study_read(_os.fspath(path)))

    @property
    def document(self):
        """The study as one JSON text."""
        return self._doc

    def variants(self):
        """The variants: a list of ``(index, {parameter: value})`` in index order."""
        return [
            (i, dict(zip(self.parameters, values)))
            for i, values in _flexmbd.study_variants(self._doc)
        ]

    def __reduce__(self):
        return (Study, (self._doc,))

    def __repr__(self):
        return f"<flexmbd.study.Study {self.name!r}: {len(self.parameters)} parameters>"


class StudyResult:
    """The records of a study in variant order: ``records`` (dicts), ``lines`` (their JSON
    text, the lines of ``records.jsonl``), ``failed`` (the records of variants that failed)."""

    def __init__(self, study, lines):
        self.study = study
        parsed = [(_json.loads(line), line) for line in lines]
        parsed.sort(key=lambda p: p[0]["variant"])
        self.records = [p[0] for p in parsed]
        self.lines = [p[1] for p in parsed]

    @property
    def failed(self):
        return [r for r in self.records if r["status"] != "ok"]

    def column(self, name):
        """One parameter or figure of merit over the variants (None where it has no value)."""
        out = []
        for r in self.records:
            if name in r["parameters"]:
                out.append(r["parameters"][name])
            else:
                out.append(r["merits"].get(name))
        return out

    def to_pandas(self):
        """The records as a pandas DataFrame (one row per variant; pandas must be installed)."""
        import pandas as pd

        rows = []
        for r in self.records:
            row = {"variant": r["variant"], **r["parameters"], "status": r["status"]}
            row.update({k: (_math.nan if v is None else v) for k, v in r["merits"].items()})
            row["table1"] = r["table1"]
            row["error"] = None if r["error"] is None else r["error"]["message"]
            rows.append(row)
        return pd.DataFrame(rows).set_index("variant")

    def __len__(self):
        return len(self.records)

    def __repr__(self):
        return (
            f"<flexmbd.study.StudyResult {self.study.name!r}: {len(self.records)} variants, "
            f"{len(self.failed)} failed>"
        )


def load(path):
    """Read a study file (and its model): a :class:`Study`."""
    return Study.read(path)


def _evaluate_batch(document, batch):
    """Evaluate a batch of variants ``[(index, [values])]`` on this worker, one thread: their
    records as JSON lines. The task that :func:`run` sends to Dask workers."""
    return _flexmbd.study_evaluate(document, batch)


def run(study, client=None, *, jobs=None, out=None, replace=False, plots=True, batch_size=None):
    """Run a study: a :class:`Study` or the path of a study file.

    - Without ``client``: on this machine, ``jobs`` threads (default one per core), each
      variant on one thread.
    - With ``client`` (a ``dask.distributed.Client``): the variants go to the cluster's workers
      in batches (``client.map``; ``batch_size`` variants each, default about four batches per
      worker thread), each batch on one thread of a worker.
    - ``out``: the output folder, written as records arrive and resumed when it holds an
      unfinished run of the same study (``replace=True`` starts over); ``plots`` draws the
      plots and ``study.html`` at the end.

    Returns a :class:`StudyResult` with every record in variant order (those of a resumed
    folder included).
    """
    if not isinstance(study, Study):
        study = Study.read(study)
    doc = study.document
    outputs = None if out is None else _flexmbd.StudyOutputs(doc, _os.fspath(out), replace)
    if jobs is not None and jobs < 1:
        from ._errors import OptionError

        raise OptionError(f"jobs must be at least 1, found {jobs}")
    if client is None:
        lines = _flexmbd.study_run(doc, 0 if jobs is None else jobs, outputs)
    else:
        lines = _run_dask(study, client, outputs, batch_size)
    if outputs is not None:
        lines = outputs.finish(plots)
    return StudyResult(study, lines)


def _run_dask(study, client, outputs, batch_size):
    from dask.distributed import as_completed

    done = set(outputs.done()) if outputs is not None else set()
    todo = [(i, values) for i, values in _flexmbd.study_variants(study.document) if i not in done]
    if not todo:
        return []
    if batch_size is None:
        threads = sum(client.nthreads().values()) or 1
        batch_size = max(1, _math.ceil(len(todo) / (4 * threads)))
    batches = [todo[k : k + batch_size] for k in range(0, len(todo), batch_size)]
    # the study document once per worker, not once per batch
    [doc] = client.scatter([study.document], broadcast=True)
    futures = client.map(_evaluate_batch, [doc] * len(batches), batches, pure=False)
    lines = []
    for f in as_completed(futures):
        got = f.result()
        if outputs is not None:
            outputs.write(got)
        lines.extend(got)
    return lines
