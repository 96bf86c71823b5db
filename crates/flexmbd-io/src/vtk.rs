//! VTK output for ParaView (docs/visualisation.md): hand-written XML UnstructuredGrid `.vtu`
//! files (ASCII) and `.pvd` collections.
//!
//! Geometry: one point per model node, in model order (a node placed `at` a host repeats the
//! host's position, so point i is always node i). Cells are VTK_LINE (3): one per truss, beam
//! and hinge between its two nodes, and one per member of a rigid body from its reference node
//! to that member (members − 1 lines; a member `at` the reference node gives a zero-length
//! line). The cell field `element` holds the element's index in the model, so every cell field
//! can be traced to its element.

use crate::static_report::{element_results, node_results};
use flexmbd_core::dynamics::Mode;
use flexmbd_core::elements::{Element, ElementKind};
use flexmbd_core::kinematics::ConstraintAnalysis;
use flexmbd_core::model::{Dof, Model};
use flexmbd_core::simulation::Frame;
use flexmbd_core::statics::StepResult;
use std::fmt::Write as _;
use std::path::Path;

/// VTK cell type of a line.
pub const VTK_LINE: u8 = 3;

/// A named data array: `values.len() == n × components`.
#[derive(Clone, Debug)]
pub struct Field {
    /// Array name.
    pub name: String,
    /// Components per tuple.
    pub components: usize,
    /// Values, tuple by tuple.
    pub values: Vec<f64>,
    /// Written as Int32 (element types and indices).
    pub integer: bool,
}

impl Field {
    /// A Float64 field.
    pub fn real(name: &str, components: usize, values: Vec<f64>) -> Self {
        Field {
            name: name.to_string(),
            components,
            values,
            integer: false,
        }
    }
    /// An Int32 field.
    pub fn int(name: &str, values: Vec<f64>) -> Self {
        Field {
            name: name.to_string(),
            components: 1,
            values,
            integer: true,
        }
    }
}

/// An unstructured grid of line cells with point and cell data.
#[derive(Clone, Debug, Default)]
pub struct Grid {
    /// Point coordinates.
    pub points: Vec<[f64; 3]>,
    /// Line cells (point index pairs).
    pub cells: Vec<[usize; 2]>,
    /// Model element index of every cell.
    pub cell_element: Vec<usize>,
    /// Point data.
    pub point_data: Vec<Field>,
    /// Cell data.
    pub cell_data: Vec<Field>,
}

/// Numeric element type code of the `element_type` cell field.
pub fn element_type_code(e: &Element) -> f64 {
    match e {
        Element::Truss(_) => 0.0,
        Element::Beam(_) => 1.0,
        Element::Hinge(_) => 2.0,
        Element::Rigid(_) => 3.0,
    }
}

/// The line cells of a model: (point pair, element index).
pub fn model_cells(model: &Model) -> Vec<([usize; 2], usize)> {
    let mut cells = Vec::new();
    for (k, entry) in model.elements.iter().enumerate() {
        match &entry.element {
            Element::Truss(t) => cells.push((t.nodes, k)),
            Element::Beam(b) => cells.push((b.nodes, k)),
            Element::Hinge(h) => cells.push((h.nodes, k)),
            Element::Rigid(r) => {
                for &m in &r.nodes[1..] {
                    cells.push(([r.nodes[0], m], k));
                }
            }
        }
    }
    cells
}

/// Number of line cells [`model_cells`] gives.
pub fn cell_count(model: &Model) -> usize {
    model_cells(model).len()
}

/// Size of the model: the diagonal of the bounding box of the reference positions (1 if zero).
pub fn model_size(model: &Model) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for n in &model.nodes {
        for i in 0..3 {
            lo[i] = lo[i].min(n.x0[i]);
            hi[i] = hi[i].max(n.x0[i]);
        }
    }
    let d = (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f64>().sqrt();
    if d.is_finite() && d > 0.0 {
        d
    } else {
        1.0
    }
}

impl Grid {
    /// The model's lines at nodal positions `x` (global coordinate vector), with the cell
    /// fields `element`, `element_type` and `section` (beam width and thickness [m] when the
    /// section is known, else 0).
    pub fn new(model: &Model, x: &[f64]) -> Self {
        let points = model
            .nodes
            .iter()
            .map(|n| [x[n.ix_pos], x[n.ix_pos + 1], x[n.ix_pos + 2]])
            .collect();
        let (cells, cell_element): (Vec<_>, Vec<_>) = model_cells(model).into_iter().unzip();
        let mut g = Grid {
            points,
            cells,
            cell_element,
            ..Grid::default()
        };
        g.add_cell_field(Field::int(
            "element",
            (0..model.elements.len()).map(|k| k as f64).collect(),
        ));
        g.add_cell_field(Field::int(
            "element_type",
            model
                .elements
                .iter()
                .map(|e| element_type_code(&e.element))
                .collect(),
        ));
        let section = model
            .elements
            .iter()
            .flat_map(|e| match &e.element {
                Element::Beam(b) => match b.props.as_deref() {
                    // fibre = outermost distances along local z (thickness/2), local y (width/2)
                    Some(p) if p.area > 0.0 => [2.0 * p.fibre[1], 2.0 * p.fibre[0]],
                    _ => [0.0; 2],
                },
                _ => [0.0; 2],
            })
            .collect();
        g.add_cell_field(Field::real("section", 2, section));
        g
    }

    /// Add a cell field given per element (`values.len() == elements × components`); it is
    /// repeated for every cell of the element.
    pub fn add_cell_field(&mut self, f: Field) {
        let c = f.components;
        let values = self
            .cell_element
            .iter()
            .flat_map(|&k| f.values[k * c..(k + 1) * c].iter().copied())
            .collect();
        self.cell_data.push(Field { values, ..f });
    }

    /// Add a point field (`values.len() == points × components`).
    pub fn add_point_field(&mut self, f: Field) {
        debug_assert_eq!(f.values.len(), self.points.len() * f.components);
        self.point_data.push(f);
    }

    /// The `.vtu` document.
    pub fn to_vtu(&self) -> String {
        let mut s = String::new();
        s += "<?xml version=\"1.0\"?>\n";
        s += "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
        s += "  <UnstructuredGrid>\n";
        let _ = writeln!(
            s,
            "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
            self.points.len(),
            self.cells.len()
        );
        s += "      <PointData>\n";
        for f in &self.point_data {
            write_array(&mut s, f);
        }
        s += "      </PointData>\n      <CellData>\n";
        for f in &self.cell_data {
            write_array(&mut s, f);
        }
        s += "      </CellData>\n      <Points>\n";
        write_array(
            &mut s,
            &Field::real(
                "Points",
                3,
                self.points.iter().flat_map(|p| p.iter().copied()).collect(),
            ),
        );
        s += "      </Points>\n      <Cells>\n";
        let conn: Vec<String> = self
            .cells
            .iter()
            .map(|c| format!("{} {}", c[0], c[1]))
            .collect();
        let offsets: Vec<String> = (1..=self.cells.len())
            .map(|i| (2 * i).to_string())
            .collect();
        let types = vec![VTK_LINE.to_string(); self.cells.len()];
        for (name, ty, v) in [
            ("connectivity", "Int64", conn),
            ("offsets", "Int64", offsets),
            ("types", "UInt8", types),
        ] {
            let _ = writeln!(
                s,
                "        <DataArray type=\"{ty}\" Name=\"{name}\" format=\"ascii\">\n          {}\n        </DataArray>",
                v.join(" ")
            );
        }
        s += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
        s
    }

    /// Write the `.vtu` file.
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        std::fs::write(path, self.to_vtu())
    }
}

/// A finite number as VTK's ASCII reader takes it (non-finite values are written as 0).
fn num(v: f64) -> String {
    if v.is_finite() {
        format!("{v:e}")
    } else {
        "0".into()
    }
}

fn write_array(s: &mut String, f: &Field) {
    let ty = if f.integer { "Int32" } else { "Float64" };
    let body: Vec<String> = if f.integer {
        f.values.iter().map(|&v| (v as i64).to_string()).collect()
    } else {
        f.values.iter().map(|&v| num(v)).collect()
    };
    let _ = writeln!(
        s,
        "        <DataArray type=\"{ty}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n          {}\n        </DataArray>",
        xml_escape(&f.name),
        f.components,
        body.join(" ")
    );
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A `.pvd` collection: (time step value, file name relative to the `.pvd`); `note` is written
/// as an XML comment (where and why a static path stopped part-way).
pub fn pvd(entries: &[(f64, String)], note: Option<&str>) -> String {
    let mut s = String::from("<?xml version=\"1.0\"?>\n");
    if let Some(n) = note {
        // "--" may not occur inside an XML comment
        let mut c = n.to_string();
        while c.contains("--") {
            c = c.replace("--", "- -");
        }
        let _ = writeln!(s, "<!-- {c} -->");
    }
    s += "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
    for (t, file) in entries {
        let _ = writeln!(
            s,
            "    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>",
            num(*t),
            xml_escape(file)
        );
    }
    s += "  </Collection>\n</VTKFile>\n";
    s
}

/// Pad or cut to 6 components per element (`e` or `σ` per element, from a global vector).
fn per_element6(model: &Model, v: &[f64]) -> Vec<f64> {
    model
        .elements
        .iter()
        .flat_map(|entry| {
            let ne = entry.element.ne();
            let mut r = [0.0; 6];
            for (m, r) in r.iter_mut().enumerate().take(ne.min(6)) {
                *r = v[entry.ie + m];
            }
            r
        })
        .collect()
}

/// The reference geometry with the motions and self-stress states of a kinematic analysis.
///
/// Point data per motion K (1-based): `motion_K` (translational velocity, 3) and
/// `motion_K_angular` (angular velocity about the global axes, 3); a node `at` a host takes
/// the host's translation. Cell data per self-stress state K: `self_stress_K`, the largest
/// |value| over the element's modes in the state.
pub fn check_grid(model: &Model, analysis: &ConstraintAnalysis) -> Grid {
    let x0 = model.x0();
    let mut g = Grid::new(model, &x0);
    let n = model.nodes.len();
    for (k, motion) in analysis.motions.iter().enumerate() {
        let mut v = vec![[0.0; 6]; n];
        for c in &motion.coordinates {
            if let Some(id) = model.node_id(&c.node) {
                v[id][c.dof.index()] = c.value;
            }
        }
        for (i, node) in model.nodes.iter().enumerate() {
            if let Some(h) = node.host {
                for d in [Dof::X, Dof::Y, Dof::Z] {
                    if v[i][d.index()] == 0.0 {
                        v[i][d.index()] = v[h][d.index()];
                    }
                }
            }
        }
        g.add_point_field(Field::real(
            &format!("motion_{}", k + 1),
            3,
            v.iter().flat_map(|a| a[..3].to_vec()).collect(),
        ));
        g.add_point_field(Field::real(
            &format!("motion_{}_angular", k + 1),
            3,
            v.iter().flat_map(|a| a[3..].to_vec()).collect(),
        ));
    }
    for (k, state) in analysis.self_stresses.iter().enumerate() {
        let mut v = vec![0.0; model.elements.len()];
        for d in &state.deformations {
            if let Some(i) = model.elements.iter().position(|e| e.name == d.element) {
                v[i] = f64::max(v[i], d.value.abs());
            }
        }
        g.add_cell_field(Field::real(&format!("self_stress_{}", k + 1), 1, v));
    }
    g
}

/// One load step: deformed positions, `displacement` and `rotation` (rotation vector, zero
/// where the node does not rotate) per point; `e`, `sigma` (padded to 6) and `max_stress`
/// (0 where unknown) per cell.
pub fn step_grid(model: &Model, step: &StepResult) -> Grid {
    let mut g = Grid::new(model, &step.x);
    let nodes = node_results(model, step);
    g.add_point_field(Field::real(
        "displacement",
        3,
        nodes.iter().flat_map(|n| n.displacement).collect(),
    ));
    g.add_point_field(Field::real(
        "rotation",
        3,
        nodes
            .iter()
            .flat_map(|n| n.rotation.unwrap_or([0.0; 3]))
            .collect(),
    ));
    g.add_cell_field(Field::real("e", 6, per_element6(model, &step.e)));
    g.add_cell_field(Field::real("sigma", 6, per_element6(model, &step.sigma)));
    let els = element_results(model, step);
    g.add_cell_field(Field::real(
        "max_stress",
        1,
        els.iter().map(|e| e.max_stress.unwrap_or(0.0)).collect(),
    ));
    g
}

/// One output time of a simulation: the fields of [`step_grid`] (deformed positions,
/// `displacement`, `rotation`, `e`, `sigma`, `max_stress`) plus the point vectors `velocity`
/// [m/s] and `angular_velocity` [rad/s] (global axes; zero where the node does not rotate).
pub fn sim_grid(model: &Model, frame: &Frame) -> Grid {
    let mut g = step_grid(model, &frame.as_step());
    let (v, w): (Vec<[f64; 3]>, Vec<[f64; 3]>) = frame
        .node_velocities(model)
        .into_iter()
        .map(|(v, w)| (v, w.unwrap_or([0.0; 3])))
        .unzip();
    g.add_point_field(Field::real("velocity", 3, v.concat()));
    g.add_point_field(Field::real("angular_velocity", 3, w.concat()));
    g
}

/// Scale factor that makes the largest nodal translation of `mode` 10 % of the model size
/// (1 if the mode does not translate any node).
pub fn mode_scale(model: &Model, mode: &Mode) -> f64 {
    let max = mode
        .nodal
        .iter()
        .map(|(t, _)| (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt())
        .fold(0.0, f64::max);
    if max > 0.0 && max.is_finite() {
        0.1 * model_size(model) / max
    } else {
        1.0
    }
}

/// A mode about the static state `step`: the step's geometry and fields ([`step_grid`]) plus
/// point data `mode` (translation, 3) and `mode_rotation` (rotation vector, 3), scaled by
/// [`mode_scale`], for ParaView's Warp By Vector.
pub fn mode_grid(model: &Model, step: &StepResult, mode: &Mode) -> Grid {
    let mut g = step_grid(model, step);
    let s = mode_scale(model, mode);
    let pick = |rot: bool| -> Vec<f64> {
        (0..model.nodes.len())
            .flat_map(|i| {
                let (t, r) = mode.nodal.get(i).copied().unwrap_or(([0.0; 3], [0.0; 3]));
                let v = if rot { r } else { t };
                v.map(|a| a * s)
            })
            .collect()
    };
    g.add_point_field(Field::real("mode", 3, pick(false)));
    g.add_point_field(Field::real("mode_rotation", 3, pick(true)));
    g
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pvd_and_vtu_are_well_formed() {
        let g = Grid {
            points: vec![[0.0; 3], [1.0, 0.0, 0.0]],
            cells: vec![[0, 1]],
            cell_element: vec![0],
            point_data: vec![Field::real("d", 3, vec![0.0, 0.0, 0.0, f64::NAN, 1.0, 2.0])],
            cell_data: vec![Field::int("element", vec![0.0])],
        };
        let s = g.to_vtu();
        assert!(s.contains("NumberOfPoints=\"2\" NumberOfCells=\"1\""));
        assert!(!s.contains("NaN"));
        let p = pvd(&[(0.5, "a_1.vtu".into())], None);
        assert!(p.contains("timestep=\"5e-1\""));
    }
}
