//! The variants of a study: a grid, a list, or a Latin hypercube (McKay, Beckman and Conover,
//! Technometrics 21 (1979) 239–245: every parameter's range cut into `samples` equal strata,
//! one point in each, the strata of the parameters paired by independent random permutations).

use crate::spec::{Axis, Parameter, Sampling, Study};
use serde::{Deserialize, Serialize};

/// One member of the family: its index in the study and its parameter values (in the study's
/// parameter order).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Variant {
    /// Index in the study (0-based; the order of the grid, the list or the sample).
    pub index: usize,
    /// Parameter values.
    pub values: Vec<f64>,
}

/// The points of a grid axis.
fn axis_points(axis: &Axis) -> Vec<f64> {
    match *axis {
        Axis::Values(ref v) => v.clone(),
        Axis::Range {
            from,
            to,
            count,
            log,
        } => {
            let n = count.unwrap_or(1);
            (0..n)
                .map(|i| {
                    let s = if n == 1 {
                        0.0
                    } else {
                        i as f64 / (n - 1) as f64
                    };
                    if i + 1 == n && n > 1 {
                        to
                    } else if log {
                        from * (to / from).powf(s)
                    } else {
                        from + s * (to - from)
                    }
                })
                .collect()
        }
    }
}

/// The number of variants of a grid (saturating).
pub fn grid_size(parameters: &[Parameter]) -> usize {
    parameters
        .iter()
        .map(|p| axis_points(&p.axis).len())
        .fold(1usize, usize::saturating_mul)
}

/// The study's variants, in index order.
pub fn variants(study: &Study) -> Vec<Variant> {
    let rows: Vec<Vec<f64>> = match &study.sampling {
        Sampling::Grid => {
            let axes: Vec<Vec<f64>> = study
                .parameters
                .iter()
                .map(|p| axis_points(&p.axis))
                .collect();
            let n = grid_size(&study.parameters);
            (0..n)
                .map(|mut k| {
                    // the last parameter varies fastest
                    let mut row = vec![0.0; axes.len()];
                    for (j, a) in axes.iter().enumerate().rev() {
                        row[j] = a[k % a.len()];
                        k /= a.len();
                    }
                    row
                })
                .collect()
        }
        Sampling::List(rows) => rows.clone(),
        Sampling::Latin { samples, seed } => latin(&study.parameters, *samples, *seed),
    };
    rows.into_iter()
        .enumerate()
        .map(|(index, values)| Variant { index, values })
        .collect()
}

/// A Latin hypercube: for parameter j, the point of variant i lies in stratum π_j(i) of its
/// range, at a uniform random place inside it (in the logarithm for a `log` range).
fn latin(parameters: &[Parameter], n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = SplitMix64(seed);
    let mut rows = vec![vec![0.0; parameters.len()]; n];
    for (j, p) in parameters.iter().enumerate() {
        let Axis::Range { from, to, log, .. } = p.axis else {
            continue; // the study reader allows only ranges here
        };
        // Fisher–Yates shuffle of the strata
        let mut perm: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            let k = (rng.next_f64() * (i + 1) as f64) as usize;
            perm.swap(i, k.min(i));
        }
        for (i, row) in rows.iter_mut().enumerate() {
            let s = (perm[i] as f64 + rng.next_f64()) / n as f64;
            row[j] = if log {
                from * (to / from).powf(s)
            } else {
                from + s * (to - from)
            };
        }
    }
    rows
}

/// SplitMix64 (Steele, Lea and Flood, OOPSLA 2014): a small generator whose sequence is fixed
/// by its definition, so a seed gives the same variants with every build and on every machine.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1): the top 53 bits.
    fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn range(name: &str, from: f64, to: f64, count: Option<usize>, log: bool) -> Parameter {
        Parameter {
            name: name.into(),
            axis: Axis::Range {
                from,
                to,
                count,
                log,
            },
        }
    }

    #[test]
    fn splitmix64_gives_the_published_sequence() {
        // the reference values of SplitMix64 with seed 1234567 (Vigna's splitmix64.c, as in
        // the test vectors of the `rand_xoshiro` crate's SplitMix64)
        let mut r = SplitMix64(1234567);
        let expected = [
            6457827717110365317u64,
            3203168211198807973,
            9817491932198370423,
            4593380528125082431,
            16408922859458223821,
        ];
        for e in expected {
            assert_eq!(r.next_u64(), e);
        }
    }

    #[test]
    fn a_grid_has_every_combination_with_the_last_parameter_fastest() {
        let p = vec![
            Parameter {
                name: "a".into(),
                axis: Axis::Values(vec![1.0, 2.0]),
            },
            range("b", 10.0, 30.0, Some(3), false),
        ];
        assert_eq!(grid_size(&p), 6);
        let pts = axis_points(&p[1].axis);
        assert_eq!(pts, vec![10.0, 20.0, 30.0]);
        let log = axis_points(&range("c", 1e-4, 1e-2, Some(3), true).axis);
        assert!((log[1] - 1e-3).abs() < 1e-18 && log[2] == 1e-2);
    }

    #[test]
    fn a_latin_hypercube_has_one_point_in_every_stratum_of_every_parameter() {
        let p = vec![
            range("a", 0.0, 1.0, None, false),
            range("b", -2.0, 2.0, None, false),
            range("c", 1e-4, 1e-2, None, true),
        ];
        let n = 50;
        let rows = latin(&p, n, 7);
        for (j, par) in p.iter().enumerate() {
            let Axis::Range { from, to, log, .. } = par.axis else {
                unreachable!()
            };
            let mut hit = vec![0; n];
            for r in &rows {
                let s = if log {
                    (r[j] / from).ln() / (to / from).ln()
                } else {
                    (r[j] - from) / (to - from)
                };
                assert!((0.0..1.0).contains(&s));
                hit[(s * n as f64) as usize] += 1;
            }
            assert!(hit.iter().all(|&h| h == 1), "{hit:?}");
        }
        // the same seed gives the same points; another seed others
        assert_eq!(rows, latin(&p, n, 7));
        assert_ne!(rows, latin(&p, n, 8));
    }
}
