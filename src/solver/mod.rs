//! The discrete contact problem on this rank's part, and the algorithms that
//! solve it (one file per paper algorithm).
//!
//! [`Problem::setup`] assembles `K + r B^T W B` once (with Dirichlet rows and
//! columns eliminated symmetrically), the lifted load vector, and the KSP,
//! whose factorization (`KSPSetUp`) happens once, in the Factorization stage.

pub mod anderson;
pub mod cf_fp;
pub mod checks;
pub mod deferred;
pub mod direct;
pub mod linear;
pub mod ordering;
pub mod outcome;
pub mod penalty;
pub mod seat;
pub mod snesvi;
pub mod ssn;
pub mod stopping;
pub mod surface;
pub mod touching;
pub mod ubr;
pub mod wellposed;

use linear::{Engine, LinearSolver};
use surface::Surface;

use crate::contact::ContactSet;
use crate::error::Error;
use crate::fem;
use crate::mesh::distribute::LocalMesh;
use crate::options::Settings;
use crate::petsc::{self, options, sys, Ksp, Matrix, NullSpace, Vector};
use mpi::collective::SystemOperation;
use mpi::datatype::{Equivalence, Partition, PartitionMut};
use mpi::traits::*;

/// The per-rank layout of a distributed array gathered on the host.
pub struct Layout {
    counts: Vec<i32>,
    displs: Vec<i32>,
}

impl Layout {
    pub fn new<C: Communicator>(world: &C, local: usize) -> Layout {
        let mut counts = vec![0i32; world.size() as usize];
        world.all_gather_into(&(local as i32), &mut counts[..]);
        let displs = counts
            .iter()
            .scan(0i32, |acc, &c| {
                let s = *acc;
                *acc += c;
                Some(s)
            })
            .collect();
        Layout { counts, displs }
    }

    pub fn total(&self) -> usize {
        self.counts.iter().map(|&c| c as usize).sum()
    }

    /// Rank `p`'s count.
    pub fn count(&self, p: usize) -> usize {
        self.counts[p] as usize
    }

    /// `local` of every rank, in rank order, on the host (empty elsewhere).
    pub fn gather<C: Communicator>(&self, world: &C, local: &[f64]) -> Vec<f64> {
        let mut all = if world.rank() == 0 {
            vec![0.0; self.total()]
        } else {
            Vec::new()
        };
        self.gather_into(world, local, &mut all);
        all
    }

    /// [`Layout::gather`] into `all` (the host's, of length [`Layout::total`];
    /// unused elsewhere): no allocation, for the solves of every iteration.
    pub fn gather_into<C: Communicator>(&self, world: &C, local: &[f64], all: &mut [f64]) {
        let root = world.process_at_rank(0);
        if world.rank() == 0 {
            let mut part = PartitionMut::new(all, &self.counts[..], &self.displs[..]);
            root.gather_varcount_into_root(local, &mut part);
        } else {
            root.gather_varcount_into(local);
        }
    }

    /// `local` of every rank, in rank order, on every rank.
    pub fn all_gather<C: Communicator, T: Equivalence + Default + Clone>(
        &self,
        world: &C,
        local: &[T],
    ) -> Vec<T> {
        let mut all = vec![T::default(); self.total()];
        let mut part = PartitionMut::new(&mut all[..], &self.counts[..], &self.displs[..]);
        world.all_gather_varcount_into(local, &mut part);
        all
    }

    /// The host's `all` back to the ranks, each its part into `local`.
    pub fn scatter<C: Communicator>(&self, world: &C, all: &[f64], local: &mut [f64]) {
        let root = world.process_at_rank(0);
        if world.rank() == 0 {
            let part = Partition::new(all, &self.counts[..], &self.displs[..]);
            root.scatter_varcount_into_root(&part, local);
        } else {
            root.scatter_varcount_into(local);
        }
    }
}

/// Sum of `vals` over all ranks, in one reduction.
pub fn allreduce_sum<C: Communicator, const N: usize>(world: &C, vals: [f64; N]) -> [f64; N] {
    let mut out = [0.0; N];
    world.all_reduce_into(&vals[..], &mut out[..], SystemOperation::sum());
    out
}

/// Elementwise sum of `vals` over all ranks.
pub fn allreduce_sum_vec<C: Communicator>(world: &C, vals: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; vals.len()];
    world.all_reduce_into(vals, &mut out[..], SystemOperation::sum());
    out
}

pub fn allreduce_max_n<C: Communicator, const N: usize>(world: &C, vals: [f64; N]) -> [f64; N] {
    let mut out = [0.0; N];
    world.all_reduce_into(&vals[..], &mut out[..], SystemOperation::max());
    out
}

pub fn allreduce_max<C: Communicator>(world: &C, v: f64) -> f64 {
    let mut out = 0.0;
    world.all_reduce_into(&v, &mut out, SystemOperation::max());
    out
}

pub fn allreduce_count<C: Communicator>(world: &C, v: usize) -> usize {
    let mut out = 0u64;
    world.all_reduce_into(&(v as u64), &mut out, SystemOperation::sum());
    out as usize
}

/// The local sums of `||u - u_prev||^2` and `||u||^2` with the lumped mass.
pub fn mass_norms(lumped_mass: &[f64], d: usize, u: &[f64], u_prev: &[f64]) -> (f64, f64) {
    let (mut du2, mut u2) = (0.0, 0.0);
    for (j, m) in lumped_mass.iter().enumerate() {
        for c in 0..d {
            let x = u[j * d + c];
            let dx = x - u_prev[j * d + c];
            du2 += m * dx * dx;
            u2 += m * x * x;
        }
    }
    (du2, u2)
}

/// Everything the iterations need, assembled once.
pub struct Problem {
    pub dim: usize,
    /// `K_r = K + r B^T W B` (Dirichlet rows and columns replaced by
    /// `diag_scale * I`), its solver, the load without contact terms, and r.
    pub lin: LinearSolver,
    /// The load vector f (tractions), for the equilibrium check.
    pub load: Vector,
    /// Owned dofs that carry a Dirichlet condition.
    pub is_dirichlet: Vec<bool>,
    pub lumped_mass: Vec<f64>,
    pub contact: ContactSet,
    /// Per contact unknown (candidate i, component c at `i * dim + c`): a
    /// Dirichlet component.
    pub contact_dirichlet: Vec<bool>,
    /// Whether `r B_t^T W B_t` is in the matrix too (friction).
    pub tangential: bool,
    /// Owned Dirichlet dofs and values, and the diagonal put on their rows.
    pub dirichlet: Vec<(usize, f64)>,
    pub diag_scale: f64,
    /// The contact terms in the matrix.
    pub terms: ContactTerms,
    /// First global node of this rank.
    pub owned_start: usize,
    pub time_assembly: f64,
    pub time_factorization: f64,
    pub matrix_mallocs: f64,
}

impl Problem {
    /// r of the UBR iteration (of the matrix, or of the condensed solver).
    pub fn r(&self) -> f64 {
        self.lin.r()
    }

    /// B and B^T W of the contact set.
    pub fn surface(&self) -> Surface<'_> {
        Surface {
            cs: &self.contact,
            dim: self.dim,
            tangential: self.tangential,
            dirichlet: &self.contact_dirichlet,
        }
    }
}

/// Default largest number of contact unknowns for the condensed back-end,
/// in 2D and 3D (MUMPS called directly: METIS ordering, the Schur unknowns
/// last, u_n alone when frictionless along an axis). Measured on one rank,
/// factorization + r choice + iterations, full against condensed: 2D
/// hertz_37473 (329 unknowns) 2.2 -> 0.7 s; 3D block3d_2357 (262) 0.14 ->
/// 0.13 s, block3d_10761 (762) 2.00 -> 1.48 s, block3d_17887 (1042) 7.1 ->
/// 4.8 s, a generated 83,300-node block (2380) 58.1 -> 48.0 s; Coulomb
/// (every component) block3d_10761 (2286) 5.6 -> 3.1 s, block3d_17887
/// (3126) 10.6 -> 6.5 s. Above a few thousand unknowns the dense m^3/3 of
/// the Schur block (on rank 0) grows past what 20-130 iterations save; in 2D
/// the sparse solves are cheap and the break-even comes sooner.
pub const CONDENSE_MAX: [usize; 2] = [2000, 4000];

/// The UBR matrix block `r w (n n^T)` (frictionless) or `r w I` (with friction) of one node.
pub fn contact_block(dim: usize, n: &[f64], rw: f64, tangential: bool) -> Vec<f64> {
    let mut b = vec![0.0; dim * dim];
    for i in 0..dim {
        for j in 0..dim {
            b[i * dim + j] = if tangential {
                if i == j {
                    rw
                } else {
                    0.0
                }
            } else {
                rw * n[i] * n[j]
            };
        }
    }
    b
}

/// Chooses the default linear solver: a Cholesky factorization by MUMPS,
/// unless the user picked something else.
fn default_solver_options(dim: usize) -> Result<(), Error> {
    let pc = options::get_string("-pc_type")?;
    let direct = matches!(pc.as_deref(), None | Some("cholesky") | Some("lu"));
    if direct {
        options::set_default("-pc_type", "cholesky")?;
        options::set_default("-ksp_type", "preonly")?;
        options::set_default("-pc_factor_mat_solver_type", "mumps")?;
        // PETSc's MUMPS interface (-ubr_mumps_direct 0; the direct driver,
        // src/solver/direct.rs, chooses its ordering itself). Debian's
        // MUMPS has no METIS/SCOTCH. Measured here: in 2D AMD factorizes
        // fastest (0.20 s vs PORD 0.33 s at 75k dofs); in 3D PORD's nested
        // dissection halves the factorization (2.0 s vs AMD 4.2 s at 54k dofs).
        if options::get_string("-pc_factor_mat_solver_type")?.as_deref() == Some("mumps") {
            options::set_default("-mat_mumps_icntl_7", if dim == 3 { "4" } else { "0" })?;
            // Workspace margin over the analysis' estimate: at MUMPS' 20%, 3 of
            // 30 factorizations of a 3D hex + prism mesh on 3 ranks failed for
            // want of workspace (PC_FACTOR_OUTMEMORY); none at 60%.
            options::set_default("-mat_mumps_icntl_14", "60")?;
        }
    } else {
        options::set_default("-ksp_type", "cg")?;
        if options::get_string("-ksp_type")?.as_deref() == Some("cg") {
            // Converge on the true residual, not the preconditioned one.
            options::set_default("-ksp_norm_type", "unpreconditioned")?;
        }
        // Measure the inner tolerance against the initial residual b - A u^{k-1}:
        // the change that this UBR iteration brings, not the whole load (which
        // a prescribed displacement can make huge).
        options::set_default("-ksp_converged_use_initial_residual_norm", "1")?;
        if pc.as_deref() == Some("gamg") {
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

/// Which contact terms the assembled matrix carries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ContactTerms {
    /// `r B^T W B` of UBR (normal only, or normal and tangential), factorized once.
    Ubr { tangential: bool },
    /// None: K alone, not factorized (SSN-C adds its active terms and factorizes each iteration).
    None,
}

/// The KSP for `matrix` from the options database (default: a MUMPS Cholesky
/// factorization), with the rigid-body near-nullspace for algebraic multigrid
/// and the previous iterate as initial guess for Krylov methods. Returns the
/// solver, a description for the summary, and whether it is iterative.
pub fn linear_solver(matrix: &Matrix, mesh: &LocalMesh) -> Result<(Ksp, String, bool), Error> {
    let comm = petsc::comm_world();
    let d = mesh.dim;
    let nown = mesh.owned_count * d;
    default_solver_options(d)?;
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
    let description = match options::get_string("-pc_factor_mat_solver_type")? {
        Some(s) if pc_type == "cholesky" || pc_type == "lu" => {
            format!("{ksp_type} + {pc_type} ({s})")
        }
        _ => format!("{ksp_type} + {pc_type}"),
    };
    Ok((ksp, description, iterative))
}

impl Problem {
    /// Assembles `K + r B^T W B` at `r` (none for SSN-C), the lifted load,
    /// and the solver, and factorizes once (a direct solver): the condensed
    /// back-end where it applies (MUMPS called directly, on any rank count,
    /// few enough contact unknowns, see [`CONDENSE_MAX`]; not under the
    /// paper's stop with `-ubr_monitor` or `-plot_history`).
    pub fn setup<C: Communicator>(
        world: &C,
        mesh: &LocalMesh,
        settings: &Settings,
        contact: ContactSet,
        terms: ContactTerms,
        r: f64,
        stages: &crate::petsc::Stages,
    ) -> Result<Problem, Error> {
        let comm = petsc::comm_world();
        let d = mesh.dim;
        let tangential = terms == ContactTerms::Ubr { tangential: true };
        let t0 = std::time::Instant::now();
        let guard = stages.assembly.push()?;
        let extra: Vec<(usize, Vec<f64>)> = match terms {
            ContactTerms::Ubr { tangential } => contact
                .node
                .iter()
                .zip(&contact.w)
                .map(|(&v, &w)| (v, contact_block(d, &contact.n, r * w, tangential)))
                .collect(),
            ContactTerms::None => Vec::new(),
        };
        // The nodal graph, once for the assembly and METIS' ordering.
        let adjacency = fem::node_adjacency(mesh);
        let el = fem::assemble_stiffness(comm, mesh, &adjacency, settings, &extra)?;
        let a = el.stiffness;
        let load_local = fem::loads::external_load(mesh, settings, &el.lumped_mass)?;
        let dir = fem::dirichlet_dofs(mesh, &settings.dirichlet)?;
        let nown = mesh.owned_count * d;
        let load = Vector::new(comm, nown, d)?;
        load.write(|f| f.copy_from_slice(&load_local))?;
        let xd = load.duplicate()?;
        xd.set(0.0)?;
        xd.write(|x| {
            for &(i, v) in &dir {
                x[i] = v;
            }
        })?;
        let rhs0 = load.duplicate()?;
        a.mult(&xd, &rhs0)?;
        // rhs0 = f - A x_D
        rhs0.write(|b| {
            load.read(|f| {
                for (bi, fi) in b.iter_mut().zip(f) {
                    *bi = fi - *bi;
                }
            })
        })??;
        // Dirichlet rows: scale the identity like the matrix so that
        // iterative solvers and pivoting see no outlier.
        let diag = load.duplicate()?;
        a.diagonal(&diag)?;
        let dsum = diag.read(|v| v.iter().map(|x| x.abs()).sum::<f64>())?;
        let [dsum, dcount] = allreduce_sum(world, [dsum, nown as f64]);
        let diag_scale = if dcount > 0.0 && dsum > 0.0 {
            dsum / dcount
        } else {
            1.0
        };
        let rows: Vec<sys::PetscInt> = dir
            .iter()
            .map(|&(i, _)| (mesh.owned_start * d + i) as sys::PetscInt)
            .collect();
        a.zero_rows_columns(&rows, diag_scale)?;
        rhs0.write(|b| {
            for &(i, v) in &dir {
                b[i] = diag_scale * v;
            }
        })?;
        let mut is_dirichlet = vec![false; nown];
        let mut xd_all = vec![0.0; nown];
        for &(i, v) in &dir {
            is_dirichlet[i] = true;
            xd_all[i] = v;
        }
        let contact_dirichlet: Vec<bool> = contact
            .node
            .iter()
            .flat_map(|&v| (0..d).map(move |c| v * d + c))
            .map(|i| is_dirichlet[i])
            .collect();
        let xd_c: Vec<f64> = contact
            .node
            .iter()
            .flat_map(|&v| (0..d).map(move |c| v * d + c))
            .map(|i| xd_all[i])
            .collect();
        a.set_spd()?;
        let matrix_mallocs = a.stats()?.mallocs;
        drop(guard);
        let time_assembly = t0.elapsed().as_secs_f64();

        let t1 = std::time::Instant::now();
        let guard = stages.factorization.push()?;
        // The Schur components of a candidate: the normal axis alone when
        // frictionless along an axis (u_n is then a dof), else all; and the
        // contact unknowns in all (the same decision on every rank).
        let axis = (0..d).find(|&c| contact.n[c].abs() == 1.0);
        let comps: Vec<usize> = match axis {
            Some(a) if !tangential => vec![a],
            _ => (0..d).collect(),
        };
        let schur_size = allreduce_count(world, contact.len()) * comps.len();
        // Not when the paper's change (4.16)/(5.6) of every iteration is wanted.
        let every_change = settings.ubr.stop == stopping::StopRule::Paper
            && (settings.ubr.monitor || settings.plot_history.is_some());
        // MUMPS driven directly for UBR's default solver (a Cholesky
        // factorization by MUMPS), PETSc's KSP otherwise.
        let pc = options::get_string("-pc_type")?;
        let ksp_type = options::get_string("-ksp_type")?;
        let solver_type = options::get_string("-pc_factor_mat_solver_type")?;
        let direct = terms != ContactTerms::None
            && settings.ubr.mumps_direct
            && matches!(pc.as_deref(), None | Some("cholesky") | Some("lu"))
            && matches!(ksp_type.as_deref(), None | Some("preonly"))
            && matches!(solver_type.as_deref(), None | Some("mumps"));
        let condense = direct
            && !every_change
            && schur_size > 0
            && schur_size <= settings.ubr.condense_max.unwrap_or(CONDENSE_MAX[d - 2]);
        let mut operator = None;
        let (engine, description, iterative) = if direct {
            let surface = Surface {
                cs: &contact,
                dim: d,
                tangential,
                dirichlet: &contact_dirichlet,
            };
            let dm = direct::Direct::new(
                world,
                &a,
                mesh,
                &adjacency,
                &surface,
                condense.then_some(if settings.ubr.schur_distributed {
                    direct::SchurLayout::Distributed
                } else {
                    direct::SchurLayout::Centralized
                }),
                &comps,
            )?;
            let description = format!(
                "MUMPS Cholesky, called directly ({}; {:.3e} flops)",
                dm.ordering, dm.flops
            );
            (Engine::Direct(Box::new(dm)), description, false)
        } else {
            let (ksp, mut description, iterative) = linear_solver(&a, mesh)?;
            if iterative && terms != ContactTerms::None && settings.ubr.sbaij {
                description.push_str(", SBAIJ products");
                // Products read half the bytes (measured: 1.7x faster CG
                // iterations with GAMG on the 136k-node block, 2 ranks);
                // GAMG builds its hierarchy from the AIJ matrix.
                operator = Some(a.sbaij_copy(comm, d)?);
                ksp.set_operators_split(operator.as_ref().expect("just set"), &a)?;
            }
            if terms != ContactTerms::None {
                ksp.set_up()?; // the one factorization of UBR
            }
            (Engine::Ksp(ksp), description, iterative)
        };
        drop(adjacency);
        let adaptive_inner = iterative && !options::has_name("-ksp_rtol")?;
        let lin = LinearSolver::new(
            engine,
            a,
            operator,
            rhs0,
            iterative,
            adaptive_inner,
            description,
            r,
            xd_c,
            dir.clone(),
            d,
        )?;
        let mut problem = Problem {
            dim: d,
            lin,
            load,
            is_dirichlet,
            lumped_mass: el.lumped_mass,
            contact,
            contact_dirichlet,
            tangential,
            dirichlet: dir,
            diag_scale,
            terms,
            owned_start: mesh.owned_start,
            time_assembly,
            time_factorization: 0.0,
            matrix_mallocs,
        };
        if condense {
            let Problem {
                lin,
                contact,
                contact_dirichlet,
                ..
            } = &mut problem;
            let surface = Surface {
                cs: contact,
                dim: d,
                tangential,
                dirichlet: contact_dirichlet,
            };
            lin.condense(&surface, &comps)?;
        }
        drop(guard);
        problem.time_factorization = t1.elapsed().as_secs_f64();
        Ok(problem)
    }
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
