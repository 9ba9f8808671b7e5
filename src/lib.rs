//! ubr-petsc: Uzawa block relaxation (Koko 2010) for unilateral contact in
//! linear elasticity, distributed on PETSc and MPI.
//!
//! # Floors
//!
//! The modules stand on floors; a module imports from its own floor and
//! those below, never from above (`tests/house.rs` checks it on the `use`
//! lines and `crate::` paths). Bottom to top:
//!
//! 1. [`error`], [`petsc`], [`mumps`], [`dense`], [`comm`], [`progress`]:
//!    errors, the PETSc and MUMPS bindings, dense algebra, the MPI
//!    collectives, the progress line;
//! 2. [`options`]: the settings and the typed values options parse to;
//! 3. [`element`]: shape functions, quadrature, Jacobians, Hooke's law
//!    (pure functions of coordinates, no mesh);
//! 4. [`mesh`]: meshes, their generators and readers, the distribution;
//! 5. [`fem`]: assembly, loads, stresses;
//! 6. [`contact`]: candidates, the obstacle, the operators B and B^T W, the
//!    pointwise projections;
//! 7. [`linalg`]: the linear back-ends (PETSc's KSP, MUMPS called
//!    directly, orderings, the Schur complement);
//! 8. [`wellposed`], [`touching`]: the analysis of the scene (what holds
//!    each body; parts of the mesh that touch or overlap);
//! 9. [`solver`]: the discrete problem and the algorithms (UBR-C, UBR-TF,
//!    CF-FP, the choice of r, the comparators SSN-C and SNES VI);
//! 10. [`checks`]: the checks of a solution and the set-up warnings;
//! 11. [`report`]: the summary, the JSON report, the output files;
//! 12. [`app`], then `main.rs`: the run, step by step.
//!
//! There are no exceptions.

pub mod app;
pub mod checks;
pub mod comm;
pub mod contact;
pub mod dense;
pub mod element;
pub mod error;
pub mod fem;
pub mod linalg;
pub mod mesh;
pub mod mumps;
pub mod options;
pub mod petsc;
pub mod progress;
pub mod report;
pub mod solver;
pub mod touching;
pub mod wellposed;

pub use petsc::{Events, Stages};
