//! Thin, owned bindings to PETSc: the bindgen'd `sys` module and RAII wrappers.
//!
//! Every `PetscErrorCode` goes through [`check`], which turns it into an
//! [`Error::Petsc`] carrying PETSc's own message (captured by an error handler
//! installed at start-up, so PETSc prints no traceback of its own).

#[allow(
    non_camel_case_types,
    non_snake_case,
    non_upper_case_globals,
    dead_code,
    improper_ctypes,
    clippy::all
)]
pub mod sys {
    include!(concat!(env!("OUT_DIR"), "/petsc_sys.rs"));
}

mod log;
mod objects;
pub use log::{Events, Stages};
pub use objects::*;

use crate::error::Error;
use std::cell::RefCell;
use std::ffi::{c_char, c_int, c_void, CStr, CString};

thread_local! {
    /// PETSc's last error: its message and where it was raised.
    static LAST_ERROR: RefCell<Option<(String, String)>> = const { RefCell::new(None) };
}

unsafe extern "C" fn record_error(
    _comm: sys::MPI_Comm,
    line: c_int,
    func: *const c_char,
    file: *const c_char,
    n: sys::PetscErrorCode,
    p: sys::PetscErrorType,
    mess: *const c_char,
    _ctx: *mut c_void,
) -> sys::PetscErrorCode {
    let s = |ptr: *const c_char| {
        if ptr.is_null() {
            String::new()
        } else {
            CStr::from_ptr(ptr).to_string_lossy().into_owned()
        }
    };
    if p == sys::PETSC_ERROR_INITIAL {
        // One line: PETSc's messages may hold several.
        let mut text = s(mess).split_whitespace().collect::<Vec<_>>().join(" ");
        if text.is_empty() {
            let mut generic: *const c_char = std::ptr::null();
            sys::PetscErrorMessage(n, &mut generic, std::ptr::null_mut());
            text = s(generic);
        }
        let place = format!("PETSc error {n} in {}() at {}:{line}", s(func), s(file));
        LAST_ERROR.with(|e| *e.borrow_mut() = Some((text, place)));
    }
    n
}

/// PETSc's message of a failed call (without where it was raised).
fn take_error(code: sys::PetscErrorCode) -> (String, String) {
    LAST_ERROR
        .with(|e| e.borrow_mut().take())
        .unwrap_or_else(|| (format!("PETSc error {code}"), String::new()))
}

/// Turns a PETSc error code into a `Result`.
pub fn check(code: sys::PetscErrorCode) -> Result<(), Error> {
    if code == 0 {
        return Ok(());
    }
    let (text, place) = take_error(code);
    let message = if place.is_empty() {
        text
    } else {
        format!("{text} ({place})")
    };
    Err(Error::Petsc { code, message })
}

/// Like [`check`], the error being PETSc's message alone (for a message
/// of ours that says what it means).
fn check_text(code: sys::PetscErrorCode) -> Result<(), String> {
    if code == 0 {
        return Ok(());
    }
    Err(take_error(code).0)
}

/// PETSc's lifetime. Created after MPI (rsmpi) and dropped before it:
/// dropping calls `PetscFinalize`, which prints `-log_view`.
pub struct Petsc {
    _private: (),
}

impl Petsc {
    /// Initializes PETSc on `comm` with the process's arguments (program
    /// name first; the options files already expanded, see
    /// [`crate::options::files`]), so that `-help` and `-log_view` work.
    pub fn init(comm: sys::MPI_Comm, args: &[String]) -> Result<Petsc, Error> {
        let args: Vec<CString> = args
            .iter()
            .map(|a| CString::new(a.as_str()).unwrap_or_else(|_| CString::new("?").unwrap()))
            .collect();
        // PETSc keeps pointers to argv: leak it for the life of the process.
        let mut ptrs: Vec<*mut c_char> = args.into_iter().map(|a| a.into_raw()).collect();
        let mut argc = ptrs.len() as c_int;
        ptrs.push(std::ptr::null_mut());
        let mut argv = Box::leak(ptrs.into_boxed_slice()).as_mut_ptr();
        unsafe {
            sys::PETSC_COMM_WORLD = comm;
            let code = sys::PetscInitialize(
                &mut argc,
                &mut argv,
                std::ptr::null(),
                c"ubr-petsc: Uzawa block relaxation for unilateral contact. Run with -help for the options.\n"
                    .as_ptr(),
            );
            if code != 0 {
                return Err(Error::Petsc {
                    code,
                    message: "PetscInitialize failed".into(),
                });
            }
            check(sys::PetscPushErrorHandler(
                Some(record_error),
                std::ptr::null_mut(),
            ))?;
        }
        Ok(Petsc { _private: () })
    }
}

impl Drop for Petsc {
    fn drop(&mut self) {
        unsafe {
            sys::PetscFinalize();
        }
    }
}

/// PETSc's self communicator.
pub fn comm_self() -> sys::MPI_Comm {
    unsafe { sys::ubr_comm_self() }
}

/// PETSc's world communicator (set from rsmpi's world at `Petsc::init`).
pub fn comm_world() -> sys::MPI_Comm {
    unsafe { sys::PETSC_COMM_WORLD }
}

/// The options database, read as strings and parsed by the caller so that
/// errors name the option.
pub mod options {
    use super::*;

    fn cname(name: &str) -> CString {
        CString::new(name).expect("option names have no NUL")
    }

    /// The raw string value of `-name`, `Some("")` when given without a value.
    pub fn get_string(name: &str) -> Result<Option<String>, Error> {
        let key = cname(name);
        let mut buf = vec![0 as c_char; 4096];
        let mut set = sys::PETSC_FALSE;
        unsafe {
            check(sys::PetscOptionsGetString(
                std::ptr::null_mut(),
                std::ptr::null(),
                key.as_ptr(),
                buf.as_mut_ptr(),
                buf.len(),
                &mut set,
            ))?;
        }
        if set == sys::PETSC_FALSE {
            return Ok(None);
        }
        let s = unsafe { CStr::from_ptr(buf.as_ptr()) };
        Ok(Some(s.to_string_lossy().into_owned()))
    }

    pub fn has_name(name: &str) -> Result<bool, Error> {
        let key = cname(name);
        let mut set = sys::PETSC_FALSE;
        unsafe {
            check(sys::PetscOptionsHasName(
                std::ptr::null_mut(),
                std::ptr::null(),
                key.as_ptr(),
                &mut set,
            ))?;
        }
        Ok(set == sys::PETSC_TRUE)
    }

    thread_local! {
        /// The options the program set itself ([`set_default`]): not the
        /// user's, so never reported as unused.
        static SET_BY_PROGRAM: RefCell<Vec<String>> = const { RefCell::new(Vec::new()) };
    }

    /// Sets `-name value` unless the user already set `-name`.
    pub fn set_default(name: &str, value: &str) -> Result<(), Error> {
        if has_name(name)? {
            return Ok(());
        }
        SET_BY_PROGRAM.with(|s| s.borrow_mut().push(name.to_string()));
        let key = cname(name);
        let val = cname(value);
        unsafe {
            check(sys::PetscOptionsSetValue(
                std::ptr::null_mut(),
                key.as_ptr(),
                val.as_ptr(),
            ))
        }
    }

    /// The options of the database that nothing has read so far (names with
    /// their leading `-`), leaving out those the program set itself.
    pub fn unused() -> Result<Vec<String>, Error> {
        let mut out = left_in(std::ptr::null_mut())?;
        let ours = SET_BY_PROGRAM.with(|s| s.borrow().clone());
        out.retain(|name| !ours.contains(name));
        Ok(out)
    }

    /// The options of database `db` (null: the global one) that nothing
    /// has read (names with their leading `-`).
    pub(super) fn left_in(db: sys::PetscOptions) -> Result<Vec<String>, Error> {
        let mut n: sys::PetscInt = 0;
        let mut names: *mut *mut c_char = std::ptr::null_mut();
        let mut values: *mut *mut c_char = std::ptr::null_mut();
        unsafe {
            check(sys::PetscOptionsLeftGet(
                db,
                &mut n,
                &mut names,
                &mut values,
            ))?;
        }
        let mut out = Vec::with_capacity(n as usize);
        for i in 0..n as usize {
            let p = unsafe { *names.add(i) };
            if !p.is_null() {
                let name = unsafe { CStr::from_ptr(p).to_string_lossy().into_owned() };
                out.push(format!("-{}", name.trim_start_matches('-')));
            }
        }
        unsafe {
            check(sys::PetscOptionsLeftRestore(
                db,
                &mut n,
                &mut names,
                &mut values,
            ))?;
        }
        Ok(out)
    }

    /// Every option of the database with its value (None: given without
    /// one), without marking any as used. (A value with a space reads as
    /// its first word: PETSc's listing does not quote it.)
    pub fn all_pairs() -> Result<Vec<(String, Option<String>)>, Error> {
        let mut ptr: *mut c_char = std::ptr::null_mut();
        unsafe {
            check(sys::PetscOptionsGetAll(std::ptr::null_mut(), &mut ptr))?;
        }
        let all = unsafe { CStr::from_ptr(ptr).to_string_lossy().into_owned() };
        unsafe {
            sys::ubr_free(ptr as *mut c_void);
        }
        let words: Vec<&str> = all.split_whitespace().collect();
        let mut out: Vec<(String, Option<String>)> = Vec::new();
        for w in words {
            if crate::options::files::is_key(w) {
                out.push((w.to_string(), None));
            } else if let Some((_, v @ None)) = out.last_mut() {
                *v = Some(w.to_string());
            }
        }
        Ok(out)
    }

    /// The names of every option in the database (with their leading `-`).
    pub fn all_names() -> Result<Vec<String>, Error> {
        let mut ptr: *mut c_char = std::ptr::null_mut();
        unsafe {
            check(sys::PetscOptionsGetAll(std::ptr::null_mut(), &mut ptr))?;
        }
        let all = unsafe { CStr::from_ptr(ptr).to_string_lossy().into_owned() };
        unsafe {
            sys::ubr_free(ptr as *mut c_void);
        }
        Ok(all
            .split_whitespace()
            .filter(|t| t.starts_with('-') && t.len() > 1 && t.parse::<f64>().is_err())
            .map(|t| t.to_string())
            .collect())
    }
}

/// PETSc's registries of linear solvers, asked before any work so that a
/// wrong name in the options is bad input (`options::solver`), not an error
/// in the middle of the set-up.
pub mod registry {
    use super::*;

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

    fn names(list: sys::PetscFunctionList) -> Result<Vec<String>, Error> {
        let mut array: *mut *const c_char = std::ptr::null_mut();
        let mut n: c_int = 0;
        let mut out = Vec::new();
        unsafe {
            check(sys::PetscFunctionListGet(list, &mut array, &mut n))?;
            for i in 0..n.max(0) as usize {
                let p = *array.add(i);
                if !p.is_null() {
                    out.push(CStr::from_ptr(p).to_string_lossy().into_owned());
                }
            }
            sys::ubr_free(array as *mut c_void);
        }
        out.sort();
        out.dedup();
        Ok(out)
    }

    /// The Krylov methods of this PETSc (`-ksp_type`).
    pub fn ksp_types() -> Result<Vec<String>, Error> {
        unsafe {
            check(sys::KSPInitializePackage())?;
            names(sys::KSPList)
        }
    }

    /// The preconditioners of this PETSc (`-pc_type`).
    pub fn pc_types() -> Result<Vec<String>, Error> {
        unsafe {
            check(sys::PCInitializePackage())?;
            names(sys::PCList)
        }
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
        unsafe {
            check(sys::MatInitializePackage())?;
            check(sys::MatSolverTypeGet(
                pkg.as_ref().map_or(std::ptr::null(), |p| p.as_ptr()),
                mt.as_ptr(),
                factor.raw(),
                &mut found,
                &mut found_mat,
                &mut create,
            ))?;
        }
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
        let all = unsafe {
            let mut ptr: *mut c_char = std::ptr::null_mut();
            check_text(sys::PetscOptionsGetAll(std::ptr::null_mut(), &mut ptr))?;
            let all = CStr::from_ptr(ptr).to_owned();
            sys::ubr_free(ptr as *mut c_void);
            all
        };
        unsafe {
            let mut copy: sys::PetscOptions = std::ptr::null_mut();
            check_text(sys::PetscOptionsCreate(&mut copy))?;
            let mut ksp: sys::KSP = std::ptr::null_mut();
            if sys::PetscOptionsInsertString(copy, all.as_ptr()) != 0 {
                // Not a copy to judge by (PETSc's listing does not quote
                // values): the run's solver will read the options itself.
                take_error(0);
                sys::PetscOptionsDestroy(&mut copy);
                return Ok(Vec::new());
            }
            let read = check_text(sys::KSPCreate(comm_self(), &mut ksp))
                .and_then(|()| {
                    check_text(sys::PetscObjectSetOptions(ksp as sys::PetscObject, copy))
                })
                .and_then(|()| check_text(sys::KSPSetFromOptions(ksp)));
            if !ksp.is_null() {
                sys::KSPDestroy(&mut ksp);
            }
            let used = read.and_then(|()| {
                let left = options::left_in(copy).map_err(|e| e.to_string())?;
                let names = all.to_string_lossy();
                let mut used: Vec<String> = names
                    .split_whitespace()
                    .filter(|w| crate::options::files::is_key(w))
                    .filter(|w| !left.iter().any(|l| l == w))
                    .map(String::from)
                    .collect();
                used.dedup();
                Ok(used)
            });
            sys::PetscOptionsDestroy(&mut copy);
            used
        }
    }
}

/// A `-log_view` stage. `push` returns a guard that pops it.
#[derive(Clone, Copy)]
pub struct LogStage(sys::PetscLogStage);

impl LogStage {
    pub fn register(name: &str) -> Result<LogStage, Error> {
        let n = CString::new(name).unwrap();
        let mut s: sys::PetscLogStage = 0;
        unsafe { check(sys::PetscLogStageRegister(n.as_ptr(), &mut s))? };
        Ok(LogStage(s))
    }
    pub fn push(self) -> Result<StageGuard, Error> {
        unsafe { check(sys::PetscLogStagePush(self.0))? };
        Ok(StageGuard)
    }
}

pub struct StageGuard;
impl Drop for StageGuard {
    fn drop(&mut self) {
        unsafe {
            sys::PetscLogStagePop();
        }
    }
}

/// A `-log_view` event.
#[derive(Clone, Copy)]
pub struct LogEvent(sys::PetscLogEvent);

impl LogEvent {
    pub fn register(name: &str) -> Result<LogEvent, Error> {
        let n = CString::new(name).unwrap();
        let mut classid: sys::PetscClassId = 0;
        let mut e: sys::PetscLogEvent = 0;
        unsafe {
            check(sys::PetscClassIdRegister(c"UBR".as_ptr(), &mut classid))?;
            check(sys::PetscLogEventRegister(n.as_ptr(), classid, &mut e))?;
        }
        Ok(LogEvent(e))
    }
    pub fn begin(self) -> EventGuard {
        unsafe {
            sys::ubr_log_event_begin(self.0);
        }
        EventGuard(self.0)
    }
}

pub struct EventGuard(sys::PetscLogEvent);
impl Drop for EventGuard {
    fn drop(&mut self) {
        unsafe {
            sys::ubr_log_event_end(self.0);
        }
    }
}
