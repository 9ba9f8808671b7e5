//! The one error type of the program, a variant per kind of failure, and its
//! exit status (docs/DESIGN.md, "Exit status"): 1 an error of PETSc or an
//! internal one (a bug, or the machine), 2 bad input or an ill-posed scene,
//! 3 not converged, 4 out of memory; `main` also ends a panic with 70 on
//! every rank. `main` prints the error once.
//!
//! Memory that runs out where no error can be returned (a Rust
//! allocation, a library that does not check its own) ends the run in
//! [`memory`]: one line naming it, exit status 4 on every rank.

pub mod memory;
pub use memory::fallible;

/// Every way a run can fail.
#[derive(Clone, Debug, thiserror::Error)]
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
    /// Memory ran out (an allocation failed in MUMPS, in PETSc, in OpenBLAS'
    /// work space or in ours): the run needs more memory than a rank may
    /// use. Exit status 4: neither bad input nor a method that did not
    /// converge; the same run succeeds with more memory or more ranks.
    #[error("error: out of memory: {0}")]
    OutOfMemory(String),
    /// PETSc reported an error. Exit status 1 (a bug, or the machine); 4,
    /// and a message that says so, when an allocation failed
    /// ([`Error::is_out_of_memory`]).
    #[error("{}", petsc_message(*code, message))]
    Petsc { code: i32, message: String },
    /// Anything else that is our fault. Exit status 1.
    #[error("internal error: {0}")]
    Internal(String),
}

/// The exit status of a run that ran out of memory.
pub const EXIT_OUT_OF_MEMORY: i32 = 4;

/// PETSc's error code for a failed allocation (`PETSC_ERR_MEM`).
const PETSC_ERR_MEM: i32 = 55;

impl Error {
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::BadInput(_) | Error::Mesh(_) | Error::Output { .. } | Error::IllPosed(_) => 2,
            Error::NotConverged(_) | Error::LinearSolver(_) => 3,
            Error::OutOfMemory(_) => EXIT_OUT_OF_MEMORY,
            Error::Petsc { .. } if self.is_out_of_memory() => EXIT_OUT_OF_MEMORY,
            Error::Petsc { .. } | Error::Internal(_) => 1,
        }
    }

    /// Whether memory ran out: [`Error::OutOfMemory`], or PETSc's error for
    /// a failed allocation. PETSc 3.18's `PetscMallocAlign` raises it with
    /// its arguments out of order (the caller's line as the error code, its
    /// function's name as the message), so it is known by where it was
    /// raised, as well as by `PETSC_ERR_MEM`.
    pub fn is_out_of_memory(&self) -> bool {
        match self {
            Error::OutOfMemory(_) => true,
            Error::Petsc { code, message } => petsc_out_of_memory(*code, message),
            _ => false,
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
                | Error::OutOfMemory(_)
        )
    }

    /// The same error with `note` appended to its message (a hint that
    /// the place where it was found cannot give).
    pub fn with_note(self, note: &str) -> Error {
        let add = |m: String| format!("{m}; {note}");
        match self {
            Error::BadInput(m) => Error::BadInput(add(m)),
            Error::Mesh(m) => Error::Mesh(add(m)),
            Error::IllPosed(m) => Error::IllPosed(add(m)),
            Error::NotConverged(m) => Error::NotConverged(add(m)),
            Error::LinearSolver(m) => Error::LinearSolver(add(m)),
            Error::OutOfMemory(m) => Error::OutOfMemory(add(m)),
            Error::Internal(m) => Error::Internal(add(m)),
            Error::Petsc { code, message } => Error::Petsc {
                code,
                message: add(message),
            },
            Error::Output {
                option,
                path,
                reason,
            } => Error::Output {
                option,
                path,
                reason: add(reason),
            },
        }
    }

    /// Whether the run reports this error as its outcome, after writing its
    /// outputs, when it comes after the assembly: the method did not
    /// converge, a linear solve failed, or memory ran out in a collective
    /// step (every rank has it, so every rank goes on to the outputs).
    pub fn is_outcome(&self) -> bool {
        matches!(
            self,
            Error::NotConverged(_) | Error::LinearSolver(_) | Error::OutOfMemory(_)
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

fn petsc_out_of_memory(code: i32, message: &str) -> bool {
    code == PETSC_ERR_MEM || message.contains(" in PetscMallocAlign() at ")
}

/// The message of [`Error::Petsc`].
fn petsc_message(code: i32, message: &str) -> String {
    if petsc_out_of_memory(code, message) {
        format!("error: out of memory: PETSc could not allocate: {message}; the run needs more memory than a rank may use, or more ranks")
    } else {
        format!("PETSc error: {message}")
    }
}

/// Shorthand for a bad-input error.
pub fn bad<T>(msg: impl Into<String>) -> Result<T, Error> {
    Err(Error::BadInput(msg.into()))
}
