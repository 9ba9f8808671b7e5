//! A graph partition in parallel: PT-Scotch (`SCOTCH_dgraphPart`) through
//! PETSc's `MatPartitioning` (Debian's PETSc is built with it and links
//! `libptscotch`; nothing else to link). Each rank gives the rows of the
//! graph it holds and gets back the part of each of them.

use super::{check, ensure_running, slice_from, sys, Matrix};
use crate::error::Error;
use std::ffi::c_void;

/// A copy of `v` in memory from `PetscMalloc` (at least one entry), which a
/// `MATMPIADJ` matrix takes over and frees with `PetscFree`.
fn petsc_copy(v: &[sys::PetscInt]) -> Result<*mut sys::PetscInt, Error> {
    let bytes = v.len().max(1) * std::mem::size_of::<sys::PetscInt>();
    let mut p: *mut sys::PetscInt = std::ptr::null_mut();
    // SAFETY: PetscMallocA (as PetscMalloc1 calls it: one array, not
    // cleared) writes the address of `bytes` fresh bytes, aligned for any
    // type, into `p`; the names are static C strings.
    check(unsafe {
        sys::PetscMallocA(
            1,
            sys::PETSC_FALSE,
            line!() as i32,
            c"petsc_copy".as_ptr(),
            c"partition.rs".as_ptr(),
            bytes,
            &mut p as *mut *mut sys::PetscInt as *mut c_void,
        )
    })?;
    // SAFETY: `p` holds `bytes` >= v.len() entries, fresh (no overlap).
    unsafe { std::ptr::copy_nonoverlapping(v.as_ptr(), p, v.len()) };
    Ok(p)
}

/// PETSc's partitioning context, destroyed on drop.
///
/// Invariant: `raw` is a MatPartitioning that PETSc made and that is not
/// destroyed (null only while the constructor fails, which
/// `MatPartitioningDestroy` accepts).
struct Partitioning {
    raw: sys::MatPartitioning,
}

impl Drop for Partitioning {
    fn drop(&mut self) {
        if super::running() {
            // SAFETY: our reference to a live context (the invariant),
            // given up once, while PETSc runs.
            unsafe { sys::MatPartitioningDestroy(&mut self.raw) };
        }
    }
}

/// The parts (0 to the size of `comm` - 1) of this rank's vertices of a
/// graph of `n_global` vertices split over the ranks of `comm` (live) in
/// contiguous blocks in rank order: this rank's block has `xadj.len() - 1`
/// vertices, vertex `i`'s neighbours are the global vertex numbers
/// `adjncy[xadj[i]..xadj[i + 1]]` (increasing, without `i` itself; every
/// edge given from both ends). PT-Scotch's default strategy, imbalance
/// 1%. Collective; every rank needs at least one vertex.
pub fn ptscotch(
    comm: sys::MPI_Comm,
    n_global: usize,
    xadj: &[sys::PetscInt],
    adjncy: &[sys::PetscInt],
) -> Result<Vec<usize>, Error> {
    ensure_running()?;
    let local = xadj.len().saturating_sub(1);
    let i = petsc_copy(xadj)?;
    let j = petsc_copy(adjncy)?;
    let mut adj = Matrix {
        raw: std::ptr::null_mut(),
    };
    // SAFETY: `comm` is live (the contract); `i` and `j` are PetscMalloc'd
    // arrays of local + 1 row pointers and of their column numbers, which
    // the matrix takes over (freed with it; a failure here leaks them);
    // no weights (null); PETSc writes the new matrix into `adj.raw`.
    check(unsafe {
        sys::MatCreateMPIAdj(
            comm,
            local as sys::PetscInt,
            n_global as sys::PetscInt,
            i,
            j,
            std::ptr::null_mut(),
            &mut adj.raw,
        )
    })?;
    let mut part = Partitioning {
        raw: std::ptr::null_mut(),
    };
    // SAFETY: `comm` is live; PETSc writes a new context into `part.raw`.
    check(unsafe { sys::MatPartitioningCreate(comm, &mut part.raw) })?;
    // SAFETY: both live; the context takes its own reference to the graph.
    check(unsafe { sys::MatPartitioningSetAdjacency(part.raw, adj.raw) })?;
    let kind = sys::MATPARTITIONINGPTSCOTCH.as_ptr() as *const std::ffi::c_char;
    // SAFETY: a live context and PETSc's static name of a registered type.
    check(unsafe { sys::MatPartitioningSetType(part.raw, kind) })?;
    let mut is: sys::IS = std::ptr::null_mut();
    // SAFETY: a live context with its graph and type set; PETSc writes a
    // new index set (the part of each local vertex) into `is`.
    check(unsafe { sys::MatPartitioningApply(part.raw, &mut is) })?;
    let parts = read_parts(is, local);
    // SAFETY: the index set made above, ours, destroyed once.
    let d = unsafe { sys::ISDestroy(&mut is) };
    let parts = parts?;
    check(d)?;
    Ok(parts)
}

/// The `local` entries of the live index set `is`, as parts.
fn read_parts(is: sys::IS, local: usize) -> Result<Vec<usize>, Error> {
    let mut size: sys::PetscInt = 0;
    // SAFETY: `is` is live; PETSc writes its local size.
    check(unsafe { sys::ISGetLocalSize(is, &mut size) })?;
    if size as usize != local {
        return Err(Error::Internal(format!(
            "PT-Scotch returned {size} parts for {local} vertices"
        )));
    }
    let mut idx: *const sys::PetscInt = std::ptr::null();
    // SAFETY: `is` is live; PETSc writes the address of its `size` entries.
    check(unsafe { sys::ISGetIndices(is, &mut idx) })?;
    // SAFETY: `size` entries at `idx`, unchanged until restored below.
    let parts = unsafe { slice_from(idx, local) }
        .iter()
        .map(|&p| p.max(0) as usize)
        .collect();
    // SAFETY: gives back the array got above, once.
    check(unsafe { sys::ISRestoreIndices(is, &mut idx) })?;
    Ok(parts)
}
