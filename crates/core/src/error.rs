//! Prism's error type: every failure a user can cause (bad scene, missing file, bad option) becomes one of these,
//! printed as a single line by the CLI. Library code never panics on user input.

use std::path::PathBuf;

/// A position in a source file, 1-based, as editors show it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SourcePos {
    pub file: PathBuf,
    pub line: usize,
    pub col: usize,
}

impl std::fmt::Display for SourcePos {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}:{}", self.file.display(), self.line, self.col)
    }
}

#[derive(Debug, thiserror::Error)]
pub enum PrismError {
    /// A syntax or schema error in a scene file, with its position.
    #[error("{pos}: {message}")]
    Parse { pos: SourcePos, message: String },
    /// A scene that parsed but makes no sense (NaN transform, zero-area triangle, unknown material ...).
    /// `context` names the file and the entity or field.
    #[error("{context}: {message}")]
    Scene { context: String, message: String },
    /// A file that could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// An image or mesh file that exists but cannot be decoded.
    #[error("{}: {message}", path.display())]
    Format { path: PathBuf, message: String },
    /// A bad option or setting (CLI flag, render setting).
    #[error("{0}")]
    Invalid(String),
}

impl PrismError {
    pub fn scene(context: impl Into<String>, message: impl Into<String>) -> Self {
        PrismError::Scene { context: context.into(), message: message.into() }
    }
    pub fn invalid(message: impl Into<String>) -> Self {
        PrismError::Invalid(message.into())
    }
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        PrismError::Io { path: path.into(), source }
    }
    pub fn format(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        PrismError::Format { path: path.into(), message: message.into() }
    }
}

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
