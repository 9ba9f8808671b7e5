//! ubr-petsc: Uzawa block relaxation (Koko 2010) for unilateral contact in
//! linear elasticity, distributed on PETSc and MPI.

pub mod app;
pub mod checks;
pub mod comm;
pub mod contact;
pub mod dense;
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
pub mod wellposed;

pub use petsc::{Events, Stages};
