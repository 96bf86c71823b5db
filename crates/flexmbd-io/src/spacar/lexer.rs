//! Lines, fields and numbers of a SPACAR `.dat` file.
//!
//! Free format (spacar-format.md §2): fields are separated by blanks, tabs or commas; `#`, `%`
//! and `;` start a comment that runs to the end of the line. Numbers accept any floating-point
//! syntax, including the Fortran exponent letter `d` (`1.5d-3`); non-finite values (`NaN`,
//! `inf`, or `1e999`, which overflows) are errors.

use crate::error::{at_line, InputError};

/// One field of a line.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Token<'a> {
    /// The text.
    pub text: &'a str,
    /// 1-based column (in characters).
    pub col: usize,
}

/// A data line: its fields (keyword first) and the comment after them.
#[derive(Debug)]
pub(crate) struct Line<'a> {
    /// 1-based line number.
    pub no: usize,
    /// Fields, keyword first; empty for a blank or comment-only line.
    pub tokens: Vec<Token<'a>>,
    /// Comment text after the comment character, trimmed; `None` if the line has none.
    pub comment: Option<&'a str>,
    /// Column just after the last character of the data part (for "missing field" errors).
    pub end_col: usize,
}

fn is_comment_char(c: char) -> bool {
    matches!(c, '#' | '%' | ';')
}

fn is_separator(c: char) -> bool {
    c.is_whitespace() || c == ','
}

/// Split one line (without its newline) into fields and comment.
pub(crate) fn split_line(no: usize, raw: &str) -> Line<'_> {
    let mut tokens = Vec::with_capacity(12);
    let mut comment = None;
    let mut start: Option<(usize, usize)> = None; // (byte, col)
    let mut col = 0;
    let mut end_col = 1;
    for (b, c) in raw.char_indices() {
        col += 1;
        if is_comment_char(c) {
            if let Some((sb, sc)) = start.take() {
                tokens.push(Token {
                    text: &raw[sb..b],
                    col: sc,
                });
            }
            comment = Some(raw[b + c.len_utf8()..].trim());
            break;
        }
        if is_separator(c) {
            if let Some((sb, sc)) = start.take() {
                tokens.push(Token {
                    text: &raw[sb..b],
                    col: sc,
                });
            }
        } else {
            if start.is_none() {
                start = Some((b, col));
            }
            end_col = col + 1;
        }
    }
    if comment.is_none() {
        if let Some((sb, sc)) = start {
            tokens.push(Token {
                text: &raw[sb..],
                col: sc,
            });
        }
    }
    Line {
        no,
        tokens,
        comment,
        end_col,
    }
}

/// The lines of a file: `\n`, `\r\n` or `\r` (old Mac) line ends, a leading byte-order mark
/// ignored.
pub(crate) fn lines(text: &str) -> impl Iterator<Item = Line<'_>> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut rest = Some(text);
    std::iter::from_fn(move || {
        let t = rest?;
        match t.find(['\n', '\r']) {
            Some(i) => {
                let end = if t[i..].starts_with("\r\n") {
                    i + 2
                } else {
                    i + 1
                };
                rest = Some(&t[end..]);
                Some(&t[..i])
            }
            None => {
                rest = None;
                Some(t)
            }
        }
    })
    .enumerate()
    .map(|(i, l)| split_line(i + 1, l))
}

/// Parse a floating-point field: any Rust float syntax plus a Fortran `d` exponent; finite only.
pub(crate) fn parse_float(s: &str) -> Result<f64, String> {
    let owned;
    let t = if s.contains(['d', 'D']) && !s.contains(['e', 'E']) {
        owned = s.replace(['d', 'D'], "e");
        owned.as_str()
    } else {
        s
    };
    // Rust also accepts "inf", "nan" and "infinity": the finiteness test below rejects them
    let v: f64 = t
        .parse()
        .map_err(|_| format!("expected a number, found `{}`", s.escape_debug()))?;
    if !v.is_finite() {
        return Err(format!("the number `{}` is not finite", s.escape_debug()));
    }
    Ok(v)
}

/// Parse a whole-number field.
pub(crate) fn parse_int(s: &str) -> Result<i64, String> {
    let digits = s.strip_prefix(['+', '-']).unwrap_or(s);
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return Err(format!(
            "expected a whole number, found `{}`",
            s.escape_debug()
        ));
    }
    s.parse::<i64>()
        .map_err(|_| format!("the number `{s}` is too large"))
}

/// The keyword of a line as the parser matches it: upper case, special characters escaped.
/// Borrowed when the file writes it in upper case already (the usual case: no allocation per
/// line of a model of 10^5 elements).
pub(crate) fn keyword<'l>(token: &'l str) -> std::borrow::Cow<'l, str> {
    if token
        .bytes()
        .all(|b| b.is_ascii_uppercase() || b.is_ascii_digit() || b == b'_')
    {
        std::borrow::Cow::Borrowed(token)
    } else {
        std::borrow::Cow::Owned(token.escape_debug().to_string().to_ascii_uppercase())
    }
}

/// Reads the fields of one keyword line, with errors at the field's column.
pub(crate) struct Fields<'a, 'l> {
    file: &'a str,
    line: &'l Line<'l>,
    /// The number of the item the line defines, once read: messages name the item as
    /// "BEAM" before and "BEAM 3" after ([`Fields::named`]).
    number: Option<u32>,
    pos: usize,
}

impl<'a, 'l> Fields<'a, 'l> {
    /// The fields after the keyword.
    pub fn new(file: &'a str, line: &'l Line<'l>) -> Self {
        Self {
            file,
            line,
            number: None,
            pos: 1,
        }
    }

    /// From here on, messages name the item with its number (`BEAM 3`).
    pub fn named(&mut self, number: u32) {
        self.number = Some(number);
    }

    /// Name of the item for messages, e.g. "BEAM" or "BEAM 3".
    pub fn item(&self) -> String {
        let kw = keyword(self.line.tokens[0].text);
        match self.number {
            Some(n) => format!("{kw} {n}"),
            None => kw.into_owned(),
        }
    }

    /// An error at the current field (or at the end of the line).
    pub fn err_here(&self, msg: impl std::fmt::Display) -> InputError {
        let col = self
            .line
            .tokens
            .get(self.pos)
            .map_or(self.line.end_col, |t| t.col);
        at_line(
            self.file,
            self.line.no,
            col,
            format!("{}: {msg}", self.item()),
        )
    }

    /// An error at field `i` (0 = keyword).
    pub fn err_at(&self, i: usize, msg: impl std::fmt::Display) -> InputError {
        let col = self.line.tokens.get(i).map_or(self.line.end_col, |t| t.col);
        at_line(
            self.file,
            self.line.no,
            col,
            format!("{}: {msg}", self.item()),
        )
    }

    /// Number of fields not read yet.
    pub fn remaining(&self) -> usize {
        self.line.tokens.len().saturating_sub(self.pos)
    }

    fn next_token(&mut self, what: &str) -> Result<&'l str, InputError> {
        match self.line.tokens.get(self.pos) {
            Some(t) => {
                self.pos += 1;
                Ok(t.text)
            }
            None => Err(self.err_here(format!("missing {what}"))),
        }
    }

    /// A whole number ≥ 1 (node, element, mode or coordinate number).
    pub fn positive(&mut self, what: &str) -> Result<u32, InputError> {
        let t = self.next_token(what)?;
        let v = parse_int(t).map_err(|m| self.back_err(format!("{what}: {m}")))?;
        if v < 1 || v > u32::MAX as i64 {
            return Err(self.back_err(format!(
                "{what} must be a whole number ≥ 1, found `{}`",
                t.escape_debug()
            )));
        }
        Ok(v as u32)
    }

    /// A finite floating-point number.
    pub fn float(&mut self, what: &str) -> Result<f64, InputError> {
        let t = self.next_token(what)?;
        parse_float(t).map_err(|m| self.back_err(format!("{what}: {m}")))
    }

    /// A word (e.g. a routine name).
    pub fn word(&mut self, what: &str) -> Result<String, InputError> {
        Ok(self.next_token(what)?.to_string())
    }

    /// All remaining fields as whole numbers ≥ 1.
    pub fn rest_positive(&mut self, what: &str) -> Result<Vec<u32>, InputError> {
        let mut v = Vec::with_capacity(self.remaining());
        while self.remaining() > 0 {
            v.push(self.positive(what)?);
        }
        Ok(v)
    }

    /// All remaining fields as finite numbers.
    pub fn rest_floats(&mut self, what: &str) -> Result<Vec<f64>, InputError> {
        let mut v = Vec::with_capacity(self.remaining());
        while self.remaining() > 0 {
            v.push(self.float(what)?);
        }
        Ok(v)
    }

    /// Error if fields are left over.
    pub fn done(&self) -> Result<(), InputError> {
        if self.remaining() > 0 {
            return Err(self.err_here(format!(
                "unexpected extra field `{}`",
                self.line.tokens[self.pos].text.escape_debug()
            )));
        }
        Ok(())
    }

    /// Error at the field just read.
    fn back_err(&self, msg: String) -> InputError {
        self.err_at(self.pos - 1, msg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splits_fields_and_comments() {
        let l = split_line(3, "X\t 1  0.5,-2 3 #node 1");
        let t: Vec<_> = l.tokens.iter().map(|t| (t.text, t.col)).collect();
        assert_eq!(t, [("X", 1), ("1", 4), ("0.5", 7), ("-2", 11), ("3", 14)]);
        assert_eq!(l.comment, Some("node 1"));
        let l = split_line(1, "TIMESTEP 1.2 8000 % time");
        assert_eq!(l.tokens.len(), 3);
        assert_eq!(l.comment, Some("time"));
        let l = split_line(1, "   ");
        assert!(l.tokens.is_empty() && l.comment.is_none());
        let l = split_line(1, "COLOR 1 2 3;x");
        assert_eq!(l.tokens.len(), 4);
    }

    #[test]
    fn line_ends() {
        // LF, CRLF and CR (old Mac) are all line ends; a CR-only file is not one comment
        for text in [
            "#t\nX 1 0 0 0\nEND",
            "#t\r\nX 1 0 0 0\r\nEND",
            "#t\rX 1 0 0 0\rEND",
        ] {
            let l: Vec<_> = lines(text).collect();
            assert_eq!(l.len(), 3, "{text:?}");
            assert_eq!(l[1].no, 2);
            assert_eq!(l[1].tokens.len(), 5);
            assert_eq!(l[2].tokens[0].text, "END");
        }
        assert_eq!(lines("a\r\rb").count(), 3);
        assert_eq!(lines("a\n").count(), 2);
    }

    #[test]
    fn numbers() {
        assert_eq!(parse_float("0.").unwrap(), 0.0);
        assert_eq!(parse_float("-.5").unwrap(), -0.5);
        assert_eq!(parse_float("1.5d-3").unwrap(), 1.5e-3);
        assert_eq!(parse_float("2D2").unwrap(), 200.0);
        assert!(parse_float("1e999").is_err());
        assert!(parse_float("NaN").is_err());
        assert!(parse_float("inf").is_err());
        assert!(parse_float("abc").is_err());
        assert_eq!(parse_int("+12").unwrap(), 12);
        assert!(parse_int("1.0").is_err());
        assert!(parse_int("99999999999999999999").is_err());
        assert!(parse_int("").is_err());
    }

    #[test]
    fn crlf_and_bom() {
        let v: Vec<_> = lines("\u{feff}X 1 0 0 0\r\nEND\r\n").collect();
        assert_eq!(v[0].tokens[0].text, "X");
        assert_eq!(v[1].tokens[0].text, "END");
        assert_eq!(v[1].no, 2);
    }
}
