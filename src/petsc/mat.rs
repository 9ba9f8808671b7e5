//! PETSc matrices: the distributed sparse matrix ([`Matrix`], AIJ or
//! SBAIJ) and the dense columns of many right-hand sides
//! ([`DenseColumns`]).

use super::{
    check, comm_self, ensure_running, mpi_check, running, slice_from, slice_from_mut, sys,
    NullSpace, Vector,
};
use crate::error::Error;
use std::ffi::c_void;

/// A distributed sparse matrix (`MATAIJ`).
///
/// Invariant: `raw` is a Mat that PETSc made and that is not destroyed, of
/// which this value owns one reference (null only while a constructor
/// fails, which `MatDestroy` accepts).
pub struct Matrix {
    pub(super) raw: sys::Mat,
}

/// Compressed rows: row pointers, column indices, values.
type Csr = (Vec<sys::PetscInt>, Vec<sys::PetscInt>, Vec<f64>);

/// The arrays a matrix made on them lives in, freed by PETSc's container
/// when the matrix itself is destroyed (its last reference, a KSP's or a
/// SNES's included), not when our wrapper is.
///
/// # Safety
/// `p` is the pointer that [`attach_arrays`] gave the container (a leaked
/// `Box<Vec<Csr>>`), passed once, when the container is destroyed.
// SAFETY: only PETSc calls it, as the destroy of the container that
// attach_arrays made, with the pointer of the contract above.
unsafe extern "C" fn free_csr_arrays(p: *mut c_void) -> sys::PetscErrorCode {
    // SAFETY: `p` came from Box::into_raw in attach_arrays and is freed
    // once (the contract).
    drop(unsafe { Box::from_raw(p as *mut Vec<Csr>) });
    0
}

/// Hands `arrays` to `mat` (live): composed with it in a container whose
/// destroy frees them.
fn attach_arrays(mat: sys::Mat, arrays: Vec<Csr>) -> Result<(), Error> {
    let mut c: sys::PetscContainer = std::ptr::null_mut();
    // SAFETY: PETSc writes a new container into `c`.
    check(unsafe { sys::PetscContainerCreate(comm_self(), &mut c) })?;
    let p = Box::into_raw(Box::new(arrays)) as *mut c_void;
    let r = compose_container(mat, c, p);
    // SAFETY: gives up our reference to the container made above, once: the
    // matrix holds its own now (on an error, the container and, once its
    // destroy is set, the arrays go; a failure before that leaks them).
    let d = unsafe { sys::PetscContainerDestroy(&mut c) };
    r?;
    check(d)
}

/// Puts `p` (a leaked `Box<Vec<Csr>>`) in the live container `c`, with
/// [`free_csr_arrays`] as its destroy, and composes `c` with `mat` (live).
fn compose_container(mat: sys::Mat, c: sys::PetscContainer, p: *mut c_void) -> Result<(), Error> {
    // SAFETY: `c` is live; PETSc stores the pointer without reading it.
    check(unsafe { sys::PetscContainerSetPointer(c, p) })?;
    // SAFETY: `c` is live; free_csr_arrays frees the box at `p`, which
    // nothing else frees.
    check(unsafe { sys::PetscContainerSetUserDestroy(c, Some(free_csr_arrays)) })?;
    let name = c"ubr_csr_arrays";
    // SAFETY: `mat` and `c` are live, the name a static C string; the
    // matrix takes a reference to the container.
    check(unsafe {
        sys::PetscObjectCompose(
            mat as sys::PetscObject,
            name.as_ptr(),
            c as sys::PetscObject,
        )
    })
}

impl Drop for Matrix {
    fn drop(&mut self) {
        if running() {
            // SAFETY: our reference to a live Mat (the invariant), given up
            // once, while PETSc runs.
            unsafe { sys::MatDestroy(&mut self.raw) };
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

/// The number of ranks of `comm` (live).
fn comm_size(comm: sys::MPI_Comm) -> Result<usize, Error> {
    let mut size = 0;
    // SAFETY: `comm` is a live communicator (the module's contract); MPI
    // writes one int into `size`.
    let r = unsafe { mpi::ffi::MPI_Comm_size(comm, &mut size) };
    mpi_check(r, "MPI_Comm_size")?;
    Ok(size.max(0) as usize)
}

/// The sum of `count` over the ranks of `comm` (live) up to this one, this
/// one included (collective).
fn inclusive_sum(comm: sys::MPI_Comm, count: u64) -> Result<u64, Error> {
    let mut end = 0u64;
    // SAFETY: one u64 read from `count` and one written into `end`, the
    // type and operation rsmpi's (MPI's predefined handles); `comm` is live.
    let r = unsafe {
        mpi::ffi::MPI_Scan(
            &count as *const u64 as *const c_void,
            &mut end as *mut u64 as *mut c_void,
            1,
            mpi::ffi::RSMPI_UINT64_T,
            mpi::ffi::RSMPI_SUM,
            comm,
        )
    };
    mpi_check(r, "MPI_Scan")?;
    Ok(end)
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
        ensure_running()?;
        let m = if comm_size(comm)? == 1 {
            Matrix::seq_on_arrays(comm, local, (rowptr, cols, vals))?
        } else {
            Matrix::mpi_on_split_arrays(comm, local, (rowptr, cols, vals))?
        };
        // SAFETY: m.raw is live (the invariant).
        check(unsafe { sys::MatSetBlockSize(m.raw, bs as sys::PetscInt) })?;
        m.set_flag(sys::MAT_NEW_NONZERO_ALLOCATION_ERR)?;
        m.set_flag(sys::MAT_NO_OFF_PROC_ENTRIES)?;
        Ok(m)
    }

    /// One rank: PETSc's matrix on the arrays themselves, which it keeps
    /// (the preallocation route copies them entry by entry: block3d_17887
    /// 28 ms).
    fn seq_on_arrays(comm: sys::MPI_Comm, local: usize, csr: Csr) -> Result<Matrix, Error> {
        let (mut rowptr, mut cols, mut vals) = csr;
        let n = local as sys::PetscInt;
        let mut raw: sys::Mat = std::ptr::null_mut();
        // SAFETY: rowptr holds n + 1 offsets into cols and vals, which hold
        // rowptr[n] entries each (asserted by the caller); PETSc keeps the
        // pointers, and the arrays then move (not their heap buffers) into
        // the matrix's container, which frees them only when PETSc destroys
        // the matrix. PETSc writes the new Mat into `raw`.
        check(unsafe {
            sys::MatCreateSeqAIJWithArrays(
                comm,
                n,
                n,
                rowptr.as_mut_ptr(),
                cols.as_mut_ptr(),
                vals.as_mut_ptr(),
                &mut raw,
            )
        })?;
        let m = Matrix { raw };
        attach_arrays(m.raw, vec![(rowptr, cols, vals)])?;
        Ok(m)
    }

    /// Several ranks: the rows split into their "diagonal" part (the
    /// columns this rank owns, numbered from its first) and the others
    /// (global numbers), PETSc's matrix on these arrays themselves
    /// (MatCreateMPIAIJWithSplitArrays; the preallocation route copies
    /// entry by entry). The diagonal part stays in `cols` and `vals`, moved
    /// forward in place: only the others (the interface's few) are copied.
    /// A copy of the whole (as before) doubled the assembly's peak, and the
    /// arrays freed after it stayed in the process (SuperLU_DIST's library
    /// turns off glibc's mmap for large blocks, `mallopt(M_MMAP_MAX, 0)`,
    /// when it loads): 1.94 GB resident per rank after the assembly of the
    /// 1M-node block on 2 ranks, 1.21 GB now.
    fn mpi_on_split_arrays(comm: sys::MPI_Comm, local: usize, csr: Csr) -> Result<Matrix, Error> {
        let (rowptr, mut dj, mut da) = csr;
        let count = local as u64;
        let end = inclusive_sum(comm, count)?;
        let (lo, hi) = ((end - count) as sys::PetscInt, end as sys::PetscInt);
        let owned = |c: &sys::PetscInt| (lo..hi).contains(c);
        let no = dj.iter().filter(|c| !owned(c)).count();
        let mut di: Vec<sys::PetscInt> = Vec::with_capacity(local + 1);
        let mut oi: Vec<sys::PetscInt> = Vec::with_capacity(local + 1);
        let (mut oj, mut oa) = (Vec::with_capacity(no), Vec::with_capacity(no));
        di.push(0);
        oi.push(0);
        // The diagonal entries written at w <= k, the entry read.
        let mut w = 0;
        for r in 0..local {
            for k in rowptr[r] as usize..rowptr[r + 1] as usize {
                let c = dj[k];
                if owned(&c) {
                    dj[w] = c - lo;
                    da[w] = da[k];
                    w += 1;
                } else {
                    oj.push(c);
                    oa.push(da[k]);
                }
            }
            di.push(w as sys::PetscInt);
            oi.push(oj.len() as sys::PetscInt);
        }
        drop(rowptr);
        // The tails go unused (a shrink would copy).
        dj.truncate(w);
        da.truncate(w);
        let n = local as sys::PetscInt;
        let mut raw: sys::Mat = std::ptr::null_mut();
        // SAFETY: di and oi hold n + 1 offsets into (dj, da) and (oj, oa),
        // built just above to match; PETSc keeps the pointers, and the
        // arrays then move (not their heap buffers) into the matrix's
        // container, which frees them only when PETSc destroys the matrix.
        // PETSc writes the new Mat into `raw`.
        check(unsafe {
            sys::MatCreateMPIAIJWithSplitArrays(
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
            )
        })?;
        let m = Matrix { raw };
        attach_arrays(m.raw, vec![(di, dj, da), (oi, oj, oa)])?;
        Ok(m)
    }

    /// A matrix of type `ty` (a NUL-terminated name) with `local` rows and
    /// columns on this rank, not yet preallocated.
    fn empty(
        comm: sys::MPI_Comm,
        local: usize,
        ty: &[u8],
        bs: Option<usize>,
    ) -> Result<Matrix, Error> {
        assert_eq!(ty.last(), Some(&0), "a C string");
        ensure_running()?;
        let mut raw: sys::Mat = std::ptr::null_mut();
        // SAFETY: `comm` is live; PETSc writes a new Mat into `raw`.
        check(unsafe { sys::MatCreate(comm, &mut raw) })?;
        let m = Matrix { raw };
        let (n, det) = (local as sys::PetscInt, sys::PETSC_DETERMINE);
        // SAFETY: m.raw is live (the invariant).
        check(unsafe { sys::MatSetSizes(m.raw, n, n, det, det) })?;
        if let Some(bs) = bs {
            // SAFETY: m.raw is live.
            check(unsafe { sys::MatSetBlockSize(m.raw, bs as sys::PetscInt) })?;
        }
        // SAFETY: m.raw is live; `ty` is NUL-terminated (asserted).
        check(unsafe { sys::MatSetType(m.raw, ty.as_ptr() as *const _) })?;
        Ok(m)
    }

    fn set_flag(&self, option: sys::MatOption) -> Result<(), Error> {
        // SAFETY: self.raw is live (the invariant).
        check(unsafe { sys::MatSetOption(self.raw, option, sys::PETSC_TRUE) })
    }

    /// Adds a dense block; rows given as -1 are skipped (PETSc ignores negative indices).
    pub fn add_values(
        &self,
        rows: &[sys::PetscInt],
        cols: &[sys::PetscInt],
        vals: &[f64],
    ) -> Result<(), Error> {
        assert_eq!(rows.len() * cols.len(), vals.len());
        // SAFETY: self.raw is live; PETSc reads rows.len() rows,
        // cols.len() columns and their product of values (asserted).
        check(unsafe {
            sys::MatSetValues(
                self.raw,
                rows.len() as sys::PetscInt,
                rows.as_ptr(),
                cols.len() as sys::PetscInt,
                cols.as_ptr(),
                vals.as_ptr(),
                sys::ADD_VALUES,
            )
        })
    }

    pub fn assemble(&self) -> Result<(), Error> {
        // SAFETY: self.raw is live (the invariant).
        check(unsafe { sys::MatAssemblyBegin(self.raw, sys::MAT_FINAL_ASSEMBLY) })?;
        // SAFETY: self.raw is live; ends the assembly begun above.
        check(unsafe { sys::MatAssemblyEnd(self.raw, sys::MAT_FINAL_ASSEMBLY) })
    }

    pub fn set_spd(&self) -> Result<(), Error> {
        self.set_flag(sys::MAT_SPD)?;
        self.set_flag(sys::MAT_SYMMETRIC)?;
        self.set_flag(sys::MAT_SYMMETRY_ETERNAL)
    }

    /// This rank's first row and one past its last.
    fn ownership(&self) -> Result<(sys::PetscInt, sys::PetscInt), Error> {
        let (mut lo, mut hi): (sys::PetscInt, sys::PetscInt) = (0, 0);
        // SAFETY: self.raw is live; PETSc writes two integers.
        check(unsafe { sys::MatGetOwnershipRange(self.raw, &mut lo, &mut hi) })?;
        Ok((lo, hi))
    }

    /// `f(cols, vals)` of the global row `row`, one of this rank's.
    /// (`f` must not change this matrix.)
    fn with_row<R>(
        &self,
        row: sys::PetscInt,
        f: impl FnOnce(&[sys::PetscInt], &[f64]) -> R,
    ) -> Result<R, Error> {
        let mut ncols: sys::PetscInt = 0;
        let mut cols: *const sys::PetscInt = std::ptr::null();
        let mut vals: *const f64 = std::ptr::null();
        // SAFETY: self.raw is live and assembled; PETSc checks that the row
        // is this rank's and writes its length and the addresses of its
        // columns and values, valid until the restore below.
        check(unsafe { sys::MatGetRow(self.raw, row, &mut ncols, &mut cols, &mut vals) })?;
        let n = ncols.max(0) as usize;
        // SAFETY: n columns and n values, valid and unchanged until the
        // restore below (the contract on f); the slices do not outlive this
        // call (R cannot borrow them).
        let (cs, vs) = unsafe { (slice_from(cols, n), slice_from(vals, n)) };
        let r = f(cs, vs);
        // SAFETY: gives back the row got above, once.
        check(unsafe { sys::MatRestoreRow(self.raw, row, &mut ncols, &mut cols, &mut vals) })?;
        Ok(r)
    }

    /// The upper block triangle of this symmetric matrix in symmetric block
    /// storage (SBAIJ, `bs x bs` blocks), built from its rows through a
    /// block CSR (MatConvert's generic path inserts entry by entry: 30 s on
    /// 136k nodes). A matrix-vector product reads about half the bytes of
    /// AIJ's.
    pub fn sbaij_copy(&self, comm: sys::MPI_Comm, bs: usize) -> Result<Matrix, Error> {
        let (rstart, rend) = self.ownership()?;
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
                self.with_row(row, |cs, vs| {
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
                })?;
            }
            ii.push(jj.len() as sys::PetscInt);
        }
        let m = Matrix::empty(comm, n, sys::MATSBAIJ, None)?;
        let b = bs as sys::PetscInt;
        // Each is a no-op for the other type (one rank: seqsbaij).
        // SAFETY: m.raw is live; ii holds nb + 1 offsets into jj (block
        // columns) and vv (bs2 values a block), built above to match;
        // PETSc copies them.
        check(unsafe {
            sys::MatSeqSBAIJSetPreallocationCSR(m.raw, b, ii.as_ptr(), jj.as_ptr(), vv.as_ptr())
        })?;
        // SAFETY: as above.
        check(unsafe {
            sys::MatMPISBAIJSetPreallocationCSR(m.raw, b, ii.as_ptr(), jj.as_ptr(), vv.as_ptr())
        })?;
        // Contact blocks added later (a change of r) come whole.
        m.set_flag(sys::MAT_IGNORE_LOWER_TRIANGULAR)?;
        m.set_flag(sys::MAT_NO_OFF_PROC_ENTRIES)?;
        Ok(m)
    }

    /// `y = A x`.
    pub fn mult(&self, x: &Vector, y: &Vector) -> Result<(), Error> {
        // SAFETY: the three are live (PETSc checks their layouts).
        check(unsafe { sys::MatMult(self.raw, x.raw, y.raw) })
    }

    /// `y = A^T x`.
    pub fn mult_transpose(&self, x: &Vector, y: &Vector) -> Result<(), Error> {
        // SAFETY: the three are live (PETSc checks their layouts).
        check(unsafe { sys::MatMultTranspose(self.raw, x.raw, y.raw) })
    }

    /// The product `P^T A P` (a new matrix, collective).
    pub fn ptap(&self, p: &Matrix) -> Result<Matrix, Error> {
        ensure_running()?;
        let mut raw: sys::Mat = std::ptr::null_mut();
        // SAFETY: both are live; PETSc writes the new product into `raw`.
        check(unsafe {
            sys::MatPtAP(
                self.raw,
                p.raw,
                sys::MAT_INITIAL_MATRIX,
                sys::PETSC_DEFAULT as f64,
                &mut raw,
            )
        })?;
        Ok(Matrix { raw })
    }

    /// Zeroes the given global rows and columns and puts `diag` on the diagonal.
    pub fn zero_rows_columns(&self, rows: &[sys::PetscInt], diag: f64) -> Result<(), Error> {
        let (n, none) = (rows.len() as sys::PetscInt, std::ptr::null_mut());
        // SAFETY: self.raw is live; PETSc reads rows.len() rows (no vectors
        // to fix: the null ones).
        check(unsafe { sys::MatZeroRowsColumns(self.raw, n, rows.as_ptr(), diag, none, none) })
    }

    pub fn diagonal(&self, d: &Vector) -> Result<(), Error> {
        // SAFETY: both are live (PETSc checks their layouts).
        check(unsafe { sys::MatGetDiagonal(self.raw, d.raw) })
    }

    /// This rank's rows as visited by `f(row, cols, vals)` (global,
    /// 0-based; columns increasing), in row order. (`f` must not change
    /// this matrix.)
    pub fn for_each_owned_row(
        &self,
        mut f: impl FnMut(usize, &[sys::PetscInt], &[f64]),
    ) -> Result<(), Error> {
        let (lo, hi) = self.ownership()?;
        for row in lo..hi {
            self.with_row(row, |c, v| f(row as usize, c, v))?;
        }
        Ok(())
    }

    pub fn stats(&self) -> Result<MatStats, Error> {
        let mut info = sys::MatInfo::default();
        // SAFETY: self.raw is live; PETSc writes one MatInfo (collective).
        check(unsafe { sys::MatGetInfo(self.raw, sys::MAT_GLOBAL_SUM, &mut info) })?;
        Ok(MatStats {
            nonzeros_used: info.nz_used,
            nonzeros_allocated: info.nz_allocated,
            mallocs: info.mallocs,
        })
    }

    /// A copy of this matrix, values included.
    pub fn duplicate(&self) -> Result<Matrix, Error> {
        ensure_running()?;
        let mut raw: sys::Mat = std::ptr::null_mut();
        // SAFETY: self.raw is live; PETSc writes a new Mat into `raw`.
        check(unsafe { sys::MatDuplicate(self.raw, sys::MAT_COPY_VALUES, &mut raw) })?;
        Ok(Matrix { raw })
    }

    /// Copies the values of `other` (same nonzero pattern) into this matrix.
    pub fn copy_from(&self, other: &Matrix) -> Result<(), Error> {
        // SAFETY: both are live (PETSc checks their sizes).
        check(unsafe { sys::MatCopy(other.raw, self.raw, sys::SAME_NONZERO_PATTERN) })
    }

    pub fn set_near_nullspace(&self, ns: &NullSpace) -> Result<(), Error> {
        // SAFETY: both are live; the matrix takes a reference to the space.
        check(unsafe { sys::MatSetNearNullSpace(self.raw, ns.raw) })
    }
}

/// A dense matrix of `cols` columns distributed by rows like a vector with
/// `local` entries on this rank (many right-hand sides at once).
///
/// Invariant: `raw` is a live dense Mat of ours with `local` rows on this
/// rank and `cols` columns.
pub struct DenseColumns {
    pub(super) raw: sys::Mat,
    local: usize,
    cols: usize,
}

impl Drop for DenseColumns {
    fn drop(&mut self) {
        if running() {
            // SAFETY: our reference to a live Mat (the invariant), given up
            // once, while PETSc runs.
            unsafe { sys::MatDestroy(&mut self.raw) };
        }
    }
}

impl DenseColumns {
    pub fn new(comm: sys::MPI_Comm, local: usize, cols: usize) -> Result<DenseColumns, Error> {
        ensure_running()?;
        let mut raw: sys::Mat = std::ptr::null_mut();
        let (m, n) = (local as sys::PetscInt, cols as sys::PetscInt);
        let (decide, det) = (sys::PETSC_DECIDE, sys::PETSC_DETERMINE);
        // SAFETY: `comm` is live; PETSc allocates the entries itself (the
        // null array) and writes a new Mat into `raw`.
        check(unsafe {
            sys::MatCreateDense(comm, m, decide, det, n, std::ptr::null_mut(), &mut raw)
        })?;
        Ok(DenseColumns { raw, local, cols })
    }

    /// This rank's rows, column-major (column j at `j * local`). (`f` must
    /// not read or change this matrix through its other methods.)
    pub fn write<R>(&self, f: impl FnOnce(&mut [f64]) -> R) -> Result<R, Error> {
        let mut lda: sys::PetscInt = 0;
        // SAFETY: self.raw is live; PETSc writes one integer.
        check(unsafe { sys::MatDenseGetLDA(self.raw, &mut lda) })?;
        assert_eq!(lda as usize, self.local, "dense columns are contiguous");
        let mut a: *mut f64 = std::ptr::null_mut();
        // SAFETY: self.raw is live; PETSc writes the address of its local
        // entries, writable until the restore below.
        check(unsafe { sys::MatDenseGetArray(self.raw, &mut a) })?;
        // SAFETY: local x cols entries, contiguous (lda = local, asserted),
        // ours until the restore below (the contract on f); the slice does
        // not outlive f.
        let r = f(unsafe { slice_from_mut(a, self.local * self.cols) });
        // SAFETY: gives back the array got above, once.
        check(unsafe { sys::MatDenseRestoreArray(self.raw, &mut a) })?;
        Ok(r)
    }

    /// This rank's rows, column-major (see [`DenseColumns::write`]).
    pub fn read<R>(&self, f: impl FnOnce(&[f64]) -> R) -> Result<R, Error> {
        let mut a: *const f64 = std::ptr::null();
        // SAFETY: self.raw is live; PETSc writes the address of its local
        // entries, readable until the restore below.
        check(unsafe { sys::MatDenseGetArrayRead(self.raw, &mut a) })?;
        // SAFETY: local x cols entries (the matrix was made with the
        // leading dimension `local`), unchanged until the restore below
        // (the contract on f); the slice does not outlive f.
        let r = f(unsafe { slice_from(a, self.local * self.cols) });
        // SAFETY: gives back the array got above, once.
        check(unsafe { sys::MatDenseRestoreArrayRead(self.raw, &mut a) })?;
        Ok(r)
    }
}
