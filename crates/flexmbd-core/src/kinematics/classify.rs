//! The whole kinematic check of a design in one call, as the command line, the viewer and
//! (later) Python and design studies use it: Dcc with its SVD, the Table 1 class, motions and
//! self-stresses ([`check`]); optionally the automatic choice of as many generalised
//! coordinates as there are motions ([`auto_generalised`]); then the verified repair advice
//! ([`advise`]); in the designer's language, the twists and wrenches of the bodies
//! ([`super::screw`]), the comparison with an intended freedom ([`super::freedom`]) and the
//! wires that remove a motion ([`super::advice::wire_advice`]).

use super::advice::{advise, auto_generalised, wire_advice, Action, StateAdvice, WireAdvice};
use super::freedom::{compare_freedom, FreedomCheck, IntendedFreedom};
use super::screw::{screws, ScrewAnalysis};
use super::{check, CheckOptions, ConstraintAnalysis, KinematicsError};
use crate::model::{Model, Partition};

/// What [`classify`] computes.
#[derive(Clone, Debug)]
pub struct ClassifyOptions {
    /// Rank decision of the SVD.
    pub check: CheckOptions,
    /// Choose the generalised coordinates automatically before the advice.
    pub auto: bool,
    /// The most verified suggestions per motion or self-stress state (0: no advice).
    pub max_suggestions: usize,
}

impl Default for ClassifyOptions {
    fn default() -> Self {
        Self {
            check: CheckOptions::default(),
            auto: false,
            max_suggestions: 6,
        }
    }
}

/// The stages of [`classify`], for progress reports and to say where it failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Dcc, its SVD and the classification of the model as given.
    Check,
    /// The automatic choice of generalised coordinates.
    Auto,
    /// The verified repair advice.
    Advice,
}

/// Why the kinematic check failed, and at which stage.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}", match .stage {
    Stage::Check => "kinematic analysis failed",
    Stage::Auto => "automatic choice of generalised coordinates failed",
    Stage::Advice => "repair advice failed",
})]
pub struct ClassifyError {
    /// The stage that failed.
    pub stage: Stage,
    /// Why.
    #[source]
    pub source: KinematicsError,
}

/// The result of [`classify`].
#[derive(Clone, Debug)]
pub struct Classification {
    /// The analysis of the model's own partition when the generalised coordinates were chosen
    /// automatically (`None` without the automatic choice: it is `analysis`, not kept twice).
    pub before: Option<ConstraintAnalysis>,
    /// The generalised coordinates chosen automatically, when asked for.
    pub chosen: Option<Vec<Action>>,
    /// The partition the advice is for (the model's, or with the chosen coordinates).
    pub partition: Partition,
    /// The analysis of that partition.
    pub analysis: ConstraintAnalysis,
    /// Verified suggestions per motion and self-stress state of `analysis`.
    pub advice: Vec<StateAdvice>,
    /// The motions and self-stresses of `analysis` as twists and wrenches of the bodies.
    pub screws: ScrewAnalysis,
    /// The design's freedom against the intended freedom, when one is stated.
    pub freedom: Option<FreedomCheck>,
    /// Verified wires that remove each motion of `analysis` (dense path).
    pub wires: Vec<WireAdvice>,
}

impl Classification {
    /// True when the design is exactly constrained: no motion and no self-stress.
    pub fn is_exact(&self) -> bool {
        self.analysis.n_motions() == 0 && self.analysis.n_self_stresses() == 0
    }
}

/// The kinematic check of `model` in its reference configuration.
pub fn classify(model: &Model, opts: &ClassifyOptions) -> Result<Classification, ClassifyError> {
    classify_with(model, opts, |_| {})
}

/// [`classify`], telling `stage` when each stage starts.
pub fn classify_with(
    model: &Model,
    opts: &ClassifyOptions,
    stage: impl FnMut(Stage),
) -> Result<Classification, ClassifyError> {
    classify_intended(model, opts, &[], stage)
}

/// [`classify_with`] against the intended freedom `intended` (none: no comparison): the wire
/// suggestions are ranked by how little they change it.
pub fn classify_intended(
    model: &Model,
    opts: &ClassifyOptions,
    intended: &[IntendedFreedom],
    mut stage: impl FnMut(Stage),
) -> Result<Classification, ClassifyError> {
    let at = |stage| move |source| ClassifyError { stage, source };
    let x = model.x0();
    stage(Stage::Check);
    if super::rows(model, &model.partition).is_empty() {
        return Err(at(Stage::Check)(KinematicsError::NoConstraintRows));
    }
    let before = check(model, &model.partition, &x, &opts.check).map_err(at(Stage::Check))?;
    let (partition, analysis, chosen) = if opts.auto {
        stage(Stage::Auto);
        let c =
            auto_generalised(model, &model.partition, &x, &opts.check).map_err(at(Stage::Auto))?;
        (c.partition, c.analysis, Some((c.chosen, before)))
    } else {
        (model.partition.clone(), before, None)
    };
    let (chosen, before) = chosen.unzip();
    let screws = screws(model, &partition, &x, &analysis).map_err(at(Stage::Check))?;
    let freedom = if intended.is_empty() {
        None
    } else {
        Some(
            compare_freedom(model, &model.partition, &x, intended, &opts.check)
                .map_err(at(Stage::Check))?,
        )
    };
    stage(Stage::Advice);
    let advice = advise(
        model,
        &partition,
        &x,
        &analysis,
        &opts.check,
        opts.max_suggestions,
    )
    .map_err(at(Stage::Advice))?;
    let wires = wire_advice(
        model,
        &x,
        &analysis,
        &screws,
        intended,
        &opts.check,
        opts.max_suggestions,
    )
    .map_err(at(Stage::Advice))?;
    Ok(Classification {
        before,
        chosen,
        partition,
        analysis,
        advice,
        screws,
        freedom,
        wires,
    })
}
