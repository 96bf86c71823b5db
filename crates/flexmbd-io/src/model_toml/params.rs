//! `[parameters]` and the values written as expressions of them (docs/model-format.md,
//! "Parameters and expressions"): the parameter table evaluated in file order with the
//! overrides of the caller, and every real value of the file ([`Real`]) evaluated with it.
//! Errors name file, line, column (in the expression) and item.

use super::expr::{eval, is_builtin, is_name, ExprError};
use super::schema::{Real, RealValue};
use super::spans::name_item;
use crate::error::{at, InputError};
use indexmap::IndexMap;
use std::ops::Range;
use toml::Spanned;

/// The evaluated parameters of a file, and what evaluates its values.
pub(super) struct Params<'a> {
    text: &'a str,
    file: &'a str,
    /// Name → value, in file order.
    pub(super) values: IndexMap<String, f64>,
}

impl<'a> Params<'a> {
    /// Evaluate `[parameters]` in file order; a name in `set` takes the value given there
    /// instead of the file's (its dependents follow). A name of `set` the file does not
    /// declare is an error listing those it does.
    pub(super) fn read(
        table: Option<&IndexMap<String, Spanned<toml::Value>>>,
        set: &[(String, f64)],
        text: &'a str,
        file: &'a str,
    ) -> Result<Self, InputError> {
        let mut p = Params {
            text,
            file,
            values: IndexMap::new(),
        };
        let mut entries: Vec<(&String, &Spanned<toml::Value>)> =
            table.into_iter().flatten().collect();
        entries.sort_by_key(|(_, v)| v.span().start);
        let declared: Vec<&str> = entries.iter().map(|(k, _)| k.as_str()).collect();
        for (name, v) in &entries {
            let span = v.span();
            let bad = |msg: String| p.error(span.start, format!("parameter `{name}`: {msg}"));
            if !is_name(name) {
                return Err(bad(
                    "a parameter name is a letter or `_` followed by letters, digits or `_`".into(),
                ));
            }
            if is_builtin(name) {
                return Err(bad(format!(
                    "`{name}` is a built-in function or constant; choose another name"
                )));
            }
            let value = match set.iter().rev().find(|(k, _)| k == *name) {
                Some((_, x)) => *x,
                None => match v.get_ref() {
                    toml::Value::Float(x) if x.is_finite() => *x,
                    toml::Value::Float(x) => return Err(bad(format!("{x} is not finite"))),
                    toml::Value::Integer(k) => *k as f64,
                    toml::Value::String(s) => p.eval_at(s, string_start(text, &span), |u| {
                        declared.contains(&u).then(|| {
                            format!(
                                "`{u}` is declared after `{name}`; a parameter may use only those above it"
                            )
                        })
                    })?,
                    other => {
                        return Err(bad(format!(
                            "expected a number or an expression in a string, found {}",
                            other.type_str()
                        )))
                    }
                },
            };
            p.values.insert(name.to_string(), value);
        }
        if let Some((name, _)) = set.iter().find(|(k, _)| !p.values.contains_key(k)) {
            return Err(InputError::File {
                file: file.into(),
                message: format!(
                    "cannot set parameter `{name}`: the model does not declare it; {}",
                    p.declared()
                ),
            });
        }
        Ok(p)
    }

    /// "the parameters are: a, b" or that there are none.
    fn declared(&self) -> String {
        if self.values.is_empty() {
            "the model declares no parameters ([parameters])".into()
        } else {
            let names: Vec<&str> = self.values.keys().map(String::as_str).collect();
            format!("the parameters are: {}", names.join(", "))
        }
    }

    /// An error at byte `offset`, naming the item there.
    fn error(&self, offset: usize, msg: String) -> InputError {
        at(
            self.file,
            self.text,
            offset,
            name_item(self.text, offset, msg),
        )
    }

    /// Evaluate expression `expr` written at byte `start` of the text (its first character);
    /// `unknown` may explain a name that is not a parameter (else the parameters are listed).
    fn eval_at(
        &self,
        expr: &str,
        start: usize,
        unknown: impl Fn(&str) -> Option<String>,
    ) -> Result<f64, InputError> {
        eval(expr, &|n| self.values.get(n).copied()).map_err(|e: ExprError| {
            let why = match &e.unknown {
                Some(u) => {
                    unknown(u).unwrap_or_else(|| format!("{}; {}", e.message, self.declared()))
                }
                None => e.message,
            };
            self.error(
                start + e.offset.min(expr.len()),
                format!("in \"{expr}\": {why}"),
            )
        })
    }

    /// A real value of the file.
    pub(super) fn real(&self, r: &Real) -> Result<f64, InputError> {
        match &r.value {
            RealValue::Num(x) => Ok(*x),
            RealValue::Expr(s) => self.eval_at(s, string_start(self.text, &r.span), |_| None),
        }
    }

    /// An optional real value.
    pub(super) fn opt(&self, r: &Option<Real>) -> Result<Option<f64>, InputError> {
        r.as_ref().map(|r| self.real(r)).transpose()
    }

    /// A list of real values.
    pub(super) fn arr<const N: usize>(&self, r: &[Real; N]) -> Result<[f64; N], InputError> {
        let mut out = [0.0; N];
        for (o, x) in out.iter_mut().zip(r) {
            *o = self.real(x)?;
        }
        Ok(out)
    }

    /// An optional list of real values.
    pub(super) fn opt_arr<const N: usize>(
        &self,
        r: &Option<[Real; N]>,
    ) -> Result<Option<[f64; N]>, InputError> {
        r.as_ref().map(|r| self.arr(r)).transpose()
    }

    /// An expression inside a value read without the places of its parts (a node's position):
    /// found in the text of the value (`within`), else at the value's start.
    pub(super) fn expr_in(&self, expr: &str, within: &Range<usize>) -> Result<f64, InputError> {
        let end = within.end.min(self.text.len());
        let start = within.start.min(end);
        let offset = [format!("\"{expr}\""), format!("'{expr}'")]
            .iter()
            .filter_map(|q| self.text[start..end].find(q.as_str()))
            .min()
            .map_or(start, |i| start + i + 1);
        self.eval_at(expr, offset, |_| None)
    }
}

/// The offset of the first character of the string value at `span` (after its quotes).
fn string_start(text: &str, span: &Range<usize>) -> usize {
    let s = text.get(span.clone()).unwrap_or_default();
    let quotes = if s.starts_with("\"\"\"") || s.starts_with("'''") {
        3
    } else {
        usize::from(s.starts_with('"') || s.starts_with('\''))
    };
    span.start + quotes
}
