//! flexmbd-io: model formats in, results out.
//!
//! - [`model_toml`]: the native TOML model format (docs/model-format.md) → `flexmbd_core::Model`.
//! - [`report`]: the kinematic analysis as JSON and as aligned text tables.
//!
//! Every input error is a [`InputError`] naming file, line and item.

pub mod error;
pub mod model_toml;
pub mod report;

pub use error::InputError;
pub use model_toml::{parse_model, read_model};
