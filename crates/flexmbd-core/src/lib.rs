//! flexmbd-core: the analysis library of flexmbd.
//!
//! Model, element library, assembly and analyses for flexible multibody systems built from
//! elements with physically meaningful deformation modes (Jonker/Meijaard; SPACAR). No file
//! formats, no printing: those live in `flexmbd-io` and `flexmbd-cli`.
//!
//! Pipeline:
//!
//! ```text
//! text → flexmbd_io::parse → ModelSpec → ModelBuilder → Model
//!      → assembly::evaluate (e, D at x) → kinematics::check (Dcc, SVD, Table 1, advice)
//! ```
//!
//! Notation follows `docs/notation.md`: x nodal coordinates, e deformations, D = ∂e/∂x, Dcc the
//! Jacobian of the fixed and input deformations with respect to the dependent coordinates.

#![allow(non_snake_case)]

pub mod assembly;
pub mod dynamics;
pub mod elements;
pub mod kinematics;
pub mod linalg;
pub mod linearized;
pub mod math;
pub mod model;
pub mod results;
pub mod section;
pub mod simulation;
pub mod statics;

pub use model::{CoordKind, DefKind, Model, ModelBuilder, ModelError, Partition};
