//! Deterministic, seeded fuzzing through the library API (issue 15, item 6; docs/reliability.md,
//! "Fuzz harness").
//!
//! Inputs: seeded byte and token mutations of the shipped examples (`examples/*.toml`) and of
//! the SPACAR fixtures (`crates/flexmbd-io/tests/models/`, with `public/`), and small random
//! models generated as TOML (nodes, trusses, beams, hinges, rigid bodies, fixes, inputs, loads,
//! masses, sections). Each input is parsed; when it parses into a model of at most
//! [`MAX_COORDINATES`] coordinates, the kinematic check, a static analysis of two load steps
//! (with the compliance of one node and the lowest buckling multiplier) and three modes run in
//! process under `catch_unwind`. Asserted for every input:
//!
//! - no panic;
//! - no non-finite number in a result returned as `Ok` (a negative ω² is reported with a NaN
//!   frequency, the documented "complex" mode; its eigenvalue must still be finite);
//! - every reader error names the file and a line (`fuzz.toml:LINE:COLUMN: …`), or is one of
//!   the whole-file errors (no `[nodes]`, no element), which name the file;
//! - no input takes longer than [`BUDGET`] (reported with its seed; a hang would stop the run).
//!
//! `cargo test -p flexmbd-cli --test fuzz` runs [`SHORT_RUN`] inputs on two threads. The long
//! run for use by hand: `FLEXMBD_FUZZ_INPUTS=1000000 cargo test --release -p flexmbd-cli --test
//! fuzz -- --ignored --nocapture` (`FLEXMBD_FUZZ_SEED` picks another seed).

use flexmbd_core::dynamics::modes;
use flexmbd_core::kinematics::classify::{classify, ClassifyOptions};
use flexmbd_core::linearized::{at_step, LinearRequest};
use flexmbd_core::statics::{non_finite_parts, solve, StaticOptions};
use flexmbd_core::Model;
use flexmbd_io::InputError;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Inputs of the run in `cargo test`.
const SHORT_RUN: usize = 20_000;

/// Models with more coordinates are parsed but not analysed (bounds the work per input).
const MAX_COORDINATES: usize = 120;

/// An input that takes longer is reported (and fails the run).
const BUDGET: Duration = Duration::from_secs(10);

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Format {
    Toml,
    Dat,
}

struct Seed {
    name: String,
    format: Format,
    bytes: Vec<u8>,
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn seeds() -> Vec<Seed> {
    let mut v = Vec::new();
    let dirs = [
        root().join("examples"),
        root().join("crates/flexmbd-io/tests/models"),
        root().join("crates/flexmbd-io/tests/models/public"),
    ];
    for dir in dirs {
        let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.expect("directory entry").path())
            .collect();
        paths.sort();
        for p in paths {
            let format = match p.extension().and_then(|e| e.to_str()) {
                Some("toml") => Format::Toml,
                Some("dat") => Format::Dat,
                _ => continue,
            };
            v.push(Seed {
                name: p.file_name().unwrap().to_string_lossy().into(),
                format,
                bytes: std::fs::read(&p).unwrap(),
            });
        }
    }
    assert!(v.len() >= 15, "seed files: {}", v.len());
    v
}

const SPECIAL: &[&str] = &[
    "1e999",
    "-1e999",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e200",
    "1e-320",
    "0",
    "0.0",
    "-0.0",
    "-1",
    "-1e6",
    "1e12",
    "1e-12",
    "99999999999999999999",
    "4294967296",
    "1.5",
    "3",
    "10000",
    "",
    "x",
    "\"\"",
    "[]",
    "true",
];

fn is_num_byte(b: u8) -> bool {
    b.is_ascii_digit() || matches!(b, b'.' | b'-' | b'+' | b'e' | b'E')
}

/// The byte ranges of number-like tokens (a digit with its neighbouring number bytes).
fn number_tokens(t: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < t.len() {
        if t[i].is_ascii_digit() {
            let mut a = i;
            while a > 0 && is_num_byte(t[a - 1]) {
                a -= 1;
            }
            let mut b = i;
            while b < t.len() && is_num_byte(t[b]) {
                b += 1;
            }
            out.push((a, b));
            i = b;
        } else {
            i += 1;
        }
    }
    out
}

fn lines(t: &[u8]) -> Vec<Vec<u8>> {
    t.split(|b| *b == b'\n').map(<[u8]>::to_vec).collect()
}

/// One to three random edits: bytes, truncation, a number replaced by a special value, a line
/// deleted, duplicated or swapped, a number scaled.
fn mutate(rng: &mut StdRng, text: &[u8]) -> Vec<u8> {
    let mut t = text.to_vec();
    for _ in 0..rng.random_range(1..=3) {
        match rng.random_range(0..8) {
            0 => {
                for _ in 0..rng.random_range(1..6) {
                    if t.is_empty() {
                        break;
                    }
                    let i = rng.random_range(0..t.len());
                    t[i] = match rng.random_range(0..5) {
                        0 => rng.random(),
                        1 => b"0123456789"[rng.random_range(0..10)],
                        2 => b" \t\n#%;,-.eEdD+"[rng.random_range(0..14)],
                        3 => b"[]{}=\"',"[rng.random_range(0..8)],
                        _ => rng.random_range(b'A'..=b'z'),
                    };
                }
            }
            1 => {
                let n = rng.random_range(0..=t.len());
                t.truncate(n);
            }
            2 | 3 => {
                let toks = number_tokens(&t);
                if !toks.is_empty() {
                    let (a, b) = toks[rng.random_range(0..toks.len())];
                    let s = SPECIAL[rng.random_range(0..SPECIAL.len())];
                    t.splice(a..b, s.bytes());
                }
            }
            4 => {
                let toks = number_tokens(&t);
                if !toks.is_empty() {
                    let (a, b) = toks[rng.random_range(0..toks.len())];
                    let v: f64 = std::str::from_utf8(&t[a..b])
                        .ok()
                        .and_then(|s| s.parse().ok())
                        .unwrap_or(1.0);
                    let f = [-1.0, 0.0, 1e-6, 1e3, 1e9, 2.0][rng.random_range(0..6)];
                    let s = format!("{:?}", v * f);
                    t.splice(a..b, s.bytes());
                }
            }
            5 => {
                let mut ls = lines(&t);
                if !ls.is_empty() {
                    let i = rng.random_range(0..ls.len());
                    ls.remove(i);
                    t = ls.join(&b'\n');
                }
            }
            6 => {
                let mut ls = lines(&t);
                if !ls.is_empty() {
                    let i = rng.random_range(0..ls.len());
                    let l = ls[i].clone();
                    let j = rng.random_range(0..=ls.len());
                    ls.insert(j, l);
                    t = ls.join(&b'\n');
                }
            }
            _ => {
                let mut ls = lines(&t);
                if ls.len() > 1 {
                    let i = rng.random_range(0..ls.len());
                    let j = rng.random_range(0..ls.len());
                    ls.swap(i, j);
                    t = ls.join(&b'\n');
                }
            }
        }
    }
    t
}

/// A small random model as TOML: 2 to 6 nodes (some rotational), trusses, beams (constants or
/// section + material), hinges, rigid bodies, supports, inputs, loads, masses and statics data.
fn generate(rng: &mut StdRng) -> Vec<u8> {
    use std::fmt::Write;
    let mut s = String::new();
    let nn = rng.random_range(2..=6);
    let coord = |rng: &mut StdRng| -> String {
        match rng.random_range(0..40) {
            0 => "1e200".into(),
            1 => "-1e-300".into(),
            _ => format!("{:.3}", rng.random_range(-1.0..1.0f64)),
        }
    };
    let rot: Vec<bool> = (0..nn).map(|_| rng.random_bool(0.6)).collect();
    s.push_str("[model]\nname = \"generated\"\n\n[nodes]\n");
    for (i, &r) in rot.iter().enumerate() {
        let x = format!("[{}, {}, {}]", coord(rng), coord(rng), coord(rng));
        if r {
            let _ = writeln!(s, "n{i} = {{ x = {x}, rot = true }}");
        } else {
            let _ = writeln!(s, "n{i} = {x}");
        }
    }
    let pick = |rng: &mut StdRng| rng.random_range(0..nn);
    let pair = |rng: &mut StdRng| {
        let a = rng.random_range(0..nn);
        let mut b = rng.random_range(0..nn);
        if b == a && rng.random_bool(0.95) {
            b = (a + 1) % nn;
        }
        (a, b)
    };
    // supports and inputs
    let _ = writeln!(s, "\n[fix]");
    let fixed = pick(rng);
    let _ = writeln!(s, "n{fixed} = \"all\"");
    if rng.random_bool(0.3) {
        let k = pick(rng);
        if k != fixed {
            let _ = writeln!(s, "n{k} = [\"z\"]");
        }
    }
    if rng.random_bool(0.2) {
        let k = pick(rng);
        if k != fixed {
            let d = ["x", "y", "z"][rng.random_range(0..3)];
            let _ = writeln!(s, "\n[inputs]\nn{k} = \"{d}\"");
        }
    }
    let _ = writeln!(
        s,
        "\n[[material]]\nid = \"m\"\nE = {}\nnu = 0.3\nrho = {}",
        ["200e9", "1e3", "0.2", "1e20", "0"][rng.random_range(0..5)],
        ["7800.0", "0", "1e-9"][rng.random_range(0..3)]
    );
    let _ = writeln!(
        s,
        "\n[[section]]\nid = \"s\"\nshape = \"rectangle\"\nw = {}\nt = {}",
        ["0.02", "0.001", "1e-6"][rng.random_range(0..3)],
        ["0.0005", "0.002", "0.02"][rng.random_range(0..3)]
    );
    if rng.random_bool(0.3) {
        let _ = writeln!(s, "shear = false");
    }
    let ne = rng.random_range(1..=5);
    let mut rigid_done = false;
    for k in 0..ne {
        let (a, b) = pair(rng);
        match rng.random_range(0..6) {
            0 | 1 => {
                let _ = writeln!(
                    s,
                    "\n[[truss]]\nid = \"e{k}\"\nnodes = [\"n{a}\", \"n{b}\"]\nEA = {}",
                    ["1e6", "0", "1e12", "-5"][rng.random_range(0..4)]
                );
            }
            2 | 3 => {
                let _ = writeln!(s, "\n[[beam]]\nid = \"e{k}\"\nnodes = [\"n{a}\", \"n{b}\"]");
                if rng.random_bool(0.7) {
                    let _ = writeln!(
                        s,
                        "orient = [{}, {}, {}]",
                        coord(rng),
                        coord(rng),
                        coord(rng)
                    );
                }
                if rng.random_bool(0.6) {
                    let _ = writeln!(s, "section = \"s\"\nmaterial = \"m\"");
                } else {
                    let _ = writeln!(s, "EA = 1e6\nGJ = 1.0\nEIy = 2.0\nEIz = 3.0\nrho_a = 0.1");
                }
                if rng.random_bool(0.3) {
                    let _ = writeln!(s, "segments = {}", rng.random_range(1..=4));
                }
                if rng.random_bool(0.3) {
                    let _ = writeln!(s, "free = [{}]", rng.random_range(1..=6));
                }
            }
            4 => {
                let _ = writeln!(
                    s,
                    "\n[[hinge]]\nid = \"e{k}\"\nnodes = [\"n{a}\", \"n{b}\"]\naxis = [0.0, 0.0, 1.0]\nfree = [1]"
                );
            }
            _ if !rigid_done => {
                rigid_done = true;
                let c = pick(rng);
                let _ = writeln!(
                    s,
                    "\n[[rigid]]\nid = \"e{k}\"\nnodes = [\"n{a}\", \"n{b}\", \"n{c}\"]"
                );
            }
            _ => {
                let _ = writeln!(
                    s,
                    "\n[[truss]]\nid = \"e{k}\"\nnodes = [\"n{a}\", \"n{b}\"]\nEA = 1e5"
                );
            }
        }
    }
    for _ in 0..rng.random_range(0..=2) {
        let n = pick(rng);
        let f = ["1.0", "-1e3", "1e-14", "1e7", "0.0"][rng.random_range(0..5)];
        let _ = writeln!(
            s,
            "\n[[load]]\nnode = \"n{n}\"\nforce = [{f}, {}, {f}]",
            coord(rng)
        );
    }
    for _ in 0..rng.random_range(0..=2) {
        let n = pick(rng);
        let _ = writeln!(
            s,
            "\n[[mass]]\nnode = \"n{n}\"\nm = {}",
            ["1.0", "0.0", "1e-9", "1e6"][rng.random_range(0..4)]
        );
    }
    if rng.random_bool(0.2) {
        let n = pick(rng);
        let _ = writeln!(
            s,
            "\n[[prescribe]]\nnode = \"n{n}\"\ndof = \"x\"\nvalue = {}",
            coord(rng)
        );
    }
    s.into_bytes()
}

/// Whether a reader error names the file and a line, or is a whole-file error.
fn names_a_line(e: &InputError, file: &str) -> bool {
    match e {
        InputError::At { file: f, line, .. } => f == file && *line >= 1,
        InputError::File { file: f, message } => f == file && !message.is_empty(),
        InputError::Read { .. } => false,
    }
}

/// The `.dat` reader's messages as strings (`fuzz.dat:LINE:…`), as the flexmbd-io test.
fn dat_message_has_line(msg: &str) -> bool {
    let Some(rest) = msg.strip_prefix("fuzz.dat:") else {
        return false;
    };
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    digits > 0 && rest[digits..].starts_with(':')
}

/// What one input did.
enum Outcome {
    /// The reader refused it (with a line).
    Refused,
    /// Parsed, too large to analyse.
    Large,
    /// Parsed and analysed (the analyses may fail with an error, which is fine).
    Analysed,
    /// A broken promise (message).
    Problem(String),
}

fn parse(format: Format, bytes: &[u8]) -> Result<Model, String> {
    match format {
        Format::Toml => {
            // the TOML reader takes text; invalid UTF-8 is refused by the file reader, whose
            // message (line and byte) is tested in reliability.rs: here the lossy text
            let text = String::from_utf8_lossy(bytes);
            match flexmbd_io::parse_model_file(&text, "fuzz.toml") {
                Ok(f) => Ok(f.model),
                Err(e) if names_a_line(&e, "fuzz.toml") => Err(String::new()),
                Err(e) => Err(format!("reader error without file and line: {e}")),
            }
        }
        Format::Dat => {
            let text = String::from_utf8_lossy(bytes);
            let r = flexmbd_io::parse_dat(&text, "fuzz.dat")
                .map_err(|e| e.to_string())
                .and_then(|m| m.to_model_file().map_err(|e| e.to_string()));
            match r {
                Ok((f, _)) => Ok(f.model),
                Err(msg) if dat_message_has_line(&msg) => Err(String::new()),
                Err(msg) => Err(format!("reader error without file and line: {msg}")),
            }
        }
    }
}

fn finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Check, static (2 steps; at the last one the compliance of the last node and 1 buckling
/// multiplier) and 3 modes.
fn analyse_model(model: &Model) -> Result<(), String> {
    if let Ok(c) = classify(model, &ClassifyOptions::default()) {
        let a = &c.analysis;
        if !finite(&a.singular_values) || !a.tol.is_finite() {
            return Err(format!(
                "check: singular values not finite: {:?}",
                a.singular_values
            ));
        }
    }
    let opts = StaticOptions {
        steps: 2,
        max_iterations: 12,
        max_halvings: 3,
        ..Default::default()
    };
    let req = LinearRequest {
        compliance: vec![model.nodes.len().saturating_sub(1)],
        buckling: 1,
        ..Default::default()
    };
    let Ok(sol) = solve(model, &opts, |_, _| {}) else {
        return Ok(());
    };
    for (k, st) in sol.steps.iter().enumerate() {
        let bad = non_finite_parts(st);
        if !bad.is_empty() {
            return Err(format!("static step {k}: not finite: {bad:?}"));
        }
    }
    let Some(last) = sol.steps.last() else {
        return Ok(());
    };
    // the linearised results at the last step only (bounds the work)
    let k = sol.steps.len() - 1;
    {
        let lin = at_step(model, last, &req);
        for (node, c) in &lin.compliance {
            if !c.global.iter().all(|r| finite(r)) {
                return Err(format!("static step {k}: compliance of {node} not finite"));
            }
        }
        if let Some(b) = &lin.buckling {
            if !finite(&b.multipliers) || !finite(&b.reversed) {
                return Err(format!("static step {k}: buckling multipliers not finite"));
            }
        }
    }
    if let Ok(m) = modes(model, last, 3) {
        for (k, mode) in m.modes.iter().enumerate() {
            let freq_ok = mode.frequency.is_finite()
                || (mode.frequency.is_nan() && mode.eigenvalue < 0.0 && !mode.rigid_body);
            if !mode.eigenvalue.is_finite() || !freq_ok || !finite(&mode.shape) {
                return Err(format!(
                    "mode {k}: not finite (ω² {}, f {})",
                    mode.eigenvalue, mode.frequency
                ));
            }
        }
    }
    Ok(())
}

fn run_one(format: Format, bytes: &[u8]) -> Outcome {
    let model = match parse(format, bytes) {
        Ok(m) => m,
        Err(msg) if msg.is_empty() => return Outcome::Refused,
        Err(msg) => return Outcome::Problem(msg),
    };
    if model.nx > MAX_COORDINATES {
        return Outcome::Large;
    }
    match analyse_model(&model) {
        Ok(()) => Outcome::Analysed,
        Err(msg) => Outcome::Problem(msg),
    }
}

#[derive(Default, Debug)]
struct Figures {
    inputs: usize,
    refused: usize,
    large: usize,
    analysed: usize,
    panics: usize,
    slow: usize,
    problems: usize,
    /// Time per origin (seed file or "generated"), for the report.
    time: std::collections::BTreeMap<String, f64>,
}

/// Runs `count` inputs from `seed` on two threads; returns the figures and the first reports.
fn campaign(count: usize, seed: u64) -> (Figures, Vec<String>) {
    let seeds = seeds();
    let next = AtomicUsize::new(0);
    let figures = Mutex::new(Figures::default());
    let reports = Mutex::new(Vec::new());
    // silence the default panic message: panics are counted and reported with their input
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                if i >= count {
                    break;
                }
                // every input has its own generator: the run does not depend on the threads
                let mut rng =
                    StdRng::seed_from_u64(seed ^ (i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
                let (name, format, bytes) = if i % 4 == 3 {
                    ("generated".to_string(), Format::Toml, generate(&mut rng))
                } else {
                    let sd = &seeds[rng.random_range(0..seeds.len())];
                    (sd.name.clone(), sd.format, mutate(&mut rng, &sd.bytes))
                };
                let t0 = Instant::now();
                let r = std::panic::catch_unwind(|| run_one(format, &bytes));
                let dt = t0.elapsed();
                let mut f = figures.lock().unwrap();
                f.inputs += 1;
                *f.time.entry(name.clone()).or_default() += dt.as_secs_f64();
                let report = |what: String| {
                    let mut r = reports.lock().unwrap();
                    if r.len() < 20 {
                        r.push(format!(
                            "input {i} (seed {seed:#x}, from {name}): {what}\n{}",
                            String::from_utf8_lossy(&bytes)
                        ));
                    }
                };
                match r {
                    Ok(Outcome::Refused) => f.refused += 1,
                    Ok(Outcome::Large) => f.large += 1,
                    Ok(Outcome::Analysed) => f.analysed += 1,
                    Ok(Outcome::Problem(msg)) => {
                        f.problems += 1;
                        report(msg);
                    }
                    Err(p) => {
                        f.panics += 1;
                        let msg = p
                            .downcast_ref::<String>()
                            .cloned()
                            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                            .unwrap_or_default();
                        report(format!("panic: {msg}"));
                    }
                }
                if dt > BUDGET {
                    f.slow += 1;
                    report(format!(
                        "took {:.1} s (budget {:?})",
                        dt.as_secs_f64(),
                        BUDGET
                    ));
                }
            });
        }
    });
    std::panic::set_hook(hook);
    (figures.into_inner().unwrap(), reports.into_inner().unwrap())
}

fn run_and_check(count: usize, seed: u64) {
    let t0 = Instant::now();
    let (f, reports) = campaign(count, seed);
    let secs = t0.elapsed().as_secs_f64();
    eprintln!(
        "fuzz: {} inputs in {secs:.1} s ({:.0}/s): {} refused by the readers (with a line), {} parsed but larger than {MAX_COORDINATES} coordinates, {} analysed; {} panics, {} over the {:?} budget, {} broken promises",
        f.inputs,
        f.inputs as f64 / secs,
        f.refused,
        f.large,
        f.analysed,
        f.panics,
        f.slow,
        BUDGET,
        f.problems
    );
    let mut by_time: Vec<(&String, &f64)> = f.time.iter().collect();
    by_time.sort_by(|a, b| b.1.total_cmp(a.1));
    for (name, t) in by_time.iter().take(6) {
        eprintln!("fuzz: {t:.1} s on inputs from {name}");
    }
    for r in &reports {
        eprintln!("--- {r}");
    }
    assert_eq!(f.inputs, count);
    assert!(
        f.panics == 0 && f.slow == 0 && f.problems == 0,
        "panics {}, slow {}, problems {}: first reports above",
        f.panics,
        f.slow,
        f.problems
    );
    // the mutations reach the analyses, and the readers refuse some
    assert!(
        f.analysed > count / 10 && f.refused > count / 10,
        "analysed {}, refused {}",
        f.analysed,
        f.refused
    );
}

#[test]
fn fuzz_short_run() {
    run_and_check(SHORT_RUN, 0x00f1_e8bd);
}

/// The long run, by hand: `FLEXMBD_FUZZ_INPUTS=1000000 cargo test --release -p flexmbd-cli
/// --test fuzz -- --ignored --nocapture`.
#[test]
#[ignore]
fn fuzz_long_run() {
    let count = std::env::var("FLEXMBD_FUZZ_INPUTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(200_000);
    let seed = std::env::var("FLEXMBD_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x10c6_7a11);
    run_and_check(count, seed);
}
