//! The section structure and the keyword lines of a `.dat` file.
//!
//! ```text
//! kinematic section   END  HALT   static/dynamic section   [END HALT  state-space block]
//! END END   [VISUALIZATION …]
//! ```
//!
//! Keywords are matched case-insensitively. Which keywords belong to which section, and what
//! happens to a keyword in the wrong place or an unknown keyword, is in docs/spacar-import.md:
//! in short, anything that could change the kinematic result (an unknown keyword or a planar
//! element in the kinematic section, a kinematic keyword after `HALT`) is an error; anything
//! else is a warning.

use super::lexer::{lines, Fields, Line};
use super::*;
use crate::error::InputError;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Section {
    Kinematic,
    Static,
    StateSpace,
    /// After `END END`.
    Trailer,
    Visualization,
}

const KINEMATIC: &[&str] = &[
    "X", "BEAM", "BEAMW", "RBEAM", "HINGE", "TRUSS", "FIX", "RLSE", "DYNE", "DYNX",
];
const STATIC: &[&str] = &[
    "ESTIFF", "EM", "XM", "ESIG", "GRAVITY", "ITERSTEP", "TIMESTEP", "ERROR", "XF", "DELXF",
    "DELINPX", "DELINPE", "OUTLEVEL", "INPUTF", "OUTX", "OUTXP", "EDAMP", "ED", "STARTDE",
    "STARTDX",
];
const PLANAR: &[&str] = &["PLBEAM", "PLTRUSS", "PLHINGE", "PINBODY", "PLRBEAM"];
const VISUAL: &[&str] = &[
    "INITIAL",
    "COLOR",
    "BEAMPROPS",
    "CROSSTYPE",
    "CROSSDIM",
    "GRAPHICS",
    "FACECOLOR",
    "OPACITY",
    "DONOTDRAW",
    "BEAMVIS",
    "TRUSSVIS",
];

struct Parser<'a> {
    file: &'a str,
    m: SpacarModel,
    section: Section,
    /// Line of an `END` not yet followed by `END` or `HALT`.
    pending_end: Option<usize>,
}

/// Read all lines into a [`SpacarModel`] (no cross-checks yet).
pub(super) fn parse(text: &str, file: &str) -> Result<SpacarModel, InputError> {
    let name = Path::new(file)
        .file_stem()
        .map_or_else(|| file.to_string(), |s| s.to_string_lossy().into_owned());
    let mut p = Parser {
        file,
        m: SpacarModel {
            file: file.to_string(),
            name,
            ..Default::default()
        },
        section: Section::Kinematic,
        pending_end: None,
    };
    let mut last_line = 0;
    for line in lines(text) {
        last_line = line.no;
        // control characters (other than tab) in a field or comment: written as `\u{..}`
        // wherever the text is copied (converted TOML comments, messages)
        let has_control = |t: &str| t.chars().any(|c| c.is_control() && c != '\t');
        if line.tokens.iter().any(|t| has_control(t.text)) || line.comment.is_some_and(has_control)
        {
            p.warn(
                line.no,
                "the line holds control characters; where its text is copied (the comments of `flexmbd convert`, messages) they are written as \\u{..}",
            );
        }
        if line.tokens.is_empty() {
            if p.m.title.is_none() && p.m.elements.is_empty() && p.m.positions.is_empty() {
                if let Some(c) = line.comment.filter(|c| !c.is_empty()) {
                    p.m.title = Some(c.to_string());
                }
            }
            continue;
        }
        p.line(&line)?;
    }
    p.finish(last_line.max(1));
    Ok(p.m)
}

impl<'a> Parser<'a> {
    fn warn(&mut self, line: usize, message: impl Into<String>) {
        self.m.warnings.push(Warning {
            line,
            message: message.into(),
        });
    }

    fn raw(line: &Line, kw: &str) -> RawLine {
        RawLine {
            keyword: kw.to_string(),
            fields: line.tokens[1..]
                .iter()
                .map(|t| t.text.to_string())
                .collect(),
            line: line.no,
        }
    }

    fn next_section(&mut self, line: usize, why: &str) {
        self.section = match self.section {
            Section::Kinematic => Section::Static,
            Section::Static => Section::StateSpace,
            Section::StateSpace => {
                self.warn(line, format!("{why} after the state-space block has no meaning; the lines after it are read as part of that block"));
                Section::StateSpace
            }
            s => s,
        };
    }

    fn line(&mut self, line: &Line) -> Result<(), InputError> {
        let kw = super::lexer::keyword(line.tokens[0].text);
        let no = line.no;
        if matches!(self.section, Section::Trailer | Section::Visualization) {
            return self.trailer(line, &kw);
        }
        match &*kw {
            "END" => {
                if self.pending_end.take().is_some() {
                    // END END: the analysis input is complete
                    self.m.structure.end_lines.push(no);
                    self.m.structure.complete = true;
                    self.section = Section::Trailer;
                } else {
                    self.m.structure.end_lines.push(no);
                    self.pending_end = Some(no);
                }
                return self.no_fields(line, &kw);
            }
            "HALT" => {
                self.m.structure.halt_lines.push(no);
                if self.pending_end.take().is_none() {
                    self.warn(
                        no,
                        "HALT without an END before it; taken as the end of the section",
                    );
                }
                self.next_section(no, "HALT");
                return self.no_fields(line, &kw);
            }
            _ => {}
        }
        if let Some(end) = self.pending_end.take() {
            self.warn(
                end,
                format!("END is followed by `{kw}` (line {no}) instead of HALT or END; the END is taken as the end of the section"),
            );
            self.next_section(end, "END");
        }
        if kw == "VISUALIZATION" || kw == "VISUALISATION" {
            self.warn(
                no,
                "VISUALIZATION before the closing END END: the analysis input ends here",
            );
            self.section = Section::Visualization;
            return Ok(());
        }
        let mut f = Fields::new(self.file, line);
        match self.section {
            Section::Kinematic => self.kinematic(line, &kw, &mut f),
            _ => self.static_line(line, &kw, &mut f),
        }
    }

    fn no_fields(&mut self, line: &Line, kw: &str) -> Result<(), InputError> {
        if line.tokens.len() > 1 {
            self.warn(
                line.no,
                format!("{kw}: the fields after the keyword are ignored"),
            );
        }
        Ok(())
    }

    fn trailer(&mut self, line: &Line, kw: &str) -> Result<(), InputError> {
        if kw == "VISUALIZATION" || kw == "VISUALISATION" {
            self.section = Section::Visualization;
            return Ok(());
        }
        if self.section == Section::Visualization {
            if !VISUAL.contains(&kw) {
                self.warn(
                    line.no,
                    format!("unknown visualisation keyword `{kw}`: kept, not used"),
                );
            }
            self.m.visualization.push(Self::raw(line, kw));
        } else {
            self.warn(
                line.no,
                format!("`{kw}` after the closing END END is ignored"),
            );
            self.m.ignored.push(Self::raw(line, kw));
        }
        Ok(())
    }

    fn finish(&mut self, last_line: usize) {
        if self.m.structure.complete {
            return;
        }
        let msg = match (self.section, self.pending_end) {
            (Section::Kinematic, None) => {
                "the file ends inside the kinematic section (no END): it may be truncated"
            }
            (Section::Kinematic, Some(_)) => {
                "the file ends after the kinematic section's END without HALT or END END"
            }
            _ => "the file ends without the closing END END: it may be truncated",
        };
        self.warn(last_line, msg);
    }

    /// A keyword of the kinematic section.
    fn kinematic(&mut self, line: &Line, kw: &str, f: &mut Fields) -> Result<(), InputError> {
        let no = line.no;
        match kw {
            "X" => {
                let node = f.positive("node number")?;
                f.named(node);
                let values = f.rest_floats("coordinate")?;
                if values.len() != 3 && values.len() != 4 {
                    return Err(f.err_at(
                        2,
                        format!(
                            "expected 3 coordinates x y z (or 4 Euler parameters for a rotational node), found {}",
                            values.len()
                        ),
                    ));
                }
                self.m.positions.push(Position {
                    node,
                    values,
                    line: no,
                });
            }
            "BEAM" | "BEAMW" | "RBEAM" | "HINGE" | "TRUSS" => {
                let number = f.positive("element number")?;
                f.named(number);
                let kind = element(kw, f)?;
                f.done()?;
                self.m.elements.push(Element {
                    number,
                    kind,
                    line: no,
                });
            }
            "RLSE" | "DYNE" | "INPUTE" => {
                let element = f.positive("element number")?;
                f.named(element);
                let modes = f.rest_positive("deformation mode")?;
                if modes.is_empty() {
                    return Err(f.err_here("missing deformation mode numbers"));
                }
                let list = ModeList {
                    element,
                    modes,
                    line: no,
                };
                match kw {
                    "RLSE" => self.m.rlse.push(list),
                    "DYNE" => self.m.dyne.push(list),
                    _ => self.m.inpute.push(list),
                }
            }
            "FIX" | "INPUTX" | "DYNX" => {
                let node = f.positive("node number")?;
                f.named(node);
                let coords = f.rest_positive("coordinate number")?;
                if let Some(c) = coords.iter().position(|&c| c > 4) {
                    return Err(f.err_at(
                        2 + c,
                        format!(
                            "coordinate {} does not exist (1–3 for a translational node, 1–4 for a rotational node)",
                            coords[c]
                        ),
                    ));
                }
                let list = CoordList {
                    node,
                    coords: (!coords.is_empty()).then_some(coords),
                    line: no,
                };
                match kw {
                    "FIX" => self.m.fix.push(list),
                    "INPUTX" => self.m.inputx.push(list),
                    _ => self.m.dynx.push(list),
                }
            }
            _ if PLANAR.contains(&kw) => {
                return Err(f.err_at(
                    0,
                    "planar elements are not supported: spacar-format.md gives no definition of their nodes and deformations",
                ));
            }
            _ if STATIC.contains(&kw) || kw.starts_with("USER") => {
                if kw.starts_with("USER") && !matches!(kw, "USERSIG" | "USERINP") {
                    return Err(f.err_at(0, format!("user routine `{kw}` in the kinematic section is not supported: it may change the kinematics, and flexmbd cannot run MATLAB routines")));
                }
                self.warn(
                    no,
                    format!("{kw} belongs after HALT (static/dynamic section); read as such"),
                );
                self.static_line(line, kw, f)?;
            }
            _ => {
                return Err(f.err_at(
                    0,
                    "unknown keyword in the kinematic section: it could define an element, a support or a degree of freedom, so ignoring it could change the kinematic result",
                ));
            }
        }
        Ok(())
    }

    /// A keyword of the static/dynamic section or the state-space block.
    fn static_line(&mut self, line: &Line, kw: &str, f: &mut Fields) -> Result<(), InputError> {
        let no = line.no;
        match kw {
            "ESTIFF" | "EM" | "ESIG" | "EDAMP" | "ED" => {
                let element = f.positive("element number")?;
                f.named(element);
                let values = f.rest_floats("value")?;
                if values.is_empty() {
                    return Err(f.err_here("missing values"));
                }
                let v = ElementValues {
                    element,
                    values,
                    line: no,
                };
                match kw {
                    "ESTIFF" => self.m.estiff.push(v),
                    "EM" => self.m.em.push(v),
                    "ESIG" => self.m.esig.push(v),
                    _ => self.m.edamp.push(v),
                }
            }
            "XM" | "XF" | "DELXF" => {
                let node = f.positive("node number")?;
                f.named(node);
                let values = f.rest_floats("value")?;
                if values.is_empty() {
                    return Err(f.err_here("missing values"));
                }
                let v = NodeValues {
                    node,
                    values,
                    line: no,
                };
                match kw {
                    "XM" => self.m.xm.push(v),
                    "XF" => self.m.xf.push(v),
                    _ => self.m.delxf.push(v),
                }
            }
            "INPUTX" | "DELINPX" => {
                let node = f.positive("node number")?;
                f.named(node);
                let coord = f.positive("coordinate number")?;
                let value = f.float("value")?;
                // a file for a time simulation may give the velocity and acceleration too
                let mut rates = [0.0; 2];
                for (r, what) in rates.iter_mut().zip(["velocity", "acceleration"]) {
                    if f.remaining() > 0 {
                        *r = f.float(what)?;
                    }
                }
                f.done()?;
                let v = CoordValue {
                    node,
                    coord,
                    value,
                    rates,
                    line: no,
                };
                if kw == "INPUTX" {
                    self.m.inputx_values.push(v);
                } else {
                    self.m.delinpx.push(v);
                }
            }
            "INPUTE" | "DELINPE" => {
                let element = f.positive("element number")?;
                f.named(element);
                let mode = f.positive("deformation mode")?;
                let value = f.float("value")?;
                f.done()?;
                let v = ModeValue {
                    element,
                    mode,
                    value,
                    line: no,
                };
                if kw == "INPUTE" {
                    self.m.inpute_values.push(v);
                } else {
                    self.m.delinpe.push(v);
                }
            }
            "STARTDE" | "STARTDX" => {
                let (what, index) = if kw == "STARTDE" {
                    ("element number", "deformation mode")
                } else {
                    ("node number", "coordinate number")
                };
                let number = f.positive(what)?;
                f.named(number);
                let index = f.positive(index)?;
                let value = f.float("initial value")?;
                let rate = if f.remaining() > 0 {
                    f.float("initial rate")?
                } else {
                    0.0
                };
                f.done()?;
                let v = StartValue {
                    number,
                    index,
                    value,
                    rate,
                    line: no,
                };
                if kw == "STARTDE" {
                    self.m.startde.push(v);
                } else {
                    self.m.startdx.push(v);
                }
            }
            "GRAVITY" | "ITERSTEP" | "TIMESTEP" | "ERROR" | "OUTLEVEL" => {
                let values = f.rest_floats("value")?;
                let (min, max) = match kw {
                    "GRAVITY" => (3, 3),
                    "ITERSTEP" => (1, 6),
                    "TIMESTEP" | "ERROR" => (1, 2),
                    _ => (1, 2),
                };
                if values.len() < min || values.len() > max {
                    let n = if min == max {
                        format!("{min}")
                    } else {
                        format!("{min} to {max}")
                    };
                    return Err(
                        f.err_at(1, format!("expected {n} numbers, found {}", values.len()))
                    );
                }
                let slot = match kw {
                    "GRAVITY" => &mut self.m.gravity,
                    "ITERSTEP" => &mut self.m.iterstep,
                    "TIMESTEP" => &mut self.m.timestep,
                    "ERROR" => &mut self.m.error_tol,
                    _ => &mut self.m.outlevel,
                };
                let previous = slot.replace(Values { values, line: no });
                if let Some(p) = previous {
                    self.warn(
                        no,
                        format!(
                            "{kw} given again (first on line {}); the last one is kept",
                            p.line
                        ),
                    );
                }
            }
            "INPUTF" | "OUTX" | "OUTXP" => {
                let index = f.positive("input/output index")?;
                f.named(index);
                let node = f.positive("node number")?;
                let dir = f.positive("direction")?;
                f.done()?;
                let kind = match kw {
                    "INPUTF" => IoKind::Force,
                    "OUTX" => IoKind::Displacement,
                    _ => IoKind::Velocity,
                };
                if self.section == Section::Static {
                    self.warn(no, format!("{kw} belongs to the state-space block (after a second END / HALT); read as such"));
                }
                self.m.state_space.push(StateSpaceIo {
                    kind,
                    index,
                    node,
                    dir,
                    line: no,
                });
            }
            _ if kw.starts_with("USER") => {
                let name = f.word("routine name")?;
                let what = match kw {
                    "USERSIG" => "nodal loads / generalised stresses",
                    "USERINP" => "prescribed motions of the INPUTX coordinates",
                    _ => "user data",
                };
                self.warn(no, format!("user routine {kw} {name} ({what}) is not supported: flexmbd cannot run MATLAB routines; it matters for statics/dynamics only, the kinematic check is unaffected"));
                self.m.user_routines.push(UserRoutine {
                    keyword: kw.to_string(),
                    name,
                    line: no,
                });
            }
            _ if KINEMATIC.contains(&kw) || PLANAR.contains(&kw) => {
                return Err(f.err_at(0, format!("{kw} belongs in the kinematic section (before the first END); after HALT it cannot be used, and ignoring it could change the kinematic result")));
            }
            _ if VISUAL.contains(&kw) => {
                self.warn(
                    no,
                    format!(
                        "visualisation keyword {kw} before the closing END END; kept, not used"
                    ),
                );
                self.m.visualization.push(Self::raw(line, kw));
            }
            _ => {
                self.warn(no, format!("unknown keyword `{kw}` in the static/dynamic section is ignored (it cannot change the kinematic result)"));
                self.m.ignored.push(Self::raw(line, kw));
            }
        }
        Ok(())
    }
}

/// The fields of an element line after its number.
fn element(kw: &str, f: &mut Fields) -> Result<ElementKind, InputError> {
    let orient = |f: &mut Fields, what: &str| -> Result<Option<[f64; 3]>, InputError> {
        match f.remaining() {
            0 => Ok(None),
            _ => Ok(Some([f.float(what)?, f.float(what)?, f.float(what)?])),
        }
    };
    Ok(match kw {
        "BEAM" => ElementKind::Beam {
            xp: f.positive("translational node p")?,
            rp: f.positive("rotational node p")?,
            xq: f.positive("translational node q")?,
            rq: f.positive("rotational node q")?,
            orient: orient(f, "orientation vector (local y)")?,
        },
        "BEAMW" => ElementKind::BeamW {
            xp: f.positive("translational node p")?,
            rp: f.positive("rotational node p")?,
            wp: f.positive("warping node p")?,
            xq: f.positive("translational node q")?,
            rq: f.positive("rotational node q")?,
            wq: f.positive("warping node q")?,
            orient: orient(f, "orientation vector (local y)")?,
        },
        "RBEAM" => ElementKind::RBeam {
            xp: f.positive("translational node p")?,
            rp: f.positive("rotational node p")?,
            xq: f.positive("translational node q")?,
            orient: orient(f, "orientation vector (local y)")?,
        },
        "HINGE" => ElementKind::Hinge {
            rp: f.positive("rotational node p")?,
            rq: f.positive("rotational node q")?,
            axis: [
                f.float("hinge axis")?,
                f.float("hinge axis")?,
                f.float("hinge axis")?,
            ],
        },
        _ => ElementKind::Truss {
            xp: f.positive("translational node p")?,
            xq: f.positive("translational node q")?,
        },
    })
}
