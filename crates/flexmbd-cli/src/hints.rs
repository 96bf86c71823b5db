//! The command line's spelling of the neutral hints in flexmbd-core's errors: core says "use the
//! sparse eigen solver", the CLI adds which option does that (docs: core messages name no flag).

use flexmbd_core::dynamics::state_space::StateSpaceError;
use flexmbd_core::dynamics::ModalError;
use flexmbd_core::kinematics::classify::{ClassifyError, Stage};
use flexmbd_core::linearized::LinearError;
use flexmbd_core::statics::SolveError;

/// The options that act on the failure of `e` (searched through its chain of causes), if flexmbd
/// knows them.
pub fn cli_hint(e: &anyhow::Error) -> Option<&'static str> {
    e.chain().find_map(|cause| {
        if let Some(m) = cause.downcast_ref::<ModalError>() {
            return modal(m);
        }
        if let Some(s) = cause.downcast_ref::<StateSpaceError>() {
            return match s {
                StateSpaceError::Modal(ModalError::TooLarge(_)) => Some(
                    "use --solver sparse (or auto) with --modes N (e.g. --modes 20), and --static-correction for the exact static gain",
                ),
                StateSpaceError::Modal(m) => modal(m),
                StateSpaceError::SparseNeedsModes { .. } => {
                    Some("give --modes N (e.g. --modes 20), with --static-correction for the exact static gain")
                }
                StateSpaceError::NoRotation { .. } => {
                    Some("in a TOML model, `rot = true` gives a node rotation coordinates")
                }
                _ => None,
            };
        }
        if let Some(c) = cause.downcast_ref::<ClassifyError>() {
            if matches!(c.source, flexmbd_core::kinematics::KinematicsError::TooLarge { .. }) {
                return Some("use --method sparse (or auto)");
            }
            if c.stage == Stage::Check
                && !matches!(c.source, flexmbd_core::kinematics::KinematicsError::TooLarge { .. })
            {
                return Some("check the model for NaN coordinates, or try another --rank-tol");
            }
        }
        if let Some(LinearError::TooLarge(_)) = cause.downcast_ref::<LinearError>() {
            return Some(
                "leave out --compliance and --buckling (and `compliance`, `buckling` in the model's [static] table), or use a model with fewer elements",
            );
        }
        cause.downcast_ref::<SolveError>().and_then(solve_hint)
    })
}

/// The options that act on a static path that failed with `e`.
pub fn solve_hint(e: &SolveError) -> Option<&'static str> {
    match e {
        SolveError::NoConvergence { .. } => Some(
            "more load steps: --steps N (or `steps` in the model's [static] table); at a limit point (snap-through) follow the path by arc length: --path arc-length (or `path = \"arc-length\"` in [static])",
        ),
        SolveError::Inverted { .. } => {
            Some("more load steps: --steps N (or `steps` in the model's [static] table)")
        }
        _ => None,
    }
}

fn modal(m: &ModalError) -> Option<&'static str> {
    match m {
        ModalError::NoMass => Some(
            "in a TOML model: a [[material]] with `rho` for the beams, or [[mass]] / [[inertia]] entries",
        ),
        ModalError::DenseInaccurate { .. } => Some("use --solver sparse"),
        ModalError::TooLarge(_) => {
            Some("use --solver sparse (or auto), which computes the lowest --count N modes only")
        }
        ModalError::TooManyModes { .. } => Some(
            "ask for fewer modes (--count N, at most a third of the degrees of freedom), or choose the solver explicitly: --solver sparse (slow for many modes) or --solver dense",
        ),
        ModalError::SparseSingular => Some("run `flexmbd check` on the model, or use --solver dense"),
        ModalError::NotConverged { .. } => Some("ask for fewer modes (--count), or use --solver dense"),
        _ => None,
    }
}
