//! Dense symmetric positive definite matrices on one rank, by LAPACK and
//! BLAS themselves (the libraries PETSc and MUMPS load): the Schur
//! complement of the direct back-end. They work on the upper triangle of a
//! column-major array, which is how MUMPS returns a symmetric Schur
//! complement (its lower triangle by rows, ICNTL(19) = 1): no copy to mirror
//! it, no PETSc matrix around it.
//!
//! LAPACK's routines are `lapack-sys`'s declarations (Fortran's calling
//! convention, as Debian's liblapack3 and OpenBLAS export them; the library
//! itself is linked by `build.rs`, the one PETSc and MUMPS load). The three
//! BLAS routines, which `lapack-sys` does not cover, are declared here.
//! Every call passes arrays whose sizes are checked against the orders it
//! states.

use lapack_sys::dpotrf_;
use std::os::raw::{c_char, c_int};

// BLAS (Fortran interface: every argument by reference).
extern "C" {
    fn dtrsm_(
        side: *const c_char,
        uplo: *const c_char,
        transa: *const c_char,
        diag: *const c_char,
        m: *const c_int,
        n: *const c_int,
        alpha: *const f64,
        a: *const f64,
        lda: *const c_int,
        b: *mut f64,
        ldb: *const c_int,
    );
    fn dtrsv_(
        uplo: *const c_char,
        trans: *const c_char,
        diag: *const c_char,
        n: *const c_int,
        a: *const f64,
        lda: *const c_int,
        x: *mut f64,
        incx: *const c_int,
    );
    fn dsymv_(
        uplo: *const c_char,
        n: *const c_int,
        alpha: *const f64,
        a: *const f64,
        lda: *const c_int,
        x: *const f64,
        incx: *const c_int,
        beta: *const f64,
        y: *mut f64,
        incy: *const c_int,
    );
}

const UPPER: c_char = b'U' as c_char;

/// OpenBLAS' work space: the one buffer (`BUFFER_SIZE`, 128 MiB on Debian's
/// x86-64 builds, plus a page) that its level-3 routines and its LAPACK
/// take from `blas_memory_alloc` and give back (kept mapped) at the end of
/// each call, mapped on the first such call.
pub const OPENBLAS_BUFFER: usize = (128 << 20) + (1 << 20);

/// The address of symbol `name` among the libraries the process loaded
/// (RTLD_DEFAULT, glibc's null handle), or null.
pub(crate) fn loaded_symbol(name: &std::ffi::CStr) -> *mut std::ffi::c_void {
    extern "C" {
        fn dlsym(handle: *mut std::ffi::c_void, name: *const c_char) -> *mut std::ffi::c_void;
    }
    // SAFETY: dlsym reads a NUL-terminated name and returns an address or
    // null, which the callers check before any use.
    unsafe { dlsym(std::ptr::null_mut(), name.as_ptr()) }
}

/// Whether the BLAS of the process is OpenBLAS.
pub fn openblas() -> bool {
    !loaded_symbol(c"openblas_get_config").is_null()
}

/// One OpenMP thread per rank unless `OMP_NUM_THREADS` says otherwise.
/// Debian's SuperLU_DIST (`-pc_factor_mat_solver_type superlu_dist`, which
/// PETSc loads with OpenMP's runtime) runs a thread per core it may use,
/// and its solves with more than one were wrong here (hertz2d h 0.1, one
/// rank, 2 threads: UBR "moves without bound" at every run, LU or
/// Cholesky; one thread: the answer of MUMPS): its threads call the serial
/// OpenBLAS at once. `mpirun` binding each rank to one core hid it on 2
/// ranks; started without mpirun, or at 3 ranks and more (bound to a
/// socket), every rank ran a thread per core, on cores the other ranks use
/// too. The runtime read the variable when it loaded, so the count is set
/// through its call (found in the process, if loaded at all).
pub fn one_openmp_thread() {
    if std::env::var_os("OMP_NUM_THREADS").is_some() {
        return;
    }
    let f = loaded_symbol(c"omp_set_num_threads");
    if !f.is_null() {
        // SAFETY: the address of OpenMP's `void omp_set_num_threads(int)`.
        let set: extern "C" fn(c_int) = unsafe { std::mem::transmute(f) };
        set(1);
    }
}

/// One OpenBLAS thread per rank where `ranks_here` ranks share this
/// machine, unless `OPENBLAS_NUM_THREADS`, `GOTO_NUM_THREADS` or
/// `OMP_NUM_THREADS` (which OpenBLAS reads, in that order) says otherwise.
/// Debian's threaded OpenBLAS (`libopenblas0-pthread`, the BLAS of many
/// machines) runs a thread per core the rank may use: where Open MPI does
/// not bind each rank to one core (`--bind-to none`, or a socket from 3
/// ranks on), the ranks' threads share the cores and wait on each other
/// (block3d h 0.0333, 2 ranks on 2 cores, `--bind-to none`: 20.6 s against
/// 15.0 s with one thread each). One rank alone keeps OpenBLAS' threads
/// (16.5-16.9 s against 22.3-23.7 s with the serial OpenBLAS, started
/// without mpirun). Nothing to do for the serial OpenBLAS or another BLAS.
pub fn one_blas_thread_per_rank(ranks_here: usize) {
    if ranks_here < 2
        || [
            "OPENBLAS_NUM_THREADS",
            "GOTO_NUM_THREADS",
            "OMP_NUM_THREADS",
        ]
        .iter()
        .any(|v| std::env::var_os(v).is_some())
    {
        return;
    }
    let f = loaded_symbol(c"openblas_set_num_threads");
    if !f.is_null() {
        // SAFETY: the address of OpenBLAS' `void openblas_set_num_threads(int)`.
        let set: extern "C" fn(c_int) = unsafe { std::mem::transmute(f) };
        set(1);
    }
}

/// Maps OpenBLAS' work space now, while the process is small, or says that
/// it cannot be mapped. OpenBLAS maps its buffer on the first level-3 call
/// (a MUMPS factorization, LAPACK's Cholesky) and, when `mmap` and `malloc`
/// both fail (an address-space limit, `ulimit -v`), retries for ever
/// (`blas_memory_alloc` in driver/others/memory.c, OpenBLAS 0.3.21, has no
/// error return): the rank spins there and every other rank waits for it.
/// Mapped once (the serial OpenBLAS, or `OPENBLAS_NUM_THREADS=1`: one
/// buffer, reused by every later call), it is never mapped again. The
/// check first maps and unmaps a region of the buffer's size itself (a
/// failure is reported, not met in OpenBLAS), then makes one 1 x 1
/// triangular solve. Nothing to do for another BLAS. `Err`: the bytes that
/// could not be mapped.
pub fn reserve_blas_workspace() -> Result<(), usize> {
    use std::alloc::{GlobalAlloc, Layout, System};
    if !openblas() {
        return Ok(());
    }
    let layout = Layout::from_size_align(OPENBLAS_BUFFER, 4096).expect("a valid layout");
    // The system allocator itself: a null pointer is an answer here, not a
    // failure to report (the program's allocator ends the run on one).
    // SAFETY: a layout of non-zero size.
    let probe = unsafe { System.alloc(layout) };
    if probe.is_null() {
        return Err(OPENBLAS_BUFFER);
    }
    // SAFETY: the block allocated just above, with the same layout, freed
    // once.
    unsafe { System.dealloc(probe, layout) };
    let (one, alpha, a, mut b) = (1 as c_int, 1.0f64, 1.0f64, 1.0f64);
    let (left, notrans, nonunit) = (b'L' as c_char, b'N' as c_char, b'N' as c_char);
    // SAFETY: a 1 x 1 triangular solve: every argument points to a live
    // scalar of the type the Fortran interface reads.
    unsafe {
        dtrsm_(
            &left, &UPPER, &notrans, &nonunit, &one, &one, &alpha, &a, &one, &mut b, &one,
        );
    }
    Ok(())
}

/// `n` zeros, or `Err(bytes)` when they cannot be allocated (a large dense
/// array: the caller reports it, collectively, instead of the allocator
/// ending the run).
pub fn try_zeros(n: usize) -> Result<Vec<f64>, usize> {
    let mut v = Vec::new();
    crate::error::fallible(|| v.try_reserve_exact(n)).map_err(|_| n * 8)?;
    v.resize(n, 0.0);
    Ok(v)
}

/// A copy of `a`, or `Err(bytes)` (see [`try_zeros`]).
pub fn try_copy(a: &[f64]) -> Result<Vec<f64>, usize> {
    let mut v = Vec::new();
    crate::error::fallible(|| v.try_reserve_exact(a.len())).map_err(|_| a.len() * 8)?;
    v.extend_from_slice(a);
    Ok(v)
}

/// The Cholesky factor `U^T U` of an `n x n` symmetric positive definite
/// matrix given by its upper triangle (column-major); the default is the
/// empty one (order 0).
#[derive(Default)]
pub struct SpdFactor {
    n: usize,
    u: Vec<f64>,
}

impl SpdFactor {
    /// Factorizes `a` in place (its upper triangle, column-major; the
    /// strict lower triangle is neither read nor kept). `Err(k)`: the
    /// leading minor of order k is not positive definite (LAPACK's INFO).
    pub fn new(n: usize, mut a: Vec<f64>) -> Result<SpdFactor, i32> {
        assert_eq!(a.len(), n * n);
        if n > 0 {
            let (nn, mut info) = (n as c_int, 0 as c_int);
            // SAFETY: `a` holds n x n entries (asserted), leading dimension
            // n; the scalars are live values of the types LAPACK reads.
            unsafe { dpotrf_(&UPPER, &nn, a.as_mut_ptr(), &nn, &mut info) };
            if info != 0 {
                return Err(info);
            }
        }
        Ok(SpdFactor { n, u: a })
    }

    /// Factorizes `modify` applied to a copy of `a` (`n x n`, upper
    /// triangle) into this factor's array: no allocation when the order is
    /// the same. On failure the factor is left empty.
    pub fn refactor_with(
        &mut self,
        n: usize,
        a: &[f64],
        modify: impl FnOnce(&mut [f64]),
    ) -> Result<(), i32> {
        let mut u = std::mem::take(&mut self.u);
        self.n = 0;
        u.clear();
        u.extend_from_slice(a);
        modify(&mut u);
        *self = SpdFactor::new(n, u)?;
        Ok(())
    }

    /// `x = A^{-1} b`: `U^T y = b`, then `U x = y`, two BLAS triangular
    /// solves (dtrsv). LAPACK's dpotrs does the same with dtrsm on one
    /// column, which OpenBLAS runs 2-4x slower (one core, m = 1984: 5.5
    /// against 2.6 ms; m = 3126: 13.6 against 7.1 ms): the condensed UBR
    /// iteration's dense solve. (`Err` is kept for the callers; a factor
    /// made by [`SpdFactor::new`] cannot fail here.)
    pub fn solve(&self, b: &[f64], x: &mut [f64]) -> Result<(), i32> {
        assert!(b.len() == self.n && x.len() == self.n);
        x.copy_from_slice(b);
        if self.n == 0 {
            return Ok(());
        }
        let (nn, one) = (self.n as c_int, 1 as c_int);
        let (trans, notrans, nonunit) = (b'T' as c_char, b'N' as c_char, b'N' as c_char);
        // SAFETY: the factor holds n x n entries (made so by `new`, leading
        // dimension n), x holds n (asserted), increment one; the scalars are
        // live values of the types BLAS reads.
        unsafe {
            dtrsv_(
                &UPPER,
                &trans,
                &nonunit,
                &nn,
                self.u.as_ptr(),
                &nn,
                x.as_mut_ptr(),
                &one,
            );
            dtrsv_(
                &UPPER,
                &notrans,
                &nonunit,
                &nn,
                self.u.as_ptr(),
                &nn,
                x.as_mut_ptr(),
                &one,
            );
        }
        Ok(())
    }
}

/// `y = A x`, A symmetric `n x n` given by its upper triangle (column-major).
pub fn sym_upper_mv(n: usize, a: &[f64], x: &[f64], y: &mut [f64]) {
    assert!(a.len() == n * n && x.len() == n && y.len() == n);
    if n == 0 {
        return;
    }
    let (nn, inc, one, zero) = (n as c_int, 1 as c_int, 1.0f64, 0.0f64);
    // SAFETY: `a` holds n x n entries, x and y n each (asserted); the
    // scalars are live values of the types BLAS reads.
    unsafe {
        dsymv_(
            &UPPER,
            &nn,
            &one,
            a.as_ptr(),
            &nn,
            x.as_ptr(),
            &inc,
            &zero,
            y.as_mut_ptr(),
            &inc,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A = B^T B + n I for a fixed B; only its upper triangle is filled (the
    /// lower one holds garbage that must not be read).
    fn upper(n: usize) -> (Vec<f64>, Vec<f64>) {
        let b: Vec<f64> = (0..n * n)
            .map(|k| ((k * 7 + 3) % 11) as f64 - 5.0)
            .collect();
        let mut full = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                let mut s = if i == j { n as f64 } else { 0.0 };
                for k in 0..n {
                    s += b[k * n + i] * b[k * n + j];
                }
                full[j * n + i] = s;
            }
        }
        let mut up = full.clone();
        for j in 0..n {
            for i in j + 1..n {
                up[j * n + i] = f64::NAN;
            }
        }
        (full, up)
    }

    #[test]
    fn solves_from_the_upper_triangle() {
        let n = 9;
        let (full, up) = upper(n);
        let x: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let mut b = vec![0.0; n];
        for i in 0..n {
            b[i] = (0..n).map(|j| full[j * n + i] * x[j]).sum();
        }
        let mut y = vec![0.0; n];
        sym_upper_mv(n, &up, &x, &mut y);
        for i in 0..n {
            assert!((y[i] - b[i]).abs() < 1e-12 * b[i].abs().max(1.0));
        }
        let mut f = SpdFactor::new(n, up.clone()).unwrap();
        let mut z = vec![0.0; n];
        f.solve(&b, &mut z).unwrap();
        for i in 0..n {
            assert!((z[i] - x[i]).abs() < 1e-10, "{} against {}", z[i], x[i]);
        }
        // Refactorized after a diagonal shift: still solves its own system.
        f.refactor_with(n, &up, |s| {
            for i in 0..n {
                s[i * n + i] += 3.0;
            }
        })
        .unwrap();
        f.solve(&b, &mut z).unwrap();
        for i in 0..n {
            let r: f64 = (0..n).map(|j| full[j * n + i] * z[j]).sum::<f64>() + 3.0 * z[i];
            assert!((r - b[i]).abs() < 1e-9 * b[i].abs().max(1.0));
        }
    }

    #[test]
    fn an_array_too_large_is_refused_not_fatal() {
        // 2^44 entries, 128 TiB: more than a process's address space. The
        // program's allocator would end the run; here the caller is told.
        assert_eq!(try_zeros(1 << 44).err(), Some(8 << 44));
        assert_eq!(try_zeros(3).unwrap(), vec![0.0; 3]);
        assert_eq!(try_copy(&[1.0, 2.0]).unwrap(), vec![1.0, 2.0]);
    }

    #[test]
    fn an_indefinite_matrix_is_refused() {
        // [[1, 2], [2, 1]] (upper triangle): eigenvalues 3 and -1.
        assert_eq!(
            SpdFactor::new(2, vec![1.0, f64::NAN, 2.0, 1.0]).err(),
            Some(2)
        );
    }
}
