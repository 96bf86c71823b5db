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
