//! A static path that may have stopped part-way (issue 17, "nothing lost"): every command that
//! follows the load steps writes the results of the converged steps in every format asked for,
//! marks where and why the path stopped and what to try ([`flexmbd_io::stopped::StopNote`]),
//! and then exits 1 ([`Path::finish`]). A path of which no state converged is a plain error.

use anyhow::Context;
use flexmbd_core::statics::{SolveError, StaticAnalysis, StaticSolution, Stopped};
use flexmbd_io::stopped::StopNote;
use std::process::ExitCode;

/// The converged part of a static path, and why it stopped if it did.
pub struct Path {
    /// The converged steps (all of them for a complete path) with their linearised results.
    pub analysis: StaticAnalysis,
    /// Why the path stopped before its last step.
    pub stop: Option<SolveError>,
}

impl Path {
    /// From the result of a static analysis; an error (with `what` as its context) when no
    /// state converged.
    #[allow(clippy::result_large_err)]
    pub fn of_analysis(r: Result<StaticAnalysis, Stopped>, what: &str) -> anyhow::Result<Self> {
        match r {
            Ok(analysis) => Ok(Self {
                analysis,
                stop: None,
            }),
            Err(s) if s.analysis.solution.steps.is_empty() => {
                Err(anyhow::Error::new(s.error).context(what.to_string()))
            }
            Err(s) => {
                let (analysis, error) = s.into_parts();
                Ok(Self {
                    analysis,
                    stop: Some(error),
                })
            }
        }
    }

    /// From the result of a static solution (no linearised results).
    #[allow(clippy::result_large_err)]
    pub fn of_solution(r: Result<StaticSolution, Stopped>, what: &str) -> anyhow::Result<Self> {
        Self::of_analysis(
            r.map(|solution| StaticAnalysis {
                solution,
                linear: Vec::new(),
            }),
            what,
        )
    }

    /// The converged steps.
    pub fn solution(&self) -> &StaticSolution {
        &self.analysis.solution
    }

    /// Releases the states of every step but `k` (coordinates, deformations, stress
    /// resultants, reactions, multipliers; load factors and counts stay), and of step `k` what
    /// a linearisation does not read (its deformations and reactions), for a command that goes
    /// on with the linearised stage of that one step after its notes are made
    /// ([`Path::note`]): the reference state of a large model is as large as the one analysed
    /// (0.2 KB per beam), and the deformations and reactions of the one kept are another 0.1 KB.
    pub fn keep_only_linearised_state(&mut self, k: usize) {
        for (i, s) in self.analysis.solution.steps.iter_mut().enumerate() {
            let mut release = vec![&mut s.e, &mut s.reactions];
            if i != k {
                release.extend([&mut s.x, &mut s.sigma, &mut s.multipliers]);
                s.tangent_eigenvalues = None;
            }
            for v in release {
                *v = Vec::new();
            }
        }
    }

    /// The mark of the outputs: where and why the path stopped, what to try.
    pub fn note(&self) -> Option<StopNote> {
        self.stop
            .as_ref()
            .map(|e| StopNote::new(&self.analysis.solution, e, crate::hints::solve_hint(e)))
    }

    /// Exit 0 for a complete path; for one that stopped, the error (exit 1) after the outputs
    /// are written.
    pub fn finish(self) -> anyhow::Result<ExitCode> {
        let Some(e) = self.stop else {
            return Ok(ExitCode::SUCCESS);
        };
        let sol = &self.analysis.solution;
        let last = sol.steps.last().map_or(0.0, |s| s.load_factor);
        Err(anyhow::Error::new(e)).with_context(|| {
            format!(
                "the static path stopped after step {} (load factor {last:.6}); the results of the converged steps are written",
                sol.steps.len() - 1
            )
        })
    }
}
