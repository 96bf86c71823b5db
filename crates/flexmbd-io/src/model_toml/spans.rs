//! Places in the TOML text: the item an error of the TOML parser is in (from the text around
//! it), the line of a key inside a table, and line and column of a byte offset.

use crate::spec::Pos;
use std::ops::Range;

/// The top-level tables of the format, for messages.
const SECTIONS: [&str; 17] = [
    "model",
    "parameters",
    "nodes",
    "fix",
    "inputs",
    "truss",
    "beam",
    "hinge",
    "rigid",
    "material",
    "section",
    "load",
    "mass",
    "prescribe",
    "static",
    "simulate",
    "velocity",
];

/// Line and column of byte offsets in one text, from the offsets of its line starts found once
/// (a model of 10^5 items asks for 10^5 places: scanning the text from its start for each was
/// quadratic).
pub(super) struct Lines {
    starts: Vec<usize>,
    len: usize,
}

impl Lines {
    pub(super) fn new(text: &str) -> Self {
        let starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Lines {
            starts,
            len: text.len(),
        }
    }

    /// Line and column (1-based, the column in bytes) of a byte offset, as
    /// [`crate::error::line_col`] gives them.
    pub(super) fn pos(&self, offset: usize) -> Pos {
        let offset = offset.min(self.len);
        // the last line start at or before the offset
        let line = self.starts.partition_point(|&s| s <= offset);
        let start = self.starts[line.max(1) - 1];
        Pos {
            line: line.max(1),
            column: offset - start + 1,
        }
    }
}

/// Prefix a TOML-level error message (syntax, unknown key, missing field, wrong type) with the
/// item it is in, found from the text: the last table header before `offset` and, in [nodes],
/// [fix] and [inputs], the key of the entry; in an element table, its `id`.
pub(super) fn name_item(text: &str, offset: usize, msg: String) -> String {
    let offset = offset.min(text.len());
    let line_start = text[..offset].rfind('\n').map_or(0, |p| p + 1);
    let line_end = text[offset..].find('\n').map_or(text.len(), |p| offset + p);
    let before: Vec<&str> = text[..line_start].lines().collect();
    let here = &text[line_start..line_end];
    // the header: the error line itself, or the nearest one above it
    let is_header = |l: &str| l.trim_start().starts_with('[');
    let (header, body_above): (Option<&str>, &[&str]) = if is_header(here) {
        (Some(here), &[])
    } else {
        match before.iter().rposition(|l| is_header(l)) {
            Some(i) => (Some(before[i]), &before[i + 1..]),
            None => (None, &before[..]),
        }
    };
    let header_name = header.map(|h| {
        let h = h.trim().trim_start_matches('[');
        h[..h.find(']').unwrap_or(h.len())].trim().to_string()
    });
    let (section, sub) = match &header_name {
        Some(h) => match h.split_once('.') {
            Some((a, b)) => (a.trim().to_string(), Some(unquote(b.trim()))),
            None => (h.clone(), None),
        },
        None => (String::new(), None),
    };
    let entry_table = matches!(section.as_str(), "nodes" | "fix" | "inputs") && sub.is_some();
    if let (Some(h), "duplicate key") = (&header_name, msg.as_str()) {
        if is_header(here) && !entry_table {
            return format!("the table `[{h}]` appears twice");
        }
    }
    // the entry key: on the error line or the nearest `key =` line above it in the table
    let entry_key = || {
        std::iter::once(here)
            .chain(body_above.iter().rev().copied())
            .find_map(line_key)
    };
    let item = match section.as_str() {
        "nodes" | "fix" | "inputs" if !is_header(here) || sub.is_some() => {
            let what = match section.as_str() {
                "nodes" => "node",
                "fix" => "fix entry",
                _ => "inputs entry",
            };
            let key = sub.or_else(entry_key);
            if let (Some(k), "duplicate key") = (&key, msg.as_str()) {
                return format!("{what} `{k}` is defined twice");
            }
            key.map(|k| format!("{what} `{k}`"))
        }
        "nodes" | "fix" | "inputs" => Some(format!("[{section}]")),
        "model" => Some("[model]".to_string()),
        "parameters" => Some(match entry_key() {
            Some(k) if !is_header(here) => format!("parameter `{k}`"),
            _ => "[parameters]".to_string(),
        }),
        "truss" | "beam" | "hinge" | "rigid" | "material" | "section" | "load" | "mass"
        | "inertia" | "prescribe"
            if header.is_some_and(|h| !h.trim_start().starts_with("[["))
                && msg.contains("expected a sequence") =>
        {
            return format!("`[{section}]` must be written `[[{section}]]` (one table per entry)");
        }
        "truss" | "beam" | "hinge" | "rigid" | "material" | "section" | "load" | "mass"
        | "inertia" | "prescribe" => {
            // a `key = "..."` line in the table's body (above and below the error line)
            let start = if is_header(here) {
                line_end
            } else {
                line_start
            };
            let below = text[start.min(text.len())..]
                .lines()
                .take_while(|l| !is_header(l));
            let body: Vec<&str> = body_above
                .iter()
                .copied()
                .chain(std::iter::once(here).filter(|l| !is_header(l)))
                .chain(below)
                .collect();
            let value_of = |key: &str| {
                body.iter().find_map(|l| {
                    let (k, v) = l.split_once('=')?;
                    (k.trim() == key).then(|| quoted(v.trim()))?
                })
            };
            // the table's number among the tables of its kind (1-based)
            let array_header = |l: &str| {
                let l = l.trim();
                l.strip_prefix("[[")
                    .and_then(|r| r.split_once("]]"))
                    .is_some_and(|(name, _)| name.trim() == section)
            };
            let index =
                before.iter().filter(|l| array_header(l)).count() + usize::from(array_header(here));
            let what = match section.as_str() {
                "truss" | "beam" | "hinge" | "rigid" => "element",
                other => other,
            };
            Some(match (value_of("id"), section.as_str()) {
                (Some(id), _) => format!("{what} `{id}`"),
                (None, "load" | "mass" | "inertia" | "prescribe") => {
                    match value_of("node").or_else(|| value_of("element")) {
                        Some(n) => format!("[[{section}]] {index} (on `{n}`)"),
                        None => format!("[[{section}]] {index}"),
                    }
                }
                (None, _) => format!("[[{section}]] {index}"),
            })
        }
        "static" => Some("[static]".to_string()),
        // a top-level `section = value` before any header
        "" => match line_key(here) {
            Some(k) if SECTIONS.contains(&k.as_str()) => Some(format!("[{k}]")),
            // a key before the first table header
            Some(k) if msg == "duplicate key" => {
                return format!("`{k}` is given twice before the first [table]");
            }
            _ => None,
        },
        _ => None,
    };
    match item {
        Some(item) => match (line_key(here), msg.as_str()) {
            (Some(k), "duplicate key") => format!("{item}: `{k}` is given twice"),
            _ => format!("{item}: {msg}"),
        },
        None => match msg.strip_prefix("unknown field") {
            // a top-level key is a section
            Some(rest) if header_name.as_deref().is_none_or(|h| !h.contains('.')) => {
                format!("unknown section{rest}")
            }
            _ => msg,
        },
    }
}

/// The span of the `key = value` line in the body of a table (whose span starts at its header),
/// or the table's span when the key is not found there.
pub(super) fn key_span(text: &str, table: &Range<usize>, key: &str) -> Range<usize> {
    let start = table.start.min(text.len());
    let mut offset = start;
    for (k, line) in text[start..].split_inclusive('\n').enumerate() {
        let trimmed = line.trim_start();
        if k > 0 && trimmed.starts_with('[') {
            break; // the next table
        }
        if line_key(line).as_deref() == Some(key) {
            let lead = line.len() - trimmed.len();
            return offset + lead..offset + line.len();
        }
        offset += line.len();
    }
    table.clone()
}

/// The key of a `key = value` line, if the line starts with one.
fn line_key(line: &str) -> Option<String> {
    let (k, _) = line.split_once('=')?;
    let k = k.trim();
    let ok = !k.is_empty()
        && k.chars()
            .all(|c| c.is_alphanumeric() || "_-\"' .".contains(c));
    ok.then(|| unquote(k))
}

/// A key without its quotes.
fn unquote(k: &str) -> String {
    k.trim_matches(|c| c == '"' || c == '\'').to_string()
}

/// The content of a quoted string at the start of `v`.
fn quoted(v: &str) -> Option<String> {
    let q = v.chars().next().filter(|c| *c == '"' || *c == '\'')?;
    let rest = &v[1..];
    Some(rest[..rest.find(q)?].to_string())
}

#[cfg(test)]
mod lines_tests {
    use super::Lines;

    #[test]
    fn lines_give_the_places_of_line_col() {
        // every offset of a text with empty lines, a last line without a newline and a
        // multi-byte character, against the scan from the start
        let text = "a = 1\n\n[nodes]\nμ = [0, 0, 0]\nlast";
        let lines = Lines::new(text);
        for offset in (0..=text.len() + 2).filter(|&o| o > text.len() || text.is_char_boundary(o)) {
            let (line, column) = crate::error::line_col(text, offset);
            let p = lines.pos(offset);
            assert_eq!((p.line, p.column), (line, column), "offset {offset}");
        }
    }
}
