//! The Python extension module `flexmbd._flexmbd` (the package `flexmbd` wraps it; see
//! `python/flexmbd/__init__.py` and docs/python.md).
//!
//! One function per analysis, each the core call of the matching `flexmbd` command on the
//! same readers (`flexmbd_io`), run with the GIL released; results are frozen classes whose
//! arrays are NumPy arrays and whose `to_dict()` is the command's `--json` document. Errors
//! are the exception classes of `flexmbd/_errors.py` ([`errors`]).

mod check;
mod convert;
mod document;
mod errors;
mod model;
mod simulate;
mod state_space;
mod states;
mod statics;
mod study;

use pyo3::prelude::*;

/// flexmbd's analyses (the Python package `flexmbd` is the interface to use).
#[pymodule]
fn _flexmbd(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<model::PyModel>()?;
    m.add_class::<document::Document>()?;
    m.add_class::<check::CheckResult>()?;
    m.add_class::<statics::StaticResult>()?;
    m.add_class::<statics::ModesResult>()?;
    m.add_class::<state_space::StateSpace>()?;
    m.add_class::<simulate::SimulationResult>()?;
    m.add_class::<states::States>()?;
    m.add_function(wrap_pyfunction!(document::load, m)?)?;
    m.add_function(wrap_pyfunction!(document::parse_toml, m)?)?;
    m.add_function(wrap_pyfunction!(model::parse, m)?)?;
    m.add_function(wrap_pyfunction!(check::check, m)?)?;
    m.add_function(wrap_pyfunction!(statics::static_, m)?)?;
    m.add_function(wrap_pyfunction!(statics::modes, m)?)?;
    m.add_function(wrap_pyfunction!(state_space::state_space, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::simulate, m)?)?;
    m.add_class::<study::StudyOutputs>()?;
    m.add_function(wrap_pyfunction!(study::study_read, m)?)?;
    m.add_function(wrap_pyfunction!(study::study_variants, m)?)?;
    m.add_function(wrap_pyfunction!(study::study_evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(study::study_run, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
