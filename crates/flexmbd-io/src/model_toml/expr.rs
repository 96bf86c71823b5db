//! Expressions of model values (docs/model-format.md, "Parameters and expressions"): a small
//! recursive-descent evaluator of real arithmetic over named parameters.
//!
//! ```text
//! expr    = term { ("+" | "-") term }
//! term    = unary { ("*" | "/") unary }
//! unary   = ("-" | "+") unary | power
//! power   = primary [ "^" unary ]            right-associative: 2^3^2 = 2^9
//! primary = number | name | name "(" expr { "," expr } ")" | "(" expr ")"
//! ```
//!
//! Numbers as in TOML and Rust (`2`, `1e-3`, `.5`, `2.5E+3`); names `[A-Za-z_][A-Za-z0-9_]*`.
//! Unary minus binds weaker than `^` (`-2^2` = -4). Functions: sin cos tan asin acos atan
//! atan2 sqrt abs exp ln log10 min max; constants `pi` and `deg` (= pi/180, so `30*deg` is 30°
//! in radians). A division by zero or a result that is not finite is an error.

/// An expression that cannot be evaluated: what, and where in the expression (byte offset).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct ExprError {
    /// Byte offset of the problem in the expression.
    pub offset: usize,
    /// What is wrong.
    pub message: String,
    /// The name that is not defined, for an unknown name (the caller lists the defined ones).
    pub unknown: Option<String>,
}

/// The functions of the language with their number of arguments (`None`: one or more).
const FUNCTIONS: [(&str, Option<usize>); 14] = [
    ("sin", Some(1)),
    ("cos", Some(1)),
    ("tan", Some(1)),
    ("asin", Some(1)),
    ("acos", Some(1)),
    ("atan", Some(1)),
    ("atan2", Some(2)),
    ("sqrt", Some(1)),
    ("abs", Some(1)),
    ("exp", Some(1)),
    ("ln", Some(1)),
    ("log10", Some(1)),
    ("min", None),
    ("max", None),
];

/// The constants of the language.
const CONSTANTS: [(&str, f64); 2] = [
    ("pi", std::f64::consts::PI),
    ("deg", std::f64::consts::PI / 180.0),
];

/// True for a built-in function or constant name (a parameter may not have it).
pub fn is_builtin(name: &str) -> bool {
    FUNCTIONS.iter().any(|(f, _)| *f == name) || CONSTANTS.iter().any(|(c, _)| *c == name)
}

/// True for a name of the language: `[A-Za-z_][A-Za-z0-9_]*`.
pub fn is_name(name: &str) -> bool {
    let mut c = name.chars();
    c.next()
        .is_some_and(|f| f.is_ascii_alphabetic() || f == '_')
        && c.all(|x| x.is_ascii_alphanumeric() || x == '_')
}

/// Evaluate `text`; `lookup` gives the value of a name that is not built in.
pub fn eval(text: &str, lookup: &dyn Fn(&str) -> Option<f64>) -> Result<f64, ExprError> {
    let mut p = Parser {
        s: text.as_bytes(),
        i: 0,
        lookup,
    };
    p.skip();
    if p.i == p.s.len() {
        return Err(p.err(0, "the expression is empty".into()));
    }
    let v = p.expr()?;
    p.skip();
    if p.i < p.s.len() {
        return Err(p.err(p.i, format!("unexpected `{}`", p.s[p.i..].escape_ascii())));
    }
    Ok(v)
}

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
    lookup: &'a dyn Fn(&str) -> Option<f64>,
}

impl Parser<'_> {
    fn err(&self, offset: usize, message: String) -> ExprError {
        ExprError {
            offset,
            message,
            unknown: None,
        }
    }

    fn skip(&mut self) {
        while self.s.get(self.i).is_some_and(u8::is_ascii_whitespace) {
            self.i += 1;
        }
    }

    /// The next byte after blanks (not consumed).
    fn peek(&mut self) -> Option<u8> {
        self.skip();
        self.s.get(self.i).copied()
    }

    /// `v` unless it is not finite (an error at `at` naming `what`).
    fn finite(&self, v: f64, at: usize, what: &str) -> Result<f64, ExprError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(at, format!("{what} is not finite ({v})")))
        }
    }

    fn expr(&mut self) -> Result<f64, ExprError> {
        let mut v = self.term()?;
        while let Some(op @ (b'+' | b'-')) = self.peek() {
            let at = self.i;
            self.i += 1;
            let r = self.term()?;
            v = if op == b'+' { v + r } else { v - r };
            v = self.finite(v, at, "the result")?;
        }
        Ok(v)
    }

    fn term(&mut self) -> Result<f64, ExprError> {
        let mut v = self.unary()?;
        while let Some(op @ (b'*' | b'/')) = self.peek() {
            let at = self.i;
            self.i += 1;
            let r = self.unary()?;
            if op == b'/' && r == 0.0 {
                return Err(self.err(at, "division by zero".into()));
            }
            v = if op == b'*' { v * r } else { v / r };
            v = self.finite(v, at, "the result")?;
        }
        Ok(v)
    }

    fn unary(&mut self) -> Result<f64, ExprError> {
        match self.peek() {
            Some(b'-') => {
                self.i += 1;
                Ok(-self.unary()?)
            }
            Some(b'+') => {
                self.i += 1;
                self.unary()
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<f64, ExprError> {
        let base = self.primary()?;
        if self.peek() != Some(b'^') {
            return Ok(base);
        }
        let at = self.i;
        self.i += 1;
        let exponent = self.unary()?;
        self.finite(base.powf(exponent), at, "the power")
    }

    fn primary(&mut self) -> Result<f64, ExprError> {
        let start = self.i;
        match self.peek() {
            None => Err(self.err(self.s.len(), "the expression ends too early".into())),
            Some(b'(') => {
                self.i += 1;
                let v = self.expr()?;
                self.expect(b')', start)?;
                Ok(v)
            }
            Some(c) if c.is_ascii_digit() || c == b'.' => self.number(),
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => self.name(),
            Some(_) => {
                let at = self.i;
                let c = self.s[at..].iter().take(1).copied().collect::<Vec<u8>>();
                Err(self.err(at, format!("unexpected `{}`", c.escape_ascii())))
            }
        }
    }

    /// `c`, or an error (the group opened at `open`).
    fn expect(&mut self, c: u8, open: usize) -> Result<(), ExprError> {
        if self.peek() == Some(c) {
            self.i += 1;
            return Ok(());
        }
        let found = match self.s.get(self.i) {
            Some(x) => format!("found `{}`", [*x].escape_ascii()),
            None => "the expression ends".into(),
        };
        Err(self.err(
            self.i,
            format!(
                "expected `{}` to close the `(` at character {}, {found}",
                c as char,
                open + 1
            ),
        ))
    }

    fn number(&mut self) -> Result<f64, ExprError> {
        let start = self.i;
        let digits = |p: &mut Self| {
            while p
                .s
                .get(p.i)
                .is_some_and(|c| c.is_ascii_digit() || *c == b'.')
            {
                p.i += 1;
            }
        };
        digits(self);
        if matches!(self.s.get(self.i), Some(b'e' | b'E')) {
            let mut j = self.i + 1;
            if matches!(self.s.get(j), Some(b'+' | b'-')) {
                j += 1;
            }
            if self.s.get(j).is_some_and(u8::is_ascii_digit) {
                self.i = j;
                digits(self);
            }
        }
        let text = std::str::from_utf8(&self.s[start..self.i]).unwrap_or_default();
        text.parse::<f64>()
            .map_err(|_| self.err(start, format!("`{text}` is not a number")))
    }

    fn name(&mut self) -> Result<f64, ExprError> {
        let start = self.i;
        while self
            .s
            .get(self.i)
            .is_some_and(|c| c.is_ascii_alphanumeric() || *c == b'_')
        {
            self.i += 1;
        }
        let name = std::str::from_utf8(&self.s[start..self.i]).unwrap_or_default();
        if let Some((_, arity)) = FUNCTIONS.iter().find(|(f, _)| *f == name) {
            return self.call(name, *arity, start);
        }
        if self.peek() == Some(b'(') {
            return Err(self.err(start, format!("unknown function `{name}`")));
        }
        if let Some((_, v)) = CONSTANTS.iter().find(|(c, _)| *c == name) {
            return Ok(*v);
        }
        (self.lookup)(name).ok_or_else(|| ExprError {
            offset: start,
            message: format!("unknown name `{name}`"),
            unknown: Some(name.to_string()),
        })
    }

    /// A function call `name(args)`; `arity` `None` takes one or more.
    fn call(&mut self, name: &str, arity: Option<usize>, start: usize) -> Result<f64, ExprError> {
        if self.peek() != Some(b'(') {
            return Err(self.err(
                start,
                format!("`{name}` is a function: write `{name}(...)`"),
            ));
        }
        let open = self.i;
        self.i += 1;
        let mut args = vec![self.expr()?];
        while self.peek() == Some(b',') {
            self.i += 1;
            args.push(self.expr()?);
        }
        self.expect(b')', open)?;
        if arity.is_some_and(|n| n != args.len()) {
            return Err(self.err(
                start,
                format!(
                    "`{name}` takes {} argument{}, found {}",
                    arity.unwrap_or(1),
                    if arity == Some(1) { "" } else { "s" },
                    args.len()
                ),
            ));
        }
        let a = args[0];
        let v = match name {
            "sin" => a.sin(),
            "cos" => a.cos(),
            "tan" => a.tan(),
            "asin" => a.asin(),
            "acos" => a.acos(),
            "atan" => a.atan(),
            "atan2" => a.atan2(args[1]),
            "sqrt" => a.sqrt(),
            "abs" => a.abs(),
            "exp" => a.exp(),
            "ln" => a.ln(),
            "log10" => a.log10(),
            "min" => args.iter().copied().fold(a, f64::min),
            _ => args.iter().copied().fold(a, f64::max),
        };
        self.finite(v, start, &format!("`{name}(...)`"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(s: &str) -> Result<f64, ExprError> {
        eval(s, &|n| match n {
            "t" => Some(2e-4),
            "L" => Some(0.05),
            _ => None,
        })
    }

    fn close(a: f64, b: f64) {
        assert!((a - b).abs() <= 1e-15 * b.abs().max(1.0), "{a} != {b}");
    }

    #[test]
    fn numbers() {
        close(ev("1e-3").unwrap(), 0.001);
        close(ev(".5").unwrap(), 0.5);
        close(ev("2.5E+3").unwrap(), 2500.0);
        close(ev("  7 ").unwrap(), 7.0);
        close(ev("3.").unwrap(), 3.0);
    }

    #[test]
    fn precedence_and_associativity() {
        // hand-computed: 1 + 2*3 = 7; (1+2)*3 = 9; 2^3^2 = 2^9 = 512; -2^2 = -4;
        // 8/4/2 = 1 (left-assoc); 10-4-3 = 3; 2^-1 = 0.5; -(-3) = 3
        close(ev("1 + 2*3").unwrap(), 7.0);
        close(ev("(1+2)*3").unwrap(), 9.0);
        close(ev("2^3^2").unwrap(), 512.0);
        close(ev("-2^2").unwrap(), -4.0);
        close(ev("8/4/2").unwrap(), 1.0);
        close(ev("10-4-3").unwrap(), 3.0);
        close(ev("2^-1").unwrap(), 0.5);
        close(ev("--3").unwrap(), 3.0);
        close(ev("2*-3").unwrap(), -6.0);
    }

    #[test]
    fn names_functions_constants() {
        // L/2 = 0.025; t^3*L = 8e-12*0.05 = 4e-13; 30° = pi/6, sin = 1/2; cos(60°) = 1/2;
        // atan2(1, 1) = pi/4; sqrt(2)^2 = 2; ln(exp(1.5)) = 1.5; log10(1000) = 3
        close(ev("L/2").unwrap(), 0.025);
        close(ev("t^3*L").unwrap(), 4e-13);
        close(ev("sin(30*deg)").unwrap(), 0.5);
        close(ev("cos(60*deg)").unwrap(), 0.5);
        close(ev("atan2(1, 1)").unwrap(), std::f64::consts::FRAC_PI_4);
        close(ev("sqrt(2)^2").unwrap(), 2.0);
        close(ev("ln(exp(1.5))").unwrap(), 1.5);
        close(ev("log10(1000)").unwrap(), 3.0);
        close(ev("abs(-2) + min(3, 1, 2) + max(4, 5)").unwrap(), 8.0);
        close(ev("asin(1)").unwrap(), std::f64::consts::FRAC_PI_2);
        close(
            ev("acos(0) + atan(1) + tan(0)").unwrap(),
            0.75 * std::f64::consts::PI,
        );
        close(ev("180*deg").unwrap(), std::f64::consts::PI);
    }

    #[test]
    fn errors_with_positions() {
        let e = ev("L/0").unwrap_err();
        assert_eq!((e.offset, e.message.as_str()), (1, "division by zero"));
        let e = ev("2*h + 1").unwrap_err();
        assert_eq!((e.offset, e.unknown.as_deref()), (2, Some("h")));
        let e = ev("sqrt(-1)").unwrap_err();
        assert_eq!(e.offset, 0);
        assert!(e.message.contains("not finite"), "{}", e.message);
        let e = ev("(1 + 2").unwrap_err();
        assert_eq!(e.offset, 6);
        assert!(e.message.contains("expected `)`"), "{}", e.message);
        let e = ev("1 + * 2").unwrap_err();
        assert_eq!(e.offset, 4);
        let e = ev("1 2").unwrap_err();
        assert_eq!(e.offset, 2);
        let e = ev("").unwrap_err();
        assert!(e.message.contains("empty"));
        let e = ev("atan2(1)").unwrap_err();
        assert!(e.message.contains("takes 2 arguments"), "{}", e.message);
        let e = ev("foo(1)").unwrap_err();
        assert!(
            e.message.contains("unknown function `foo`"),
            "{}",
            e.message
        );
        let e = ev("sin").unwrap_err();
        assert!(e.message.contains("is a function"), "{}", e.message);
        let e = ev("exp(1000)").unwrap_err();
        assert!(e.message.contains("not finite"), "{}", e.message);
        let e = ev("1.2.3").unwrap_err();
        assert!(e.message.contains("not a number"), "{}", e.message);
        let e = ev("10^400").unwrap_err();
        assert_eq!(e.offset, 2);
    }

    #[test]
    fn names_and_builtins() {
        assert!(is_name("t_1") && is_name("_x") && is_name("L"));
        assert!(!is_name("1t") && !is_name("a.b") && !is_name("") && !is_name("a-b"));
        assert!(is_builtin("pi") && is_builtin("deg") && is_builtin("sin"));
        assert!(!is_builtin("t"));
    }
}
