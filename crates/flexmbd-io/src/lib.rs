//! flexmbd-io: model formats in, results out.
//!
//! - [`spec`]: [`ModelSpec`], the complete, editable model document every reader produces, and
//!   its one build (`ModelSpec::build_file` → `Model` with its settings).
//! - [`model_toml`]: the native TOML model format (docs/model-format.md) ↔ [`ModelSpec`].
//! - [`report`]: the kinematic analysis as JSON and as aligned text tables.
//! - [`spacar`]: SPACAR `.dat` models (docs/spacar-import.md) → `SpacarModel` → [`ModelSpec`].
//! - [`vtk`]: ParaView `.vtu`/`.pvd` files; [`plots`]: PNG/SVG plots (docs/visualisation.md).
//! - [`html_view`]: the self-contained HTML 3D viewer (`flexmbd view`).
//!
//! Every input error is a [`InputError`] naming file, line and item.

pub mod error;
pub mod html_view;
pub mod limits;
pub mod model_toml;
pub mod modes_report;
pub mod plots;
pub mod report;
pub mod requests;
pub mod screw_report;
pub mod sim_report;
pub mod spacar;
pub mod spec;
pub mod statespace_report;
pub mod static_report;
pub mod stopped;
mod stream_json;
pub mod vtk;

pub use error::InputError;
pub use model_toml::{
    parse_model, parse_model_file, parse_spec, parse_spec_with, read_model, read_model_file,
    read_model_file_with, read_spec, read_spec_with, write_toml,
};
pub use spacar::{parse_dat, read_dat, SpacarModel};
pub use spec::{ModelFile, ModelSpec, Settings, SimulateSettings, SpecError};
