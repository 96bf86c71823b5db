//! Errors of a study: its file or its model (file, line, column, item), its output folder.

pub use flexmbd_io::error::InputError;

/// Why a study cannot be read or run. A variant that fails is not an error of the study: it
/// is a record with its failure ([`crate::Record::error`]).
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The study file or its model file is wrong (or cannot be read): file, line and item.
    #[error("{0}")]
    Input(#[from] InputError),
    /// The output folder cannot be used: written, or resumed.
    #[error("{dir}: {message}")]
    Output {
        /// The folder.
        dir: String,
        /// What is wrong.
        message: String,
    },
}

impl StudyError {
    /// Whether the error is the user's input (a study or model file), as opposed to an output
    /// that cannot be written.
    pub fn is_input(&self) -> bool {
        matches!(
            self,
            StudyError::Input(InputError::At { .. } | InputError::File { .. })
        )
    }

    pub(crate) fn output(dir: &std::path::Path, message: impl Into<String>) -> Self {
        StudyError::Output {
            dir: dir.display().to_string(),
            message: message.into(),
        }
    }
}
