//! The mark of a static path that stopped part-way (issue 17, "nothing lost"): the results of
//! every converged step are written as usual, and every format says after which step the path
//! stopped, why, and what to try (docs/statics.md, "A path that stops part-way").

use flexmbd_core::statics::StaticSolution;
use serde_json::{json, Value};

/// Where and why a static path stopped, and what to try.
#[derive(Clone, Debug, PartialEq)]
pub struct StopNote {
    /// The last converged step: (index, load factor); `None` when no state converged.
    pub after: Option<(usize, f64)>,
    /// Why it stopped (the error's message).
    pub reason: String,
    /// What to try, in the words of the front end (options, model fields), if it knows.
    pub hint: Option<String>,
}

impl StopNote {
    /// The note for the converged part `sol` of a path that stopped with `reason`.
    pub fn new(sol: &StaticSolution, reason: &dyn std::fmt::Display, hint: Option<&str>) -> Self {
        Self {
            after: sol
                .steps
                .last()
                .map(|st| (sol.steps.len() - 1, st.load_factor)),
            reason: reason.to_string(),
            hint: hint.map(str::to_string),
        }
    }

    /// One line: "stopped after step K (load factor T): REASON".
    pub fn line(&self) -> String {
        format!("stopped {}", self.place())
    }

    /// "after step K (load factor T): REASON".
    fn place(&self) -> String {
        match self.after {
            Some((k, t)) => format!("after step {k} (load factor {t:.6}): {}", self.reason),
            None => format!("before any state converged: {}", self.reason),
        }
    }

    /// The block of the text reports: "STOPPED after step K …", then what to try.
    pub fn text(&self) -> String {
        let mut s = format!("\nSTOPPED {}\n", self.place());
        if let Some(h) = &self.hint {
            s += &format!("  what to try: {h}\n");
        }
        s
    }

    /// A comment line for the end of a CSV file (readers skip it with their comment option,
    /// e.g. pandas `comment='#'`).
    pub fn csv_comment(&self) -> String {
        let mut s = format!("# {}", self.line());
        if let Some(h) = &self.hint {
            s += &format!("; what to try: {h}");
        }
        s.replace(['\n', '\r'], " ") + "\n"
    }

    /// The JSON object: `after_step`, `load_factor` (null when no state converged), `reason`,
    /// `what_to_try` (null when unknown).
    pub fn json(&self) -> Value {
        json!({
            "after_step": self.after.map(|a| a.0),
            "load_factor": self.after.map(|a| a.1),
            "reason": self.reason,
            "what_to_try": self.hint,
        })
    }
}

/// The `stopped` field of a JSON document: the note, or null for a complete path.
pub fn json_field(note: Option<&StopNote>) -> Value {
    note.map_or(Value::Null, StopNote::json)
}
