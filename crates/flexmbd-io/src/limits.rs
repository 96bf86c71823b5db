//! Upper bounds on the counts a model file or a command line may ask for (docs/reliability.md).
//!
//! They keep a small input from asking for unbounded memory or time (a 400-byte file with
//! `segments = 9223372036854775807` would otherwise run until the machine gives up); each is far
//! above what a model of a compliant mechanism needs. A value above its limit is invalid input.

/// Most elements one `[[beam]]` may be split into (`segments`).
pub const MAX_SEGMENTS: usize = 10_000;
/// Most load steps of a static solution (`[static] steps`, `ITERSTEP`, `--steps`).
pub const MAX_STEPS: usize = 100_000;
/// Most Newton iterations per load step (`[static] max_iterations`).
pub const MAX_ITERATIONS: usize = 10_000;
/// Most buckling multipliers reported per step (`[static] buckling`).
pub const MAX_BUCKLING: usize = MAX_MODES;
/// Most modes, frequencies per step or buckling multipliers a command line may ask for
/// (`--count`, `--modes`, `--buckling`).
pub const MAX_MODES: usize = 10_000;
