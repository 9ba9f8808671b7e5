//! PETSc's registries of linear solvers, asked before any work so that a
//! wrong name in the options is bad input (`options::solver`), not an error
//! in the middle of the set-up.

use super::{check, check_text, comm_self, options, strings_from, sys, take_error};
use crate::error::Error;
use std::ffi::{c_char, c_int, c_void, CStr, CString};

/// How a factorization is asked for (`-pc_type lu|cholesky|ilu|icc`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Factor {
    Lu,
    Cholesky,
    Ilu,
    Icc,
}

impl Factor {
    fn raw(self) -> sys::MatFactorType {
        match self {
            Factor::Lu => sys::MAT_FACTOR_LU,
            Factor::Cholesky => sys::MAT_FACTOR_CHOLESKY,
            Factor::Ilu => sys::MAT_FACTOR_ILU,
            Factor::Icc => sys::MAT_FACTOR_ICC,
        }
    }
}

/// The solver packages PETSc 3.18 knows by name (`MATSOLVER*` of petscmat.h).
const PACKAGES: &[&str] = &[
    "mumps",
    "superlu",
    "superlu_dist",
    "strumpack",
    "umfpack",
    "cholmod",
    "klu",
    "spqr",
    "mkl_pardiso",
    "mkl_cpardiso",
    "pastix",
    "petsc",
    "elemental",
    "sparseelemental",
    "scalapack",
    "essl",
    "lusol",
    "matlab",
    "bas",
    "cusparse",
    "cusparseband",
    "cuda",
    "hipsparse",
    "hipsparseband",
    "hip",
    "kokkos",
    "kokkosdevice",
];

/// The names of a PETSc function list (initialized by its package).
fn names(list: sys::PetscFunctionList) -> Result<Vec<String>, Error> {
    let mut array: *mut *const c_char = std::ptr::null_mut();
    let mut n: c_int = 0;
    // SAFETY: `list` is a registry PETSc initialized (the callers
    // initialize its package first); PETSc allocates an array of its n
    // names and writes its address and n.
    check(unsafe { sys::PetscFunctionListGet(list, &mut array, &mut n) })?;
    // SAFETY: `array` holds n pointers to the list's names, C strings that
    // live as long as the list.
    let mut out = unsafe { strings_from(array, n.max(0) as usize) };
    // SAFETY: the array (not the names) was allocated by PETSc for us;
    // freed once, here.
    check(unsafe { sys::ubr_free(array as *mut c_void) })?;
    out.sort();
    out.dedup();
    Ok(out)
}

/// The Krylov methods of this PETSc (`-ksp_type`).
pub fn ksp_types() -> Result<Vec<String>, Error> {
    // SAFETY: registers PETSc's KSP package (once; no arguments).
    check(unsafe { sys::KSPInitializePackage() })?;
    // SAFETY: a read of the handle of PETSc's list, set by the package's
    // initialization above, on this rank's one thread.
    names(unsafe { sys::KSPList })
}

/// The preconditioners of this PETSc (`-pc_type`).
pub fn pc_types() -> Result<Vec<String>, Error> {
    // SAFETY: registers PETSc's PC package (once; no arguments).
    check(unsafe { sys::PCInitializePackage() })?;
    // SAFETY: a read of the handle of PETSc's list, set by the package's
    // initialization above, on this rank's one thread.
    names(unsafe { sys::PCList })
}

/// Whether `package` (None: any) is a solver package of this PETSc
/// (None if not) that factorizes a matrix of type `mat_type`
/// (`seqaij`, `mpiaij`) as `factor`.
pub fn factorizes(
    package: Option<&str>,
    mat_type: &str,
    factor: Factor,
) -> Result<Option<bool>, Error> {
    let pkg = package.map(|p| CString::new(p).unwrap_or_default());
    let mt = CString::new(mat_type).expect("no NUL");
    let (mut found, mut found_mat) = (sys::PETSC_FALSE, sys::PETSC_FALSE);
    let mut create: sys::MatSolverFunction = None;
    // SAFETY: registers PETSc's Mat package (once; no arguments).
    check(unsafe { sys::MatInitializePackage() })?;
    // SAFETY: the names are C strings (the package's may be null: any);
    // PETSc writes two bools and a function pointer of ours.
    check(unsafe {
        sys::MatSolverTypeGet(
            pkg.as_ref().map_or(std::ptr::null(), |p| p.as_ptr()),
            mt.as_ptr(),
            factor.raw(),
            &mut found,
            &mut found_mat,
            &mut create,
        )
    })?;
    if package.is_some() && found == sys::PETSC_FALSE {
        return Ok(None);
    }
    Ok(Some(create.is_some()))
}

/// The packages of this PETSc that factorize `mat_type` as `factor`.
pub fn packages_for(mat_type: &str, factor: Factor) -> Result<Vec<&'static str>, Error> {
    let mut out = Vec::new();
    for p in PACKAGES {
        if factorizes(Some(p), mat_type, factor)? == Some(true) {
            out.push(*p);
        }
    }
    Ok(out)
}

/// Reads the linear solver's options (`-ksp_*`, `-pc_*`) into a solver
/// of this rank alone, as the run's solver will: no communication, so
/// every rank ends alike. It reads a copy of the options database, so
/// that an option only it read is still reported as unused at the end.
/// Returns the options it read; `Err`: PETSc's message.
pub fn read_solver_options() -> Result<Vec<String>, String> {
    let all = options::listing(check_text)?;
    let mut copy: sys::PetscOptions = std::ptr::null_mut();
    // SAFETY: PETSc writes a new, empty options database into `copy`.
    check_text(unsafe { sys::PetscOptionsCreate(&mut copy) })?;
    let used = read_into(copy, &all);
    // SAFETY: `copy` was made above and is destroyed once; nothing refers
    // to it any more (the solver that read it is destroyed in read_into).
    let d = unsafe { sys::PetscOptionsDestroy(&mut copy) };
    let used = used?;
    check_text(d)?;
    Ok(used)
}

/// [`read_solver_options`] on the live database `copy`, filled from the
/// listing `all`.
fn read_into(copy: sys::PetscOptions, all: &CStr) -> Result<Vec<String>, String> {
    // SAFETY: `copy` is live (the contract above); `all` a C string.
    if unsafe { sys::PetscOptionsInsertString(copy, all.as_ptr()) } != 0 {
        // Not a copy to judge by (PETSc's listing does not quote
        // values): the run's solver will read the options itself.
        take_error(0);
        return Ok(Vec::new());
    }
    let mut ksp: sys::KSP = std::ptr::null_mut();
    // SAFETY: PETSc writes a new KSP on its self communicator into `ksp`.
    let read = check_text(unsafe { sys::KSPCreate(comm_self(), &mut ksp) })
        .and_then(|()| {
            // SAFETY: `ksp` was made just above; `copy` is live and
            // outlives it (destroyed after it, by the caller).
            check_text(unsafe { sys::PetscObjectSetOptions(ksp as sys::PetscObject, copy) })
        })
        // SAFETY: `ksp` is live.
        .and_then(|()| check_text(unsafe { sys::KSPSetFromOptions(ksp) }));
    if !ksp.is_null() {
        // SAFETY: the KSP made above, destroyed once.
        unsafe { sys::KSPDestroy(&mut ksp) };
    }
    read?;
    let left = options::left_in(copy).map_err(|e| e.to_string())?;
    let names = all.to_string_lossy();
    let mut used: Vec<String> = names
        .split_whitespace()
        .filter(|w| super::options::is_key(w))
        .filter(|w| !left.iter().any(|l| l == w))
        .map(String::from)
        .collect();
    used.dedup();
    Ok(used)
}
