//! The Schur complement of the condensed back-end on the host: where MUMPS
//! builds it, its gathering from a distributed grid, and its dense
//! Cholesky factor.

use super::direct::host_verdict;
use crate::comm::Layout;
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
    /// On the host (ICNTL(19) = 1).
    Centralized,
    /// Over every rank (ICNTL(19) = 3, a 1 x P grid), gathered on the host.
    Distributed,
}

/// Column block of a distributed Schur complement (ScaLAPACK's NB).
pub(super) const SCHUR_BLOCK: usize = 64;

/// The number of rows or columns of an order-`n` matrix that process `p`
/// of `procs` holds in blocks of `nb` (ScaLAPACK's NUMROC, first block on
/// process 0).
fn numroc(n: usize, nb: usize, p: usize, procs: usize) -> usize {
    let blocks = n / nb;
    let mut count = (blocks / procs) * nb;
    let extra = blocks % procs;
    if p < extra {
        count += nb;
    } else if p == extra {
        count += n % nb;
    }
    count
}

/// The distributed Schur complement (each rank's column blocks of the
/// 1 x P grid, `local`, column-major with every row) gathered on the host
/// as the whole `m x m` matrix, column-major (empty elsewhere). Process
/// column p of MUMPS' grid is rank p; a part of another size than that
/// mapping gives is an internal error.
fn gather_schur<C: Communicator>(
    world: &C,
    local: &[f64],
    m: usize,
    nb: usize,
) -> Result<Vec<f64>, Error> {
    let procs = world.size() as usize;
    let mine = numroc(m, nb, world.rank() as usize, procs) * m;
    let part = &local[..mine.min(local.len())];
    let layout = Layout::new(world, part.len());
    let all = layout.gather(world, part);
    let ok =
        world.rank() != 0 || (0..procs).all(|p| layout.count(p) == numroc(m, nb, p, procs) * m);
    host_verdict(
        world,
        (!ok).then(|| {
            Error::Internal(
                "the distributed Schur complement's parts are not the 1 x P grid's".into(),
            )
        }),
    )?;
    if world.rank() != 0 {
        return Ok(Vec::new());
    }
    let mut full = crate::dense::try_zeros(m * m).map_err(|bytes| schur_memory(m, bytes))?;
    let mut offset = 0;
    for p in 0..procs {
        let nloc = numroc(m, nb, p, procs);
        for jl in 0..nloc {
            let j = (jl / nb) * procs * nb + p * nb + jl % nb;
            full[j * m..(j + 1) * m].copy_from_slice(&all[offset + jl * m..offset + (jl + 1) * m]);
        }
        offset += nloc * m;
    }
    Ok(full)
}

/// The Schur complement on the host after a factorization (its upper
/// triangle column-major; empty elsewhere): MUMPS' own array, or the
/// distributed parts gathered.
pub(super) fn host_schur<'a, C: Communicator>(
    world: &C,
    mumps: &'a Mumps,
    m: usize,
    distributed: bool,
) -> Result<std::borrow::Cow<'a, [f64]>, Error> {
    Ok(if distributed {
        std::borrow::Cow::Owned(gather_schur(world, mumps.schur_local(), m, SCHUR_BLOCK)?)
    } else {
        std::borrow::Cow::Borrowed(mumps.schur_upper())
    })
}
