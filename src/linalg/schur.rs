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

/// The dense Cholesky factor of the host's Schur complement (a copy of
/// MUMPS' array `upper`, which stays as it is: products and shifts read
/// it), and the host's error when the factorization fails (a matrix that
/// is not positive definite: `K_r` singular or nearly so).
pub(super) fn schur_factor<C: Communicator>(
    world: &C,
    upper: &[f64],
    m: usize,
) -> (Option<SpdFactor>, Option<Error>) {
    if world.rank() != 0 {
        return (None, None);
    }
    let s = match crate::dense::try_copy(upper) {
        Ok(s) => s,
        Err(bytes) => return (None, Some(schur_memory(m, bytes))),
    };
    match SpdFactor::new(m, s) {
        Ok(f) => (Some(f), None),
        Err(k) => (None, Some(Error::LinearSolver(format!(
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

/// S's factor on the host, or the grid that holds S's factors.
pub(super) type Factors = (Option<SpdFactor>, Option<GridSchur>);

/// The Schur complement's factors after MUMPS' first factorization: on
/// the host (its LAPACK factor; S stays in MUMPS' array), or on the grid
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
        return Ok((None, Some(grid)));
    }
    let (s, failed) = schur_factor(world, host_schur(mumps), m);
    host_verdict(world, failed)?;
    Ok((s, None))
}
