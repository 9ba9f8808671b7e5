//! `ubr-petsc`: options -> scene -> run -> report. See `app::run`.

use mpi::traits::*;
use ubr_petsc::options::files::{self, Expanded};
use ubr_petsc::{app, petsc::Petsc};

/// Rank 0 reads the options files (as PETSc would) and every rank gets
/// the outcome: the arguments PETSc starts with, or the one-line error.
fn options_files<C: Communicator>(world: &C) -> Result<Expanded, String> {
    let root = world.process_at_rank(0);
    let mut bytes = Vec::new();
    if world.rank() == 0 {
        let args: Vec<String> = std::env::args().collect();
        let env = std::env::var("PETSC_OPTIONS").ok();
        let outcome = files::expand(&args, env.as_deref(), &files::petscrc_files());
        bytes = serde_json::to_vec(&outcome).expect("strings serialize");
    }
    let mut len = [bytes.len() as u64];
    root.broadcast_into(&mut len[..]);
    bytes.resize(len[0] as usize, 0);
    root.broadcast_into(&mut bytes[..]);
    serde_json::from_slice(&bytes).expect("rank 0 sent an outcome")
}

/// One OpenMP thread per rank unless `OMP_NUM_THREADS` says otherwise.
/// Debian's SuperLU_DIST (`-pc_factor_mat_solver_type superlu_dist`, which
/// PETSc loads with OpenMP's runtime) runs a thread per core it may use,
/// and its solves with more than one were wrong here (hertz2d h 0.1, one
/// rank, 2 threads: UBR "moves without bound" at every run, LU or
/// Cholesky; one thread: the answer of MUMPS). `mpirun` binding each rank
/// to one core hid it on 2 ranks; started without mpirun, or at 3 ranks
/// and more (bound to a socket), every rank ran a thread per core, on
/// cores the other ranks use too. The runtime read the variable when it
/// loaded, so the count is set through its call (found in the process, if
/// loaded at all).
fn one_openmp_thread() {
    if std::env::var_os("OMP_NUM_THREADS").is_some() {
        return;
    }
    extern "C" {
        fn dlsym(
            handle: *mut std::ffi::c_void,
            name: *const std::ffi::c_char,
        ) -> *mut std::ffi::c_void;
    }
    // SAFETY: dlsym (RTLD_DEFAULT: the null handle) reads a NUL-terminated
    // name and returns the symbol's address or null.
    let f = unsafe { dlsym(std::ptr::null_mut(), c"omp_set_num_threads".as_ptr()) };
    if !f.is_null() {
        // SAFETY: the address of OpenMP's `void omp_set_num_threads(int)`.
        let set: extern "C" fn(std::ffi::c_int) = unsafe { std::mem::transmute(f) };
        set(1);
    }
}

fn main() {
    // PT-Scotch (`-partition ptscotch`) runs threads of its own by default,
    // and its threaded algorithms give another partition at every run
    // (measured: 49 to 60 UBR iterations in repeats of one GAMG run); one
    // thread per rank, as each rank has its own core, makes it the same
    // run to run. A setting of the user's stays. Set before MPI starts
    // any thread of its own.
    if std::env::var_os("SCOTCH_PTHREAD_NUMBER").is_none() {
        std::env::set_var("SCOTCH_PTHREAD_NUMBER", "1");
    }
    one_openmp_thread();
    let Some(universe) = mpi::initialize() else {
        eprintln!("error: MPI could not be initialized");
        std::process::exit(1);
    };
    let world = universe.world();
    let rank = world.rank();
    // A panic on one rank must not leave the others waiting in a collective.
    std::panic::set_hook(Box::new(|info| {
        eprintln!("internal error (bug): {info}");
        mpi::topology::SimpleCommunicator::world().abort(70);
    }));
    // The options files, expanded before PETSc (which would end a mistake
    // in one in a traceback, and one that includes itself in a stack
    // overflow): one line and exit status 2 on every rank.
    let expanded = match options_files(&world) {
        Ok(e) => e,
        Err(msg) => {
            if rank == 0 {
                eprintln!("error: {msg}");
            }
            drop(universe);
            std::process::exit(2);
        }
    };
    if let Some(env) = &expanded.env {
        std::env::set_var("PETSC_OPTIONS", env);
    }
    files::record(&expanded);
    let code = {
        let petsc = match Petsc::init(world.as_raw(), &expanded.args) {
            Ok(p) => p,
            Err(e) => {
                eprintln!("{e}");
                world.abort(1);
            }
        };
        let code = match app::run(&world) {
            Ok(()) => 0,
            Err(e) => {
                if !e.is_collective() {
                    // Possibly seen by this rank only: end every rank now.
                    eprintln!("[rank {rank}] {e}");
                    world.abort(e.exit_code());
                }
                if rank == 0 {
                    eprintln!("{e}");
                }
                e.exit_code()
            }
        };
        drop(petsc);
        code
    };
    drop(universe);
    std::process::exit(code);
}
