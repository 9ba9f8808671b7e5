//! The linear back-ends of UBR and its comparators: the KSP from the
//! options database ([`linear_solver`]), MUMPS called directly
//! ([`direct`]) with its orderings ([`ordering`]), and the solver that
//! applies `K_r^{-1}` to UBR's right-hand sides ([`linear`]).

pub mod direct;
mod distsol;
mod grid;
pub mod linear;
pub mod memfit;
pub mod ordering;
mod schur;

use crate::error::Error;
use crate::mesh::distribute::LocalMesh;
use crate::options::LinearBackend;
use crate::petsc::{self, options, sys, Ksp, Matrix, NullSpace, Vector};

/// Default largest number of contact unknowns for the condensed back-end
/// (MUMPS called directly: the Schur unknowns last, u_n alone when
/// frictionless along an axis), in 2D and 3D, frictionless and with
/// friction (every component, and often 100-250 iterations against
/// 30-70). Above it the dense m^3/3 of the Schur block (on rank 0 below
/// [`SCHUR_GRID_RANKS`]) and the larger sparse factorization (the Schur unknowns ride up to the
/// root) cost more than the full sparse solves they save. Measured
/// (factorization + r choice + iterations, full against condensed):
/// - 1 rank: 2D hertz_37473 (329 unknowns) 2.2 -> 0.7 s; 3D block3d_2357
///   (262) 0.14 -> 0.13 s, block3d_10761 (762) 2.00 -> 1.48 s,
///   block3d_17887 (1042) 7.1 -> 4.8 s, a generated 83,300-node block
///   (2380) 58.1 -> 48.0 s; Coulomb block3d_10761 (2286) 5.6 -> 3.1 s,
///   block3d_17887 (3126) 10.6 -> 6.5 s.
/// - 2 ranks (2026-11-28): 2D Coulomb on the generated Hertz scene at
///   `-mesh_h 0.01` (582k nodes, 2516 unknowns) 153.4 -> 14.0 s (246 full
///   solves of 0.57 s against a dense solve of 3 ms; the Schur block adds
///   2.4 s to the sparse factorization); 3D Coulomb on the generated block
///   at `-mesh_h 0.0333` (63k nodes, 5952 unknowns) 71.5 -> 39.6 s (158
///   full solves of 0.35 s; the Schur block adds 15.5 s to the sparse
///   factorization and 4.0 s of dense Cholesky). Frictionless, 27 such
///   iterations would not pay for those 19.5 s: 3D keeps 4000 there.
///   2D frictionless on the Hertz scene at `-mesh_h 0.005` (2.33M nodes,
///   2514 unknowns, 92 iterations) 313.6 -> 63.1 s. 3D Tresca, few
///   iterations (the block at `-mesh_h 0.037`, 47k nodes, 4872 unknowns,
///   46-50 iterations) 35.3 -> 24.8 s, rank 0's peak 927 -> 1996 MiB.
///
/// In 2D the sparse solves grow as n log n and the dense one as m^2 ~ n
/// (a boundary's unknowns), so the break-even comes late.
pub const CONDENSE_MAX: [[usize; 2]; 2] = [[6000, 6000], [4000, 6000]];

/// In 3D, at the default `-ubr_condense_max`, the condensation is declined
/// after MUMPS' analysis with the Schur complement where that analysis
/// predicts fewer sparse factorization flops (RINFOG(1)) than this times
/// m^3, m the Schur block's order: the dense block's Cholesky (m^3 / 3,
/// again at each change of r) and its solves (2 m^2 each) then outweigh
/// the full sparse solves they save (a contact surface that holds a large
/// share of a small mesh's unknowns: a plate on its face, a ball's whole
/// skin). The analysis is made again without it. Measured (1 rank, total
/// s, condensed against full solves, own Gmsh scenes; ratio RINFOG / m^3):
/// a 1 x 1 x 0.1 plate pressed on a large ball, its bottom face the
/// contact surface, h 0.05 / 0.033 / 0.025 (ratio 0.12-0.13): frictionless
/// 0.28 / 0.11, 1.82 / 0.68; Coulomb 0.32 / 0.28, 2.02 / 1.09, 7.32 / 2.40;
/// a ball on a plane under its weight, its whole skin the surface (0.25,
/// 0.26), Coulomb: 3.87 / 2.52, 6.52 / 3.88; disc3d_halfball_coulomb of
/// tests/scenes (0.17): 1.35 / 0.49; plates 0.2 thick (0.25, 0.31):
/// frictionless 0.26 / 0.18, 2.20 / 1.12, Coulomb 0.32 / 0.36, 2.75 /
/// 2.05; 0.4 thick (0.84, 0.91): frictionless 0.46 / 0.57, 3.93 / 3.14,
/// Coulomb 0.61 / 0.85, 3.73 / 5.24; 0.7 thick (2.2, 2.4): 0.98 / 1.42,
/// 7.71 / 7.42, 0.93 / 2.01, 7.65 / 11.99; hemisphere3d_coulomb (0.92)
/// 0.37 / 0.81; block3d_17887 frictionless (42) 3.36 / 5.74, Coulomb (2.7)
/// 5.73 / 15.97. In 2D the full solves cost more than their flops (many
/// small fronts: 5 ms for 10,000 unknowns), and a 4 x 0.1 strip on its
/// long edge (ratio 0.15-0.19) condenses faster (0.18 / 1.49 s, Coulomb
/// 0.69 / 7.54): 2D keeps the count alone.
pub const CONDENSE_DENSE_SHARE: f64 = 0.5;

/// The rank count from which the Schur complement of a condensed run is
/// distributed over the ranks and factorized and solved there by ScaLAPACK
/// by default (`-ubr_schur_distributed`; [`grid`]), in 2D and in 3D.
/// Measured on a 16-core machine (2026-11-28; total s, LAPACK on rank 0
/// against ScaLAPACK): generated block, Coulomb, 5952 unknowns: 16 ranks
/// 13.5 against 8.1 and 9.1 (the dense factorization 1.56 against 0.28 s,
/// 143 solves 3.38 against 0.92 s), 8 ranks 16.1 against 11.2;
/// frictionless 3D (1984 unknowns) 5.6-5.7 against 5.1, 2D (1258) 2.8-2.9
/// against 2.6. On 2 ranks (this project's 2-core machine, 2026-11-29,
/// interleaved, medians of 3-10 runs, with MUMPS' pre-splitting of 3D
/// fronts): 3D gains, the rank-0 factorizations of S shared: the 63k-node
/// block (1984 unknowns) 12.49 -> 12.00 s, its Coulomb variant at h 0.05
/// 2.62 -> 2.40 s, block3d-coulomb on block3d_17887 3.49 -> 3.21 s,
/// block3d_17887 1.504 -> 1.503 s; 2D loses on the small scenes, whose
/// solves are short and whose one-column solves on a 1 x 2 grid wait on
/// each other's blocks: hertz_37473 0.294 -> 0.300 s (its iterations
/// 0.013 -> 0.015 s), hertz-coulomb 0.340 -> 0.343 s, the 582k-node 2D
/// scene 5.66 -> 5.62 s. (The measurement of 2026-11-28, medians of 2-3
/// runs and without the pre-splitting, had found no gain on 2 ranks.)
pub const SCHUR_GRID_RANKS: [usize; 2] = [4, 2];

/// The default of `-ubr_schur_distributed`: whether `ranks` ranks in
/// dimension `d` distribute the Schur complement ([`SCHUR_GRID_RANKS`];
/// never where MUMPS came without ScaLAPACK).
pub fn schur_grid(d: usize, ranks: usize) -> bool {
    ranks >= SCHUR_GRID_RANKS[d - 2] && grid::scalapack_loaded()
}

/// The default of `-ubr_condense_max` in dimension `d`, with friction
/// (`tangential`) or not ([`CONDENSE_MAX`]).
pub fn condense_max(d: usize, tangential: bool) -> usize {
    CONDENSE_MAX[d - 2][usize::from(tangential)]
}

/// Puts PETSc's defaults of `backend` in the options database: a Cholesky
/// factorization by MUMPS, unless the user picked something else.
fn default_solver_options(backend: &LinearBackend, dim: usize) -> Result<(), Error> {
    if let LinearBackend::Factorization { package, .. } = backend {
        options::set_default("-pc_type", "cholesky")?;
        options::set_default("-ksp_type", "preonly")?;
        options::set_default("-pc_factor_mat_solver_type", "mumps")?;
        // PETSc's MUMPS interface (-ubr_mumps_direct 0; the direct driver,
        // src/linalg/direct.rs, chooses its ordering itself). Debian's
        // MUMPS has no METIS/SCOTCH. Measured here: in 2D AMD factorizes
        // fastest (0.20 s vs PORD 0.33 s at 75k dofs); in 3D PORD's nested
        // dissection halves the factorization (2.0 s vs AMD 4.2 s at 54k dofs).
        if package == "mumps" {
            options::set_default("-mat_mumps_icntl_7", if dim == 3 { "4" } else { "0" })?;
            // Workspace margin over the analysis' estimate: at MUMPS' 20%, 3 of
            // 30 factorizations of a 3D hex + prism mesh on 3 ranks failed for
            // want of workspace (PC_FACTOR_OUTMEMORY); none at 60%.
            options::set_default("-mat_mumps_icntl_14", "60")?;
        }
        // A Krylov method around the factorization (`-ksp_type cg` or
        // `gmres` with the default preconditioner) gets the inexact inner
        // solves too; measured against the whole load, a solve started from
        // u^{k-1} stopped at 0 iterations once a UBR iteration changed u by
        // less than a tenth, and UBR stalled (hertz2d h 0.1: 588 iterations,
        // not converged, against 32). Without effect for preonly.
        options::set_default("-ksp_converged_use_initial_residual_norm", "1")?;
    } else if let LinearBackend::Preconditioned { pc, ksp } = backend {
        options::set_default("-ksp_type", "cg")?;
        if ksp == "cg" {
            // Converge on the true residual, not the preconditioned one.
            options::set_default("-ksp_norm_type", "unpreconditioned")?;
        }
        // Measure the inner tolerance against the initial residual b - A u^{k-1}:
        // the change that this UBR iteration brings, not the whole load (which
        // a prescribed displacement can make huge).
        options::set_default("-ksp_converged_use_initial_residual_norm", "1")?;
        if pc == "gamg" {
            // Measured on the 1M-node block (2 ranks, bench/scale3d, AIJ
            // products, the same day, 2026-11-24; bench/README.md): PETSc
            // 3.18's defaults (threshold -1, square_graph 1) set up in
            // 29.1 s and take 181 CG iterations, total 158.7 s; dropping
            // graph edges under 2% and aggressive coarsening on two levels,
            // 20.6-23.1 s and 190 cheaper iterations, median total 149.6 s
            // of six runs.
            options::set_default("-pc_gamg_threshold", "0.02")?;
            options::set_default("-pc_gamg_square_graph", "2")?;
        }
    }
    Ok(())
}

/// The KSP for `matrix` from the options database (default: a MUMPS Cholesky
/// factorization), with the rigid-body near-nullspace for algebraic multigrid
/// and the previous iterate as initial guess for Krylov methods. Returns the
/// solver, a description for the summary, and whether it is iterative.
pub fn linear_solver(
    matrix: &Matrix,
    mesh: &LocalMesh,
    backend: &LinearBackend,
) -> Result<(Ksp, String, bool), Error> {
    let comm = petsc::comm_world();
    let d = mesh.dim;
    let nown = mesh.owned_count * d;
    default_solver_options(backend, d)?;
    let ksp = Ksp::new(comm)?;
    ksp.set_operators(matrix)?;
    ksp.set_from_options()?;
    let pc_type = ksp.pc_type()?;
    let ksp_type = ksp.ksp_type()?;
    let iterative = ksp_type != "preonly";
    if pc_type == "gamg" || pc_type == "ml" || pc_type == "hypre" {
        let coords = Vector::new(comm, nown, d)?;
        coords.write(|c| c.copy_from_slice(&mesh.coords[..nown]))?;
        let ns = NullSpace::rigid_body(&coords)?;
        matrix.set_near_nullspace(&ns)?;
    }
    if iterative {
        ksp.set_initial_guess_nonzero(true)?;
    }
    let description = match backend {
        LinearBackend::Factorization { package, .. }
            if pc_type == "cholesky" || pc_type == "lu" =>
        {
            format!("{ksp_type} + {pc_type} ({package})")
        }
        _ => format!("{ksp_type} + {pc_type}"),
    };
    Ok((ksp, description, iterative))
}

/// Whether the entry `(row, col)` of value `v` goes into a factorization:
/// all but the exact zeros that couple two different nodes (`d` dofs a
/// node), i.e. the couplings of the Dirichlet rows and columns, which
/// `MatZeroRowsColumns` zeroes but keeps in the pattern; a direct solver
/// would factorize them as fill (block3d_17887: 5.45e10 -> 4.78e10 flops
/// with the Schur block). A node's own block is kept whole: a change of r
/// and the contact terms add to those blocks only, so what is left out
/// stays zero. UBR's direct back-end ([`direct`]) and the comparators'
/// matrices ([`without_zero_couplings`]) use this one rule, so that
/// comparisons are on equal matrices.
pub(crate) fn factorized_entry(row: usize, col: usize, v: f64, d: usize) -> bool {
    v != 0.0 || col / d == row / d
}

/// Rows, columns (1-based) and values of matrix entries.
pub(super) type Triplets = (Vec<i32>, Vec<i32>, Vec<f64>);

/// This rank's lower-triangle entries of `a` (1-based) that MUMPS gets
/// (those [`factorized_entry`] keeps), and for every lower-triangle
/// entry in row order whether it is one of them (for `Direct::refactorize`).
pub(super) fn lower_triplets(a: &Matrix, d: usize) -> Result<(Triplets, Vec<bool>), Error> {
    // Counted first: arrays grown by doubling held up to twice the entries
    // (and three times while one was copied), in memory the process does
    // not give back (README, field notes): the 1M-node block on 2 ranks
    // grew by 754 MB a rank here, by 453 MB with the exact sizes.
    let mut lower = 0;
    a.for_each_owned_row(|row, cols, _| {
        lower += cols.iter().filter(|&&c| c as usize <= row).count();
    })?;
    let (mut irn, mut jcn) = (Vec::with_capacity(lower), Vec::with_capacity(lower));
    let mut val = Vec::with_capacity(lower);
    let mut kept = Vec::with_capacity(lower);
    a.for_each_owned_row(|row, cols, vals| {
        for (&c, &v) in cols.iter().zip(vals) {
            let c = c as usize;
            if c <= row {
                let keep = factorized_entry(row, c, v, d);
                kept.push(keep);
                if keep {
                    irn.push(row as i32 + 1);
                    jcn.push(c as i32 + 1);
                    val.push(v);
                }
            }
        }
    })?;
    Ok(((irn, jcn, val), kept))
}

/// A copy of `a` with the entries [`factorized_entry`] keeps: the matrix
/// the comparators (SNES VI, SSN-C) factorize (block3d_17887: SNES VI
/// 13.2 -> 11.7 s).
pub(crate) fn without_zero_couplings(a: &Matrix, d: usize) -> Result<Matrix, Error> {
    let mut rowptr: Vec<sys::PetscInt> = vec![0];
    let (mut cols, mut vals) = (Vec::new(), Vec::new());
    a.for_each_owned_row(|row, cs, vs| {
        for (&c, &v) in cs.iter().zip(vs) {
            if factorized_entry(row, c as usize, v, d) {
                cols.push(c);
                vals.push(v);
            }
        }
        rowptr.push(cols.len() as sys::PetscInt);
    })?;
    let m = Matrix::new_aij_csr(petsc::comm_world(), rowptr.len() - 1, d, rowptr, cols, vals)?;
    m.set_spd()?;
    Ok(m)
}
