//! RAII wrappers for the PETSc objects the solver uses: Vec, Mat, KSP, MatNullSpace.

use super::{check, sys};
use crate::error::Error;
use std::ffi::CStr;

/// A distributed PETSc vector (`Vec`).
pub struct Vector {
    pub(crate) raw: sys::Vec,
}

impl Drop for Vector {
    fn drop(&mut self) {
        unsafe {
            sys::VecDestroy(&mut self.raw);
        }
    }
}

impl Vector {
    /// An MPI vector with `local` entries on this rank and block size `bs`.
    pub fn new(comm: sys::MPI_Comm, local: usize, bs: usize) -> Result<Vector, Error> {
        let mut raw: sys::Vec = std::ptr::null_mut();
        unsafe {
            check(sys::VecCreate(comm, &mut raw))?;
            let v = Vector { raw };
            check(sys::VecSetSizes(
                v.raw,
                local as sys::PetscInt,
                sys::PETSC_DETERMINE,
            ))?;
            check(sys::VecSetBlockSize(v.raw, bs as sys::PetscInt))?;
            check(sys::VecSetType(
                v.raw,
                sys::VECSTANDARD.as_ptr() as *const _,
            ))?;
            Ok(v)
        }
    }

    /// A sequential vector of `n` entries on this rank alone.
    pub fn new_seq(n: usize) -> Result<Vector, Error> {
        let mut raw: sys::Vec = std::ptr::null_mut();
        unsafe {
            check(sys::VecCreateSeq(
                super::comm_self(),
                n as sys::PetscInt,
                &mut raw,
            ))?
        };
        Ok(Vector { raw })
    }

    pub fn duplicate(&self) -> Result<Vector, Error> {
        let mut raw: sys::Vec = std::ptr::null_mut();
        unsafe { check(sys::VecDuplicate(self.raw, &mut raw))? };
        Ok(Vector { raw })
    }

    pub fn set(&self, value: f64) -> Result<(), Error> {
        unsafe { check(sys::VecSet(self.raw, value)) }
    }

    pub fn copy_from(&self, other: &Vector) -> Result<(), Error> {
        unsafe { check(sys::VecCopy(other.raw, self.raw)) }
    }

    /// `self += alpha * x`.
    pub fn axpy(&self, alpha: f64, x: &Vector) -> Result<(), Error> {
        unsafe { check(sys::VecAXPY(self.raw, alpha, x.raw)) }
    }

    pub fn norm2(&self) -> Result<f64, Error> {
        let mut n = 0.0;
        unsafe { check(sys::VecNorm(self.raw, sys::NORM_2, &mut n))? };
        Ok(n)
    }

    pub fn local_size(&self) -> Result<usize, Error> {
        let mut n: sys::PetscInt = 0;
        unsafe { check(sys::VecGetLocalSize(self.raw, &mut n))? };
        Ok(n as usize)
    }

    /// Reads the locally owned entries.
    pub fn read<R>(&self, f: impl FnOnce(&[f64]) -> R) -> Result<R, Error> {
        let n = self.local_size()?;
        let mut ptr: *const f64 = std::ptr::null();
        unsafe { check(sys::VecGetArrayRead(self.raw, &mut ptr))? };
        let slice = if n == 0 {
            &[][..]
        } else {
            unsafe { std::slice::from_raw_parts(ptr, n) }
        };
        let r = f(slice);
        unsafe { check(sys::VecRestoreArrayRead(self.raw, &mut ptr))? };
        Ok(r)
    }

    /// Writes the locally owned entries.
    pub fn write<R>(&self, f: impl FnOnce(&mut [f64]) -> R) -> Result<R, Error> {
        let n = self.local_size()?;
        let mut ptr: *mut f64 = std::ptr::null_mut();
        unsafe { check(sys::VecGetArray(self.raw, &mut ptr))? };
        let slice = if n == 0 {
            &mut [][..]
        } else {
            unsafe { std::slice::from_raw_parts_mut(ptr, n) }
        };
        let r = f(slice);
        unsafe { check(sys::VecRestoreArray(self.raw, &mut ptr))? };
        Ok(r)
    }
}

/// A distributed sparse matrix (`MATAIJ`).
pub struct Matrix {
    pub(crate) raw: sys::Mat,
}

/// Compressed rows: row pointers, column indices, values.
type Csr = (Vec<sys::PetscInt>, Vec<sys::PetscInt>, Vec<f64>);

/// The arrays a matrix made on them lives in, freed by PETSc's container
/// when the matrix itself is destroyed (its last reference, a KSP's or a
/// SNES's included), not when our wrapper is.
unsafe extern "C" fn free_csr_arrays(p: *mut std::ffi::c_void) -> sys::PetscErrorCode {
    drop(Box::from_raw(p as *mut Vec<Csr>));
    0
}

/// Hands `arrays` to `mat`: composed with it in a container whose destroy
/// frees them.
fn attach_arrays(mat: sys::Mat, arrays: Vec<Csr>) -> Result<(), Error> {
    let p = Box::into_raw(Box::new(arrays)) as *mut std::ffi::c_void;
    let mut c: sys::PetscContainer = std::ptr::null_mut();
    unsafe {
        let r = sys::PetscContainerCreate(super::comm_self(), &mut c);
        if r != 0 {
            drop(Box::from_raw(p as *mut Vec<Csr>));
            return check(r);
        }
        check(sys::PetscContainerSetPointer(c, p))?;
        check(sys::PetscContainerSetUserDestroy(c, Some(free_csr_arrays)))?;
        let name = std::ffi::CString::new("ubr_csr_arrays").expect("no NUL");
        let r = sys::PetscObjectCompose(
            mat as sys::PetscObject,
            name.as_ptr(),
            c as sys::PetscObject,
        );
        sys::PetscContainerDestroy(&mut c); // the matrix holds it now
        check(r)
    }
}

impl Drop for Matrix {
    fn drop(&mut self) {
        unsafe {
            sys::MatDestroy(&mut self.raw);
        }
    }
}

/// What `MatGetInfo` says of an assembled matrix (summed over ranks).
#[derive(Clone, Copy, Debug)]
pub struct MatStats {
    pub nonzeros_used: f64,
    pub nonzeros_allocated: f64,
    pub mallocs: f64,
}

impl Matrix {
    /// An assembled AIJ matrix with `local` rows and columns on this rank and
    /// block size `bs`, from the compressed rows of this rank: row i has the
    /// global columns `cols[rowptr[i]..rowptr[i + 1]]` (increasing) and the
    /// values at the same positions. PETSc's matrix lives on these arrays
    /// (one rank) or on their split into the owned and the other columns
    /// (several), which PETSc's matrix keeps (in a composed container)
    /// until it is destroyed: no copy entry by entry. A later entry outside
    /// the pattern is an error; no entry goes to another rank.
    pub fn new_aij_csr(
        comm: sys::MPI_Comm,
        local: usize,
        bs: usize,
        rowptr: Vec<sys::PetscInt>,
        cols: Vec<sys::PetscInt>,
        vals: Vec<f64>,
    ) -> Result<Matrix, Error> {
        assert_eq!(rowptr.len(), local + 1);
        assert_eq!(cols.len(), vals.len());
        let mut size = 0;
        unsafe { mpi::ffi::MPI_Comm_size(comm, &mut size) };
        if size == 1 {
            // One rank: PETSc's matrix on the arrays themselves, which it
            // keeps (the preallocation route copies them entry by entry:
            // block3d_17887 28 ms).
            let (mut rowptr, mut cols, mut vals) = (rowptr, cols, vals);
            let n = local as sys::PetscInt;
            let mut raw: sys::Mat = std::ptr::null_mut();
            unsafe {
                check(sys::MatCreateSeqAIJWithArrays(
                    comm,
                    n,
                    n,
                    rowptr.as_mut_ptr(),
                    cols.as_mut_ptr(),
                    vals.as_mut_ptr(),
                    &mut raw,
                ))?;
            }
            // (Moving the vectors moves no element: the pointers stay valid.)
            let m = Matrix { raw };
            attach_arrays(m.raw, vec![(rowptr, cols, vals)])?;
            unsafe { check(sys::MatSetBlockSize(m.raw, bs as sys::PetscInt))? };
            m.set_flag(sys::MAT_NEW_NONZERO_ALLOCATION_ERR)?;
            m.set_flag(sys::MAT_NO_OFF_PROC_ENTRIES)?;
            return Ok(m);
        }
        // Several ranks: the rows split into their "diagonal" part (the
        // columns this rank owns, numbered from its first) and the others
        // (global numbers), PETSc's matrix on these arrays themselves
        // (MatCreateMPIAIJWithSplitArrays; the preallocation route copies
        // entry by entry).
        let mut end = 0u64;
        let count = local as u64;
        unsafe {
            mpi::ffi::MPI_Scan(
                &count as *const u64 as *const std::ffi::c_void,
                &mut end as *mut u64 as *mut std::ffi::c_void,
                1,
                mpi::ffi::RSMPI_UINT64_T,
                mpi::ffi::RSMPI_SUM,
                comm,
            );
        }
        let (lo, hi) = ((end - count) as sys::PetscInt, end as sys::PetscInt);
        let owned = |c: &sys::PetscInt| (lo..hi).contains(c);
        let nd = cols.iter().filter(|c| owned(c)).count();
        let no = cols.len() - nd;
        let mut di: Vec<sys::PetscInt> = Vec::with_capacity(local + 1);
        let mut oi: Vec<sys::PetscInt> = Vec::with_capacity(local + 1);
        let (mut dj, mut da) = (Vec::with_capacity(nd), Vec::with_capacity(nd));
        let (mut oj, mut oa) = (Vec::with_capacity(no), Vec::with_capacity(no));
        di.push(0);
        oi.push(0);
        for r in 0..local {
            for k in rowptr[r] as usize..rowptr[r + 1] as usize {
                let c = cols[k];
                if owned(&c) {
                    dj.push(c - lo);
                    da.push(vals[k]);
                } else {
                    oj.push(c);
                    oa.push(vals[k]);
                }
            }
            di.push(dj.len() as sys::PetscInt);
            oi.push(oj.len() as sys::PetscInt);
        }
        drop((rowptr, cols, vals));
        let n = local as sys::PetscInt;
        let mut raw: sys::Mat = std::ptr::null_mut();
        unsafe {
            check(sys::MatCreateMPIAIJWithSplitArrays(
                comm,
                n,
                n,
                sys::PETSC_DETERMINE,
                sys::PETSC_DETERMINE,
                di.as_mut_ptr(),
                dj.as_mut_ptr(),
                da.as_mut_ptr(),
                oi.as_mut_ptr(),
                oj.as_mut_ptr(),
                oa.as_mut_ptr(),
                &mut raw,
            ))?;
        }
        let m = Matrix { raw };
        attach_arrays(m.raw, vec![(di, dj, da), (oi, oj, oa)])?;
        unsafe { check(sys::MatSetBlockSize(m.raw, bs as sys::PetscInt))? };
        m.set_flag(sys::MAT_NEW_NONZERO_ALLOCATION_ERR)?;
        m.set_flag(sys::MAT_NO_OFF_PROC_ENTRIES)?;
        Ok(m)
    }

    /// A matrix of type `ty` with `local` rows and columns on this rank,
    /// not yet preallocated.
    fn empty(
        comm: sys::MPI_Comm,
        local: usize,
        ty: &[u8],
        bs: Option<usize>,
    ) -> Result<Matrix, Error> {
        let mut raw: sys::Mat = std::ptr::null_mut();
        unsafe {
            check(sys::MatCreate(comm, &mut raw))?;
            let m = Matrix { raw };
            let n = local as sys::PetscInt;
            check(sys::MatSetSizes(
                m.raw,
                n,
                n,
                sys::PETSC_DETERMINE,
                sys::PETSC_DETERMINE,
            ))?;
            if let Some(bs) = bs {
                check(sys::MatSetBlockSize(m.raw, bs as sys::PetscInt))?;
            }
            check(sys::MatSetType(m.raw, ty.as_ptr() as *const _))?;
            Ok(m)
        }
    }

    fn set_flag(&self, option: sys::MatOption) -> Result<(), Error> {
        unsafe { check(sys::MatSetOption(self.raw, option, sys::PETSC_TRUE)) }
    }

    /// Adds a dense block; rows given as -1 are skipped (PETSc ignores negative indices).
    pub fn add_values(
        &self,
        rows: &[sys::PetscInt],
        cols: &[sys::PetscInt],
        vals: &[f64],
    ) -> Result<(), Error> {
        debug_assert_eq!(rows.len() * cols.len(), vals.len());
        unsafe {
            check(sys::MatSetValues(
                self.raw,
                rows.len() as sys::PetscInt,
                rows.as_ptr(),
                cols.len() as sys::PetscInt,
                cols.as_ptr(),
                vals.as_ptr(),
                sys::ADD_VALUES,
            ))
        }
    }

    pub fn assemble(&self) -> Result<(), Error> {
        unsafe {
            check(sys::MatAssemblyBegin(self.raw, sys::MAT_FINAL_ASSEMBLY))?;
            check(sys::MatAssemblyEnd(self.raw, sys::MAT_FINAL_ASSEMBLY))
        }
    }

    pub fn set_spd(&self) -> Result<(), Error> {
        unsafe {
            check(sys::MatSetOption(self.raw, sys::MAT_SPD, sys::PETSC_TRUE))?;
            check(sys::MatSetOption(
                self.raw,
                sys::MAT_SYMMETRIC,
                sys::PETSC_TRUE,
            ))?;
            check(sys::MatSetOption(
                self.raw,
                sys::MAT_SYMMETRY_ETERNAL,
                sys::PETSC_TRUE,
            ))
        }
    }

    /// The upper block triangle of this symmetric matrix in symmetric block
    /// storage (SBAIJ, `bs x bs` blocks), built from its rows through a
    /// block CSR (MatConvert's generic path inserts entry by entry: 30 s on
    /// 136k nodes). A matrix-vector product reads about half the bytes of
    /// AIJ's.
    pub fn sbaij_copy(&self, comm: sys::MPI_Comm, bs: usize) -> Result<Matrix, Error> {
        let (mut rstart, mut rend): (sys::PetscInt, sys::PetscInt) = (0, 0);
        unsafe { check(sys::MatGetOwnershipRange(self.raw, &mut rstart, &mut rend))? };
        let n = (rend - rstart) as usize;
        assert_eq!(n % bs, 0);
        assert_eq!(rstart as usize % bs, 0);
        let (nb, bs2) = (n / bs, bs * bs);
        let first_block = rstart as usize / bs;
        let mut ii: Vec<sys::PetscInt> = Vec::with_capacity(nb + 1);
        ii.push(0);
        let mut jj: Vec<sys::PetscInt> = Vec::new();
        let mut vv: Vec<f64> = Vec::new();
        for ib in 0..nb {
            let gi = (first_block + ib) as sys::PetscInt;
            let start = jj.len();
            for a in 0..bs {
                let row = rstart + (ib * bs + a) as sys::PetscInt;
                let mut ncols: sys::PetscInt = 0;
                let mut cols: *const sys::PetscInt = std::ptr::null();
                let mut vals: *const f64 = std::ptr::null();
                unsafe {
                    check(sys::MatGetRow(
                        self.raw, row, &mut ncols, &mut cols, &mut vals,
                    ))?
                };
                let (cs, vs) = unsafe {
                    (
                        std::slice::from_raw_parts(cols, ncols as usize),
                        std::slice::from_raw_parts(vals, ncols as usize),
                    )
                };
                for (&c, &v) in cs.iter().zip(vs) {
                    let jb = c / bs as sys::PetscInt;
                    if jb < gi {
                        continue;
                    }
                    let k = match jj[start..].binary_search(&jb) {
                        Ok(k) => k,
                        Err(k) => {
                            // Rows of one block row share their blocks: a
                            // new block comes at the end but for rare rows.
                            jj.insert(start + k, jb);
                            let at = (start + k) * bs2;
                            vv.splice(at..at, std::iter::repeat_n(0.0, bs2));
                            k
                        }
                    };
                    vv[(start + k) * bs2 + a * bs + (c as usize % bs)] = v;
                }
                unsafe {
                    check(sys::MatRestoreRow(
                        self.raw, row, &mut ncols, &mut cols, &mut vals,
                    ))?
                };
            }
            ii.push(jj.len() as sys::PetscInt);
        }
        let m = Matrix::empty(comm, n, sys::MATSBAIJ, None)?;
        unsafe {
            let b = bs as sys::PetscInt;
            // Each is a no-op for the other type (one rank: seqsbaij).
            check(sys::MatSeqSBAIJSetPreallocationCSR(
                m.raw,
                b,
                ii.as_ptr(),
                jj.as_ptr(),
                vv.as_ptr(),
            ))?;
            check(sys::MatMPISBAIJSetPreallocationCSR(
                m.raw,
                b,
                ii.as_ptr(),
                jj.as_ptr(),
                vv.as_ptr(),
            ))?;
        }
        // Contact blocks added later (a change of r) come whole.
        m.set_flag(sys::MAT_IGNORE_LOWER_TRIANGULAR)?;
        m.set_flag(sys::MAT_NO_OFF_PROC_ENTRIES)?;
        Ok(m)
    }

    /// `y = A x`.
    pub fn mult(&self, x: &Vector, y: &Vector) -> Result<(), Error> {
        unsafe { check(sys::MatMult(self.raw, x.raw, y.raw)) }
    }

    /// Zeroes the given global rows and columns and puts `diag` on the diagonal.
    pub fn zero_rows_columns(&self, rows: &[sys::PetscInt], diag: f64) -> Result<(), Error> {
        unsafe {
            check(sys::MatZeroRowsColumns(
                self.raw,
                rows.len() as sys::PetscInt,
                rows.as_ptr(),
                diag,
                std::ptr::null_mut(),
                std::ptr::null_mut(),
            ))
        }
    }

    pub fn diagonal(&self, d: &Vector) -> Result<(), Error> {
        unsafe { check(sys::MatGetDiagonal(self.raw, d.raw)) }
    }

    /// This rank's rows as visited by `f(row, cols, vals)` (global,
    /// 0-based; columns increasing), in row order.
    pub fn for_each_owned_row(
        &self,
        mut f: impl FnMut(usize, &[sys::PetscInt], &[f64]),
    ) -> Result<(), Error> {
        let (mut lo, mut hi): (sys::PetscInt, sys::PetscInt) = (0, 0);
        unsafe { check(sys::MatGetOwnershipRange(self.raw, &mut lo, &mut hi))? };
        for row in lo..hi {
            let mut ncols: sys::PetscInt = 0;
            let mut cols: *const sys::PetscInt = std::ptr::null();
            let mut vals: *const f64 = std::ptr::null();
            unsafe {
                check(sys::MatGetRow(
                    self.raw, row, &mut ncols, &mut cols, &mut vals,
                ))?;
                let n = ncols as usize;
                let (c, v) = if n == 0 {
                    (&[][..], &[][..])
                } else {
                    (
                        std::slice::from_raw_parts(cols, n),
                        std::slice::from_raw_parts(vals, n),
                    )
                };
                f(row as usize, c, v);
                check(sys::MatRestoreRow(
                    self.raw, row, &mut ncols, &mut cols, &mut vals,
                ))?;
            }
        }
        Ok(())
    }

    pub fn stats(&self) -> Result<MatStats, Error> {
        let mut info = sys::MatInfo::default();
        unsafe { check(sys::MatGetInfo(self.raw, sys::MAT_GLOBAL_SUM, &mut info))? };
        Ok(MatStats {
            nonzeros_used: info.nz_used,
            nonzeros_allocated: info.nz_allocated,
            mallocs: info.mallocs,
        })
    }

    /// A copy of this matrix, values included.
    pub fn duplicate(&self) -> Result<Matrix, Error> {
        let mut raw: sys::Mat = std::ptr::null_mut();
        unsafe { check(sys::MatDuplicate(self.raw, sys::MAT_COPY_VALUES, &mut raw))? };
        Ok(Matrix { raw })
    }

    /// Copies the values of `other` (same nonzero pattern) into this matrix.
    pub fn copy_from(&self, other: &Matrix) -> Result<(), Error> {
        unsafe { check(sys::MatCopy(other.raw, self.raw, sys::SAME_NONZERO_PATTERN)) }
    }

    pub fn set_near_nullspace(&self, ns: &NullSpace) -> Result<(), Error> {
        unsafe { check(sys::MatSetNearNullSpace(self.raw, ns.raw)) }
    }
}

/// A (near-)null space, e.g. the rigid-body modes built from coordinates.
pub struct NullSpace {
    raw: sys::MatNullSpace,
}

impl Drop for NullSpace {
    fn drop(&mut self) {
        unsafe {
            sys::MatNullSpaceDestroy(&mut self.raw);
        }
    }
}

impl NullSpace {
    /// Rigid-body modes from a coordinate vector whose block size is the dimension.
    pub fn rigid_body(coords: &Vector) -> Result<NullSpace, Error> {
        let mut raw: sys::MatNullSpace = std::ptr::null_mut();
        unsafe { check(sys::MatNullSpaceCreateRigidBody(coords.raw, &mut raw))? };
        Ok(NullSpace { raw })
    }
}

/// A Krylov solver (`KSP`) with its preconditioner.
pub struct Ksp {
    raw: sys::KSP,
}

impl Drop for Ksp {
    fn drop(&mut self) {
        unsafe {
            sys::KSPDestroy(&mut self.raw);
        }
    }
}

impl Ksp {
    pub fn new(comm: sys::MPI_Comm) -> Result<Ksp, Error> {
        let mut raw: sys::KSP = std::ptr::null_mut();
        unsafe { check(sys::KSPCreate(comm, &mut raw))? };
        Ok(Ksp { raw })
    }

    pub fn set_operators(&self, a: &Matrix) -> Result<(), Error> {
        unsafe { check(sys::KSPSetOperators(self.raw, a.raw, a.raw)) }
    }

    /// The operator `a` (products) and the matrix `p` the preconditioner is
    /// built from.
    pub fn set_operators_split(&self, a: &Matrix, p: &Matrix) -> Result<(), Error> {
        unsafe { check(sys::KSPSetOperators(self.raw, a.raw, p.raw)) }
    }

    /// Reads `-ksp_*` and `-pc_*`: the user's choice wins over the defaults
    /// set before this call.
    pub fn set_from_options(&self) -> Result<(), Error> {
        unsafe { check(sys::KSPSetFromOptions(self.raw)) }
    }

    pub fn set_up(&self) -> Result<(), Error> {
        unsafe { check(sys::KSPSetUp(self.raw)) }
    }

    pub fn set_initial_guess_nonzero(&self, yes: bool) -> Result<(), Error> {
        let flag = if yes {
            sys::PETSC_TRUE
        } else {
            sys::PETSC_FALSE
        };
        unsafe { check(sys::KSPSetInitialGuessNonzero(self.raw, flag)) }
    }

    pub fn set_rtol(&self, rtol: f64) -> Result<(), Error> {
        unsafe {
            check(sys::KSPSetTolerances(
                self.raw,
                rtol,
                sys::PETSC_DEFAULT as f64,
                sys::PETSC_DEFAULT as f64,
                sys::PETSC_DEFAULT,
            ))
        }
    }

    /// Solves `A x = b`; a solve that PETSc reports as diverged (a failed
    /// factorization, a breakdown, too many iterations) is an error.
    pub fn solve(&self, b: &Vector, x: &Vector) -> Result<usize, Error> {
        unsafe { check(sys::KSPSolve(self.raw, b.raw, x.raw))? };
        let mut reason: sys::KSPConvergedReason = 0;
        let mut its: sys::PetscInt = 0;
        unsafe {
            check(sys::KSPGetConvergedReason(self.raw, &mut reason))?;
            check(sys::KSPGetIterationNumber(self.raw, &mut its))?;
        }
        if (reason as i32) < 0 {
            let mut name: *const std::ffi::c_char = std::ptr::null();
            unsafe {
                sys::KSPGetConvergedReasonString(self.raw, &mut name);
            }
            let name = if name.is_null() {
                format!("{}", reason as i32)
            } else {
                unsafe { CStr::from_ptr(name).to_string_lossy().into_owned() }
            };
            let mut detail = String::new();
            if name.contains("PC_FAILED") {
                let mut pc: sys::PC = std::ptr::null_mut();
                let mut why: sys::PCFailedReason = 0;
                unsafe {
                    sys::KSPGetPC(self.raw, &mut pc);
                    sys::PCGetFailedReasonRank(pc, &mut why);
                }
                detail = format!(" (preconditioner failure reason {})", why as i32);
            }
            return Err(Error::LinearSolver(format!(
                "linear solve failed after {its} iterations: {name}{detail}"
            )));
        }
        Ok(its as usize)
    }

    /// Keep the preconditioner when the operator's values change (the
    /// algebraic multigrid of `K + r B^T W B` serves another r as well).
    pub fn set_reuse_preconditioner(&self, yes: bool) -> Result<(), Error> {
        unsafe {
            check(sys::KSPSetReusePreconditioner(
                self.raw,
                if yes {
                    sys::PETSC_TRUE
                } else {
                    sys::PETSC_FALSE
                },
            ))
        }
    }

    /// Solves `A X = B` for all columns at once (`KSPMatSolve`; a direct
    /// factorization solves them in one pass over its factors).
    pub fn mat_solve(&self, b: &DenseColumns, x: &DenseColumns) -> Result<(), Error> {
        unsafe { check(sys::KSPMatSolve(self.raw, b.raw, x.raw)) }
    }

    pub fn pc_type(&self) -> Result<String, Error> {
        let mut pc: sys::PC = std::ptr::null_mut();
        let mut t: sys::PCType = std::ptr::null();
        unsafe {
            check(sys::KSPGetPC(self.raw, &mut pc))?;
            check(sys::PCGetType(pc, &mut t))?;
        }
        Ok(if t.is_null() {
            String::new()
        } else {
            unsafe { CStr::from_ptr(t).to_string_lossy().into_owned() }
        })
    }

    pub fn ksp_type(&self) -> Result<String, Error> {
        let mut t: sys::KSPType = std::ptr::null();
        unsafe { check(sys::KSPGetType(self.raw, &mut t))? };
        Ok(if t.is_null() {
            String::new()
        } else {
            unsafe { CStr::from_ptr(t).to_string_lossy().into_owned() }
        })
    }
}

/// A dense matrix of `cols` columns distributed by rows like a vector with
/// `local` entries on this rank (many right-hand sides at once).
pub struct DenseColumns {
    raw: sys::Mat,
    local: usize,
    cols: usize,
}

impl Drop for DenseColumns {
    fn drop(&mut self) {
        unsafe {
            sys::MatDestroy(&mut self.raw);
        }
    }
}

impl DenseColumns {
    pub fn new(comm: sys::MPI_Comm, local: usize, cols: usize) -> Result<DenseColumns, Error> {
        let mut raw: sys::Mat = std::ptr::null_mut();
        unsafe {
            check(sys::MatCreateDense(
                comm,
                local as sys::PetscInt,
                sys::PETSC_DECIDE,
                sys::PETSC_DETERMINE,
                cols as sys::PetscInt,
                std::ptr::null_mut(),
                &mut raw,
            ))?
        };
        Ok(DenseColumns { raw, local, cols })
    }

    /// This rank's rows, column-major (column j at `j * local`).
    pub fn write<R>(&self, f: impl FnOnce(&mut [f64]) -> R) -> Result<R, Error> {
        let mut a: *mut f64 = std::ptr::null_mut();
        let mut lda: sys::PetscInt = 0;
        unsafe {
            check(sys::MatDenseGetLDA(self.raw, &mut lda))?;
            assert_eq!(lda as usize, self.local, "dense columns are contiguous");
            check(sys::MatDenseGetArray(self.raw, &mut a))?;
            let r = f(std::slice::from_raw_parts_mut(a, self.local * self.cols));
            check(sys::MatDenseRestoreArray(self.raw, &mut a))?;
            Ok(r)
        }
    }

    pub fn read<R>(&self, f: impl FnOnce(&[f64]) -> R) -> Result<R, Error> {
        let mut a: *const f64 = std::ptr::null();
        unsafe {
            check(sys::MatDenseGetArrayRead(self.raw, &mut a))?;
            let r = f(std::slice::from_raw_parts(a, self.local * self.cols));
            check(sys::MatDenseRestoreArrayRead(self.raw, &mut a))?;
            Ok(r)
        }
    }
}

/// The data the SNES callbacks of a linear residual `F(x) = A x - b` need.
struct LinearResidual {
    a: sys::Mat,
    b: sys::Vec,
}

unsafe extern "C" fn linear_residual(
    _snes: sys::SNES,
    x: sys::Vec,
    f: sys::Vec,
    ctx: *mut std::ffi::c_void,
) -> sys::PetscErrorCode {
    let c = &*(ctx as *const LinearResidual);
    let e = sys::MatMult(c.a, x, f);
    if e != 0 {
        return e;
    }
    sys::VecAXPY(f, -1.0, c.b)
}

unsafe extern "C" fn constant_jacobian(
    _snes: sys::SNES,
    _x: sys::Vec,
    _j: sys::Mat,
    _p: sys::Mat,
    _ctx: *mut std::ffi::c_void,
) -> sys::PetscErrorCode {
    0 // the Jacobian of a linear residual is its (already assembled) matrix
}

/// A PETSc nonlinear solver (`SNES`) on the linear residual `A x - b` with
/// variable bounds (SNES VI), for the SNES VI comparator.
pub struct Snes {
    raw: sys::SNES,
    _ctx: Box<LinearResidual>,
}

impl Drop for Snes {
    fn drop(&mut self) {
        unsafe {
            sys::SNESDestroy(&mut self.raw);
        }
    }
}

impl Snes {
    /// `vinewtonrsls` (unless `-snes_type` says otherwise) on `F(x) = A x - b`,
    /// with `lower <= x <= upper`; every SNES option applies.
    pub fn new_vi(a: &Matrix, b: &Vector, lower: &Vector, upper: &Vector) -> Result<Snes, Error> {
        let mut raw: sys::SNES = std::ptr::null_mut();
        let ctx = Box::new(LinearResidual { a: a.raw, b: b.raw });
        unsafe {
            check(sys::SNESCreate(super::comm_world(), &mut raw))?;
            let s = Snes { raw, _ctx: ctx };
            check(sys::SNESSetType(
                s.raw,
                sys::SNESVINEWTONRSLS.as_ptr() as *const _,
            ))?;
            let f = b.duplicate()?;
            check(sys::SNESSetFunction(
                s.raw,
                f.raw,
                Some(linear_residual),
                &*s._ctx as *const LinearResidual as *mut std::ffi::c_void,
            ))?;
            check(sys::SNESSetJacobian(
                s.raw,
                a.raw,
                a.raw,
                Some(constant_jacobian),
                std::ptr::null_mut(),
            ))?;
            check(sys::SNESVISetVariableBounds(s.raw, lower.raw, upper.raw))?;
            check(sys::SNESSetFromOptions(s.raw))?;
            Ok(s)
        }
    }

    /// Solves from the initial guess in `x`; returns (Newton iterations, linear iterations).
    pub fn solve(&self, x: &Vector) -> Result<(usize, usize), Error> {
        let mut its: sys::PetscInt = 0;
        let mut lits: sys::PetscInt = 0;
        let mut reason: sys::SNESConvergedReason = 0;
        unsafe {
            check(sys::SNESSolve(self.raw, std::ptr::null_mut(), x.raw))?;
            check(sys::SNESGetIterationNumber(self.raw, &mut its))?;
            check(sys::SNESGetLinearSolveIterations(self.raw, &mut lits))?;
            check(sys::SNESGetConvergedReason(self.raw, &mut reason))?;
        }
        if (reason as i32) <= 0 {
            let mut name: *const std::ffi::c_char = std::ptr::null();
            unsafe {
                sys::SNESGetConvergedReasonString(self.raw, &mut name);
            }
            let name = if name.is_null() {
                format!("{}", reason as i32)
            } else {
                unsafe { CStr::from_ptr(name).to_string_lossy().into_owned() }
            };
            return Err(Error::NotConverged(format!(
                "SNES VI did not converge after {its} Newton iterations: {name}"
            )));
        }
        Ok((its as usize, lits as usize))
    }
}

/// Gathers chosen entries of a distributed vector into a local sequential one
/// (e.g. the displacement at the ghost nodes of a rank's cells).
pub struct Gather {
    scatter: sys::VecScatter,
    pub local: Vector,
}

impl Drop for Gather {
    fn drop(&mut self) {
        unsafe {
            sys::VecScatterDestroy(&mut self.scatter);
        }
    }
}

impl Gather {
    /// Entries `indices` (global) of vectors laid out like `like`.
    pub fn new(like: &Vector, indices: &[sys::PetscInt]) -> Result<Gather, Error> {
        let n = indices.len() as sys::PetscInt;
        let mut local: sys::Vec = std::ptr::null_mut();
        let mut from: sys::IS = std::ptr::null_mut();
        let mut scatter: sys::VecScatter = std::ptr::null_mut();
        unsafe {
            check(sys::VecCreateSeq(super::comm_self(), n, &mut local))?;
            let local = Vector { raw: local };
            check(sys::ISCreateGeneral(
                super::comm_self(),
                n,
                indices.as_ptr(),
                sys::PETSC_COPY_VALUES,
                &mut from,
            ))?;
            let r = sys::VecScatterCreate(
                like.raw,
                from,
                local.raw,
                std::ptr::null_mut(),
                &mut scatter,
            );
            sys::ISDestroy(&mut from);
            check(r)?;
            Ok(Gather { scatter, local })
        }
    }

    /// Copies the chosen entries of `x` into `self.local` (collective).
    pub fn gather(&self, x: &Vector) -> Result<(), Error> {
        unsafe {
            check(sys::VecScatterBegin(
                self.scatter,
                x.raw,
                self.local.raw,
                sys::INSERT_VALUES,
                sys::SCATTER_FORWARD,
            ))?;
            check(sys::VecScatterEnd(
                self.scatter,
                x.raw,
                self.local.raw,
                sys::INSERT_VALUES,
                sys::SCATTER_FORWARD,
            ))
        }
    }
}
