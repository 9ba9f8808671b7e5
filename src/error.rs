//! The one error type of the program, and its exit status (DESIGN.md):
//! 2 bad input, 3 not converged, anything else a bug.

use std::fmt;

#[derive(Debug)]
pub enum Error {
    /// Bad input: an option, a file or a line is wrong. Exit status 2.
    BadInput(String),
    /// An ill-posed scene: a rigid motion that nothing restrains (named in
    /// the message). Exit status 2, like bad input: the scene must change.
    IllPosed(String),
    /// The contact iteration did not converge. Exit status 3.
    NotConverged(String),
    /// A linear solve failed (e.g. a failed factorization). Exit status 3.
    LinearSolver(String),
    /// PETSc reported an error. Exit status 1 (a bug, or the machine).
    Petsc { code: i32, message: String },
    /// Anything else that is our fault. Exit status 1.
    Internal(String),
}

impl Error {
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::BadInput(_) | Error::IllPosed(_) => 2,
            Error::NotConverged(_) | Error::LinearSolver(_) => 3,
            Error::Petsc { .. } | Error::Internal(_) => 1,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::BadInput(m) => write!(f, "error: {m}"),
            Error::IllPosed(m) => write!(f, "error: ill-posed scene: {m}"),
            Error::NotConverged(m) => write!(f, "not converged: {m}"),
            Error::LinearSolver(m) => write!(f, "error: {m}"),
            Error::Petsc { message, .. } => write!(f, "PETSc error: {message}"),
            Error::Internal(m) => write!(f, "internal error: {m}"),
        }
    }
}

impl std::error::Error for Error {}

impl From<crate::mesh::MeshError> for Error {
    fn from(e: crate::mesh::MeshError) -> Self {
        Error::BadInput(e.0)
    }
}

/// Shorthand for a bad-input error.
pub fn bad<T>(msg: impl Into<String>) -> Result<T, Error> {
    Err(Error::BadInput(msg.into()))
}
