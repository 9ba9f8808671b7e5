//! Memory that runs out where no error can be returned: the program's
//! global allocator ([`OutOfMemory`]) and a crash at the address-space
//! limit in a library that does not check its allocations
//! ([`catch_crash_near_memory_limit`]). Both end the run at once with one
//! line naming memory and the rank, and exit status
//! [`EXIT_OUT_OF_MEMORY`] on every rank (`MPI_Abort`). Nothing on the way
//! out allocates: the line is formatted on the stack and written with one
//! call.

// SAFETY: (not a block) the lint below: in this module's functions whose
// callers uphold a contract, each operation still needs its own block,
// with its comment.
#![deny(unsafe_op_in_unsafe_fn)]

use super::{Error, EXIT_OUT_OF_MEMORY};
use std::os::raw::{c_char, c_int, c_long};

// The C library's calls used on the way out (async-signal-safe ones in the
// crash handler).
extern "C" {
    fn _exit(status: c_int) -> !;
    fn getrlimit(resource: c_int, rlim: *mut Rlimit) -> c_int;
    fn open(path: *const c_char, flags: c_int, ...) -> c_int;
    fn read(fd: c_int, buf: *mut u8, count: usize) -> isize;
    fn close(fd: c_int) -> c_int;
    fn sysconf(name: c_int) -> c_long;
}

/// `struct rlimit` (Linux, 64-bit `rlim_t`).
#[repr(C)]
struct Rlimit {
    cur: u64,
    max: u64,
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

// SAFETY: every call is the system allocator's with the caller's arguments
// (its contract is theirs); a null result either ends the process or is
// returned as the system allocator returns it.
unsafe impl std::alloc::GlobalAlloc for OutOfMemory {
    /// # Safety
    /// [`std::alloc::GlobalAlloc::alloc`]'s: a layout of non-zero size.
    // SAFETY: the trait's contract (above), passed on to the system's.
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        // SAFETY: the caller's layout, under the same contract.
        let p = unsafe { std::alloc::System.alloc(layout) };
        if p.is_null() && !may_fail() {
            out_of_memory(layout.size());
        }
        p
    }

    /// # Safety
    /// [`std::alloc::GlobalAlloc::alloc_zeroed`]'s: a layout of non-zero
    /// size.
    // SAFETY: the trait's contract (above), passed on to the system's.
    unsafe fn alloc_zeroed(&self, layout: std::alloc::Layout) -> *mut u8 {
        // SAFETY: the caller's layout, under the same contract.
        let p = unsafe { std::alloc::System.alloc_zeroed(layout) };
        if p.is_null() && !may_fail() {
            out_of_memory(layout.size());
        }
        p
    }

    /// # Safety
    /// [`std::alloc::GlobalAlloc::dealloc`]'s: a block of this allocator
    /// (hence of the system's), with its layout.
    // SAFETY: the trait's contract (above), passed on to the system's.
    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        // SAFETY: every block of ours is the system's (alloc, alloc_zeroed
        // and realloc return its pointers), under the same contract.
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }

    /// # Safety
    /// [`std::alloc::GlobalAlloc::realloc`]'s: a block of this allocator
    /// with its layout, a valid non-zero new size.
    // SAFETY: the trait's contract (above), passed on to the system's.
    unsafe fn realloc(&self, ptr: *mut u8, layout: std::alloc::Layout, new_size: usize) -> *mut u8 {
        // SAFETY: a block of the system's (see dealloc), under the same
        // contract.
        let p = unsafe { std::alloc::System.realloc(ptr, layout, new_size) };
        if p.is_null() && !may_fail() {
            out_of_memory(new_size);
        }
        p
    }
}

/// A fixed buffer that `write!` fills without allocating (the rest is cut).
struct StackLine {
    buf: [u8; 512],
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

/// Whether MPI is running (started, not ended), and this rank then (-1
/// otherwise).
fn mpi_rank() -> (bool, c_int) {
    let (mut init, mut fin, mut rank) = (0, 0, -1);
    // (A failed call counts as "not running" or "no rank": nothing else can
    // be done on the way out.)
    // SAFETY: MPI_Initialized and MPI_Finalized may be called at any time;
    // each writes one int of ours.
    let asked = unsafe { mpi::ffi::MPI_Initialized(&mut init) | mpi::ffi::MPI_Finalized(&mut fin) };
    let live = asked == 0 && init != 0 && fin == 0;
    // SAFETY: MPI runs (just asked); writes one int of ours.
    if live && unsafe { mpi::ffi::MPI_Comm_rank(mpi::ffi::RSMPI_COMM_WORLD, &mut rank) } != 0 {
        rank = -1;
    }
    (live, rank)
}

/// Ends every rank with exit status 4: `MPI_Abort` while MPI runs (`live`),
/// else this process alone.
fn abort(live: bool) -> ! {
    if live {
        // SAFETY: MPI runs (`live`). It does not return; if it failed, this
        // process ends alone below.
        unsafe { mpi::ffi::MPI_Abort(mpi::ffi::RSMPI_COMM_WORLD, EXIT_OUT_OF_MEMORY) };
    }
    // SAFETY: may be called at any time; ends the process at once.
    unsafe { _exit(EXIT_OUT_OF_MEMORY) }
}

/// Ends every rank with exit status 4 after `line` (one line, newline
/// included) on stderr: for the watch of the machine's free memory
/// (`linalg::memfit::watch`), which runs beside the work and cannot return
/// an error to it.
pub fn end_out_of_memory(line: &str) -> ! {
    use std::io::Write as _;
    let (live, _) = mpi_rank();
    let _ = std::io::stderr().write_all(line.as_bytes());
    abort(live)
}

/// The end of a run that ran out of memory (see [`OutOfMemory`]).
#[cold]
fn out_of_memory(bytes: usize) -> ! {
    use std::fmt::Write as _;
    use std::io::Write as _;
    let (live, rank) = mpi_rank();
    let mut line = StackLine {
        buf: [0; 512],
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
    abort(live)
}

/// This process's address space in use and its limit (`ulimit -v`), in
/// bytes, when a limit is set; read with system calls only (no
/// allocation: it runs in a signal handler).
fn address_space() -> Option<(u64, u64)> {
    const RLIMIT_AS: c_int = 9;
    const SC_PAGESIZE: c_int = 30;
    let mut lim = Rlimit { cur: 0, max: 0 };
    // SAFETY: getrlimit writes one struct rlimit of ours.
    if unsafe { getrlimit(RLIMIT_AS, &mut lim) } != 0 || lim.cur == u64::MAX {
        return None;
    }
    // /proc/self/statm: the first field is the size of the address space
    // in pages.
    let mut buf = [0u8; 64];
    // SAFETY: a NUL-terminated path, opened read-only (flags 0).
    let fd = unsafe { open(c"/proc/self/statm".as_ptr(), 0) };
    if fd < 0 {
        return None;
    }
    // SAFETY: an open descriptor; writes at most buf.len() bytes into buf.
    let n = unsafe { read(fd, buf.as_mut_ptr(), buf.len()) };
    // SAFETY: the descriptor opened above, closed once.
    unsafe { close(fd) };
    let digits = buf[..n.max(0) as usize]
        .iter()
        .take_while(|b| b.is_ascii_digit());
    let pages = digits.fold(0u64, |a, &b| a * 10 + (b - b'0') as u64);
    // SAFETY: sysconf reads a constant of the system.
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
    use std::os::raw::c_void;
    /// # Safety
    /// PETSc's signal handler calls it with the signal and the context it
    /// was pushed with (null), which go to PETSc's default handler as they
    /// came.
    // SAFETY: only PETSc's signal handler calls it, with the arguments of
    // the contract above.
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
        // SAFETY: the signal and context as PETSc gave them (the contract).
        unsafe { sys::PetscSignalHandlerDefault(sig, ctx) }
    }
    if petsc::options::has_name("-no_signal_handler")? {
        return Ok(());
    }
    // SAFETY: a handler with PETSc's signature and no context.
    petsc::check(unsafe { sys::PetscPushSignalHandler(Some(handler), std::ptr::null_mut()) })
}

/// The end of a rank that crashed near its memory limit (see
/// [`catch_crash_near_memory_limit`]).
fn crashed_out_of_memory(sig: c_int, used: u64, limit: u64) -> ! {
    use std::fmt::Write as _;
    use std::io::Write as _;
    let (live, rank) = mpi_rank();
    let mut line = StackLine {
        buf: [0; 512],
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
    abort(live)
}
