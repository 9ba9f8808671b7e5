//! The discrete contact problem on this rank's part, and the algorithms that
//! solve it (one file per paper algorithm).
//!
//! [`Problem::assemble`] assembles `K + r B^T W B` once (with Dirichlet rows
//! and columns eliminated symmetrically) and the lifted load vector, in the
//! Assembly stage; [`Problem::factorize`] builds the linear back-end chosen
//! in [`Settings::linear`], whose factorization happens once, in the
//! Factorization stage.

pub mod anderson;
pub mod cf_fp;
pub mod deferred;
pub mod history;
pub mod mortar;
pub mod outcome;
pub mod penalty;
pub mod seat;
pub mod snesvi;
pub mod ssn;
pub mod stopping;
pub mod surface;
pub mod ubr;

use surface::Surface;

use crate::comm::{allreduce_count, allreduce_sum};
use crate::contact::surface::contact_block;
use crate::contact::ContactSet;
use crate::error::Error;
use crate::fem;
use crate::linalg::linear::{Engine, LinearSolver};
use crate::linalg::{condense_max, direct, linear_solver};
use crate::mesh::distribute::LocalMesh;
use crate::options::Settings;
use crate::petsc::{self, sys, Matrix, Vector};
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

/// The Dirichlet data of this rank, in one place: the owned dofs and their
/// values, the same per owned dof and per contact unknown, and the diagonal
/// put on their rows (the scale of the matrix' own diagonal, so that
/// iterative solvers and pivoting see no outlier).
pub struct Dirichlet {
    /// Owned dofs (local index) and prescribed values.
    pub dofs: Vec<(usize, f64)>,
    /// Per owned dof: prescribed.
    pub fixed: Vec<bool>,
    /// Per contact unknown (candidate i, component c at `i * dim + c`):
    /// prescribed, and its value (0 elsewhere).
    pub contact: Vec<bool>,
    pub contact_values: Vec<f64>,
    pub diag_scale: f64,
}

impl Dirichlet {
    /// The flags and values of `dofs` per owned dof and per contact unknown
    /// of `contact` (the diagonal is set by the elimination).
    fn new(dofs: Vec<(usize, f64)>, nown: usize, contact: &ContactSet, d: usize) -> Dirichlet {
        let mut fixed = vec![false; nown];
        let mut values = vec![0.0; nown];
        for &(i, v) in &dofs {
            fixed[i] = true;
            values[i] = v;
        }
        let unknowns = || {
            contact
                .node
                .iter()
                .flat_map(|&v| (0..d).map(move |c| v * d + c))
        };
        Dirichlet {
            contact: unknowns().map(|i| fixed[i]).collect(),
            contact_values: unknowns().map(|i| values[i]).collect(),
            dofs,
            fixed,
            diag_scale: 1.0,
        }
    }
}

/// Everything the iterations need, assembled once.
pub struct Problem {
    pub dim: usize,
    /// `K_r = K + r B^T W B` (Dirichlet rows and columns replaced by
    /// `diag_scale * I`), its solver, the load without contact terms, and r.
    pub lin: LinearSolver,
    /// The load vector f (tractions), for the equilibrium check.
    pub load: Vector,
    pub lumped_mass: Vec<f64>,
    pub contact: ContactSet,
    /// Whether `r B_t^T W B_t` is in the matrix too (friction).
    pub tangential: bool,
    pub dirichlet: Dirichlet,
    /// The contact terms in the matrix.
    pub terms: ContactTerms,
    /// First global node of this rank.
    pub owned_start: usize,
    pub time_assembly: f64,
    pub time_factorization: f64,
    pub matrix_mallocs: f64,
    /// The parts of the load of a history ([`history`]; None: one load).
    pub parts: Option<history::LoadParts>,
    /// Contact pairs: the unknowns are `v` with `u = T v` ([`mortar`]).
    pub transform: Option<mortar::Transform>,
}

impl Problem {
    /// The displacement u of the unknowns `v` (a copy without a contact
    /// pair).
    pub fn physical(&self, v: &Vector) -> Result<Vector, Error> {
        match &self.transform {
            Some(t) => t.displacement(v),
            None => {
                let u = v.duplicate()?;
                u.copy_from(v)?;
                Ok(u)
            }
        }
    }

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
            dirichlet: &self.dirichlet.contact,
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

/// What the Assembly stage builds: `K + r B^T W B` with the Dirichlet rows
/// and columns eliminated, the load f and the lifted right-hand side
/// `f - A x_D`; the load can be judged ([`crate::wellposed::check_steps`])
/// before [`Problem::factorize`].
pub struct Assembled {
    matrix: Matrix,
    /// The load vector f (tractions, pressure, body force).
    pub load: Vector,
    rhs0: Vector,
    pub dirichlet: Dirichlet,
    lumped_mass: Vec<f64>,
    adjacency: fem::Adjacency,
    pub contact: ContactSet,
    terms: ContactTerms,
    r: f64,
    pub matrix_mallocs: f64,
    pub time_assembly: f64,
    parts: Option<history::LoadParts>,
    transform: Option<mortar::Transform>,
}

impl Assembled {
    /// A history's load parts, per owned dof: each named group's f, then
    /// the rest (which stays at factor 1; `true` where there is one); the
    /// whole load for a proportional history; None without a history.
    pub fn load_parts(&self) -> Option<(Vec<&[f64]>, bool)> {
        let p = self.parts.as_ref()?;
        let mut v: Vec<&[f64]> = p.parts.iter().map(|x| x.load.as_slice()).collect();
        if let Some(r) = &p.rest {
            v.push(&r.load);
        }
        Some((v, p.rest.is_some()))
    }
}

impl Problem {
    /// Assembly stage: `K + r B^T W B` at `r` (K alone for SSN-C), the load,
    /// and the symmetric elimination of the Dirichlet dofs `dirichlet`
    /// ([`fem::dirichlet_dofs`]).
    #[allow(clippy::too_many_arguments)]
    pub fn assemble<C: Communicator>(
        world: &C,
        mesh: &LocalMesh,
        settings: &Settings,
        contact: ContactSet,
        dirichlet: Vec<(usize, f64)>,
        terms: ContactTerms,
        r: f64,
        stages: &crate::petsc::Stages,
    ) -> Result<Assembled, Error> {
        let comm = petsc::comm_world();
        let d = mesh.dim;
        let t0 = std::time::Instant::now();
        let guard = stages.assembly.push()?;
        // (A pair's slave blocks act on the changed unknowns: added after
        // the change, below.)
        let extra: Vec<(usize, Vec<f64>)> = match terms {
            ContactTerms::Ubr { tangential } => (0..contact.len())
                .filter(|&i| contact.pair[i] == usize::MAX)
                .map(|i| {
                    let block = contact_block(d, contact.n(i), r * contact.w[i], tangential);
                    (contact.node[i], block)
                })
                .collect(),
            ContactTerms::None => Vec::new(),
        };
        // The nodal graph, once for the assembly and METIS' ordering.
        let adjacency = fem::node_adjacency(mesh);
        let entries = d * d * adjacency.0[mesh.owned_count];
        crate::linalg::memfit::assembly_fits(world, entries, settings.linear.mumps_direct())?;
        let el = fem::assemble_stiffness(comm, mesh, &adjacency, settings, &extra)?;
        let load_local = fem::loads::external_load(mesh, settings, &el.lumped_mass)?;
        let nown = mesh.owned_count * d;
        let load = Vector::new(comm, nown, d)?;
        load.write(|f| f.copy_from_slice(&load_local))?;
        let friction = settings.friction != crate::options::Friction::None;
        let transform = mortar::Transform::build(world, mesh, &contact, &dirichlet, friction)?;
        let mut matrix = el.stiffness;
        // The load on the unknowns (T^T f with a contact pair); `load` stays
        // f, for the checks.
        let mut changed_load = None;
        // Mallocs not of our preallocation: PETSc's PtAP may grow its own
        // product (1 on one rank, a ball on a block meshed at hc 0.04,
        // reported as an internal error before); those of K before it count.
        let mut not_ours = 0.0;
        if let Some(t) = &transform {
            let before = matrix.stats()?.mallocs;
            matrix = t.stiffness(&matrix)?;
            not_ours = matrix.stats()?.mallocs - before;
            changed_load = Some(t.load(&load)?);
            if let ContactTerms::Ubr { tangential } = terms {
                pair_blocks(mesh, &contact, &matrix, r, tangential)?;
            }
        }
        let mut dirichlet = Dirichlet::new(dirichlet, nown, &contact, d);
        let rhs_load = changed_load.as_ref().unwrap_or(&load);
        let named = history::split(
            mesh,
            settings,
            &matrix,
            &el.lumped_mass,
            &load,
            transform.as_ref(),
        )?;
        let rhs0 = eliminate(world, mesh, &matrix, rhs_load, &mut dirichlet)?;
        let parts = history::finish(settings, named, &load, &rhs0, &dirichlet)?;
        matrix.set_spd()?;
        let matrix_mallocs = matrix.stats()?.mallocs - not_ours;
        drop(guard);
        Ok(Assembled {
            matrix,
            load,
            rhs0,
            dirichlet,
            lumped_mass: el.lumped_mass,
            adjacency,
            contact,
            terms,
            r,
            matrix_mallocs,
            time_assembly: t0.elapsed().as_secs_f64(),
            parts,
            transform,
        })
    }

    /// Factorization stage: the back-end of `settings.linear` for the
    /// assembled matrix, factorized once (a direct solver): the condensed
    /// back-end where it applies (MUMPS called directly, on any rank count,
    /// few enough contact unknowns, see [`crate::linalg::CONDENSE_MAX`]; not under the
    /// paper's stop with `-ubr_monitor` or `-plot_history`).
    pub fn factorize<C: Communicator>(
        world: &C,
        mesh: &LocalMesh,
        settings: &Settings,
        assembled: Assembled,
        stages: &crate::petsc::Stages,
    ) -> Result<Problem, Error> {
        let Assembled {
            matrix,
            load,
            rhs0,
            dirichlet,
            lumped_mass,
            adjacency,
            contact,
            terms,
            r,
            matrix_mallocs,
            time_assembly,
            parts,
            transform,
        } = assembled;
        let d = mesh.dim;
        let tangential = terms == ContactTerms::Ubr { tangential: true };
        let t1 = std::time::Instant::now();
        let guard = stages.factorization.push()?;
        let surface = Surface {
            cs: &contact,
            dim: d,
            tangential,
            dirichlet: &dirichlet.contact,
        };
        let comps = schur_components(&contact, d, tangential);
        let condense = condensed(world, settings, &contact, terms, d, comps.len());
        let engine = engine(
            world, mesh, settings, &matrix, &adjacency, &surface, terms, &comps, condense,
        )?;
        drop(adjacency);
        let adaptive_inner = engine.iterative && !settings.ksp_rtol_given;
        let mut lin = LinearSolver::new(
            engine.engine,
            matrix,
            engine.operator,
            rhs0,
            engine.iterative,
            adaptive_inner,
            engine.description,
            r,
            dirichlet.contact_values.clone(),
            dirichlet.dofs.clone(),
            d,
        )?;
        lin.warnings = engine.warnings;
        if engine.condensed {
            lin.condense(&surface, &comps)?;
        }
        drop(guard);
        Ok(Problem {
            dim: d,
            lin,
            load,
            lumped_mass,
            contact,
            tangential,
            dirichlet,
            terms,
            owned_start: mesh.owned_start,
            time_assembly,
            time_factorization: t1.elapsed().as_secs_f64(),
            matrix_mallocs,
            parts,
            transform,
        })
    }
}

/// The UBR blocks `r w n n^T` (or `r w I`) of the pairs' slave nodes, on
/// the changed unknowns of `a` ([`mortar`]).
fn pair_blocks(
    mesh: &LocalMesh,
    contact: &ContactSet,
    a: &Matrix,
    r: f64,
    tangential: bool,
) -> Result<(), Error> {
    let d = mesh.dim;
    for i in (0..contact.len()).filter(|&i| contact.pair[i] != usize::MAX) {
        let block = contact_block(d, contact.n(i), r * contact.w[i], tangential);
        let first = (mesh.owned_start + contact.node[i]) * d;
        let idx: Vec<sys::PetscInt> = (0..d).map(|c| (first + c) as sys::PetscInt).collect();
        a.add_values(&idx, &idx, &block)?;
    }
    a.assemble()
}

/// The lifted right-hand side `rhs0 = f - A x_D` (`diag_scale * x_D` on the
/// Dirichlet rows), with the Dirichlet rows and columns of `a` replaced by
/// `diag_scale * I`, the mean magnitude of the diagonal, set in `dir`.
fn eliminate<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    a: &Matrix,
    load: &Vector,
    dir: &mut Dirichlet,
) -> Result<Vector, Error> {
    let d = mesh.dim;
    let nown = mesh.owned_count * d;
    let xd = load.duplicate()?;
    xd.set(0.0)?;
    xd.write(|x| {
        for &(i, v) in &dir.dofs {
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
        .dofs
        .iter()
        .map(|&(i, _)| (mesh.owned_start * d + i) as sys::PetscInt)
        .collect();
    a.zero_rows_columns(&rows, diag_scale)?;
    rhs0.write(|b| {
        for &(i, v) in &dir.dofs {
            b[i] = diag_scale * v;
        }
    })?;
    dir.diag_scale = diag_scale;
    Ok(rhs0)
}

/// The Schur components of a candidate: the normal axis alone when
/// frictionless along an axis (u_n is then a dof), else all.
fn schur_components(contact: &ContactSet, d: usize, tangential: bool) -> Vec<usize> {
    let axis = contact
        .common_normal()
        .and_then(|n| (0..d).find(|&c| n[c].abs() == 1.0));
    match axis {
        Some(a) if !tangential => vec![a],
        _ => (0..d).collect(),
    }
}

/// Whether UBR's back-end is the condensed one: MUMPS called directly, few
/// enough contact unknowns (the same decision on every rank), and not when
/// the paper's change (4.16)/(5.6) of every iteration is wanted.
fn condensed<C: Communicator>(
    world: &C,
    settings: &Settings,
    contact: &ContactSet,
    terms: ContactTerms,
    d: usize,
    comps: usize,
) -> bool {
    let schur_size = allreduce_count(world, contact.len()) * comps;
    let every_change = settings.ubr.stop == stopping::StopRule::Paper
        && (settings.ubr.monitor || settings.plot_history.is_some());
    terms != ContactTerms::None
        && settings.linear.mumps_direct()
        && !every_change
        && schur_size > 0
        && schur_size
            <= settings.ubr.condense_max.unwrap_or(condense_max(
                d,
                terms == ContactTerms::Ubr { tangential: true },
            ))
}

/// The chosen engine, before the [`LinearSolver`] that wraps it.
struct Chosen {
    engine: Engine,
    operator: Option<Matrix>,
    description: String,
    iterative: bool,
    /// What the run's warnings should say of the choice.
    warnings: Vec<String>,
    /// Whether the engine has the Schur block (condensed solves).
    condensed: bool,
}

/// The engine of `settings.linear` for `a`: MUMPS driven directly for UBR's
/// default solver (a Cholesky factorization by MUMPS; `condense`: with the
/// Schur block of the components `comps`), PETSc's KSP otherwise (factorized here
/// for UBR, each iteration by SSN-C).
#[allow(clippy::too_many_arguments)]
fn engine<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    settings: &Settings,
    a: &Matrix,
    adjacency: &fem::Adjacency,
    surface: &Surface,
    terms: ContactTerms,
    comps: &[usize],
    condense: bool,
) -> Result<Chosen, Error> {
    let d = mesh.dim;
    if terms != ContactTerms::None && settings.linear.mumps_direct() {
        let grid = settings
            .ubr
            .schur_distributed
            .unwrap_or(crate::linalg::schur_grid(d, world.size() as usize));
        let layout = condense.then_some(if grid {
            direct::SchurLayout::Distributed
        } else {
            direct::SchurLayout::Centralized
        });
        // Measured on 2 ranks: the pre-splitting pays in 3D with the Schur
        // complement (block3d 63k nodes 13.1-13.4 -> 11.4-11.8 s of
        // factorization, 10,761 nodes 0.704 -> 0.677 s in all), costs
        // without it (it splits the root front too: 9.0-9.3 -> 9.6-9.8 s),
        // and in 2D, whose separators are lines and fronts small, changes
        // nothing at 582k nodes and costs 2% at 37k (0.298 -> 0.305 s).
        let split = |layout: Option<direct::SchurLayout>| {
            settings
                .ubr
                .split_fronts
                .unwrap_or(layout.is_some() && world.size() > 1 && d == 3)
        };
        // In 3D at the default -ubr_condense_max, the analysis may decline
        // the condensation (CONDENSE_DENSE_SHARE); not where the user
        // placed the Schur complement (-ubr_schur_distributed).
        let u = &settings.ubr;
        let auto = d == 3 && u.condense_max.is_none() && u.schur_distributed.is_none();
        let plan = direct::Plan {
            schur: layout,
            split_fronts: split(layout),
            decline_below: auto.then_some(crate::linalg::CONDENSE_DENSE_SHARE),
        };
        let mut dm = direct::Direct::new(world, a, mesh, adjacency, surface, plan, comps)?;
        // The back-end without the Schur complement (full solves).
        let full = || {
            let plan = direct::Plan {
                schur: None,
                split_fronts: split(None),
                decline_below: None,
            };
            direct::Direct::new(world, a, mesh, adjacency, surface, plan, comps)
        };
        let mut declined = String::new();
        if let Some((m, flops)) = dm.declined() {
            drop(dm);
            declined = format!(
                ", not condensed: the dense Schur complement on the {m} contact unknowns (m^3 = {:.2e}) would outweigh the sparse factorization with it ({flops:.2e} flops predicted; -ubr_condense_max {m} condenses)",
                (m as f64).powi(3)
            );
            dm = full()?;
        }
        let mut warnings = Vec::new();
        let tiny = dm.tiny_pivots();
        if condense && tiny > 0 {
            // The Schur complement is unreliable: factorized again whole.
            drop(dm);
            warnings.push(format!(
                "MUMPS replaced {tiny} tiny pivots (INFOG(25)) while computing the Schur complement of the condensed solves, which would be wrong: the run uses full solves instead. The matrix entries are tiny (E = {:.3e}): expressed in units where E is nearer 1, the condensed solves work",
                settings.young
            ));
            dm = full()?;
        }
        if !settings.ubr.distributed_rhs {
            dm.centralize_rhs();
        }
        let description = format!(
            "MUMPS Cholesky, called directly ({}; {:.3e} flops){declined}",
            dm.ordering, dm.flops
        );
        warnings.extend(dm.ordering_warning.take());
        return Ok(Chosen {
            condensed: dm.is_condensed(),
            engine: Engine::Direct(Box::new(dm)),
            operator: None,
            description,
            iterative: false,
            warnings,
        });
    }
    let (ksp, mut description, iterative) = linear_solver(a, mesh, &settings.linear)?;
    let mut operator = None;
    if iterative && terms != ContactTerms::None && settings.ubr.sbaij {
        description.push_str(", SBAIJ products");
        // Products read half the bytes (measured: 1.7x faster CG
        // iterations with GAMG on the 136k-node block, 2 ranks);
        // GAMG builds its hierarchy from the AIJ matrix.
        let sbaij = a.sbaij_copy(petsc::comm_world(), d)?;
        ksp.set_operators_split(&sbaij, a)?;
        operator = Some(sbaij);
    }
    if terms != ContactTerms::None {
        ksp.set_up()?; // the one factorization of UBR
    }
    Ok(Chosen {
        condensed: false,
        engine: Engine::Ksp(ksp),
        operator,
        description,
        iterative,
        warnings: Vec::new(),
    })
}
