//! The TOML file as serde reads it (docs/model-format.md): every table and key the format has,
//! with the spans of tables and entries for error messages. Values are checked later, when the
//! file becomes a [`crate::spec::ModelSpec`] (`read.rs`) and when that is built.

use flexmbd_core::simulation::TimeFunction;
use indexmap::IndexMap;
use serde::Deserialize;
use serde::Deserializer;
use std::ops::Range;
use toml::Spanned;

/// A real value as written: a number, or a string holding an expression of the parameters
/// (docs/model-format.md, "Parameters and expressions"), with its place in the file.
#[derive(Clone, Debug, Default)]
pub(super) struct Real {
    pub(super) value: RealValue,
    /// The value's bytes in the file (empty for a default).
    pub(super) span: Range<usize>,
}

/// A number or an expression.
#[derive(Clone, Debug)]
pub(super) enum RealValue {
    Num(f64),
    Expr(String),
}

impl Default for RealValue {
    fn default() -> Self {
        Self::Num(0.0)
    }
}

impl<'de> Deserialize<'de> for Real {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Spanned::<toml::Value>::deserialize(d)?;
        let span = v.span();
        let value = match v.into_inner() {
            toml::Value::Float(f) => RealValue::Num(f),
            toml::Value::Integer(i) => RealValue::Num(i as f64),
            toml::Value::String(s) => RealValue::Expr(s),
            other => {
                return Err(serde::de::Error::custom(format!(
                    "invalid type: {}, expected a number or an expression in a string",
                    other.type_str()
                )))
            }
        };
        Ok(Real { value, span })
    }
}

/// The whole file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileSpec {
    pub(super) model: Option<ModelSection>,
    pub(super) parameters: Option<IndexMap<String, Spanned<toml::Value>>>,
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
    #[serde(default)]
    pub(super) freedom: Vec<Spanned<FreedomSpec>>,
}

/// `[[material]]`: E and G (or ν), density.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MaterialSpec {
    pub(super) id: String,
    #[serde(rename = "E")]
    pub(super) e: Real,
    #[serde(rename = "G")]
    pub(super) g: Option<Real>,
    pub(super) nu: Option<Real>,
    #[serde(default)]
    pub(super) rho: Real,
    /// Retardation time τ [s] of the material damping.
    pub(super) damping: Option<Real>,
}

/// `[[section]]`: a shape with its dimensions [m], or properties given directly.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SectionSpec {
    pub(super) id: String,
    pub(super) shape: String,
    pub(super) w: Option<Real>,
    pub(super) t: Option<Real>,
    pub(super) d: Option<Real>,
    pub(super) d_out: Option<Real>,
    pub(super) d_in: Option<Real>,
    #[serde(rename = "A")]
    pub(super) a: Option<Real>,
    #[serde(rename = "Iy")]
    pub(super) iy: Option<Real>,
    #[serde(rename = "Iz")]
    pub(super) iz: Option<Real>,
    #[serde(rename = "J")]
    pub(super) j: Option<Real>,
    pub(super) k: Option<Real>,
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
    pub(super) force: [Real; 3],
    #[serde(default)]
    pub(super) moment: [Real; 3],
    /// φ(t) in a time simulation.
    pub(super) history: Option<TimeFunction>,
}

/// `[[mass]]`: a point mass on a node.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MassSpec {
    pub(super) node: String,
    pub(super) m: Real,
}

/// `[[inertia]]`: an inertia tensor about a rotational node (global axes, reference
/// orientation), `I = [Ixx, Ixy, Ixz, Iyy, Iyz, Izz]` [kg·m²].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct InertiaSpec {
    pub(super) node: String,
    #[serde(rename = "I")]
    pub(super) i: [Real; 6],
}

/// `[[prescribe]]`: the final value of an input coordinate or deformation.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PrescribeSpec {
    pub(super) node: Option<String>,
    pub(super) dof: Option<String>,
    pub(super) element: Option<String>,
    pub(super) mode: Option<i64>,
    pub(super) value: Real,
    /// φ(t) in a time simulation.
    pub(super) history: Option<TimeFunction>,
}

/// `[static]`: solver settings and requested outputs.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct StaticSpec {
    pub(super) steps: Option<usize>,
    pub(super) max_iterations: Option<usize>,
    pub(super) tol_force: Option<Real>,
    pub(super) tol_disp: Option<Real>,
    pub(super) gravity: Option<[Real; 3]>,
    pub(super) spin: Option<[Real; 3]>,
    pub(super) spin_point: Option<[Real; 3]>,
    #[serde(default)]
    pub(super) compliance: Vec<String>,
    #[serde(default)]
    pub(super) buckling: usize,
    #[serde(default)]
    pub(super) line_search: bool,
    #[serde(default)]
    pub(super) tangent_eigenvalues: bool,
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
    pub(super) ea: Real,
    #[serde(default)]
    pub(super) free: Vec<i64>,
    #[serde(default)]
    pub(super) input: Vec<i64>,
    /// Retardation time τ [s] of the material damping.
    pub(super) damping: Option<Real>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BeamSpec {
    pub(super) id: String,
    pub(super) nodes: Vec<String>,
    pub(super) orient: Option<[Real; 3]>,
    pub(super) ct: Option<Real>,
    #[serde(default)]
    pub(super) free: Vec<i64>,
    #[serde(default)]
    pub(super) input: Vec<i64>,
    /// Retardation time τ [s] of the material damping.
    pub(super) damping: Option<Real>,
    /// Modes rigid in statics although they have stiffness.
    #[serde(default)]
    pub(super) fixed: Vec<i64>,
    pub(super) section: Option<String>,
    pub(super) material: Option<String>,
    /// Split into this many elements.
    pub(super) segments: Option<usize>,
    #[serde(rename = "EA")]
    pub(super) ea: Option<Real>,
    #[serde(rename = "GJ")]
    pub(super) gj: Option<Real>,
    #[serde(rename = "EIy")]
    pub(super) eiy: Option<Real>,
    #[serde(rename = "EIz")]
    pub(super) eiz: Option<Real>,
    /// Mass per length ρA [kg/m] when the constants are given directly.
    pub(super) rho_a: Option<Real>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct HingeSpec {
    pub(super) id: String,
    pub(super) nodes: Vec<String>,
    pub(super) axis: [Real; 3],
    #[serde(default)]
    pub(super) k: Real,
    #[serde(default)]
    pub(super) free: Vec<i64>,
    #[serde(default)]
    pub(super) input: Vec<i64>,
    /// Retardation time τ [s] of the material damping.
    pub(super) damping: Option<Real>,
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
    pub(super) t_end: Option<Real>,
    pub(super) dt: Option<Real>,
    pub(super) step: Option<String>,
    pub(super) dt_min: Option<Real>,
    pub(super) dt_max: Option<Real>,
    pub(super) rho_inf: Option<Real>,
    pub(super) tolerance: Option<[Real; 2]>,
    pub(super) output_step: Option<Real>,
    pub(super) max_iterations: Option<usize>,
    pub(super) rayleigh: Option<[Real; 2]>,
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
    pub(super) v: [Real; 3],
    #[serde(default)]
    pub(super) omega: [Real; 3],
}

/// `[[freedom]]`: a motion a body should have.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FreedomSpec {
    pub(super) body: String,
    pub(super) translation: Option<[Real; 3]>,
    pub(super) rotation: Option<RotationSpec>,
}

/// `rotation = { point, axis, pitch }` of a `[[freedom]]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RotationSpec {
    pub(super) point: [Real; 3],
    pub(super) axis: [Real; 3],
    #[serde(default)]
    pub(super) pitch: Real,
}
