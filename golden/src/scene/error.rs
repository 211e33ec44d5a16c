//! Why a scene was refused.

use std::path::PathBuf;

/// Why a scene was refused. Every variant names the file (`origin`).
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{}: cannot read the scene file", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// Not TOML, or TOML that does not have the shape of a scene (an unknown
    /// key, a missing one, a wrong type). `line` and `column` count from 1;
    /// `field` is the path of the offending key when it is known.
    #[error("{origin}:{line}:{column}: {}{message}", field_prefix(.field))]
    Syntax {
        origin: String,
        line: usize,
        column: usize,
        field: Option<String>,
        message: String,
    },
    /// Well-formed, but a value breaks a rule (a range, a limit of the RTL,
    /// the precondition of a speed-up).
    #[error("{origin}: {field}: {message}")]
    Invalid {
        origin: String,
        field: String,
        message: String,
    },
}

fn field_prefix(field: &Option<String>) -> String {
    field.as_ref().map_or(String::new(), |f| format!("{f}: "))
}

impl SceneError {
    /// The path of the offending field (`sphere[1].radius`), when known.
    pub fn field(&self) -> Option<&str> {
        match self {
            SceneError::Io { .. } => None,
            SceneError::Syntax { field, .. } => field.as_deref(),
            SceneError::Invalid { field, .. } => Some(field),
        }
    }
}
