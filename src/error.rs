//! The one error type of the program, a variant per kind of failure, and its
//! exit status (DESIGN.md): 2 bad input or an ill-posed scene, 3 not
//! converged, 4 out of memory, anything else a bug. `main` prints it once.
//!
//! A Rust allocation that fails ends the run here too ([`OutOfMemory`], the
//! program's global allocator): one line naming the rank and the size, then
//! `MPI_Abort` with exit status 4, which ends every rank.

/// Every way a run can fail.
#[derive(Clone, Debug, thiserror::Error)]
pub enum Error {
    /// An option, or a file an option names, is wrong. Exit status 2.
    #[error("error: {0}")]
    BadInput(String),
    /// A mesh file (or generator) is wrong; the message names the file and
    /// the line or byte offset (`From<MeshError>` is in `mesh`). Exit status 2.
    #[error("error: {0}")]
    Mesh(String),
    /// An output file cannot be written. Exit status 2 (the path is the user's).
    #[error("error: option {option}: cannot write '{path}': {reason}")]
    Output {
        option: &'static str,
        path: String,
        reason: String,
    },
    /// An ill-posed scene: a rigid motion that nothing restrains (named in
    /// the message). Exit status 2, like bad input: the scene must change.
    #[error("error: ill-posed scene: {0}")]
    IllPosed(String),
    /// The contact iteration did not converge. Exit status 3.
    #[error("not converged: {0}")]
    NotConverged(String),
    /// A linear solve failed (e.g. a failed factorization). Exit status 3.
    #[error("error: {0}")]
    LinearSolver(String),
    /// Memory ran out (an allocation failed in MUMPS, in PETSc, in OpenBLAS'
    /// work space or in ours): the run needs more memory than a rank may
    /// use. Exit status 4: neither bad input nor a method that did not
    /// converge; the same run succeeds with more memory or more ranks.
    #[error("error: out of memory: {0}")]
    OutOfMemory(String),
    /// PETSc reported an error. Exit status 1 (a bug, or the machine); 4,
    /// and a message that says so, when an allocation failed
    /// ([`Error::is_out_of_memory`]).
    #[error("{}", petsc_message(*code, message))]
    Petsc { code: i32, message: String },
    /// Anything else that is our fault. Exit status 1.
    #[error("internal error: {0}")]
    Internal(String),
}

/// The exit status of a run that ran out of memory.
pub const EXIT_OUT_OF_MEMORY: i32 = 4;

/// PETSc's error code for a failed allocation (`PETSC_ERR_MEM`).
const PETSC_ERR_MEM: i32 = 55;

impl Error {
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::BadInput(_) | Error::Mesh(_) | Error::Output { .. } | Error::IllPosed(_) => 2,
            Error::NotConverged(_) | Error::LinearSolver(_) => 3,
            Error::OutOfMemory(_) => EXIT_OUT_OF_MEMORY,
            Error::Petsc { .. } if self.is_out_of_memory() => EXIT_OUT_OF_MEMORY,
            Error::Petsc { .. } | Error::Internal(_) => 1,
        }
    }

    /// Whether memory ran out: [`Error::OutOfMemory`], or PETSc's error for
    /// a failed allocation. PETSc 3.18's `PetscMallocAlign` raises it with
    /// its arguments out of order (the caller's line as the error code, its
    /// function's name as the message), so it is known by where it was
    /// raised, as well as by `PETSC_ERR_MEM`.
    pub fn is_out_of_memory(&self) -> bool {
        match self {
            Error::OutOfMemory(_) => true,
            Error::Petsc { code, message } => petsc_out_of_memory(*code, message),
            _ => false,
        }
    }

    /// Whether every rank returns this error together (decided collectively);
    /// any other may be seen by one rank only, which then ends them all.
    pub fn is_collective(&self) -> bool {
        matches!(
            self,
            Error::BadInput(_)
                | Error::Mesh(_)
                | Error::Output { .. }
                | Error::IllPosed(_)
                | Error::NotConverged(_)
                | Error::LinearSolver(_)
                | Error::OutOfMemory(_)
        )
    }

    /// The same error with `note` appended to its message (a hint that
    /// the place where it was found cannot give).
    pub fn with_note(self, note: &str) -> Error {
        let add = |m: String| format!("{m}; {note}");
        match self {
            Error::BadInput(m) => Error::BadInput(add(m)),
            Error::Mesh(m) => Error::Mesh(add(m)),
            Error::IllPosed(m) => Error::IllPosed(add(m)),
            Error::NotConverged(m) => Error::NotConverged(add(m)),
            Error::LinearSolver(m) => Error::LinearSolver(add(m)),
            Error::OutOfMemory(m) => Error::OutOfMemory(add(m)),
            Error::Internal(m) => Error::Internal(add(m)),
            Error::Petsc { code, message } => Error::Petsc {
                code,
                message: add(message),
            },
            Error::Output {
                option,
                path,
                reason,
            } => Error::Output {
                option,
                path,
                reason: add(reason),
            },
        }
    }

    /// Whether the run reports this error as its outcome, after writing its
    /// outputs, when it comes after the assembly: the method did not
    /// converge, a linear solve failed, or memory ran out in a collective
    /// step (every rank has it, so every rank goes on to the outputs).
    pub fn is_outcome(&self) -> bool {
        matches!(
            self,
            Error::NotConverged(_) | Error::LinearSolver(_) | Error::OutOfMemory(_)
        )
    }

    /// An output file that cannot be written, for option `option`.
    pub fn output(option: &'static str, path: &str, reason: impl std::fmt::Display) -> Error {
        Error::Output {
            option,
            path: path.to_string(),
            reason: reason.to_string(),
        }
    }
}

fn petsc_out_of_memory(code: i32, message: &str) -> bool {
    code == PETSC_ERR_MEM || message.contains(" in PetscMallocAlign() at ")
}

/// The message of [`Error::Petsc`].
fn petsc_message(code: i32, message: &str) -> String {
    if petsc_out_of_memory(code, message) {
        format!("error: out of memory: PETSc could not allocate: {message}; the run needs more memory than a rank may use, or more ranks")
    } else {
        format!("PETSc error: {message}")
    }
}

/// Shorthand for a bad-input error.
pub fn bad<T>(msg: impl Into<String>) -> Result<T, Error> {
    Err(Error::BadInput(msg.into()))
}

/// The program's global allocator: the system's, except that an allocation
/// it cannot make ends the run at once with one line on stderr naming the
/// rank and the size, and exit status 4 on every rank (`MPI_Abort`; before
/// MPI starts or after it ends, `_exit(4)`). Without it Rust's default
/// handler prints "memory allocation of N bytes failed" and aborts the
/// process (signal 6, a stack trace under `RUST_BACKTRACE`, and mpirun's
/// notice of a signal). The line is formatted on the stack: nothing is
/// allocated on the way out. Inside [`fallible`] a failed allocation is
/// returned (a null pointer: `try_reserve` then says so) for the caller to
/// report.
pub struct OutOfMemory;

thread_local! {
    /// Set inside [`fallible`].
    static FALLIBLE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `f` with allocations that may fail: one that does returns a null
/// pointer to its caller (`Vec::try_reserve` then returns an error)
/// instead of ending the run. For the large dense arrays whose failure the
/// program reports itself, collectively.
pub fn fallible<T>(f: impl FnOnce() -> T) -> T {
    let before = FALLIBLE.with(|c| c.replace(true));
    let out = f();
    FALLIBLE.with(|c| c.set(before));
    out
}

/// Whether a failed allocation is the caller's to handle ([`fallible`]).
fn may_fail() -> bool {
    FALLIBLE.with(|c| c.get())
}

#[global_allocator]
static ALLOCATOR: OutOfMemory = OutOfMemory;

unsafe impl std::alloc::GlobalAlloc for OutOfMemory {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        let p = std::alloc::System.alloc(layout);
        if p.is_null() && !may_fail() {
            out_of_memory(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: std::alloc::Layout) -> *mut u8 {
        let p = std::alloc::System.alloc_zeroed(layout);
        if p.is_null() && !may_fail() {
            out_of_memory(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        std::alloc::System.dealloc(ptr, layout)
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: std::alloc::Layout, new_size: usize) -> *mut u8 {
        let p = std::alloc::System.realloc(ptr, layout, new_size);
        if p.is_null() && !may_fail() {
            out_of_memory(new_size);
        }
        p
    }
}

/// A fixed buffer that `write!` fills without allocating (the rest is cut).
struct StackLine {
    buf: [u8; 320],
    len: usize,
}

impl std::fmt::Write for StackLine {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        let n = s.len().min(self.buf.len() - self.len);
        self.buf[self.len..self.len + n].copy_from_slice(&s.as_bytes()[..n]);
        self.len += n;
        Ok(())
    }
}

/// The end of a run that ran out of memory (see [`OutOfMemory`]).
#[cold]
fn out_of_memory(bytes: usize) -> ! {
    use std::fmt::Write as _;
    use std::io::Write as _;
    extern "C" {
        fn _exit(status: std::os::raw::c_int) -> !;
    }
    let (mut init, mut fin, mut rank) = (0, 0, -1);
    unsafe {
        mpi::ffi::MPI_Initialized(&mut init);
        mpi::ffi::MPI_Finalized(&mut fin);
        if init != 0 && fin == 0 {
            mpi::ffi::MPI_Comm_rank(mpi::ffi::RSMPI_COMM_WORLD, &mut rank);
        }
    }
    let mut line = StackLine {
        buf: [0; 320],
        len: 0,
    };
    let _ = if rank >= 0 {
        write!(line, "error: out of memory: rank {rank} could not allocate")
    } else {
        write!(line, "error: out of memory: could not allocate")
    };
    let _ = writeln!(
        line,
        " {:.1} MiB; the run needs more memory than a rank may use (a memory limit: ulimit -v, the batch system's), or more ranks",
        bytes as f64 / (1u64 << 20) as f64
    );
    let _ = std::io::stderr().write_all(&line.buf[..line.len]);
    unsafe {
        if init != 0 && fin == 0 {
            mpi::ffi::MPI_Abort(mpi::ffi::RSMPI_COMM_WORLD, EXIT_OUT_OF_MEMORY);
        }
        _exit(EXIT_OUT_OF_MEMORY)
    }
}

/// This process's address space in use and its limit (`ulimit -v`), in
/// bytes, when a limit is set; read with system calls only (no
/// allocation: it runs in a signal handler).
fn address_space() -> Option<(u64, u64)> {
    use std::os::raw::{c_char, c_int, c_long};
    #[repr(C)]
    struct Rlimit {
        cur: u64,
        max: u64,
    }
    extern "C" {
        fn getrlimit(resource: c_int, rlim: *mut Rlimit) -> c_int;
        fn open(path: *const c_char, flags: c_int, ...) -> c_int;
        fn read(fd: c_int, buf: *mut u8, count: usize) -> isize;
        fn close(fd: c_int) -> c_int;
        fn sysconf(name: c_int) -> c_long;
    }
    const RLIMIT_AS: c_int = 9;
    const SC_PAGESIZE: c_int = 30;
    let mut lim = Rlimit { cur: 0, max: 0 };
    if unsafe { getrlimit(RLIMIT_AS, &mut lim) } != 0 || lim.cur == u64::MAX {
        return None;
    }
    // /proc/self/statm: the first field is the size of the address space
    // in pages.
    let mut buf = [0u8; 64];
    let n = unsafe {
        let fd = open(c"/proc/self/statm".as_ptr(), 0);
        if fd < 0 {
            return None;
        }
        let n = read(fd, buf.as_mut_ptr(), buf.len());
        close(fd);
        n
    };
    let digits = buf[..n.max(0) as usize]
        .iter()
        .take_while(|b| b.is_ascii_digit());
    let pages = digits.fold(0u64, |a, &b| a * 10 + (b - b'0') as u64);
    let page = unsafe { sysconf(SC_PAGESIZE) }.max(1) as u64;
    Some((pages * page, lim.cur))
}

/// A crash (SIGSEGV, SIGBUS) with the address space near its limit
/// (`ulimit -v`, 80% or more in use) is memory that ran out in a library
/// that does not check its allocations (seen: MUMPS 5.5's analysis,
/// `dmumps_ana_gnew_`, at a 520 MB limit per rank): one line naming it and
/// exit status 4 on every rank (`MPI_Abort`). Any other signal, or a crash
/// far from the limit, goes to PETSc's own handler (its traceback, exit
/// 59). Pushed on PETSc's handler stack, so `-no_signal_handler` still
/// turns every handler off.
pub fn catch_crash_near_memory_limit() -> Result<(), Error> {
    use crate::petsc::{self, sys};
    use std::os::raw::{c_int, c_void};
    unsafe extern "C" fn handler(sig: c_int, ctx: *mut c_void) -> sys::PetscErrorCode {
        const SIGBUS: c_int = 7;
        const SIGSEGV: c_int = 11;
        if sig == SIGSEGV || sig == SIGBUS {
            if let Some((used, limit)) = address_space() {
                if used >= limit / 5 * 4 {
                    crashed_out_of_memory(sig, used, limit);
                }
            }
        }
        sys::PetscSignalHandlerDefault(sig, ctx)
    }
    if petsc::options::has_name("-no_signal_handler")? {
        return Ok(());
    }
    unsafe {
        petsc::check(sys::PetscPushSignalHandler(
            Some(handler),
            std::ptr::null_mut(),
        ))
    }
}

/// The end of a rank that crashed near its memory limit (see
/// [`catch_crash_near_memory_limit`]).
fn crashed_out_of_memory(sig: std::os::raw::c_int, used: u64, limit: u64) -> ! {
    use std::fmt::Write as _;
    use std::io::Write as _;
    extern "C" {
        fn _exit(status: std::os::raw::c_int) -> !;
    }
    let mut rank = -1;
    unsafe { mpi::ffi::MPI_Comm_rank(mpi::ffi::RSMPI_COMM_WORLD, &mut rank) };
    let mut line = StackLine {
        buf: [0; 320],
        len: 0,
    };
    let mib = |b: u64| b >> 20;
    let _ = writeln!(
        line,
        "error: out of memory: rank {rank} crashed (signal {sig}) with {} MiB of its {} MiB address-space limit (ulimit -v) in use: a library ran out of memory without checking; give each rank more memory, or use more ranks",
        mib(used),
        mib(limit)
    );
    let _ = std::io::stderr().write_all(&line.buf[..line.len]);
    unsafe {
        mpi::ffi::MPI_Abort(mpi::ffi::RSMPI_COMM_WORLD, EXIT_OUT_OF_MEMORY);
        _exit(EXIT_OUT_OF_MEMORY)
    }
}
