//! The discrete contact problem on this rank's part, and the algorithms that
//! solve it (one file per paper algorithm).
//!
//! [`Problem::setup`] assembles `K + r B^T W B` once (with Dirichlet rows and
//! columns eliminated symmetrically), the lifted load vector, and the KSP,
//! whose factorization (`KSPSetUp`) happens once, in the Factorization stage.

pub mod anderson;
pub mod cf_fp;
pub mod deferred;
pub mod outcome;
pub mod penalty;
pub mod seat;
pub mod snesvi;
pub mod ssn;
pub mod stopping;
pub mod surface;
pub mod touching;
pub mod ubr;

use surface::Surface;

use crate::comm::{allreduce_count, allreduce_sum};
use crate::contact::surface::contact_block;
use crate::contact::ContactSet;
use crate::error::Error;
use crate::fem;
use crate::linalg::linear::{Engine, LinearSolver};
use crate::linalg::{direct, linear_solver, CONDENSE_MAX};
use crate::mesh::distribute::LocalMesh;
use crate::options::Settings;
use crate::petsc::{self, options, sys, Vector};
use mpi::traits::*;

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

/// Which contact terms the assembled matrix carries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ContactTerms {
    /// `r B^T W B` of UBR (normal only, or normal and tangential), factorized once.
    Ubr { tangential: bool },
    /// None: K alone, not factorized (SSN-C adds its active terms and factorizes each iteration).
    None,
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
