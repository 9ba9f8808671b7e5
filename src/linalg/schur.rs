//! The Schur complement of the condensed back-end on the host: where MUMPS
//! builds it, its gathering from a distributed grid, and its dense
//! Cholesky factor.

use super::direct::host_verdict;
use super::grid::GridSchur;
use crate::dense::SpdFactor;
use crate::error::Error;
use crate::mumps::Mumps;
use mpi::traits::*;

/// The error of a dense Schur array of order `m` that rank 0 cannot
/// allocate (`bytes`).
pub(super) fn schur_memory(m: usize, bytes: usize) -> Error {
    Error::OutOfMemory(format!(
        "rank 0 cannot allocate the dense Schur complement on the {m} contact unknowns ({:.1} MiB a copy); -ubr_condense_max 0 solves without it, in less memory on rank 0",
        bytes as f64 / (1u64 << 20) as f64
    ))
}

/// The host's Schur complement as MUMPS returned it, its dense Cholesky
/// factor, and the host's error when the factorization fails (a matrix
/// that is not positive definite: `K_r` singular or nearly so).
pub(super) fn schur_factor<C: Communicator>(
    world: &C,
    upper: &[f64],
    m: usize,
) -> (Vec<f64>, Option<SpdFactor>, Option<Error>) {
    if world.rank() != 0 {
        return (Vec::new(), None, None);
    }
    let copies = crate::dense::try_copy(upper)
        .and_then(|s_raw| Ok((crate::dense::try_copy(&s_raw)?, s_raw)));
    let (s, s_raw) = match copies {
        Ok(c) => c,
        Err(bytes) => return (Vec::new(), None, Some(schur_memory(m, bytes))),
    };
    match SpdFactor::new(m, s) {
        Ok(f) => (s_raw, Some(f), None),
        Err(k) => (s_raw, None, Some(Error::LinearSolver(format!(
            "the dense factorization of the Schur complement on the {m} contact unknowns failed (LAPACK's Cholesky: its leading minor of order {k} is not positive definite): the matrix K + r B^T W B is singular or nearly so"
        )))),
    }
}

/// Where MUMPS builds the Schur complement of a condensed back-end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SchurLayout {
    /// On the host (ICNTL(19) = 1), factorized and solved there by LAPACK.
    Centralized,
    /// Over every rank (ICNTL(19) = 3, a 1 x P grid), factorized and
    /// solved there by ScaLAPACK ([`super::grid`]).
    Distributed,
}

/// Column block of a distributed Schur complement (ScaLAPACK's NB).
pub(super) const SCHUR_BLOCK: usize = 64;

/// The Schur complement on the host after a factorization (its upper
/// triangle column-major; empty elsewhere): MUMPS' own array.
pub(super) fn host_schur(mumps: &Mumps) -> &[f64] {
    mumps.schur_upper()
}

/// S on the host and its factor, or the grid that holds S's factors.
pub(super) type Factors = (Vec<f64>, Option<SpdFactor>, Option<GridSchur>);

/// The Schur complement's factors after MUMPS' first factorization: on
/// the host (S as MUMPS returned it, and its LAPACK factor), or on the grid
/// (ScaLAPACK's, when `distributed`). Collective.
pub(super) fn first_factors<C: Communicator>(
    world: &C,
    mumps: &Mumps,
    m: usize,
    distributed: bool,
) -> Result<Factors, Error> {
    if distributed {
        let comm = crate::petsc::comm_world();
        let grid = GridSchur::new(world, comm, mumps.schur_local(), m, SCHUR_BLOCK)?;
        return Ok((Vec::new(), None, Some(grid)));
    }
    let (s_raw, s, failed) = schur_factor(world, host_schur(mumps), m);
    host_verdict(world, failed)?;
    Ok((s_raw, s, None))
}
