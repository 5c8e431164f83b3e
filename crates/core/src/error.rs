//! Prism's error type: every failure a user can cause (bad scene, missing file, bad option) becomes one of these,
//! printed as a single line by the CLI. Library code never panics on user input.

use std::path::PathBuf;

/// A position in a source file, 1-based, as editors show it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SourcePos {
    /// The file, as the user named it (or as an include resolved it).
    pub file: PathBuf,
    /// Line, from 1.
    pub line: usize,
    /// Column, from 1.
    pub col: usize,
}

impl std::fmt::Display for SourcePos {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}:{}", self.file.display(), self.line, self.col)
    }
}

/// Every error Prism reports; its `Display` is the one line the CLI prints.
#[derive(Debug, thiserror::Error)]
pub enum PrismError {
    /// A syntax or schema error in a scene file, with its position.
    #[error("{pos}: {message}")]
    Parse {
        /// Where in the file.
        pos: SourcePos,
        /// What is wrong there.
        message: String,
    },
    /// A scene that parsed but makes no sense (NaN transform, zero-area triangle, unknown material ...).
    /// `context` names the file and the entity or field.
    #[error("{context}: {message}")]
    Scene {
        /// The file and the entity or field at fault.
        context: String,
        /// What is wrong with it.
        message: String,
    },
    /// A file that could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file that could not be read or written.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// An image or mesh file that exists but cannot be decoded.
    #[error("{}: {message}", path.display())]
    Format {
        /// The file that cannot be decoded.
        path: PathBuf,
        /// Why it cannot be decoded.
        message: String,
    },
    /// A bad option or setting (CLI flag, render setting).
    #[error("{0}")]
    Invalid(String),
}

impl PrismError {
    /// A [`PrismError::Scene`] error.
    pub fn scene(context: impl Into<String>, message: impl Into<String>) -> Self {
        PrismError::Scene { context: context.into(), message: message.into() }
    }
    /// A [`PrismError::Invalid`] error.
    pub fn invalid(message: impl Into<String>) -> Self {
        PrismError::Invalid(message.into())
    }
    /// A [`PrismError::Io`] error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        PrismError::Io { path: path.into(), source }
    }
    /// A [`PrismError::Format`] error on `path`.
    pub fn format(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        PrismError::Format { path: path.into(), message: message.into() }
    }
}

/// The result of every fallible Prism operation.
pub type Result<T, E = PrismError> = std::result::Result<T, E>;

/// `s` as one printable line: control characters (newlines, escapes, NUL ...) from file or entity names become
/// visible escapes (`\n`, `\u{1b}`), so a message can neither span lines nor drive the terminal.
pub fn printable(s: &str) -> String {
    if !s.chars().any(char::is_control) {
        return s.to_string();
    }
    s.chars().map(|c| if c.is_control() { c.escape_default().to_string() } else { c.to_string() }).collect()
}

/// Print a warning on stderr as one printable line (`warning: ...`).
pub fn warn(message: &str) {
    eprintln!("warning: {}", printable(message));
}

/// A token of a file for an error message: quoted as is when it is a short word or number (at most 32 of
/// `A-Z a-z 0-9 _ . + -`: a directive, a field name, a malformed number), otherwise only described by its length.
/// Messages never carry more of a file than such a token, so an error about a file a scene names (an `Include` of
/// a file that is no scene) cannot show its lines.
pub fn token_in_message(s: &str) -> String {
    let short_word = !s.is_empty()
        && s.len() <= 32
        && s.chars().all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '+' | '-'));
    if short_word { format!("`{s}`") } else { format!("a token of {} characters", s.chars().count()) }
}
