//! Bindings to Debian's PETSc and to MUMPS' C interface (`dmumps_c.h`,
//! libmumps-dev), generated at build time by bindgen, and a small C shim for
//! what PETSc offers only as macros (log events).

use std::env;
use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed=src/petsc/shim.c");
    println!("cargo:rerun-if-changed=src/petsc/wrapper.h");
    println!("cargo:rerun-if-changed=src/mumps/wrapper.h");
    let petsc = pkg_config::Config::new()
        .probe("PETSc")
        .or_else(|_| pkg_config::Config::new().probe("petsc"))
        .expect("PETSc not found by pkg-config: install petsc-dev (./run.sh does)");
    let mpi = pkg_config::Config::new()
        .cargo_metadata(false)
        .probe("ompi-c")
        .expect("Open MPI not found by pkg-config: install libopenmpi-dev (./run.sh does)");
    let includes: Vec<PathBuf> = petsc
        .include_paths
        .iter()
        .chain(mpi.include_paths.iter())
        .cloned()
        .collect();

    let mut build = cc::Build::new();
    build.file("src/petsc/shim.c").warnings(false);
    for p in &includes {
        build.include(p);
    }
    build.compile("ubr_petsc_shim");

    let mut builder = bindgen::Builder::default()
        .header("src/petsc/wrapper.h")
        .allowlist_function("(Petsc|Vec|Mat|KSP|PC|IS|SNES|ubr_).*")
        .allowlist_type("(Petsc|Vec|Mat|KSP|PC|IS|SNES|Insert|Norm|Scatter).*")
        .allowlist_var("(PETSC|MAT|KSP|PC|VEC|SNES|NORM|INSERT|ADD|SCATTER).*")
        .blocklist_type("MPI_.*|ompi_.*")
        .blocklist_item("FP_(NAN|INFINITE|ZERO|SUBNORMAL|NORMAL)")
        .raw_line("pub use mpi::ffi::{MPI_Comm, MPI_Datatype, MPI_File, MPI_Group, MPI_Info, MPI_Offset, MPI_Op, MPI_Request, MPI_Status, MPI_Win, MPI_Aint, MPI_Errhandler, MPI_Message};")
        .derive_default(true)
        .layout_tests(false)
        .generate_comments(false)
        .prepend_enum_name(false);
    for p in &includes {
        builder = builder.clang_arg(format!("-I{}", p.display()));
    }
    let bindings = builder.generate().expect("bindgen failed on petsc.h");
    let out = PathBuf::from(env::var("OUT_DIR").unwrap());
    bindings
        .write_to_file(out.join("petsc_sys.rs"))
        .expect("cannot write bindings");

    // MUMPS 5.5 itself (the library PETSc loads), for the direct back-end.
    let mumps = bindgen::Builder::default()
        .header("src/mumps/wrapper.h")
        .allowlist_type("DMUMPS_STRUC_C")
        .allowlist_function("dmumps_c")
        .derive_default(true)
        .layout_tests(false)
        .generate_comments(false)
        .generate()
        .expect("bindgen failed on dmumps_c.h (install libmumps-dev: ./run.sh does)");
    mumps
        .write_to_file(out.join("mumps_sys.rs"))
        .expect("cannot write bindings");
    // LAPACK and BLAS for the dense Schur complement (their sonames, as
    // PETSc and MUMPS load them: Debian's alternatives pick the library).
    for lib in ["dmumps", "mumps_common", "pord", "lapack", "blas"] {
        println!("cargo:rustc-link-lib=dylib={lib}");
    }
}
