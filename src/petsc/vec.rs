//! PETSc vectors (`Vec`) and the gather of chosen entries (`VecScatter`).

use super::{check, comm_self, ensure_running, running, slice_from, slice_from_mut, sys};
use crate::error::Error;

/// A distributed PETSc vector (`Vec`).
///
/// Invariant: `raw` is a Vec that PETSc made and that is not destroyed, of
/// which this value owns one reference (null only while a constructor
/// fails, which `VecDestroy` accepts).
pub struct Vector {
    pub(super) raw: sys::Vec,
}

impl Drop for Vector {
    fn drop(&mut self) {
        if running() {
            // SAFETY: our reference to a live Vec (the invariant), given up
            // once, while PETSc runs.
            unsafe { sys::VecDestroy(&mut self.raw) };
        }
    }
}

impl Vector {
    /// An MPI vector with `local` entries on this rank and block size `bs`.
    pub fn new(comm: sys::MPI_Comm, local: usize, bs: usize) -> Result<Vector, Error> {
        ensure_running()?;
        let mut raw: sys::Vec = std::ptr::null_mut();
        // SAFETY: `comm` is a live communicator (the module's contract);
        // PETSc writes a new Vec into `raw`.
        check(unsafe { sys::VecCreate(comm, &mut raw) })?;
        let v = Vector { raw };
        let n = local as sys::PetscInt;
        // SAFETY: v.raw is live (the invariant).
        check(unsafe { sys::VecSetSizes(v.raw, n, sys::PETSC_DETERMINE) })?;
        // SAFETY: v.raw is live.
        check(unsafe { sys::VecSetBlockSize(v.raw, bs as sys::PetscInt) })?;
        // SAFETY: v.raw is live; the type's name is a static C string.
        check(unsafe { sys::VecSetType(v.raw, sys::VECSTANDARD.as_ptr() as *const _) })?;
        Ok(v)
    }

    /// A sequential vector of `n` entries on this rank alone.
    pub fn new_seq(n: usize) -> Result<Vector, Error> {
        ensure_running()?;
        let mut raw: sys::Vec = std::ptr::null_mut();
        // SAFETY: PETSc writes a new Vec into `raw`.
        check(unsafe { sys::VecCreateSeq(comm_self(), n as sys::PetscInt, &mut raw) })?;
        Ok(Vector { raw })
    }

    pub fn duplicate(&self) -> Result<Vector, Error> {
        ensure_running()?;
        let mut raw: sys::Vec = std::ptr::null_mut();
        // SAFETY: self.raw is live; PETSc writes a new Vec into `raw`.
        check(unsafe { sys::VecDuplicate(self.raw, &mut raw) })?;
        Ok(Vector { raw })
    }

    pub fn set(&self, value: f64) -> Result<(), Error> {
        // SAFETY: self.raw is live.
        check(unsafe { sys::VecSet(self.raw, value) })
    }

    pub fn copy_from(&self, other: &Vector) -> Result<(), Error> {
        // SAFETY: both are live (PETSc checks that their layouts agree).
        check(unsafe { sys::VecCopy(other.raw, self.raw) })
    }

    /// `self += alpha * x`.
    pub fn axpy(&self, alpha: f64, x: &Vector) -> Result<(), Error> {
        // SAFETY: both are live (PETSc checks that their layouts agree).
        check(unsafe { sys::VecAXPY(self.raw, alpha, x.raw) })
    }

    pub fn norm2(&self) -> Result<f64, Error> {
        let mut n = 0.0;
        // SAFETY: self.raw is live; PETSc writes one real into `n`.
        check(unsafe { sys::VecNorm(self.raw, sys::NORM_2, &mut n) })?;
        Ok(n)
    }

    pub fn local_size(&self) -> Result<usize, Error> {
        let mut n: sys::PetscInt = 0;
        // SAFETY: self.raw is live; PETSc writes one integer into `n`.
        check(unsafe { sys::VecGetLocalSize(self.raw, &mut n) })?;
        Ok(n as usize)
    }

    /// Reads the locally owned entries. (`f` must not change this vector
    /// through its other methods.)
    pub fn read<R>(&self, f: impl FnOnce(&[f64]) -> R) -> Result<R, Error> {
        let n = self.local_size()?;
        let mut ptr: *const f64 = std::ptr::null();
        // SAFETY: self.raw is live; PETSc writes the address of its local
        // entries into `ptr`, readable until the restore below.
        check(unsafe { sys::VecGetArrayRead(self.raw, &mut ptr) })?;
        // SAFETY: `ptr` points to the n local entries, valid until the
        // restore below; the slice does not outlive `f` (R cannot borrow
        // it), and nothing writes the vector meanwhile (the contract on f).
        let r = f(unsafe { slice_from(ptr, n) });
        // SAFETY: gives back the array got above, once.
        check(unsafe { sys::VecRestoreArrayRead(self.raw, &mut ptr) })?;
        Ok(r)
    }

    /// Writes the locally owned entries. (`f` must not read or change this
    /// vector through its other methods.)
    pub fn write<R>(&self, f: impl FnOnce(&mut [f64]) -> R) -> Result<R, Error> {
        let n = self.local_size()?;
        let mut ptr: *mut f64 = std::ptr::null_mut();
        // SAFETY: self.raw is live; PETSc writes the address of its local
        // entries into `ptr`, writable until the restore below.
        check(unsafe { sys::VecGetArray(self.raw, &mut ptr) })?;
        // SAFETY: `ptr` points to the n local entries, ours until the
        // restore below; the slice does not outlive `f` (R cannot borrow
        // it), and nothing else touches the vector meanwhile (the contract
        // on f).
        let r = f(unsafe { slice_from_mut(ptr, n) });
        // SAFETY: gives back the array got above, once.
        check(unsafe { sys::VecRestoreArray(self.raw, &mut ptr) })?;
        Ok(r)
    }
}

/// Gathers chosen entries of a distributed vector into a local sequential one
/// (e.g. the displacement at the ghost nodes of a rank's cells).
///
/// Invariant: `scatter` is a live VecScatter of ours, from vectors laid out
/// like the one given to [`Gather::new`] to `local` (null only while the
/// constructor fails, which `VecScatterDestroy` accepts).
pub struct Gather {
    scatter: sys::VecScatter,
    pub local: Vector,
}

impl Drop for Gather {
    fn drop(&mut self) {
        if running() {
            // SAFETY: our live scatter (the invariant), destroyed once,
            // while PETSc runs.
            unsafe { sys::VecScatterDestroy(&mut self.scatter) };
        }
    }
}

impl Gather {
    /// Entries `indices` (global) of vectors laid out like `like`.
    pub fn new(like: &Vector, indices: &[sys::PetscInt]) -> Result<Gather, Error> {
        let n = indices.len() as sys::PetscInt;
        let local = Vector::new_seq(indices.len())?;
        let mut from: sys::IS = std::ptr::null_mut();
        // SAFETY: `indices` holds n integers, which PETSc copies
        // (PETSC_COPY_VALUES); it writes a new index set into `from`.
        check(unsafe {
            sys::ISCreateGeneral(
                comm_self(),
                n,
                indices.as_ptr(),
                sys::PETSC_COPY_VALUES,
                &mut from,
            )
        })?;
        let mut scatter: sys::VecScatter = std::ptr::null_mut();
        // SAFETY: `like`, `local` and `from` are live (the destination's
        // indices null: all of `local`, in order); PETSc writes a new
        // scatter into `scatter`.
        let r = unsafe {
            sys::VecScatterCreate(
                like.raw,
                from,
                local.raw,
                std::ptr::null_mut(),
                &mut scatter,
            )
        };
        // SAFETY: the index set made above, destroyed once (the scatter
        // keeps what it needs).
        let d = unsafe { sys::ISDestroy(&mut from) };
        // Owned (destroyed on an error below) whatever the codes.
        let gather = Gather { scatter, local };
        check(r)?;
        check(d)?;
        Ok(gather)
    }

    /// Copies the chosen entries of `x` into `self.local` (collective).
    pub fn gather(&self, x: &Vector) -> Result<(), Error> {
        let (insert, forward) = (sys::INSERT_VALUES, sys::SCATTER_FORWARD);
        // SAFETY: the scatter, `x` and `self.local` are live, `x` laid out
        // like the vector the scatter was made for (PETSc checks).
        check(unsafe {
            sys::VecScatterBegin(self.scatter, x.raw, self.local.raw, insert, forward)
        })?;
        // SAFETY: as above; ends the scatter begun just above.
        check(unsafe { sys::VecScatterEnd(self.scatter, x.raw, self.local.raw, insert, forward) })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No PETSc object before PETSc runs: an error, not a crash. (No lib
    /// test initializes PETSc in this process.)
    #[test]
    fn a_vector_is_refused_before_petsc_runs() {
        assert!(!running());
        assert!(matches!(Vector::new_seq(3), Err(Error::Internal(_))));
    }

    /// A vector dropped after `PetscFinalize` is left alone, and none can
    /// be made then. Initializes MPI and PETSc in the test process, so it
    /// runs alone: `cargo test --release --lib -- --ignored --test-threads=1
    /// drop_after_finalize`.
    #[test]
    #[ignore = "initializes MPI and PETSc in the test process"]
    fn drop_after_finalize_is_harmless() {
        use mpi::traits::AsRaw;
        let universe = mpi::initialize().expect("MPI starts");
        let world = universe.world();
        let petsc = super::super::Petsc::init(world.as_raw(), &["test".to_string()]).unwrap();
        assert!(super::super::Petsc::init(world.as_raw(), &[]).is_err());
        let v = Vector::new_seq(4).unwrap();
        v.set(1.0).unwrap();
        assert_eq!(v.norm2().unwrap(), 2.0);
        drop(petsc);
        assert!(!running());
        assert!(Vector::new_seq(1).is_err());
        drop(v);
    }
}
