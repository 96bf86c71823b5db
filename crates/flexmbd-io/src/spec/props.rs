//! Materials, sections and the beam constants they give (docs/statics.md): the checks of
//! [`super::ModelSpec::build`].

use super::build::SpecError;
use super::{BeamSpec, MaterialSpec, SectionSpec, ShapeSpec};
use flexmbd_core::section::{BeamProps, Material, Shape};
use rustc_hash::FxHashMap as HashMap;

/// Materials by name.
pub(super) type Materials = HashMap<String, Material>;
/// Sections by name, with "include shear flexibility".
pub(super) type Sections = HashMap<String, (Shape, bool)>;
/// The beam constants of each (section, material) pair met so far: a model of 10^5 beams of
/// one section computes them once.
pub(super) type SectionProps<'a> = HashMap<(&'a str, &'a str), BeamProps>;

fn positive(what: &str, v: f64) -> Result<f64, String> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("`{what}` must be a positive number, found {v}"))
    }
}

fn fail(item: &str, name: &str, src: &super::Src) -> impl Fn(String) -> SpecError {
    let (prefix, at) = (format!("{item} `{name}`: "), src.at);
    move |m| SpecError {
        kind: super::build::SpecErrorKind::Invalid(format!("{prefix}{m}")),
        at,
    }
}

/// Check the materials: E > 0, G > 0 or −1 < ν < 0.5 (not both), ρ ≥ 0, each defined once.
pub(super) fn read_materials(list: &[MaterialSpec]) -> Result<Materials, SpecError> {
    let mut out = HashMap::default();
    for s in list {
        let fail = fail("material", &s.name, &s.src);
        let e = positive("E", s.e).map_err(&fail)?;
        let g = match (s.g, s.nu) {
            (Some(g), None) => positive("G", g).map_err(&fail)?,
            (None, Some(nu)) if nu.is_finite() && nu > -1.0 && nu < 0.5 => e / (2.0 * (1.0 + nu)),
            (None, Some(nu)) => return Err(fail(format!("`nu` must be in (−1, 0.5), found {nu}"))),
            (Some(_), Some(_)) => return Err(fail("give `G` or `nu`, not both".into())),
            (None, None) => {
                return Err(fail(
                    "missing `G` (shear modulus) or `nu` (Poisson's ratio)".into(),
                ))
            }
        };
        if !(s.rho.is_finite() && s.rho >= 0.0) {
            return Err(fail(format!("`rho` must be ≥ 0, found {}", s.rho)));
        }
        if let Some(d) = s.damping.filter(|d| !(d.is_finite() && *d >= 0.0)) {
            return Err(fail(format!(
                "`damping` (the retardation time τ [s]) must be ≥ 0, found {d}"
            )));
        }
        if out
            .insert(s.name.clone(), Material { e, g, rho: s.rho })
            .is_some()
        {
            return Err(fail("defined twice".into()));
        }
    }
    Ok(out)
}

/// Check the sections: positive dimensions, a tube's inner diameter below its outer one, a
/// shear factor ≥ 0, each defined once.
pub(super) fn read_sections(list: &[SectionSpec]) -> Result<Sections, SpecError> {
    let mut out = HashMap::default();
    for s in list {
        let fail = fail("section", &s.name, &s.src);
        let shape = match s.shape {
            ShapeSpec::Rectangle { w, t } => Shape::Rectangle {
                w: positive("w", w).map_err(&fail)?,
                t: positive("t", t).map_err(&fail)?,
            },
            ShapeSpec::Circle { d } => Shape::Circle {
                d: positive("d", d).map_err(&fail)?,
            },
            ShapeSpec::Tube { d_out, d_in } => {
                let (d_out, d_in) = (
                    positive("d_out", d_out).map_err(&fail)?,
                    positive("d_in", d_in).map_err(&fail)?,
                );
                if d_in >= d_out {
                    return Err(fail(format!(
                        "`d_in` ({d_in}) must be smaller than `d_out` ({d_out})"
                    )));
                }
                Shape::Tube { d_out, d_in }
            }
            ShapeSpec::General { a, iy, iz, j, k } => Shape::General {
                a: positive("A", a).map_err(&fail)?,
                iy: positive("Iy", iy).map_err(&fail)?,
                iz: positive("Iz", iz).map_err(&fail)?,
                j: positive("J", j).map_err(&fail)?,
                k: match k {
                    None => 0.0,
                    Some(k) if k.is_finite() && k >= 0.0 => k,
                    Some(k) => {
                        return Err(fail(format!(
                            "`k` (the shear factor) must be ≥ 0 (0: shear-rigid), found {k}"
                        )))
                    }
                },
            },
        };
        if out.insert(s.name.clone(), (shape, s.shear)).is_some() {
            return Err(fail("defined twice".into()));
        }
    }
    Ok(out)
}

/// The beam's stiffness and mass constants: from `section` + `material`, or given directly;
/// `None` without either. `Err` is the message (the caller names the element).
pub(super) fn beam_constants<'a>(
    s: &'a BeamSpec,
    materials: &Materials,
    sections: &Sections,
    made: &mut SectionProps<'a>,
) -> Result<Option<BeamProps>, String> {
    let direct = [s.ea, s.gj, s.eiy, s.eiz];
    let extra = s.shear.is_some() || s.rho_i.is_some();
    let mut props = match (&s.section, &s.material) {
        (Some(sec), Some(mat)) => {
            if direct.iter().any(Option::is_some) || extra {
                return Err(
                    "give `section` and `material`, or `EA`, `GJ`, `EIy`, `EIz` directly, not both"
                        .into(),
                );
            }
            if s.rho_a.is_some() {
                return Err(format!(
                    "`rho_a` is the mass per length of constants given directly; with `section` and `material` the mass per length is the material's `rho` × the section's area: remove `rho_a`, or set `rho` of material `{mat}`"
                ));
            }
            let m = materials
                .get(mat)
                .ok_or_else(|| format!("material `{mat}` is not defined"))?;
            let (shape, shear) = sections
                .get(sec)
                .ok_or_else(|| format!("section `{sec}` is not defined"))?;
            *made
                .entry((sec, mat))
                .or_insert_with(|| BeamProps::from_section(m, shape, !shear))
        }
        (Some(_), None) => return Err("a `section` needs a `material`".into()),
        (None, Some(_)) => return Err("a `material` needs a `section`".into()),
        (None, None) if direct.iter().any(Option::is_some) || extra => {
            let get = |name: &str, v: Option<f64>| -> Result<f64, String> {
                match v {
                    Some(v) if v.is_finite() && v >= 0.0 => Ok(v),
                    Some(v) => Err(format!("`{name}` must be ≥ 0, found {v}")),
                    None => Ok(0.0),
                }
            };
            let shear = s.shear.unwrap_or_default();
            let rho_i = s.rho_i.unwrap_or_default();
            BeamProps {
                ea: get("EA", s.ea)?,
                gj: get("GJ", s.gj)?,
                eiy: get("EIy", s.eiy)?,
                eiz: get("EIz", s.eiz)?,
                rho_a: get("rho_a", s.rho_a)?,
                shear: [get("shear", Some(shear[0]))?, get("shear", Some(shear[1]))?],
                rho_i: [
                    get("rho_i", Some(rho_i[0]))?,
                    get("rho_i", Some(rho_i[1]))?,
                    get("rho_i", Some(rho_i[2]))?,
                ],
                ..Default::default()
            }
        }
        (None, None) if s.rho_a.is_some() => {
            return Err(
                "`rho_a` (mass per length) belongs to constants given directly: give the beam's `EA`, `GJ`, `EIy`, `EIz` with it (a missing one is 0), or a `section` and a `material` with density `rho` instead"
                    .into(),
            )
        }
        (None, None) => return Ok(None),
    };
    if let Some(ct) = s.ct {
        props.ct = ct;
    }
    Ok(Some(props))
}
