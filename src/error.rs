//! The one error type of the program, a variant per kind of failure, and its
//! exit status (DESIGN.md): 2 bad input or an ill-posed scene, 3 not
//! converged, anything else a bug. `main` prints it once.

/// Every way a run can fail.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// An option, or a file an option names, is wrong. Exit status 2.
    #[error("error: {0}")]
    BadInput(String),
    /// A mesh file (or generator) is wrong; the message names the file and
    /// the line or byte offset (`From<MeshError>` is in `mesh`). Exit status 2.
    #[error("error: {0}")]
    Mesh(String),
    /// An output file cannot be written. Exit status 2 (the path is the user's).
    #[error("error: option {option}: cannot write '{path}': {reason}")]
    Output {
        option: &'static str,
        path: String,
        reason: String,
    },
    /// An ill-posed scene: a rigid motion that nothing restrains (named in
    /// the message). Exit status 2, like bad input: the scene must change.
    #[error("error: ill-posed scene: {0}")]
    IllPosed(String),
    /// The contact iteration did not converge. Exit status 3.
    #[error("not converged: {0}")]
    NotConverged(String),
    /// A linear solve failed (e.g. a failed factorization). Exit status 3.
    #[error("error: {0}")]
    LinearSolver(String),
    /// PETSc reported an error. Exit status 1 (a bug, or the machine).
    #[error("PETSc error: {message}")]
    Petsc { code: i32, message: String },
    /// Anything else that is our fault. Exit status 1.
    #[error("internal error: {0}")]
    Internal(String),
}

impl Error {
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::BadInput(_) | Error::Mesh(_) | Error::Output { .. } | Error::IllPosed(_) => 2,
            Error::NotConverged(_) | Error::LinearSolver(_) => 3,
            Error::Petsc { .. } | Error::Internal(_) => 1,
        }
    }

    /// Whether every rank returns this error together (decided collectively);
    /// any other may be seen by one rank only, which then ends them all.
    pub fn is_collective(&self) -> bool {
        matches!(
            self,
            Error::BadInput(_)
                | Error::Mesh(_)
                | Error::Output { .. }
                | Error::IllPosed(_)
                | Error::NotConverged(_)
                | Error::LinearSolver(_)
        )
    }

    /// An output file that cannot be written, for option `option`.
    pub fn output(option: &'static str, path: &str, reason: impl std::fmt::Display) -> Error {
        Error::Output {
            option,
            path: path.to_string(),
            reason: reason.to_string(),
        }
    }
}

/// Shorthand for a bad-input error.
pub fn bad<T>(msg: impl Into<String>) -> Result<T, Error> {
    Err(Error::BadInput(msg.into()))
}
