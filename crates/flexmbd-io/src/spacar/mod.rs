//! SPACAR `.dat` models (docs/spacar-import.md; the format: shared docs/spacar-format.md).
//!
//! [`parse_dat`] reads every keyword of the format into a [`SpacarModel`]: the kinematic section
//! (nodes, elements, boundary conditions, partition), the static/dynamic section (stiffness,
//! masses, loads, inputs, load and time steps, user routines), the state-space block and the
//! visualisation section. Everything is kept with its line number, also the data flexmbd cannot
//! use yet, so that statics and dynamics can pick it up later. Checks that need the whole file
//! (node kinds, references, mode numbers) run after reading; every error names file, line and
//! column. Problems that cannot change the kinematic result are [`Warning`]s.
//!
//! [`SpacarModel::to_model`] builds the core [`Model`] for the kinematic check from the neutral
//! [`ModelSpec`] of [`SpacarModel::to_spec`]; [`SpacarModel::to_model_file`] builds the model for
//! statics from [`SpacarModel::to_static_spec`] (the same plus stiffness, masses, loads,
//! prescribed values, gravity and load steps; module `statics`), which the TOML writer serialises
//! ([`SpacarModel::to_toml`]).
//!
//! Node mapping: SPACAR numbers translational and rotational nodes separately. Translational
//! node `t` becomes flexmbd node `"t"` (its position); rotational node `r` becomes node `"t@r"`,
//! placed `at` `"t"` (own rotation, the host's position), where `t` is the translational node
//! the elements pair `r` with. See [`mapping`].

mod dynamics;
mod lexer;
pub mod mapping;
mod parser;
mod statics;
mod validate;

#[cfg(test)]
mod tests;

use crate::error::InputError;
use crate::spec::{ModelFile, ModelSpec, SpecError, SpecErrorKind};
use flexmbd_core::Model;
use rustc_hash::FxHashMap as HashMap;
use std::collections::BTreeMap;
use std::path::Path;

/// A non-fatal problem: the file is read, the kinematic result does not depend on it.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    /// 1-based line.
    pub line: usize,
    /// What and why.
    pub message: String,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

/// Kind of a SPACAR node number, from the element slots it appears in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NodeKind {
    /// Three position coordinates x, y, z (coordinates 1–3).
    Translational,
    /// Four Euler parameters λ0..λ3 (coordinates 1–4).
    Rotational,
    /// One warping coordinate (`BEAMW` only).
    Warping,
}

impl NodeKind {
    /// Lower-case name for messages.
    pub fn name(self) -> &'static str {
        match self {
            NodeKind::Translational => "translational",
            NodeKind::Rotational => "rotational",
            NodeKind::Warping => "warping",
        }
    }
    /// Number of coordinates.
    pub fn n_coords(self) -> u32 {
        match self {
            NodeKind::Translational => 3,
            NodeKind::Rotational => 4,
            NodeKind::Warping => 1,
        }
    }
}

/// An `X n x y z` line.
#[derive(Clone, Debug, PartialEq)]
pub struct Position {
    /// Node number.
    pub node: u32,
    /// Position [x, y, z] (3 values); 4 values are initial Euler parameters of a rotational
    /// node.
    pub values: Vec<f64>,
    /// Line.
    pub line: usize,
}

/// An element line.
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    /// Element number `ne`.
    pub number: u32,
    /// Type and nodes.
    pub kind: ElementKind,
    /// Line.
    pub line: usize,
}

/// SPACAR element types with their node slots (spacar-format.md §4.1).
#[derive(Clone, Debug, PartialEq)]
pub enum ElementKind {
    /// `BEAM ne xp λp xq λq [oy1 oy2 oy3]`: 6 deformations.
    Beam {
        /// Translational node p.
        xp: u32,
        /// Rotational node p.
        rp: u32,
        /// Translational node q.
        xq: u32,
        /// Rotational node q.
        rq: u32,
        /// Initial local y direction; `None` = SPACAR's default rule.
        orient: Option<[f64; 3]>,
    },
    /// `BEAMW ne xp λp wp xq λq wq [oy1 oy2 oy3]`: 8 deformations (6 + 2 warping).
    BeamW {
        /// Translational node p.
        xp: u32,
        /// Rotational node p.
        rp: u32,
        /// Warping node p.
        wp: u32,
        /// Translational node q.
        xq: u32,
        /// Rotational node q.
        rq: u32,
        /// Warping node q.
        wq: u32,
        /// Initial local y direction.
        orient: Option<[f64; 3]>,
    },
    /// `RBEAM ne xp λp xq [oy1 oy2 oy3]`: rigid beam with one rotational node, 3 deformations.
    RBeam {
        /// Translational node p.
        xp: u32,
        /// Rotational node p.
        rp: u32,
        /// Translational node q.
        xq: u32,
        /// Initial local y direction (mass and drawing only).
        orient: Option<[f64; 3]>,
    },
    /// `HINGE ne λp λq a1 a2 a3`: 3 deformations, 1 = rotation about the axis.
    Hinge {
        /// Rotational node p.
        rp: u32,
        /// Rotational node q.
        rq: u32,
        /// Hinge axis.
        axis: [f64; 3],
    },
    /// `TRUSS ne xp xq`: 1 deformation, the elongation.
    Truss {
        /// Translational node p.
        xp: u32,
        /// Translational node q.
        xq: u32,
    },
}

impl ElementKind {
    /// The keyword.
    pub fn keyword(&self) -> &'static str {
        match self {
            ElementKind::Beam { .. } => "BEAM",
            ElementKind::BeamW { .. } => "BEAMW",
            ElementKind::RBeam { .. } => "RBEAM",
            ElementKind::Hinge { .. } => "HINGE",
            ElementKind::Truss { .. } => "TRUSS",
        }
    }
    /// Number of deformation modes in SPACAR.
    pub fn n_modes(&self) -> u32 {
        match self {
            ElementKind::Beam { .. } => 6,
            ElementKind::BeamW { .. } => 8,
            ElementKind::RBeam { .. } => 3,
            ElementKind::Hinge { .. } => 3,
            ElementKind::Truss { .. } => 1,
        }
    }
    /// The node numbers with the kind each slot implies, in slot order.
    pub fn node_slots(&self) -> Vec<(u32, NodeKind)> {
        use NodeKind::*;
        match *self {
            ElementKind::Beam { xp, rp, xq, rq, .. } => vec![
                (xp, Translational),
                (rp, Rotational),
                (xq, Translational),
                (rq, Rotational),
            ],
            ElementKind::BeamW {
                xp,
                rp,
                wp,
                xq,
                rq,
                wq,
                ..
            } => vec![
                (xp, Translational),
                (rp, Rotational),
                (wp, Warping),
                (xq, Translational),
                (rq, Rotational),
                (wq, Warping),
            ],
            ElementKind::RBeam { xp, rp, xq, .. } => {
                vec![(xp, Translational), (rp, Rotational), (xq, Translational)]
            }
            ElementKind::Hinge { rp, rq, .. } => vec![(rp, Rotational), (rq, Rotational)],
            ElementKind::Truss { xp, xq } => vec![(xp, Translational), (xq, Translational)],
        }
    }
    /// Column names of `ESTIFF` (spacar-format.md §7.1; truss and hinge: one stiffness per
    /// deformation, interpretation).
    pub fn stiffness_columns(&self) -> &'static [&'static str] {
        match self {
            ElementKind::Beam { .. } => &["EA", "GJ", "EIy", "EIz", "ShearY", "ShearZ"],
            ElementKind::BeamW { .. } => &["EA", "GJ", "EIy", "EIz", "ShearY", "ShearZ", "ECw"],
            ElementKind::RBeam { .. } => &[],
            ElementKind::Hinge { .. } => &["k", "k2", "k3"],
            ElementKind::Truss { .. } => &["EA"],
        }
    }
    /// Column names of `EM` (spacar-format.md §7.2).
    pub fn mass_columns(&self) -> &'static [&'static str] {
        match self {
            ElementKind::Beam { .. } => &["M/L", "Jxx/L", "Jyy/L", "Jzz/L", "Jyz/L"],
            ElementKind::BeamW { .. } => &["M/L", "Jxx/L", "Jyy/L", "Jzz/L", "Jyz/L", "Jw/L"],
            ElementKind::RBeam { .. } => &["M/L"],
            ElementKind::Hinge { .. } => &[],
            ElementKind::Truss { .. } => &["M/L"],
        }
    }
}

/// A list of deformation modes of one element (`RLSE`, `DYNE`, `INPUTE`).
#[derive(Clone, Debug, PartialEq)]
pub struct ModeList {
    /// Element number.
    pub element: u32,
    /// Modes, 1-based.
    pub modes: Vec<u32>,
    /// Line.
    pub line: usize,
}

/// A list of nodal coordinates of one node (`FIX`, `INPUTX`, `DYNX`).
#[derive(Clone, Debug, PartialEq)]
pub struct CoordList {
    /// Node number.
    pub node: u32,
    /// Coordinate indices (translational 1–3 = x, y, z; rotational 1–4 = λ0..λ3); `None` =
    /// all (`FIX n`; for a rotational node λ1..λ3, λ0 stays dependent).
    pub coords: Option<Vec<u32>>,
    /// Line.
    pub line: usize,
}

/// Values for one element (`ESTIFF`, `EM`, `ESIG`).
#[derive(Clone, Debug, PartialEq)]
pub struct ElementValues {
    /// Element number.
    pub element: u32,
    /// Values as given (omitted trailing values are not stored).
    pub values: Vec<f64>,
    /// Line.
    pub line: usize,
}

/// The last entry of each element number in an element table (a later line overrides an
/// earlier one): one pass over the table, so that reading a file stays linear in its size.
fn last_per_element(list: &[ElementValues]) -> HashMap<u32, &ElementValues> {
    let mut by = HashMap::with_capacity_and_hasher(list.len(), Default::default());
    for v in list {
        by.insert(v.element, v);
    }
    by
}

/// The mode lists (`RLSE`, `DYNE`, `INPUTE`) of each element number, in file order.
fn lists_per_element(list: &[ModeList]) -> HashMap<u32, Vec<&ModeList>> {
    let mut by: HashMap<u32, Vec<&ModeList>> = HashMap::default();
    for l in list {
        by.entry(l.element).or_default().push(l);
    }
    by
}

/// Per-element lookups of a model's element tables, built once, so that reading a file stays
/// linear in its size.
pub(crate) struct ByElement<'a> {
    /// The last `ESTIFF` of each element.
    pub estiff: HashMap<u32, &'a ElementValues>,
    /// The last `EM` of each element.
    pub em: HashMap<u32, &'a ElementValues>,
    /// The last `ESIG` of each element.
    pub esig: HashMap<u32, &'a ElementValues>,
    /// The `RLSE` lists of each element.
    pub rlse: HashMap<u32, Vec<&'a ModeList>>,
    /// The `DYNE` lists of each element.
    pub dyne: HashMap<u32, Vec<&'a ModeList>>,
    /// The `INPUTE` lists of each element.
    pub inpute: HashMap<u32, Vec<&'a ModeList>>,
}

impl<'a> ByElement<'a> {
    /// The lookups of `m`.
    pub(crate) fn new(m: &'a SpacarModel) -> Self {
        Self {
            estiff: last_per_element(&m.estiff),
            em: last_per_element(&m.em),
            esig: last_per_element(&m.esig),
            rlse: lists_per_element(&m.rlse),
            dyne: lists_per_element(&m.dyne),
            inpute: lists_per_element(&m.inpute),
        }
    }
}

/// Values for one node (`XF`, `DELXF`, `XM`).
#[derive(Clone, Debug, PartialEq)]
pub struct NodeValues {
    /// Node number.
    pub node: u32,
    /// Values as given.
    pub values: Vec<f64>,
    /// Line.
    pub line: usize,
}

/// A value of one nodal coordinate (`INPUTX n c v`, `DELINPX n c v` in the static section).
#[derive(Clone, Debug, PartialEq)]
pub struct CoordValue {
    /// Node number.
    pub node: u32,
    /// Coordinate index.
    pub coord: u32,
    /// Value (absolute coordinate for `INPUTX`, increment for `DELINPX`).
    pub value: f64,
    /// Velocity and acceleration after the value (`INPUTX n c x ẋ ẍ` in a file for a time
    /// simulation); zero when not given.
    pub rates: [f64; 2],
    /// Line.
    pub line: usize,
}

/// An initial condition of a dynamic degree of freedom: `STARTDE ne m e ė` (deformation mode m
/// of a `DYNE` element) or `STARTDX n c x ẋ` (coordinate c of a `DYNX` node).
#[derive(Clone, Debug, PartialEq)]
pub struct StartValue {
    /// Element (`STARTDE`) or node (`STARTDX`) number.
    pub number: u32,
    /// Deformation mode or coordinate index, 1-based.
    pub index: u32,
    /// Initial value.
    pub value: f64,
    /// Initial rate (zero when not given).
    pub rate: f64,
    /// Line.
    pub line: usize,
}

/// A value of one deformation (`INPUTE ne m v`, `DELINPE ne m v` in the static section).
#[derive(Clone, Debug, PartialEq)]
pub struct ModeValue {
    /// Element number.
    pub element: u32,
    /// Mode, 1-based.
    pub mode: u32,
    /// Value.
    pub value: f64,
    /// Line.
    pub line: usize,
}

/// A keyword with a list of numbers (`GRAVITY`, `ITERSTEP`, `TIMESTEP`, `ERROR`, `OUTLEVEL`).
#[derive(Clone, Debug, PartialEq)]
pub struct Values {
    /// The numbers.
    pub values: Vec<f64>,
    /// Line.
    pub line: usize,
}

/// A user MATLAB routine (`USERSIG`, `USERINP`, …); flexmbd cannot run them.
#[derive(Clone, Debug, PartialEq)]
pub struct UserRoutine {
    /// Keyword.
    pub keyword: String,
    /// Routine name.
    pub name: String,
    /// Line.
    pub line: usize,
}

/// What a state-space line declares (mode 9).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IoKind {
    /// `INPUTF`: a force input.
    Force,
    /// `OUTX`: a displacement output.
    Displacement,
    /// `OUTXP`: a velocity output.
    Velocity,
}

/// `INPUTF k n dir`, `OUTX k n dir`, `OUTXP k n dir`.
#[derive(Clone, Debug, PartialEq)]
pub struct StateSpaceIo {
    /// Which.
    pub kind: IoKind,
    /// Index k of the input or output.
    pub index: u32,
    /// Node number.
    pub node: u32,
    /// Direction (coordinate index).
    pub dir: u32,
    /// Line.
    pub line: usize,
}

/// A line kept as text (visualisation, ignored keywords).
#[derive(Clone, Debug, PartialEq)]
pub struct RawLine {
    /// Keyword, upper case.
    pub keyword: String,
    /// The other fields.
    pub fields: Vec<String>,
    /// Line.
    pub line: usize,
}

/// The `END` / `HALT` structure as found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Structure {
    /// Lines of `END`.
    pub end_lines: Vec<usize>,
    /// Lines of `HALT`.
    pub halt_lines: Vec<usize>,
    /// Whether the analysis input was closed by `END END`.
    pub complete: bool,
}

/// A SPACAR model as read from a `.dat` file: all keywords, with line numbers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SpacarModel {
    /// File name for messages.
    pub file: String,
    /// Model name (the file stem).
    pub name: String,
    /// The first comment of the file, often a title or "generated with SPACAR Light x.y".
    pub title: Option<String>,
    // --- kinematic section ---
    /// `X` lines.
    pub positions: Vec<Position>,
    /// Element lines, in file order.
    pub elements: Vec<Element>,
    /// `RLSE`: released (calculable) deformations, e^c.
    pub rlse: Vec<ModeList>,
    /// `DYNE`: dynamic degrees of freedom, e^d.
    pub dyne: Vec<ModeList>,
    /// `INPUTE`: prescribed input deformations, e^m.
    pub inpute: Vec<ModeList>,
    /// `FIX`: fixed coordinates, x^o.
    pub fix: Vec<CoordList>,
    /// `INPUTX` (kinematic section): prescribed input coordinates, x^m.
    pub inputx: Vec<CoordList>,
    /// `DYNX`: dynamic-DOF coordinates, x^d.
    pub dynx: Vec<CoordList>,
    // --- static / dynamic section ---
    /// `ESTIFF`: element stiffness constants.
    pub estiff: Vec<ElementValues>,
    /// `EM`: element mass constants per unit length.
    pub em: Vec<ElementValues>,
    /// `ESIG`: pre-stress.
    pub esig: Vec<ElementValues>,
    /// `EDAMP` (also read as `ED`): element damping constants, in the columns of `ESTIFF`.
    pub edamp: Vec<ElementValues>,
    /// `STARTDE`: initial values and rates of dynamic deformations (e^d).
    pub startde: Vec<StartValue>,
    /// `STARTDX`: initial values and rates of dynamic coordinates (x^d).
    pub startdx: Vec<StartValue>,
    /// `XM`: nodal mass (1 value) or inertia tensor (6 values, rotational node).
    pub xm: Vec<NodeValues>,
    /// `XF`: initial nodal loads (force on a translational node, moment on a rotational node).
    pub xf: Vec<NodeValues>,
    /// `DELXF`: nodal load increments.
    pub delxf: Vec<NodeValues>,
    /// `INPUTX n c v` (static section): initial absolute values of input coordinates.
    pub inputx_values: Vec<CoordValue>,
    /// `DELINPX n c v`: increments of input coordinates.
    pub delinpx: Vec<CoordValue>,
    /// `INPUTE ne m v` (static section): initial values of input deformations.
    pub inpute_values: Vec<ModeValue>,
    /// `DELINPE ne m v`: increments of input deformations.
    pub delinpe: Vec<ModeValue>,
    /// `GRAVITY gx gy gz`.
    pub gravity: Option<Values>,
    /// `ITERSTEP` (load steps and Newton control, spacar-format.md §6).
    pub iterstep: Option<Values>,
    /// `TIMESTEP t_end n_steps`.
    pub timestep: Option<Values>,
    /// `ERROR abs rel` (time-integration tolerances).
    pub error_tol: Option<Values>,
    /// `OUTLEVEL`.
    pub outlevel: Option<Values>,
    /// `USERSIG`, `USERINP`, other `USER…` lines.
    pub user_routines: Vec<UserRoutine>,
    /// `INPUTF`, `OUTX`, `OUTXP` (state-space block, mode 9).
    pub state_space: Vec<StateSpaceIo>,
    /// The visualisation section, line by line.
    pub visualization: Vec<RawLine>,
    /// Lines with unknown keywords (each also a warning).
    pub ignored: Vec<RawLine>,
    /// `END` / `HALT` structure.
    pub structure: Structure,
    /// Warnings, in line order.
    pub warnings: Vec<Warning>,
    /// Kind of every node number used by an element.
    pub node_kinds: BTreeMap<u32, NodeKind>,
}

/// What kind of SPACAR analysis the file is set up for, from its static/dynamic section.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AnalysisHint {
    /// No static/dynamic data: kinematic analysis (mode 0).
    Kinematic,
    /// `ITERSTEP`: static equilibrium with load steps (mode 10).
    Static,
    /// `TIMESTEP`: forward-dynamic time simulation (mode 1).
    Dynamic,
    /// `INPUTF` / `OUTX` / `OUTXP`: linearised state space (mode 9).
    StateSpace,
}

impl AnalysisHint {
    /// Description with SPACAR's mode number.
    pub fn describe(self) -> &'static str {
        match self {
            AnalysisHint::Kinematic => "kinematic analysis only (SPACAR mode 0)",
            AnalysisHint::Static => "static equilibrium with load steps (SPACAR mode 10)",
            AnalysisHint::Dynamic => "forward-dynamic time simulation (SPACAR mode 1)",
            AnalysisHint::StateSpace => "linearised state-space model (SPACAR mode 9)",
        }
    }
}

impl SpacarModel {
    /// The analysis the file is set up for.
    pub fn analysis_hint(&self) -> AnalysisHint {
        if !self.state_space.is_empty() {
            AnalysisHint::StateSpace
        } else if self.timestep.is_some() {
            AnalysisHint::Dynamic
        } else if self.iterstep.is_some() {
            AnalysisHint::Static
        } else {
            AnalysisHint::Kinematic
        }
    }

    /// Number of node numbers of a kind used by the elements.
    pub fn count_nodes(&self, kind: NodeKind) -> usize {
        self.node_kinds.values().filter(|k| **k == kind).count()
    }

    /// The element with a number.
    pub fn element(&self, number: u32) -> Option<&Element> {
        self.elements.iter().find(|e| e.number == number)
    }

    /// The neutral model spec of the kinematic check (flexmbd nodes, elements, fix and inputs,
    /// with comments): `DYNE` deformations and `DYNX` coordinates are inputs, as in SPACAR's
    /// kinematic analysis.
    pub fn to_spec(&self) -> Result<ModelSpec, InputError> {
        mapping::to_spec(self, true)
    }

    /// The neutral model spec with the static data (beam constants, modes kept rigid, loads,
    /// masses, prescribed values, gravity, load steps; docs/spacar-import.md §6), and the
    /// warnings of that mapping (what `flexmbd static` on the `.dat` file approximates).
    pub fn to_static_spec(&self) -> Result<(ModelSpec, Vec<Warning>), InputError> {
        statics::convert(self, statics::Purpose::Document).map(|c| (c.spec, c.warnings))
    }

    /// Build the core model for the kinematic check; errors name file and line.
    pub fn to_model(&self) -> Result<Model, InputError> {
        let spec = mapping::to_spec(self, false)?;
        spec.build().map_err(|e| self.spec_error(e))
    }

    /// The model and settings for `flexmbd static`, with the warnings of the mapping (each
    /// naming a line). `DYNE` deformations with stiffness are flexible, deformations SPACAR keeps
    /// rigid stay rigid, `DYNX` coordinates are unknowns, loads and prescribed values reach
    /// their final SPACAR values (initial + increment) at load factor 1.
    pub fn to_model_file(&self) -> Result<(ModelFile, Vec<Warning>), InputError> {
        let c = statics::convert(self, statics::Purpose::Static)?;
        let file = c.spec.build_static().map_err(|e| self.spec_error(e))?;
        Ok((file, c.warnings))
    }

    /// The model and settings for `flexmbd simulate` (SPACAR mode 1, docs/spacar-import.md
    /// §7), with the warnings of the mapping (each naming a line): the model of
    /// [`Self::to_model_file`] with the `DYNE` modes without stiffness free and the inertia
    /// tensors of `XM`; `TIMESTEP`, `ERROR`, and the loads and prescribed inputs as functions
    /// of time in [`ModelFile::simulate`]. What would change the motion and cannot be mapped
    /// (user routines, element damping, initial conditions other than the reference at rest, …)
    /// is an error at its line.
    pub fn to_dynamic_model_file(&self) -> Result<(ModelFile, Vec<Warning>), InputError> {
        let d = dynamics::convert(self)?;
        let file = d.spec.build_static().map_err(|e| self.spec_error(e))?;
        Ok((file, d.warnings))
    }

    /// The equivalent native TOML model with the static data; what TOML cannot express is kept
    /// as comments.
    pub fn to_toml(&self) -> Result<String, InputError> {
        self.to_toml_with_warnings().map(|(t, _)| t)
    }

    /// [`Self::to_toml`] with the warnings of the mapping: those of [`Self::to_model_file`] and
    /// those about what the TOML format cannot express (shear flexibilities, `DYNX` in statics).
    /// They are also written into the file's header.
    pub fn to_toml_with_warnings(&self) -> Result<(String, Vec<Warning>), InputError> {
        let c = statics::convert(self, statics::Purpose::Document)?;
        // a file that does not read back is reported here, at its line
        c.spec.build().map_err(|e| self.spec_error(e))?;
        let text = crate::model_toml::write_toml(&c.spec).map_err(|m| InputError::File {
            file: self.file.clone(),
            message: m,
        })?;
        let mut w = c.warnings;
        w.extend(c.toml_warnings);
        w.sort_by_key(|w| w.line);
        Ok((text, w))
    }

    /// A model without elements is an error at the last node line (line 1 without one).
    fn no_elements(&self, message: String) -> InputError {
        let line = self.positions.last().map_or(1, |p| p.line);
        crate::error::at_line(
            &self.file,
            line,
            1,
            format!("{message} (no element line such as BEAM, TRUSS or HINGE in the file)"),
        )
    }

    /// A build error of a spec from this file, at its line (a model without elements at the
    /// last node line).
    fn spec_error(&self, e: SpecError) -> InputError {
        if let SpecErrorKind::NoElements(message) = e.kind {
            return self.no_elements(message);
        }
        crate::error::at_line(
            &self.file,
            e.line().unwrap_or(1),
            1,
            format!("{e} (in the flexmbd model built from this line)"),
        )
    }
}

/// Parse `.dat` text; `file` names it in messages (its stem becomes the model name).
pub fn parse_dat(text: &str, file: &str) -> Result<SpacarModel, InputError> {
    let mut m = parser::parse(text, file)?;
    validate::validate(&mut m)?;
    m.warnings.sort_by_key(|w| w.line);
    Ok(m)
}

/// Read and parse a `.dat` file. Bytes that are not UTF-8 (e.g. Latin-1 comments) are replaced;
/// in a data field they give an error at their line.
pub fn read_dat(path: &Path) -> Result<SpacarModel, InputError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| InputError::Read {
        file: file.clone(),
        source,
    })?;
    parse_dat(&String::from_utf8_lossy(&bytes), &file)
}
