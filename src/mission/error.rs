//! Errors a user can make in a mission file, each pinned to a field.

use std::fmt;
use std::path::PathBuf;

/// One problem found in a mission file.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// Field path in the file, e.g. `groups[1].drones[3].start`; empty for the whole file.
    pub path: String,
    /// What is wrong, in words a user can act on, e.g. `[6, 0, 0] is outside the world …`.
    pub message: String,
    /// 1-based line and column where the parser knows them.
    pub line_column: Option<(usize, usize)>,
}

impl Problem {
    /// A problem with the field at `path` that no parser located (validation
    /// problems: the file parsed, so only the field path says where).
    pub fn new(path: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            path: path.into(),
            message: message.into(),
            line_column: None,
        }
    }
}

/// Why a mission file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum MissionError {
    /// The file could not be read at all (missing, unreadable, not UTF-8). The
    /// operating system's reason is the `source`, not part of this message, so a
    /// chain printed whole (`{:#}`) says it once.
    #[error("{}: cannot read", file.display())]
    Read {
        /// The mission file, as the user named it.
        file: PathBuf,
        /// Why the operating system refused.
        #[source]
        source: std::io::Error,
    },
    /// The file was read but is not a valid mission: a YAML error (one problem) or
    /// every validation problem found at once.
    #[error("{}", Invalid { file, problems })]
    Invalid {
        /// The mission file, as the user named it.
        file: PathBuf,
        /// Never empty; in the order the checks found them, which roughly follows the file.
        problems: Vec<Problem>,
    },
}

impl MissionError {
    /// The individual problems (empty for a read error).
    pub fn problems(&self) -> &[Problem] {
        match self {
            MissionError::Read { .. } => &[],
            MissionError::Invalid { problems, .. } => problems,
        }
    }
}

/// Renders problems one per line as `file:line:column: path: message`, the form
/// editors and terminals turn into links.
struct Invalid<'a> {
    file: &'a PathBuf,
    problems: &'a [Problem],
}

impl fmt::Display for Invalid<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let count = self.problems.len();
        write!(
            f,
            "{}: invalid mission ({count} problem{})",
            self.file.display(),
            if count == 1 { "" } else { "s" }
        )?;
        for p in self.problems {
            write!(f, "\n  {}", self.file.display())?;
            if let Some((line, column)) = p.line_column {
                write!(f, ":{line}:{column}")?;
            }
            if p.path.is_empty() {
                write!(f, ": {}", p.message)?;
            } else {
                write!(f, ": {}: {}", p.path, p.message)?;
            }
        }
        Ok(())
    }
}
