//! Input errors with file, line and column.

/// A problem with a model file: where it is and what is wrong.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// The file cannot be read.
    #[error("{file}: cannot read the file: {source}")]
    Read {
        /// File name.
        file: String,
        /// Why.
        source: std::io::Error,
    },
    /// The content is wrong at a known place.
    #[error("{file}:{line}:{column}: {message}")]
    At {
        /// File name.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong, naming the item.
        message: String,
    },
    /// The content is wrong, place unknown.
    #[error("{file}: {message}")]
    File {
        /// File name.
        file: String,
        /// What is wrong.
        message: String,
    },
}

/// 1-based (line, column) of a byte offset.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let col = before.rfind('\n').map_or(offset, |p| offset - p - 1) + 1;
    (line, col)
}

/// Build an [`InputError::At`] from a byte offset.
pub fn at(file: &str, text: &str, offset: usize, message: impl Into<String>) -> InputError {
    let (line, column) = line_col(text, offset);
    InputError::At {
        file: file.to_string(),
        line,
        column,
        message: message.into(),
    }
}

/// Build an [`InputError::At`] from a 1-based line and column (line-oriented formats such as
/// SPACAR `.dat`).
pub fn at_line(file: &str, line: usize, column: usize, message: impl Into<String>) -> InputError {
    InputError::At {
        file: file.to_string(),
        line,
        column: column.max(1),
        message: message.into(),
    }
}

/// A model with no elements has nothing to analyse: the message, or `None` when it has one.
pub fn no_elements(model: &flexmbd_core::Model) -> Option<String> {
    model.elements.is_empty().then(|| {
        format!(
            "the model has no elements (trusses, beams, hinges or rigid bodies){}: there is nothing to analyse",
            if model.nodes.is_empty() {
                " and no nodes"
            } else {
                ""
            }
        )
    })
}

/// A model with no elements has nothing to analyse: an error naming the file.
pub fn require_elements(model: &flexmbd_core::Model, file: &str) -> Result<(), InputError> {
    match no_elements(model) {
        Some(message) => Err(InputError::File {
            file: file.to_string(),
            message,
        }),
        None => Ok(()),
    }
}

/// `text` with its control characters other than tab and line feed written as `\u{..}`: safe on
/// a terminal, and in a TOML comment once line feeds are replaced.
pub fn printable(text: &str) -> std::borrow::Cow<'_, str> {
    let escaped = |c: char| c.is_control() && c != '\t' && c != '\n';
    if !text.chars().any(escaped) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if escaped(c) {
            out.push_str(&format!("\\u{{{:x}}}", c as u32));
        } else {
            out.push(c);
        }
    }
    std::borrow::Cow::Owned(out)
}
