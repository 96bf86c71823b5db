//! The global `--set NAME=VALUE` (docs/model-format.md, "Parameters and expressions"): the
//! overrides every command reads its model with, and the parameter values the model was
//! evaluated with, stated in the outputs on stdout (a `parameters:` line under the title of a
//! text report, a `"parameters"` object in a JSON document). A model without parameters read
//! without `--set` gives the outputs it always gave.

use crate::BadInput;
use std::path::Path;
use std::sync::{Mutex, OnceLock};

static SET: OnceLock<Vec<(String, f64)>> = OnceLock::new();
static USED: Mutex<Vec<(String, f64)>> = Mutex::new(Vec::new());

/// Parse `NAME=VALUE`: VALUE is a number or an expression of numbers and the constants `pi`
/// and `deg` (`30*deg`).
pub fn parse_set(s: &str) -> Result<(String, f64), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("expected NAME=VALUE (t=0.2e-3), found `{s}`"))?;
    let name = name.trim();
    if name.is_empty() || name.split('.').any(str::is_empty) {
        return Err(format!(
            "expected NAME=VALUE with a parameter name or a path of keys (sections.sheet.t), found `{s}`"
        ));
    }
    let v = flexmbd_io::model_toml::expr::eval(value, &|_| None)
        .map_err(|e| format!("`{name}`: the value `{}`: {e}", value.trim()))?;
    Ok((name.to_string(), v))
}

/// Set by the global `--set` options.
pub fn set_overrides(set: Vec<(String, f64)>) {
    let _ = SET.set(set);
}

fn overrides() -> &'static [(String, f64)] {
    SET.get().map_or(&[], Vec::as_slice)
}

/// Read a TOML model file with the overrides, and remember the values used.
pub fn read_toml(path: &Path) -> anyhow::Result<flexmbd_io::ModelFile> {
    let file = path.display().to_string();
    let spec =
        flexmbd_io::read_spec_with(path, overrides()).map_err(|e| BadInput(e.to_string()))?;
    let mut used: Vec<(String, f64)> = spec
        .parameters
        .iter()
        .map(|(k, v)| (k.clone(), *v))
        .collect();
    used.extend(overrides().iter().filter(|(k, _)| k.contains('.')).cloned());
    *USED.lock().unwrap_or_else(|e| e.into_inner()) = used;
    spec.build_file()
        .map_err(|e| BadInput(flexmbd_io::model_toml::spec_error(e, &file).to_string()).into())
}

/// A SPACAR file takes no overrides.
pub fn refuse_for_dat(path: &Path) -> anyhow::Result<()> {
    match overrides().first() {
        None => Ok(()),
        Some((name, _)) => Err(BadInput(format!(
            "{}: --set {name}: parameters and overrides are a feature of TOML models; convert the SPACAR file first (flexmbd convert {} MODEL.toml) and declare [parameters] there",
            path.display(),
            path.display()
        ))
        .into()),
    }
}

/// `text` for stdout with the parameter values used: after the title line of a report
/// (`flexmbd …`), as the first key of a JSON document, or as a first line.
pub fn mark(text: &str) -> std::borrow::Cow<'_, str> {
    let used = USED.lock().unwrap_or_else(|e| e.into_inner());
    if used.is_empty() {
        return text.into();
    }
    if let Some(rest) = text.strip_prefix("{\n") {
        return format!("{}{rest}", json_head(&used)).into();
    }
    let items: Vec<String> = used.iter().map(|(k, v)| format!("{k} = {v:?}")).collect();
    let line = format!("parameters: {}\n", items.join(", "));
    match text.split_once('\n') {
        Some((title, rest)) if title.starts_with("flexmbd ") => {
            format!("{title}\n{line}{rest}").into()
        }
        _ => format!("{line}{text}").into(),
    }
}

/// The opening of a marked JSON document ([`mark`]): the brace and the parameters `used` as its
/// first member.
fn json_head(used: &[(String, f64)]) -> String {
    let map: serde_json::Map<String, serde_json::Value> = used
        .iter()
        .map(|(k, v)| (k.clone(), serde_json::Value::from(*v)))
        .collect();
    format!(
        "{{\n  \"parameters\": {},\n",
        serde_json::Value::Object(map)
    )
}

/// A writer that marks a JSON document as [`mark`] does while it is written: the parameters go
/// in after its opening "{\n", so that a document is never held whole to be marked (the modes
/// of 10⁵ beams are 0.8 GB of text).
pub struct Marked<W: std::io::Write> {
    inner: W,
    /// What the marked document starts with, while its first two bytes are awaited.
    head: Option<String>,
    seen: Vec<u8>,
}

impl<W: std::io::Write> Marked<W> {
    pub fn new(inner: W) -> Self {
        Self {
            inner,
            head: {
                let used = USED.lock().unwrap_or_else(|e| e.into_inner());
                (!used.is_empty()).then(|| json_head(&used))
            },
            seen: Vec::new(),
        }
    }

    /// The first two bytes are in (or the document ended): the head in place of "{\n", or
    /// what came.
    fn settle(&mut self) -> std::io::Result<()> {
        if let Some(head) = self.head.take() {
            if self.seen == b"{\n" {
                self.inner.write_all(head.as_bytes())?;
            } else {
                self.inner.write_all(&self.seen)?;
            }
            self.seen.clear();
        }
        Ok(())
    }
}

impl<W: std::io::Write> std::io::Write for Marked<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if self.head.is_none() {
            return self.inner.write(buf);
        }
        let take = (2 - self.seen.len()).min(buf.len());
        self.seen.extend_from_slice(&buf[..take]);
        if self.seen.len() == 2 {
            self.settle()?;
        }
        Ok(take)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.settle()?;
        self.inner.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::parse_set;

    #[test]
    fn set_values() {
        assert_eq!(parse_set("t=2e-4"), Ok(("t".into(), 2e-4)));
        assert_eq!(parse_set(" L = 0.5*0.2 "), Ok(("L".into(), 0.1)));
        // 180° = pi
        assert_eq!(
            parse_set("sections.s.t=180*deg"),
            Ok(("sections.s.t".into(), std::f64::consts::PI))
        );
        assert!(parse_set("t").is_err());
        assert!(parse_set("=1").is_err());
        assert!(parse_set("a..b=1").is_err());
        assert!(parse_set("t=abc")
            .unwrap_err()
            .contains("unknown name `abc`"));
    }
}
