//! Thin, owned bindings to PETSc: the bindgen'd `sys` module and RAII wrappers.
//!
//! Every `PetscErrorCode` goes through [`check`], which turns it into an
//! [`Error::Petsc`] carrying PETSc's own message (captured by an error handler
//! installed at start-up, so PETSc prints no traceback of its own); every
//! MPI return code of ours goes through [`mpi_check`].
//!
//! # Soundness
//!
//! Each FFI call sits in its own block with a comment (`SAFETY`) naming what
//! makes it sound. The invariants the wrappers keep:
//!
//! - A wrapper ([`Vector`], [`Matrix`], [`Ksp`], ...) owns one reference to
//!   a PETSc object that PETSc made and that is not yet destroyed; its
//!   `raw` handle is private to this module, so no other code can forge or
//!   copy one. The wrappers hold raw pointers, hence are neither `Send` nor
//!   `Sync`: moving one to another thread is a compile error, as PETSc (like
//!   this program) runs each rank on one thread. So is [`Petsc`] itself.
//! - PETSc runs from [`Petsc::init`] until its guard is dropped
//!   (`PetscFinalize`). The wrappers are *not* tied to the guard by a
//!   lifetime: that would put a lifetime parameter on every type that holds
//!   a vector or a matrix (the solver's, the comparators', the reports'),
//!   a change of every signature outside this module for a guard that lives
//!   in `main` for the whole run. Instead the invariant is checked at run
//!   time where it matters: every constructor returns an error when PETSc
//!   is not running ([`running`]), [`Petsc::init`] refuses a second
//!   initialization, and every destructor leaves its object alone once
//!   PETSc has been finalized (the handle is not touched; the object's
//!   memory goes with the process). A drop after `PetscFinalize` is thus
//!   harmless instead of a call into a finalized library (measured: an
//!   abort on `MPI_ERRORS_ARE_FATAL`), whatever the scope order in `main`;
//!   see the ignored test `petsc::vec::tests::drop_after_finalize_is_harmless`.
//! - What the type system does not check is stated on the functions: the
//!   communicators passed in are live (`comm_world`, `comm_self` or rsmpi's
//!   world), and the closures of [`Vector::read`], [`Vector::write`],
//!   [`DenseColumns`] and [`Matrix::for_each_owned_row`] do not change the
//!   same object through another of its methods (the methods that change
//!   an object take `&self`, as PETSc's handles are shared).

// SAFETY: (not a block) the lint below: in this module's functions whose
// callers uphold a contract, each operation still needs its own block,
// with its comment.
#![deny(unsafe_op_in_unsafe_fn)]

// Generated code: no lint of ours applies (its Default impls, for one, are
// blocks without comments).
#[allow(
    non_camel_case_types,
    non_snake_case,
    non_upper_case_globals,
    dead_code,
    improper_ctypes,
    clippy::all,
    clippy::restriction
)]
pub mod sys {
    include!(concat!(env!("OUT_DIR"), "/petsc_sys.rs"));
}

mod ksp;
mod log;
mod mat;
mod nullspace;
pub mod options;
pub mod partition;
pub mod registry;
mod vec;
pub use ksp::{Ksp, Snes};
pub use log::{EventGuard, Events, LogEvent, LogStage, StageGuard, Stages};
pub use mat::{DenseColumns, MatStats, Matrix};
pub use nullspace::NullSpace;
pub use vec::{Gather, Vector};

use crate::error::Error;
use std::cell::RefCell;
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::marker::PhantomData;

thread_local! {
    /// PETSc's last error: its message and where it was raised.
    static LAST_ERROR: RefCell<Option<(String, String)>> = const { RefCell::new(None) };
}

/// An owned copy of a C string (invalid UTF-8 replaced), empty for null.
///
/// # Safety
/// `ptr` is null or points to a NUL-terminated string valid for the call.
// SAFETY: a contract on the caller (above); each call site says why its
// pointer meets it.
pub(crate) unsafe fn string_from(ptr: *const c_char) -> String {
    if ptr.is_null() {
        return String::new();
    }
    // SAFETY: not null, and NUL-terminated by the contract.
    unsafe { CStr::from_ptr(ptr) }
        .to_string_lossy()
        .into_owned()
}

/// The strings of a C array of `n` string pointers, null ones left out.
///
/// # Safety
/// `array` is null or points to `n` pointers, each null or a
/// NUL-terminated string, all valid for the call.
// SAFETY: a contract on the caller (above); each call site says why its
// array meets it.
unsafe fn strings_from(array: *const *const c_char, n: usize) -> Vec<String> {
    if array.is_null() || n == 0 {
        return Vec::new();
    }
    // SAFETY: `array` points to `n` pointers (the contract).
    let ptrs = unsafe { std::slice::from_raw_parts(array, n) };
    let mut out = Vec::with_capacity(n);
    for &p in ptrs.iter().filter(|p| !p.is_null()) {
        // SAFETY: a NUL-terminated string (the contract).
        out.push(unsafe { string_from(p) });
    }
    out
}

/// `n` entries at `ptr` as a slice (empty when `n` is 0, whatever `ptr`).
///
/// # Safety
/// When `n > 0`, `ptr` points to `n` initialized values that stay valid and
/// unchanged for `'a`.
// SAFETY: a contract on the caller (above); each call site says why its
// array meets it.
unsafe fn slice_from<'a, T>(ptr: *const T, n: usize) -> &'a [T] {
    if n == 0 {
        return &[];
    }
    // SAFETY: n > 0 values at ptr, valid for 'a (the contract).
    unsafe { std::slice::from_raw_parts(ptr, n) }
}

/// Like [`slice_from`], writable.
///
/// # Safety
/// When `n > 0`, `ptr` points to `n` initialized values that nothing else
/// reads or writes during `'a`.
// SAFETY: a contract on the caller (above); each call site says why its
// array meets it.
unsafe fn slice_from_mut<'a, T>(ptr: *mut T, n: usize) -> &'a mut [T] {
    if n == 0 {
        return &mut [];
    }
    // SAFETY: n > 0 values at ptr, ours alone for 'a (the contract).
    unsafe { std::slice::from_raw_parts_mut(ptr, n) }
}

/// PETSc's error handler (pushed by [`Petsc::init`]): keeps the message of
/// an error where it is first raised, for [`check`] to return, and prints
/// nothing.
///
/// # Safety
/// `func`, `file` and `mess` are null or NUL-terminated strings valid for
/// the call, as PETSc passes them to an error handler.
// SAFETY: only PETSc calls it (as its error handler), with the arguments of
// the contract above, on the thread of the call that failed.
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
    if p == sys::PETSC_ERROR_INITIAL {
        // One line: PETSc's messages may hold several.
        // SAFETY: `mess` is null or a C string (the contract).
        let mut text = unsafe { string_from(mess) }
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ");
        if text.is_empty() {
            let mut generic: *const c_char = std::ptr::null();
            // SAFETY: writes the address of PETSc's static text for code
            // `n` (or leaves null); the second text is not asked for.
            unsafe { sys::PetscErrorMessage(n, &mut generic, std::ptr::null_mut()) };
            // SAFETY: null or one of PETSc's static C strings.
            text = unsafe { string_from(generic) };
        }
        // SAFETY: `func` and `file` are null or C strings (the contract).
        let (func, file) = unsafe { (string_from(func), string_from(file)) };
        let place = format!("PETSc error {n} in {func}() at {file}:{line}");
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

/// Turns the return code of an MPI call (`call`, its name) into a
/// `Result`: anything but `MPI_SUCCESS` is an [`Error::Internal`] with
/// MPI's own text for the code.
pub fn mpi_check(code: c_int, call: &str) -> Result<(), Error> {
    if code == 0 {
        return Ok(());
    }
    // MPI_MAX_ERROR_STRING is 256 in Open MPI, 1024 in MPICH.
    let mut buf = [0 as c_char; 1024];
    let mut len: c_int = 0;
    // SAFETY: MPI writes at most MPI_MAX_ERROR_STRING characters (NUL
    // included) into buf, and their count into len; it may be called
    // whatever the state of MPI.
    let r = unsafe { mpi::ffi::MPI_Error_string(code, buf.as_mut_ptr(), &mut len) };
    let text = if r == 0 {
        let bytes: Vec<u8> = buf.iter().map(|&c| c as u8).collect();
        CStr::from_bytes_until_nul(&bytes)
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    } else {
        String::new()
    };
    Err(Error::Internal(format!(
        "{call} failed: MPI error {code}{}{text}",
        if text.is_empty() { "" } else { ": " }
    )))
}

/// Whether PETSc is running: initialized and not yet finalized.
pub fn running() -> bool {
    let (mut init, mut fin) = (sys::PETSC_FALSE, sys::PETSC_FALSE);
    // SAFETY: each writes one flag of PETSc's into a bool of ours; both may
    // be called at any time, before PetscInitialize and after PetscFinalize
    // included.
    unsafe {
        sys::PetscInitialized(&mut init);
        sys::PetscFinalized(&mut fin);
    }
    init == sys::PETSC_TRUE && fin == sys::PETSC_FALSE
}

/// An error unless PETSc is running: every PETSc object's constructor asks
/// (see the module's documentation).
fn ensure_running() -> Result<(), Error> {
    if running() {
        return Ok(());
    }
    Err(Error::Internal(
        "a PETSc object was asked for while PETSc is not running (before Petsc::init, or after its guard was dropped)".into(),
    ))
}

/// PETSc's lifetime. Created after MPI (rsmpi) and dropped before it:
/// dropping calls `PetscFinalize`, which prints `-log_view`. One per
/// process ([`Petsc::init`] refuses a second), on one thread (neither
/// `Send` nor `Sync`).
pub struct Petsc {
    _one_thread: PhantomData<*mut ()>,
}

/// PETSc's `-help` header.
const HELP: &CStr =
    c"ubr-petsc: Uzawa block relaxation for unilateral contact. Run with -help for the options.\n";

impl Petsc {
    /// Initializes PETSc on `comm` with the process's arguments (program
    /// name first; the options files already expanded, see
    /// [`crate::options::files`]), so that `-help` and `-log_view` work.
    pub fn init(comm: sys::MPI_Comm, args: &[String]) -> Result<Petsc, Error> {
        let mut called = sys::PETSC_FALSE;
        // SAFETY: writes one flag of PETSc's into a bool of ours (callable
        // at any time).
        unsafe { sys::PetscInitialized(&mut called) };
        if called == sys::PETSC_TRUE {
            return Err(Error::Internal(
                "PETSc is initialized already: one Petsc guard per process".into(),
            ));
        }
        let args: Vec<CString> = args
            .iter()
            .map(|a| CString::new(a.as_str()).unwrap_or_else(|_| CString::new("?").unwrap()))
            .collect();
        // PETSc keeps pointers to argv: leak it for the life of the process.
        let mut ptrs: Vec<*mut c_char> = args.into_iter().map(|a| a.into_raw()).collect();
        let mut argc = ptrs.len() as c_int;
        ptrs.push(std::ptr::null_mut());
        let mut argv = Box::leak(ptrs.into_boxed_slice()).as_mut_ptr();
        // SAFETY: PETSc is not initialized (checked above), so nothing of
        // PETSc reads its world communicator yet, and this rank runs on one
        // thread (Petsc is not Send): no concurrent access to the static.
        unsafe { sys::PETSC_COMM_WORLD = comm };
        let (no_file, help) = (std::ptr::null(), HELP.as_ptr());
        // SAFETY: argc and argv point to the count and to a leaked,
        // null-ended array of argc NUL-terminated strings that live for the
        // process (PETSc keeps them); HELP is a static C string; no options
        // file (null).
        let code = unsafe { sys::PetscInitialize(&mut argc, &mut argv, no_file, help) };
        if code != 0 {
            return Err(Error::Petsc {
                code,
                message: "PetscInitialize failed".into(),
            });
        }
        // PETSc runs from here: the guard finalizes it whatever follows.
        let petsc = Petsc {
            _one_thread: PhantomData,
        };
        // SAFETY: record_error has the signature of a PETSc error handler
        // and uses no context.
        check(unsafe { sys::PetscPushErrorHandler(Some(record_error), std::ptr::null_mut()) })?;
        Ok(petsc)
    }
}

impl Drop for Petsc {
    fn drop(&mut self) {
        // SAFETY: the one guard (Petsc::init refuses a second) was made by
        // a successful PetscInitialize, and is dropped once. Objects still
        // alive after this leave PETSc alone (see the module's
        // documentation). Its error code has nowhere to go from a drop.
        unsafe { sys::PetscFinalize() };
    }
}

/// PETSc's self communicator.
pub fn comm_self() -> sys::MPI_Comm {
    // SAFETY: returns PETSc's constant PETSC_COMM_SELF (MPI_COMM_SELF);
    // reads nothing else.
    unsafe { sys::ubr_comm_self() }
}

/// PETSc's world communicator (set from rsmpi's world at `Petsc::init`).
pub fn comm_world() -> sys::MPI_Comm {
    // SAFETY: a read of a handle that only Petsc::init writes, before PETSc
    // runs, on this rank's one thread.
    unsafe { sys::PETSC_COMM_WORLD }
}
