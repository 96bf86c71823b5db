//! The intended freedom of a design (docs/kinematic-analysis.md "Intended freedom"): the
//! motions the designer wants, per body, against the freedom space the constraints allow.
//!
//! The design's freedom space is the null space of Dcc with every generalised coordinate
//! released (x^m and e^m made dependent: what the flexures allow, before a coordinate is
//! chosen to drive it). Each of its motions gives the twists of the bodies the intended
//! freedoms name, stacked into one vector t = [L ω₁; v₁(c₁); L ω₂; …] (L the model size,
//! [`super::screw::length_scale`], so that rotations and translations are comparable). The
//! intended twists are stacked the same way, zero on the other bodies. The two spans are
//! compared by their principal angles θ (the singular values of Q_Iᵀ Q_F are cos θ, Q_F and
//! Q_I orthonormal bases): they are equal when every sin θ ≤ [`FREEDOM_TOL`] and the dimensions
//! agree. A **parasitic** freedom is a design motion outside the intended span, a **missing**
//! one an intended twist outside the design's span (the right singular vectors of
//! (I − Q_I Q_Iᵀ) Q_F and (I − Q_F Q_Fᵀ) Q_I above the tolerance); a design motion in which no
//! named body moves is an internal (parasitic) motion.

use super::screw::{bodies, fit_twist, length_scale, Body, BodyTwist, Screw, VelocityField};
use super::{check, CheckOptions, KinematicsError};
use crate::linalg::svd;
use crate::math::{add, cross, dot, norm, sub};
use crate::model::{CoordKind, DefKind, Model, Partition};
use faer::Mat;
use serde::Serialize;

/// Two freedom spaces are equal when the sine of every principal angle between them is at
/// most this (and their dimensions agree).
pub const FREEDOM_TOL: f64 = 1e-6;

/// A motion a design should allow.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FreedomMotion {
    /// A translation along `direction`.
    Translation {
        /// Direction (need not be unit).
        direction: [f64; 3],
    },
    /// A rotation about the axis through `point` along `axis`, with a pitch (0: a pure
    /// rotation; h: a screw motion advancing h along the axis per radian).
    Rotation {
        /// A point of the axis [m].
        point: [f64; 3],
        /// Axis direction (need not be unit).
        axis: [f64; 3],
        /// Pitch [m/rad].
        pitch: f64,
    },
}

/// An intended freedom: a body and the motion it should have.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct IntendedFreedom {
    /// The body: the name of one of its elements or nodes ([`super::screw::bodies`]).
    pub body: String,
    /// The motion.
    pub motion: FreedomMotion,
}

impl IntendedFreedom {
    /// The twist (ω, v(c)) of unit |ω| (a rotation) or unit |v| (a translation), given at c.
    pub fn twist_at(&self, c: [f64; 3]) -> ([f64; 3], [f64; 3]) {
        match &self.motion {
            FreedomMotion::Translation { direction } => {
                let n = norm(*direction);
                ([0.0; 3], direction.map(|d| d / n))
            }
            FreedomMotion::Rotation { point, axis, pitch } => {
                let n = norm(*axis);
                let w = axis.map(|a| a / n);
                // v(c) = ω × (c − p) + h ω
                (w, add(cross(w, sub(c, *point)), w.map(|a| a * pitch)))
            }
        }
    }

    fn check_values(&self) -> Result<(), KinematicsError> {
        let bad = |what: &str| {
            Err(KinematicsError::BadFreedom(format!(
                "the intended freedom of `{}` has {what}",
                self.body
            )))
        };
        let finite = |v: &[f64]| v.iter().all(|a| a.is_finite());
        match &self.motion {
            FreedomMotion::Translation { direction } => {
                if !finite(direction) || norm(*direction) == 0.0 {
                    return bad("a zero or non-finite direction");
                }
            }
            FreedomMotion::Rotation { point, axis, pitch } => {
                if !finite(point) || !pitch.is_finite() {
                    return bad("a non-finite point or pitch");
                }
                if !finite(axis) || norm(*axis) == 0.0 {
                    return bad("a zero or non-finite axis");
                }
            }
        }
        Ok(())
    }
}

/// The body a freedom names: by body name, element name or node name; not the ground.
pub fn resolve_body(model: &Model, bodies: &[Body], name: &str) -> Option<usize> {
    let by_name = bodies.iter().position(|b| b.name == name);
    let by_element = || {
        let el = model.elements.iter().position(|e| e.name == name)?;
        bodies.iter().position(|b| b.element_ids.contains(&el))
    };
    let by_node = || {
        let id = model.node_id(name)?;
        bodies.iter().position(|b| b.node_ids.contains(&id))
    };
    by_name
        .or_else(by_element)
        .or_else(by_node)
        .filter(|&i| !bodies[i].ground)
}

/// The comparison of a design's freedom space with the intended one.
#[derive(Clone, Debug, Serialize)]
pub struct FreedomCheck {
    /// The intended freedoms, as stated.
    pub intended: Vec<IntendedFreedom>,
    /// The motions of Dcc with every generalised coordinate released.
    pub n_design_motions: usize,
    /// The dimension of the design's freedom space on the named bodies.
    pub design_dimension: usize,
    /// The dimension of the intended span.
    pub intended_dimension: usize,
    /// The principal angles between the two spans [rad], ascending (as many as the smaller
    /// dimension).
    pub principal_angles: Vec<f64>,
    /// [`FREEDOM_TOL`], the tolerance on their sines.
    pub tolerance: f64,
    /// L [m], the length that weighs rotations against translations.
    pub length_scale: f64,
    /// True when the spans are equal and no motion is internal.
    pub matches: bool,
    /// Design motions outside the intended span: the twists of the named bodies.
    pub parasitic: Vec<Vec<BodyTwist>>,
    /// Intended twists the design does not allow.
    pub missing: Vec<Vec<BodyTwist>>,
    /// Design motions in which no named body moves.
    pub internal_motions: usize,
}

/// An orthonormal basis of the span of the columns of `a` (singular values above 1e-8 s₁).
fn span(a: &Mat<f64>) -> Result<Mat<f64>, KinematicsError> {
    if a.ncols() == 0 {
        return Ok(Mat::zeros(a.nrows(), 0));
    }
    let s = svd(a.as_ref(), "a freedom space")?;
    let s1 = s.s.first().copied().unwrap_or(0.0);
    let r = s.s.iter().filter(|&&v| v > 1e-8 * s1 && v > 0.0).count();
    Ok(Mat::from_fn(a.nrows(), r, |i, j| s.U[(i, j)]))
}

/// The columns of Q that stick out of span(P) (orthonormal P): Q y for each right singular
/// vector y of (I − P Pᵀ) Q with singular value above `tol`.
fn outside(p: &Mat<f64>, q: &Mat<f64>, tol: f64) -> Result<Vec<Vec<f64>>, KinematicsError> {
    if q.ncols() == 0 {
        return Ok(Vec::new());
    }
    let rest = q - p * (p.transpose() * q);
    let s = svd(rest.as_ref(), "a freedom space")?;
    let mut out = Vec::new();
    for (k, &sk) in s.s.iter().enumerate() {
        if sk > tol {
            let y: Vec<f64> = (0..q.ncols()).map(|j| s.V[(j, k)]).collect();
            out.push(
                (0..q.nrows())
                    .map(|i| (0..q.ncols()).map(|j| q[(i, j)] * y[j]).sum())
                    .collect(),
            );
        }
    }
    Ok(out)
}

/// A stacked twist as the twists of the named bodies (those that move).
fn present(t: &[f64], named: &[usize], bodies: &[Body], l: f64) -> Vec<BodyTwist> {
    let big = t.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut out = Vec::new();
    for (k, &bi) in named.iter().enumerate() {
        let blk = &t[6 * k..6 * k + 6];
        if blk.iter().all(|v| v.abs() <= 1e-8 * big) {
            continue;
        }
        let b = &bodies[bi];
        let omega = [blk[0] / l, blk[1] / l, blk[2] / l];
        let v_c = [blk[3], blk[4], blk[5]];
        let screw = Screw::twist(omega, v_c, b.centre, l);
        let velocity = add(v_c, cross(omega, sub(screw.point, b.centre)));
        out.push(BodyTwist {
            body: b.name.clone(),
            screw,
            angular_velocity: omega,
            velocity,
            rigid_residual: 0.0,
        });
    }
    out
}

/// The partition with every generalised coordinate released.
pub fn released(partition: &Partition) -> Partition {
    let mut p = partition.clone();
    for k in p.x.iter_mut().filter(|k| **k == CoordKind::Input) {
        *k = CoordKind::Free;
    }
    for k in p.e.iter_mut().filter(|k| **k == DefKind::Input) {
        *k = DefKind::Free;
    }
    p
}

/// Compare the freedom space of `partition` (generalised coordinates released) at x with the
/// intended freedoms (module docs). A freedom that names no body of the model, or the
/// ground, is an error.
pub fn compare_freedom(
    model: &Model,
    partition: &Partition,
    x: &[f64],
    intended: &[IntendedFreedom],
    opts: &CheckOptions,
) -> Result<FreedomCheck, KinematicsError> {
    for f in intended {
        f.check_values()?;
    }
    let p = released(partition);
    let bodies = bodies(model, &p, x);
    let l = length_scale(model, x);
    let mut named: Vec<usize> = Vec::new();
    let mut of_freedom = Vec::new();
    for f in intended {
        let bi = resolve_body(model, &bodies, &f.body)
            .ok_or_else(|| KinematicsError::UnknownBody(f.body.clone()))?;
        let k = named.iter().position(|&b| b == bi).unwrap_or_else(|| {
            named.push(bi);
            named.len() - 1
        });
        of_freedom.push(k);
    }
    let a = check(model, &p, x, opts)?;
    let rows = 6 * named.len();
    // the design's stacked twists
    let mut design = Mat::zeros(rows, a.null_v.ncols());
    for j in 0..a.null_v.ncols() {
        let v: Vec<f64> = (0..a.n()).map(|i| a.null_v[(i, j)]).collect();
        let f = VelocityField::new(model, &a.cols, &v);
        for (k, &bi) in named.iter().enumerate() {
            let (w, vc, _, _) = fit_twist(model, x, &bodies[bi], &f, l)?;
            for i in 0..3 {
                design[(6 * k + i, j)] = l * w[i];
                design[(6 * k + 3 + i, j)] = vc[i];
            }
        }
    }
    let mut wanted = Mat::zeros(rows, intended.len());
    for (j, f) in intended.iter().enumerate() {
        let k = of_freedom[j];
        let (w, vc) = f.twist_at(bodies[named[k]].centre);
        for i in 0..3 {
            wanted[(6 * k + i, j)] = l * w[i];
            wanted[(6 * k + 3 + i, j)] = vc[i];
        }
    }
    let qf = span(&design)?;
    let qi = span(&wanted)?;
    let internal = a.null_v.ncols() - qf.ncols();
    let mut principal_angles = Vec::new();
    if qf.ncols() > 0 && qi.ncols() > 0 {
        let c = qi.transpose() * &qf;
        let s = svd(c.as_ref(), "principal angles")?;
        principal_angles = s.s.iter().map(|&v| v.clamp(0.0, 1.0).acos()).collect();
        principal_angles.sort_by(f64::total_cmp);
    }
    let col = |m: &Vec<f64>| present(m, &named, &bodies, l);
    let parasitic: Vec<Vec<BodyTwist>> = outside(&qi, &qf, FREEDOM_TOL)?.iter().map(col).collect();
    let missing: Vec<Vec<BodyTwist>> = outside(&qf, &qi, FREEDOM_TOL)?.iter().map(col).collect();
    Ok(FreedomCheck {
        intended: intended.to_vec(),
        n_design_motions: a.null_v.ncols(),
        design_dimension: qf.ncols(),
        intended_dimension: qi.ncols(),
        principal_angles,
        tolerance: FREEDOM_TOL,
        length_scale: l,
        matches: parasitic.is_empty() && missing.is_empty() && internal == 0,
        parasitic,
        missing,
        internal_motions: internal,
    })
}

/// The largest reciprocal product of the unit wire from node `a` to node `g` (direction `d`)
/// with the intended freedoms, each of unit |ω| (a rotation, times L) or unit |v|: how much the
/// wire would stop an intended motion (0: not at all). `resolved` pairs each freedom with the
/// index of its body in `bodies`.
pub fn intended_power(
    resolved: &[(usize, &IntendedFreedom)],
    bodies: &[Body],
    a: (usize, [f64; 3]),
    g: (usize, [f64; 3]),
    d: [f64; 3],
    l: f64,
) -> f64 {
    let vel = |f: &IntendedFreedom, body: usize, node_body: usize, p: [f64; 3]| {
        if body != node_body {
            return [0.0; 3];
        }
        let c = bodies[body].centre;
        let (w, vc) = f.twist_at(c);
        add(vc, cross(w, sub(p, c)))
    };
    resolved
        .iter()
        .map(|&(bi, f)| {
            let rel = sub(vel(f, bi, a.0, a.1), vel(f, bi, g.0, g.1));
            let unit = match f.motion {
                FreedomMotion::Rotation { .. } => l,
                FreedomMotion::Translation { .. } => 1.0,
            };
            dot(d, rel).abs() / unit
        })
        .fold(0.0, f64::max)
}
