//! Large TOML files read piece by piece, so that the parser's tokens and document of the whole
//! file are never held at once (issue 14: the toml crate held 640 MB for a 15 MB file of 10^5
//! beams, more than `flexmbd modes` then needs for the model and its analysis).
//!
//! The file is cut at line starts outside any bracket, string or inline table, found with the
//! TOML lexer (`toml_parser`, the toml crate's own): before a top-level table header `[name]`
//! or `[[name]]` with an undotted name, and inside the long entry tables `[nodes]`, `[fix]` and
//! `[inputs]` between two entries. Each piece is parsed as a document of its own, from a buffer
//! of the file's length that holds the piece at its place in the file and blanks elsewhere (for
//! a piece inside an entry table, its header is written into the blanks just before it): spans,
//! error positions and the items errors name are those of the whole file. The pieces' tables are
//! then joined; what TOML forbids across pieces is checked here (a table header given twice, an
//! entry key given twice), with the messages of the whole-file parse. A file under [`PIECE`]
//! bytes is parsed whole, as before.

use super::schema::FileSpec;
use super::spans::name_item;
use crate::error::{at, InputError};
use indexmap::IndexMap;
use std::collections::HashSet;
use toml::Spanned;
use toml_parser::lexer::TokenKind;

/// Target size of a piece [bytes]: a piece ends at the first place it may after this many.
const PIECE: usize = 1 << 18;

/// Where a piece starts, and the header of the entry table it continues (written before it).
struct Cut {
    at: usize,
    header: Option<&'static str>,
}

/// Parse the TOML model text into what serde reads, in pieces when it is long.
pub(super) fn parse_file(text: &str, file: &str) -> Result<FileSpec, InputError> {
    let cuts = match cuts(text) {
        Ok(c) => c,
        Err(pos) => return Err(toml_error(text, file, pos, "duplicate key".into())),
    };
    if cuts.len() <= 1 {
        return from_toml(text, text, file);
    }
    let mut buf = vec![b' '; text.len()];
    let mut all: Option<FileSpec> = None;
    for (i, cut) in cuts.iter().enumerate() {
        let end = cuts.get(i + 1).map_or(text.len(), |c| c.at);
        let mut from = cut.at;
        if let Some(h) = cut.header {
            from -= h.len();
            buf[from..cut.at].copy_from_slice(h.as_bytes());
        }
        buf[cut.at..end].copy_from_slice(&text.as_bytes()[cut.at..end]);
        // (ASCII blanks and header around a piece of the file cut at line starts)
        let piece = std::str::from_utf8(&buf[..end]).map_err(|e| InputError::File {
            file: file.into(),
            message: format!("not UTF-8 text: {e}"),
        })?;
        let f = from_toml(piece, text, file)?;
        all = Some(match all {
            None => f,
            Some(a) => join(a, f, text, file)?,
        });
        buf[from..end].fill(b' ');
    }
    Ok(all.unwrap_or_else(|| unreachable!("at least two pieces")))
}

/// serde's reading of TOML text `piece` (the whole file `text`, or a piece of it at its place).
fn from_toml(piece: &str, text: &str, file: &str) -> Result<FileSpec, InputError> {
    toml::from_str(piece).map_err(|e| {
        let mut msg = e.message().trim().to_string();
        if msg.starts_with("invalid type: string") && msg.contains("expected usize") {
            msg.push_str(
                " (this key takes a whole number; expressions of parameters are for real values)",
            );
        }
        match e.span() {
            Some(span) => toml_error(text, file, span.start, msg),
            None => InputError::File {
                file: file.into(),
                message: msg,
            },
        }
    })
}

/// A TOML-level error at byte `pos` of the file, with the item it is in.
fn toml_error(text: &str, file: &str, pos: usize, msg: String) -> InputError {
    at(file, text, pos, name_item(text, pos, msg))
}

/// The places the text may be cut, the first at 0; one cut for a short text. `Err(pos)`: a
/// table header at `pos` repeats an earlier one (what the whole-file parse rejects as a
/// duplicate key, and pieces could not see).
fn cuts(text: &str) -> Result<Vec<Cut>, usize> {
    let mut cuts = vec![Cut {
        at: 0,
        header: None,
    }];
    if text.len() <= PIECE {
        return Ok(cuts);
    }
    let source = toml_parser::Source::new(text);
    let mut tokens = source.lex().peekable();
    let mut depth: i64 = 0;
    let mut line_start = true;
    // the entry table being read, when it may be cut between entries
    let mut entries: Option<&'static str> = None;
    let mut headers: HashSet<String> = HashSet::new();
    while let Some(t) = tokens.next() {
        let (start, end) = (t.span().start(), t.span().end());
        match t.kind() {
            TokenKind::Newline => {
                line_start = depth == 0;
                continue;
            }
            TokenKind::Whitespace | TokenKind::Comment => continue,
            TokenKind::Eof => break,
            _ => {}
        }
        let long = start - cuts.last().map_or(0, |c| c.at) >= PIECE;
        if line_start && t.kind() == TokenKind::LeftSquareBracket {
            // a table header: up to the end of its line
            let mut close = end;
            while let Some(n) = tokens.peek() {
                if matches!(n.kind(), TokenKind::Newline | TokenKind::Eof) {
                    break;
                }
                if n.kind() != TokenKind::Comment {
                    close = n.span().end();
                }
                tokens.next();
            }
            let raw = text[start..close].trim();
            let array = raw.starts_with("[[");
            let name = normal_name(raw.trim_matches(|c| c == '[' || c == ']'));
            let dotted = name.contains('.');
            if !array && !headers.insert(name.clone()) {
                return Err(start);
            }
            if !dotted && long {
                cuts.push(Cut {
                    at: start,
                    header: None,
                });
            }
            entries = match (array, name.as_str()) {
                (false, "nodes") => Some("[nodes]\n"),
                (false, "fix") => Some("[fix]\n"),
                (false, "inputs") => Some("[inputs]\n"),
                _ => None,
            };
            line_start = false;
            continue;
        }
        if line_start && depth == 0 && long && !dotted_key(text, start) {
            if let Some(h) = entries {
                cuts.push(Cut {
                    at: start,
                    header: Some(h),
                });
            }
        }
        line_start = false;
        match t.kind() {
            TokenKind::LeftSquareBracket | TokenKind::LeftCurlyBracket => depth += 1,
            TokenKind::RightSquareBracket | TokenKind::RightCurlyBracket => depth -= 1,
            _ => {}
        }
        if depth < 0 {
            // not TOML: the whole-file parse says where
            cuts.truncate(1);
            return Ok(cuts);
        }
    }
    Ok(cuts)
}

/// Whether the key of the entry line starting at `start` is dotted (`a.b = …`: a table that
/// later lines may add to, so not a place to cut).
fn dotted_key(text: &str, start: usize) -> bool {
    let line = &text[start..];
    let line = &line[..line.find('\n').unwrap_or(line.len())];
    let key = line[..line.find('=').unwrap_or(line.len())].trim();
    let quoted = key.len() >= 2
        && (key.starts_with('"') || key.starts_with('\''))
        && key.ends_with(&key[..1])
        && !key[1..key.len() - 1].contains(['"', '\'']);
    !quoted && key.contains('.')
}

/// A table name with the blanks around its dots and the quotes of its simple parts removed
/// (`[ "nodes" ]` is `[nodes]`).
fn normal_name(raw: &str) -> String {
    raw.split('.')
        .map(|p| p.trim().trim_matches(|c| c == '"' || c == '\''))
        .collect::<Vec<_>>()
        .join(".")
}

/// The tables of two pieces (`b` after `a` in the file) as one file's.
fn join(mut a: FileSpec, b: FileSpec, text: &str, file: &str) -> Result<FileSpec, InputError> {
    let FileSpec {
        model,
        parameters,
        nodes,
        fix,
        inputs,
        truss,
        beam,
        hinge,
        rigid,
        material,
        section,
        load,
        mass,
        inertia,
        prescribe,
        statics,
        simulate,
        velocity,
        freedom,
    } = b;
    let twice = |what: &str| InputError::File {
        file: file.into(),
        message: format!("the table `[{what}]` appears twice"),
    };
    once(&mut a.model, model, || twice("model"))?;
    for (into, from) in [
        (&mut a.parameters, parameters),
        (&mut a.nodes, nodes),
        (&mut a.fix, fix),
        (&mut a.inputs, inputs),
    ] {
        join_entries(into, from, text, file)?;
    }
    // the arrays of tables, in file order
    macro_rules! append {
        ($($f:ident),*) => { $(a.$f.extend($f);)* };
    }
    append!(
        truss, beam, hinge, rigid, material, section, load, mass, inertia, prescribe, velocity,
        freedom
    );
    once(&mut a.statics, statics, || twice("static"))?;
    once(&mut a.simulate, simulate, || twice("simulate"))?;
    Ok(a)
}

/// A table that may be given once, from a later piece.
fn once<T>(
    into: &mut Option<T>,
    from: Option<T>,
    twice: impl FnOnce() -> InputError,
) -> Result<(), InputError> {
    if from.is_some() {
        if into.is_some() {
            return Err(twice());
        }
        *into = from;
    }
    Ok(())
}

type Entries = Option<IndexMap<String, Spanned<toml::Value>>>;

/// The entries of an entry table from a later piece added to the earlier pieces'; a key given
/// in both is the whole-file parse's duplicate key, at the later entry.
fn join_entries(
    into: &mut Entries,
    from: Entries,
    text: &str,
    file: &str,
) -> Result<(), InputError> {
    let Some(from) = from else {
        return Ok(());
    };
    let into = match into {
        Some(m) => m,
        None => {
            *into = Some(from);
            return Ok(());
        }
    };
    for (k, v) in from {
        let pos = v.span().start;
        if into.insert(k, v).is_some() {
            return Err(toml_error(text, file, pos, "duplicate key".into()));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{cuts, from_toml, parse_file, PIECE};
    use crate::error::InputError;

    /// A clamped strip of `n` beams in the model format, long enough to be cut for n ≳ 10^4;
    /// `extra` is appended.
    fn strip(n: usize, extra: &str) -> String {
        let mut s = String::from("[model]\nname = \"strip\"\n\n[nodes]\n");
        for i in 0..=n {
            s += &format!("n{i} = [{}, 0.0, 0.0]   # node {i}\n", i as f64 * 1e-3);
        }
        s += "\n[fix]\nn0 = \"all\"\n\n[[material]]\nid = \"steel\"\nE = 2e11\nnu = 0.3\nrho = 7800\n";
        s += "\n[[section]]\nid = \"s\"\nshape = \"rectangle\"\nw = 0.01\nt = 0.001\n";
        for k in 0..n {
            s += &format!(
                "\n[[beam]]\nid = \"b{k}\"\nnodes = [\"n{k}\", \"n{}\"]\norient = [0.0, 1.0, 0.0]\nsection = \"s\"\nmaterial = \"steel\"\n",
                k + 1
            );
        }
        s + extra
    }

    /// The line (1-based) and message of an error at a line.
    fn error_at(r: Result<super::FileSpec, InputError>) -> (usize, String) {
        match r {
            Err(InputError::At { line, message, .. }) => (line, message),
            Err(e) => panic!("expected an error at a line, got {e}"),
            Ok(_) => panic!("expected an error"),
        }
    }

    fn line_of(text: &str, needle: &str) -> usize {
        text[..text.find(needle).expect("needle")].lines().count() + 1
    }

    #[test]
    fn pieces_read_as_the_whole_file() {
        let text = strip(30_000, "\n[static]\nsteps = 4\n");
        let c = cuts(&text).unwrap();
        assert!(c.len() >= text.len() / PIECE, "{} cuts", c.len());
        assert!(
            c.iter().any(|c| c.header == Some("[nodes]\n")),
            "the node table is long enough to be cut inside"
        );
        let pieces = parse_file(&text, "m.toml").unwrap();
        let whole = from_toml(&text, &text, "m.toml").unwrap();
        let nodes = |f: &super::FileSpec| -> Vec<(String, std::ops::Range<usize>, String)> {
            let mut v: Vec<_> = f
                .nodes
                .as_ref()
                .unwrap()
                .iter()
                .map(|(k, v)| (k.clone(), v.span(), v.get_ref().to_string()))
                .collect();
            v.sort_by_key(|e| e.1.start);
            v
        };
        assert_eq!(nodes(&pieces), nodes(&whole));
        let beams = |f: &super::FileSpec| -> Vec<(std::ops::Range<usize>, String, Vec<String>)> {
            f.beam
                .iter()
                .map(|b| (b.span(), b.get_ref().id.clone(), b.get_ref().nodes.clone()))
                .collect()
        };
        assert_eq!(beams(&pieces).len(), 30_000);
        assert_eq!(beams(&pieces), beams(&whole));
        assert_eq!(pieces.fix.as_ref().unwrap().len(), 1);
        assert_eq!(pieces.material.len(), 1);
        assert_eq!(pieces.section.len(), 1);
        assert_eq!(
            pieces.statics.as_ref().map(|s| s.span()),
            whole.statics.as_ref().map(|s| s.span())
        );
        assert_eq!(
            pieces
                .model
                .as_ref()
                .and_then(|m| m.name.clone())
                .as_deref(),
            Some("strip")
        );
    }

    #[test]
    fn a_node_given_again_in_a_later_piece_is_named_at_its_line() {
        // n5 again at the end of the node table, pieces after its first definition
        let text = strip(30_000, "").replacen("n30000 = [", "n5 = [1.0, 2.0, 3.0]\nn30000 = [", 1);
        let again = text.find("n5 = [1.0").unwrap();
        assert!(
            cuts(&text)
                .unwrap()
                .iter()
                .any(|c| c.at > 0 && c.at < again),
            "the two definitions are in different pieces"
        );
        let (line, message) = error_at(parse_file(&text, "m.toml"));
        assert_eq!(line, line_of(&text, "n5 = [1.0"));
        assert!(message.contains("node `n5` is defined twice"), "{message}");
    }

    #[test]
    fn an_error_in_a_later_piece_names_its_line_and_item() {
        let text =
            strip(30_000, "").replacen("id = \"b29000\"\n", "id = \"b29000\"\nsegmentz = 3\n", 1);
        let (line, message) = error_at(parse_file(&text, "m.toml"));
        assert_eq!(line, line_of(&text, "segmentz"));
        assert!(
            message.contains("element `b29000`") && message.contains("segmentz"),
            "{message}"
        );
    }

    #[test]
    fn a_table_given_twice_far_apart_is_named() {
        let text = format!(
            "[static]\nsteps = 2\n\n{}",
            strip(30_000, "\n[static]\nsteps = 4\n")
        );
        let (line, message) = error_at(parse_file(&text, "m.toml"));
        assert_eq!(line, text.lines().count() - 1);
        assert!(message.contains("`[static]` appears twice"), "{message}");
    }

    #[test]
    fn dotted_keys_and_multi_line_values_are_not_cut() {
        // a node table of dotted keys and arrays over several lines: no cut inside it, and the
        // file reads as whole
        let mut text = String::from("[nodes]\n");
        for i in 0..60_000 {
            text += &format!("n{i}.x = [\n  {i}.0,\n  0.0,\n  0.0,\n]\n");
        }
        let c = cuts(&text).unwrap();
        assert_eq!(c.len(), 1, "no place to cut");
        let mut text = String::from("[nodes]\n");
        for i in 0..60_000 {
            text += &format!("n{i} = [\n  [{i}.0],\n  0.0,\n  0.0,\n]\n");
        }
        let c = cuts(&text).unwrap();
        assert!(c.len() > 1);
        for cut in &c[1..] {
            assert!(text[cut.at..].starts_with('n'), "cut inside a value");
        }
    }
}
