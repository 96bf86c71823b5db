//! Time functions φ(t) of loads and prescribed inputs in a time simulation: the value of a load
//! or input at time t is its model value times φ(t), with the exact first and second derivatives
//! (velocities and accelerations of prescribed motions) and the kinks (times where φ or a
//! derivative jumps) on which the integrator lands exactly.

use serde::{Deserialize, Serialize};

/// A scalar history φ(t).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum TimeFunction {
    /// φ = 1 at every time (a load present from the start).
    #[default]
    Constant,
    /// Piecewise linear through the points (t, φ), t strictly increasing; constant before the
    /// first and after the last point.
    Table(Vec<[f64; 2]>),
    /// 0 until `start`, then linear to 1 at `end`, then 1.
    Ramp {
        /// Start time [s].
        start: f64,
        /// End time [s] (> start).
        end: f64,
    },
    /// `before` up to and including `at`, `after` afterwards (a sudden load or a release).
    Step {
        /// Time of the jump [s].
        at: f64,
        /// Value up to the jump.
        before: f64,
        /// Value after the jump.
        after: f64,
    },
    /// offset + amplitude · sin(2π f t + phase).
    Sine {
        /// Amplitude.
        amplitude: f64,
        /// Frequency f [Hz].
        frequency: f64,
        /// Phase [rad].
        #[serde(default)]
        phase: f64,
        /// Offset.
        #[serde(default)]
        offset: f64,
    },
    /// A smooth start from rest to unit speed: φ' rises from 0 to 1 over `duration` T with the
    /// cycloidal acceleration φ'' = (1 − cos 2πt/T)/T, then stays 1:
    /// φ = [t²/2 + (T/2π)² (cos 2πt/T − 1)]/T for t ≤ T, φ = t − T/2 after (the spin-up
    /// manoeuvre of a hub, validation.md N01, with the angle Ω_s φ).
    SpeedRamp {
        /// Duration T of the run-up [s].
        duration: f64,
    },
    /// The polynomial φ = c₀ + c₁ t + c₂ t² + … (coefficients from the constant term up): a
    /// motion at constant acceleration is [x₀, v₀, a₀/2] (SPACAR's `INPUTX` with a position,
    /// a velocity and an acceleration).
    Polynomial(Vec<f64>),
}

/// What is wrong with a time function.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TimeFunctionError {
    /// Not finite or out of order.
    #[error("{0}")]
    Invalid(String),
}

impl TimeFunction {
    /// Check the data: finite numbers, increasing table times, positive durations.
    pub fn validate(&self) -> Result<(), TimeFunctionError> {
        let bad = |m: &str| Err(TimeFunctionError::Invalid(m.to_string()));
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        match self {
            Self::Constant => Ok(()),
            Self::Table(p) => {
                if p.is_empty() {
                    return bad("the table has no points");
                }
                if !p.iter().all(|q| finite(q)) {
                    return bad("the table holds a value that is not a finite number");
                }
                if p.windows(2).any(|w| w[1][0] <= w[0][0]) {
                    return bad("the table's times must increase strictly");
                }
                Ok(())
            }
            Self::Ramp { start, end } => {
                if !finite(&[*start, *end]) || end <= start {
                    return bad("a ramp needs finite times with end > start");
                }
                Ok(())
            }
            Self::Step { at, before, after } => {
                if !finite(&[*at, *before, *after]) {
                    return bad("a step needs finite numbers");
                }
                Ok(())
            }
            Self::Sine {
                amplitude,
                frequency,
                phase,
                offset,
            } => {
                if !finite(&[*amplitude, *frequency, *phase, *offset]) {
                    return bad("a sine needs finite numbers");
                }
                Ok(())
            }
            Self::SpeedRamp { duration } => {
                if !duration.is_finite() || *duration <= 0.0 {
                    return bad("a speed ramp needs a finite duration > 0");
                }
                Ok(())
            }
            Self::Polynomial(c) => {
                if c.is_empty() || c.len() > 16 || !finite(c) {
                    return bad("a polynomial needs 1 to 16 finite coefficients");
                }
                Ok(())
            }
        }
    }

    /// Whether φ itself jumps somewhere (not allowed for prescribed motions).
    pub fn is_discontinuous(&self) -> bool {
        matches!(self, Self::Step { before, after, .. } if before != after)
    }

    /// φ(t), φ'(t), φ''(t). At a kink the derivatives are those of the interval that ends
    /// there (left derivatives); the integrator lands on kinks, so each step sees one smooth
    /// piece.
    pub fn eval(&self, t: f64) -> [f64; 3] {
        match self {
            Self::Constant => [1.0, 0.0, 0.0],
            Self::Table(p) => {
                let n = p.len();
                if t <= p[0][0] {
                    return [p[0][1], 0.0, 0.0];
                }
                if t > p[n - 1][0] {
                    return [p[n - 1][1], 0.0, 0.0];
                }
                // the interval (t_k, t_{k+1}] holding t
                let k = p.partition_point(|q| q[0] < t).saturating_sub(1);
                let (a, b) = (p[k], p[(k + 1).min(n - 1)]);
                let slope = (b[1] - a[1]) / (b[0] - a[0]);
                [a[1] + slope * (t - a[0]), slope, 0.0]
            }
            Self::Ramp { start, end } => {
                if t <= *start {
                    [0.0, 0.0, 0.0]
                } else if t > *end {
                    [1.0, 0.0, 0.0]
                } else {
                    let s = 1.0 / (end - start);
                    [(t - start) * s, s, 0.0]
                }
            }
            Self::Step { at, before, after } => {
                if t <= *at {
                    [*before, 0.0, 0.0]
                } else {
                    [*after, 0.0, 0.0]
                }
            }
            Self::Sine {
                amplitude,
                frequency,
                phase,
                offset,
            } => {
                let w = 2.0 * std::f64::consts::PI * frequency;
                let (s, c) = (w * t + phase).sin_cos();
                [
                    offset + amplitude * s,
                    amplitude * w * c,
                    -amplitude * w * w * s,
                ]
            }
            Self::SpeedRamp { duration } => {
                let tt = *duration;
                if t <= 0.0 {
                    return [0.0, 0.0, 0.0];
                }
                if t > tt {
                    return [t - 0.5 * tt, 1.0, 0.0];
                }
                let w = 2.0 * std::f64::consts::PI / tt;
                let (s, c) = (w * t).sin_cos();
                [
                    (0.5 * t * t + (c - 1.0) / (w * w)) / tt,
                    (t - s / w) / tt,
                    (1.0 - c) / tt,
                ]
            }
            Self::Polynomial(c) => {
                // Horner for φ, φ', φ'' together
                let mut r = [0.0; 3];
                for &ck in c.iter().rev() {
                    r[2] = r[2] * t + 2.0 * r[1];
                    r[1] = r[1] * t + r[0];
                    r[0] = r[0] * t + ck;
                }
                r
            }
        }
    }

    /// φ(t) with the derivatives of the interval that starts at t (right derivatives at a
    /// kink): the rates at the start of a run, where no interval ends (a ramp from t = 0 starts
    /// at its full speed, not at rest).
    pub fn eval_right(&self, t: f64) -> [f64; 3] {
        match self {
            Self::Table(p) => {
                let n = p.len();
                if t < p[0][0] {
                    return self.eval(t);
                }
                if t >= p[n - 1][0] {
                    return [p[n - 1][1], 0.0, 0.0];
                }
                // the interval [t_k, t_{k+1}) holding t
                let k = p.partition_point(|q| q[0] <= t) - 1;
                let (a, b) = (p[k], p[k + 1]);
                let slope = (b[1] - a[1]) / (b[0] - a[0]);
                [a[1] + slope * (t - a[0]), slope, 0.0]
            }
            Self::Ramp { start, end } if t >= *start => {
                if t >= *end {
                    return [1.0, 0.0, 0.0];
                }
                let s = 1.0 / (end - start);
                [(t - start) * s, s, 0.0]
            }
            // smooth where they are evaluated, or constant on both sides of their kinks
            _ => self.eval(t),
        }
    }

    /// The times in (t0, t1) where φ or one of its first two derivatives jumps.
    pub fn kinks(&self, t0: f64, t1: f64) -> Vec<f64> {
        let all: Vec<f64> = match self {
            Self::Constant | Self::Sine { .. } | Self::Polynomial(_) => Vec::new(),
            Self::Table(p) => p.iter().map(|q| q[0]).collect(),
            Self::Ramp { start, end } => vec![*start, *end],
            Self::Step { at, .. } => vec![*at],
            Self::SpeedRamp { duration } => vec![0.0, *duration],
        };
        all.into_iter().filter(|&k| k > t0 && k < t1).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The derivatives against central differences inside each smooth piece.
    #[test]
    fn derivatives_match_central_differences() {
        let fs = [
            TimeFunction::Table(vec![[0.0, 0.0], [0.5, 2.0], [1.0, -1.0]]),
            TimeFunction::Ramp {
                start: 0.2,
                end: 0.7,
            },
            TimeFunction::Sine {
                amplitude: 0.3,
                frequency: 2.0,
                phase: 0.4,
                offset: 1.0,
            },
            TimeFunction::SpeedRamp { duration: 0.8 },
            TimeFunction::Polynomial(vec![0.5, -1.0, 2.0, 0.7]),
        ];
        for f in &fs {
            for &t in &[0.1, 0.33, 0.61, 0.77, 0.9, 1.3] {
                let h = 1e-5;
                let [_, d1, d2] = f.eval(t);
                let (p, m) = (f.eval(t + h), f.eval(t - h));
                let fd1 = (p[0] - m[0]) / (2.0 * h);
                let fd2 = (p[1] - m[1]) / (2.0 * h);
                assert!((d1 - fd1).abs() < 1e-6, "{f:?} at {t}: {d1} vs {fd1}");
                assert!((d2 - fd2).abs() < 1e-5, "{f:?} at {t}: {d2} vs {fd2}");
            }
        }
    }

    /// Constant acceleration: [x₀, v₀, a₀/2] gives x₀ + v₀ t + a₀ t²/2, v₀ + a₀ t and a₀.
    #[test]
    fn polynomial_is_motion_at_constant_acceleration() {
        let (x0, v0, a0) = (0.25, -1.5, 3.0);
        let f = TimeFunction::Polynomial(vec![x0, v0, 0.5 * a0]);
        for t in [0.0, 0.4, 2.5] {
            let [p, d1, d2] = f.eval(t);
            assert!((p - (x0 + v0 * t + 0.5 * a0 * t * t)).abs() < 1e-14);
            assert!((d1 - (v0 + a0 * t)).abs() < 1e-14);
            assert!((d2 - a0).abs() < 1e-14);
        }
        assert!(TimeFunction::Polynomial(vec![]).validate().is_err());
        assert!(TimeFunction::Polynomial(vec![1.0, f64::NAN])
            .validate()
            .is_err());
    }

    /// The spin-up angle of validation.md N01 at the end of the run-up: Ω_s T/2, and
    /// continuity of φ and φ' there.
    #[test]
    fn speed_ramp_is_the_spin_up_profile() {
        let f = TimeFunction::SpeedRamp { duration: 15.0 };
        let [v, d, a] = f.eval(15.0);
        assert!((v - 7.5).abs() < 1e-12 && (d - 1.0).abs() < 1e-12 && a.abs() < 1e-12);
        let after = f.eval(15.0 + 1e-9);
        assert!((after[0] - v).abs() < 1e-8 && (after[1] - 1.0).abs() < 1e-12);
        assert_eq!(f.kinks(0.0, 30.0), vec![15.0]);
    }

    /// At a kink the right derivatives are those of the interval that starts there, at the
    /// start of a run too (a table or ramp from t = 0 starts at its full rate).
    #[test]
    fn right_derivatives_at_kinks_start_the_next_interval() {
        let table = TimeFunction::Table(vec![[0.0, 0.0], [0.5, 2.0], [1.0, -1.0]]);
        assert_eq!(table.eval(0.0), [0.0, 0.0, 0.0]);
        assert_eq!(table.eval_right(0.0), [0.0, 4.0, 0.0]);
        assert_eq!(table.eval(0.5), [2.0, 4.0, 0.0]);
        assert_eq!(table.eval_right(0.5), [2.0, -6.0, 0.0]);
        assert_eq!(table.eval_right(1.0), [-1.0, 0.0, 0.0]);
        assert_eq!(table.eval_right(0.25), table.eval(0.25));
        let ramp = TimeFunction::Ramp {
            start: 0.0,
            end: 2.0,
        };
        assert_eq!(ramp.eval(0.0), [0.0, 0.0, 0.0]);
        assert_eq!(ramp.eval_right(0.0), [0.0, 0.5, 0.0]);
        assert_eq!(ramp.eval_right(2.0), [1.0, 0.0, 0.0]);
        assert_eq!(ramp.eval_right(-1.0), [0.0, 0.0, 0.0]);
        let spin = TimeFunction::SpeedRamp { duration: 15.0 };
        assert_eq!(spin.eval_right(0.0), spin.eval(0.0));
    }

    #[test]
    fn step_is_left_continuous_and_tables_validate() {
        let f = TimeFunction::Step {
            at: 0.0,
            before: 1.0,
            after: 0.0,
        };
        assert_eq!(f.eval(0.0)[0], 1.0);
        assert_eq!(f.eval(1e-12)[0], 0.0);
        assert!(f.is_discontinuous());
        assert!(TimeFunction::Table(vec![[0.0, 1.0], [0.0, 2.0]])
            .validate()
            .is_err());
        assert!(TimeFunction::Ramp {
            start: 1.0,
            end: 1.0
        }
        .validate()
        .is_err());
    }
}
