//! Design studies (docs/studies.md): a family of designs described by one parametric model,
//! its variants (a grid, a list or a Latin hypercube over the parameters), the figures of
//! merit of each variant (Table 1 class and counts, frequencies by mode class, support
//! stiffness along the stroke and its drop, the largest stress and actuation force, the
//! buckling margin), evaluated on all cores, written as they arrive and resumable.
//!
//! The flow: [`Study::read`] → [`variants`] → [`run`] (each variant: [`evaluate`] — the model's
//! member, then the library's analyses) → [`Outputs`] (JSON lines, CSV) → [`plots`].
//! A study is one JSON-serialisable value with the model's text inside, so that the Python
//! package can send it with a batch of variants to the workers of a Dask cluster, which call
//! [`evaluate_isolated`]: the same record, bit for bit, as the local run.

pub mod error;
pub mod evaluate;
pub mod output;
pub mod plots;
pub mod record;
pub mod run;
pub mod sampling;
pub mod spec;

pub use error::StudyError;
pub use evaluate::{evaluate, member};
pub use output::Outputs;
pub use record::{csv_header, merit_names, Failure, Record, Status};
pub use run::{evaluate_isolated, run, workers};
pub use sampling::{variants, Variant};
pub use spec::{Analyses, Axis, Parameter, Sampling, Study};
