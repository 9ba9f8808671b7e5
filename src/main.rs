//! `ubr-petsc`: options -> scene -> run -> report. See `app::run`.

use mpi::traits::*;
use ubr_petsc::{app, options, petsc::Petsc};

fn main() {
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
    // A missing options file: one line and exit status 2, before PETSc
    // (which would end in a traceback). Every rank sees the same arguments.
    let args: Vec<String> = std::env::args().collect();
    if let Some(msg) = options::unreadable_options_file(&args) {
        if rank == 0 {
            eprintln!("error: {msg}");
        }
        drop(universe);
        std::process::exit(2);
    }
    let code = {
        let petsc = match Petsc::init(world.as_raw()) {
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
