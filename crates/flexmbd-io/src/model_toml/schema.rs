//! The TOML file as serde reads it (docs/model-format.md): every table and key the format has,
//! with the spans of tables and entries for error messages. Values are checked later, when the
//! file becomes a [`crate::spec::ModelSpec`] (`read.rs`) and when that is built.

use flexmbd_core::simulation::TimeFunction;
use indexmap::IndexMap;
use serde::Deserialize;
use toml::Spanned;

/// The whole file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileSpec {
    pub(super) model: Option<ModelSection>,
    pub(super) nodes: Option<IndexMap<String, Spanned<toml::Value>>>,
    pub(super) fix: Option<IndexMap<String, Spanned<toml::Value>>>,
    pub(super) inputs: Option<IndexMap<String, Spanned<toml::Value>>>,
    #[serde(default)]
    pub(super) truss: Vec<Spanned<TrussSpec>>,
    #[serde(default)]
    pub(super) beam: Vec<Spanned<BeamSpec>>,
    #[serde(default)]
    pub(super) hinge: Vec<Spanned<HingeSpec>>,
    #[serde(default)]
    pub(super) rigid: Vec<Spanned<RigidSpec>>,
    #[serde(default)]
    pub(super) material: Vec<Spanned<MaterialSpec>>,
    #[serde(default)]
    pub(super) section: Vec<Spanned<SectionSpec>>,
    #[serde(default)]
    pub(super) load: Vec<Spanned<LoadSpec>>,
    #[serde(default)]
    pub(super) mass: Vec<Spanned<MassSpec>>,
    #[serde(default)]
    pub(super) inertia: Vec<Spanned<InertiaSpec>>,
    #[serde(default)]
    pub(super) prescribe: Vec<Spanned<PrescribeSpec>>,
    #[serde(rename = "static")]
    pub(super) statics: Option<Spanned<StaticSpec>>,
    pub(super) simulate: Option<Spanned<SimulateSpec>>,
    #[serde(default)]
    pub(super) velocity: Vec<Spanned<VelocitySpec>>,
}

/// `[[material]]`: E and G (or ν), density.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MaterialSpec {
    pub(super) id: String,
    #[serde(rename = "E")]
    pub(super) e: f64,
    #[serde(rename = "G")]
    pub(super) g: Option<f64>,
    pub(super) nu: Option<f64>,
    #[serde(default)]
    pub(super) rho: f64,
}

/// `[[section]]`: a shape with its dimensions [m], or properties given directly.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SectionSpec {
    pub(super) id: String,
    pub(super) shape: String,
    pub(super) w: Option<f64>,
    pub(super) t: Option<f64>,
    pub(super) d: Option<f64>,
    pub(super) d_out: Option<f64>,
    pub(super) d_in: Option<f64>,
    #[serde(rename = "A")]
    pub(super) a: Option<f64>,
    #[serde(rename = "Iy")]
    pub(super) iy: Option<f64>,
    #[serde(rename = "Iz")]
    pub(super) iz: Option<f64>,
    #[serde(rename = "J")]
    pub(super) j: Option<f64>,
    pub(super) k: Option<f64>,
    /// Include shear flexibility (Timoshenko); default true as SPACAR Light.
    #[serde(default = "yes")]
    pub(super) shear: bool,
}

fn yes() -> bool {
    true
}

/// `[[load]]`: dead force and moment on a node at load factor 1.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LoadSpec {
    pub(super) node: String,
    #[serde(default)]
    pub(super) force: [f64; 3],
    #[serde(default)]
    pub(super) moment: [f64; 3],
    /// φ(t) in a time simulation.
    pub(super) history: Option<TimeFunction>,
}

/// `[[mass]]`: a point mass on a node.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MassSpec {
    pub(super) node: String,
    pub(super) m: f64,
}

/// `[[inertia]]`: an inertia tensor about a rotational node (global axes, reference
/// orientation), `I = [Ixx, Ixy, Ixz, Iyy, Iyz, Izz]` [kg·m²].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct InertiaSpec {
    pub(super) node: String,
    #[serde(rename = "I")]
    pub(super) i: [f64; 6],
}

/// `[[prescribe]]`: the final value of an input coordinate or deformation.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PrescribeSpec {
    pub(super) node: Option<String>,
    pub(super) dof: Option<String>,
    pub(super) element: Option<String>,
    pub(super) mode: Option<i64>,
    pub(super) value: f64,
    /// φ(t) in a time simulation.
    pub(super) history: Option<TimeFunction>,
}

/// `[static]`: solver settings and requested outputs.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct StaticSpec {
    pub(super) steps: Option<usize>,
    pub(super) max_iterations: Option<usize>,
    pub(super) tol_force: Option<f64>,
    pub(super) tol_disp: Option<f64>,
    pub(super) gravity: Option<[f64; 3]>,
    pub(super) spin: Option<[f64; 3]>,
    pub(super) spin_point: Option<[f64; 3]>,
    #[serde(default)]
    pub(super) compliance: Vec<String>,
    #[serde(default)]
    pub(super) buckling: usize,
    #[serde(default)]
    pub(super) line_search: bool,
    pub(super) path: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ModelSection {
    pub(super) name: Option<String>,
    pub(super) description: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TrussSpec {
    pub(super) id: String,
    pub(super) nodes: Vec<String>,
    /// EA [N].
    #[serde(rename = "EA", default)]
    pub(super) ea: f64,
    #[serde(default)]
    pub(super) free: Vec<i64>,
    #[serde(default)]
    pub(super) input: Vec<i64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BeamSpec {
    pub(super) id: String,
    pub(super) nodes: Vec<String>,
    pub(super) orient: Option<[f64; 3]>,
    pub(super) ct: Option<f64>,
    #[serde(default)]
    pub(super) free: Vec<i64>,
    #[serde(default)]
    pub(super) input: Vec<i64>,
    /// Modes rigid in statics although they have stiffness.
    #[serde(default)]
    pub(super) fixed: Vec<i64>,
    pub(super) section: Option<String>,
    pub(super) material: Option<String>,
    /// Split into this many elements.
    pub(super) segments: Option<usize>,
    #[serde(rename = "EA")]
    pub(super) ea: Option<f64>,
    #[serde(rename = "GJ")]
    pub(super) gj: Option<f64>,
    #[serde(rename = "EIy")]
    pub(super) eiy: Option<f64>,
    #[serde(rename = "EIz")]
    pub(super) eiz: Option<f64>,
    /// Mass per length ρA [kg/m] when the constants are given directly.
    pub(super) rho_a: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct HingeSpec {
    pub(super) id: String,
    pub(super) nodes: Vec<String>,
    pub(super) axis: [f64; 3],
    #[serde(default)]
    pub(super) k: f64,
    #[serde(default)]
    pub(super) free: Vec<i64>,
    #[serde(default)]
    pub(super) input: Vec<i64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RigidSpec {
    pub(super) id: String,
    pub(super) nodes: Vec<String>,
}

/// `[simulate]` as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SimulateSpec {
    pub(super) t_end: Option<f64>,
    pub(super) dt: Option<f64>,
    pub(super) step: Option<String>,
    pub(super) dt_min: Option<f64>,
    pub(super) dt_max: Option<f64>,
    pub(super) rho_inf: Option<f64>,
    pub(super) tolerance: Option<[f64; 2]>,
    pub(super) output_step: Option<f64>,
    pub(super) max_iterations: Option<usize>,
    pub(super) rayleigh: Option<[f64; 2]>,
    pub(super) start: Option<String>,
    pub(super) static_steps: Option<usize>,
    pub(super) gravity_history: Option<TimeFunction>,
}

/// `[[velocity]]`: an initial velocity.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct VelocitySpec {
    pub(super) node: String,
    #[serde(default)]
    pub(super) v: [f64; 3],
    #[serde(default)]
    pub(super) omega: [f64; 3],
}
