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
    ubr_petsc::dense::one_openmp_thread();
    let Some(universe) = mpi::initialize() else {
        eprintln!("error: MPI could not be initialized");
        std::process::exit(1);
    };
    let world = universe.world();
    let rank = world.rank();
    ubr_petsc::dense::one_blas_thread_per_rank(world.split_shared(0).size() as usize);
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
