//! The run, step by step, as deal.II's step-42 reads (`make_grid`,
//! `setup_system`, `assemble`, `solve`, `output_results`): [`run`] calls
//! [`ContactProblem::run`], whose named steps are make the mesh (rank 0
//! reads or generates it), distribute it, set up the contact problem,
//! assemble and factorize, choose r, solve, check, and write the outputs,
//! each a short method in its `-log_view` stage.

use crate::checks::{self, Deformation, Diagnostics, Forces};
use crate::comm::{allreduce_count, allreduce_max, allreduce_sum};
use crate::contact::{interior, ContactSet};
use crate::error::{bad, Error};
use crate::mesh::{self, distribute, distribute::LocalMesh};
use crate::options::{
    self, unused::Unused, Algorithm, Friction, Partitioner, Settings, TrescaBound,
};
use crate::petsc::{self, Events, Stages};
use crate::progress;
use crate::report::{self, files, ContactRow, Results, Times, Totals};
use crate::solver::outcome::{self, Method, Solved};
use crate::solver::surface::UbrState;
use crate::solver::ubr::UbrOutcome;
use crate::solver::{penalty, Assembled, ContactTerms, Problem};
use crate::touching;
use crate::wellposed::{self, Restraint};
use mpi::traits::*;
use std::time::Instant;

mod history;

/// The candidates, the owned Dirichlet dofs and values, and what holds the
/// bodies.
type ContactSetup = (ContactSet, Vec<(usize, f64)>, Restraint);

/// Runs the program on every rank. Errors are collective: every rank returns
/// the same error. Options that nothing used are named on stderr.
pub fn run<C: Communicator>(world: &C) -> Result<(), Error> {
    let root = world.rank() == 0;
    if petsc::options::has_name("-help")? {
        if root {
            options::print_help();
        }
        if !petsc::options::has_name("-mesh")? && !petsc::options::has_name("-mesh_generate")? {
            return Ok(());
        }
    }
    reserve_blas_workspace(world)?;
    crate::error::memory::catch_crash_near_memory_limit()?;
    let mut unused = Unused::default();
    let mut problem = match ContactProblem::new(world) {
        Ok(problem) => problem,
        Err(e) => {
            unused.undeclared(root)?;
            return Err(e);
        }
    };
    let outcome = problem.run(&mut unused);
    // After a failure some options may not have been read yet: only the
    // names that look like the program's but are none of them are wrong.
    // A run that reached its outputs has read them all.
    match &outcome {
        Ok(()) | Err(Error::NotConverged(_)) => unused.finish(root)?,
        Err(_) if problem.outputs_reached => unused.finish(root)?,
        Err(_) => unused.undeclared(root)?,
    }
    outcome
}

/// OpenBLAS' work space, mapped at start-up on every rank
/// ([`crate::dense::reserve_blas_workspace`]): a memory limit too small for
/// it is named now, collectively, instead of a rank spinning in OpenBLAS
/// (which retries a failed mapping for ever) while the others wait for it
/// in MUMPS.
fn reserve_blas_workspace<C: Communicator>(world: &C) -> Result<(), Error> {
    let failed = crate::dense::reserve_blas_workspace().err();
    let size = world.size();
    // The lowest failing rank r as size - r (0: none failed).
    let mine = if failed.is_some() {
        size - world.rank()
    } else {
        0
    };
    let worst = allreduce_max(world, mine as f64) as i32;
    if worst == 0 {
        return Ok(());
    }
    let bytes = failed.unwrap_or(crate::dense::OPENBLAS_BUFFER);
    let first = size - worst;
    Err(Error::OutOfMemory(format!(
        "rank {first} cannot map OpenBLAS' {} MiB work space at start-up: a memory limit (ulimit -v, the batch system's) leaves less than that to the whole run",
        bytes >> 20
    )))
}

/// The scene and the state of the run between its steps.
struct ContactProblem<'w, C: Communicator> {
    world: &'w C,
    root: bool,
    settings: Settings,
    stages: Stages,
    events: Events,
    start: Instant,
    times: Times,
    /// The warnings of the run, each printed once on stderr (rank 0).
    warnings: Vec<String>,
    /// Whether parts of the mesh were found touching before the solve.
    touched: bool,
    /// The trial r0 the program starts from (the P-wave modulus, the
    /// candidate spacing and the contact-surface extent), computed at the
    /// assembly whether or not `-ubr_r` gives r: an r far from it is named
    /// when the run fails.
    r_trial: Option<f64>,
    /// Whether the run reached the output step.
    outputs_reached: bool,
    /// A load history's rows, one per step solved, and its curve's name.
    steps: Vec<report::history::StepRow>,
    curve_label: String,
}

/// An r given by `-ubr_r` more than this factor away from the trial r0
/// (either way) is far outside the range the program would choose: its
/// automatic choice stays within a few times r0, and the accuracy stop
/// holds for r/E from 1e-3 to 1e3 (`tests/r_range.rs`; r0/E is 0.9 to 11
/// on the shipped scenes).
const R_FAR: f64 = 1e6;

/// What the solve step returns.
struct Solution {
    state: UbrState,
    solved: Solved,
}

/// What the check step returns.
struct Checked {
    diag: Diagnostics,
    forces: Forces,
    u_local: Vec<f64>,
    /// Every candidate on rank 0 (empty elsewhere), sorted by node tag.
    rows: Vec<ContactRow>,
    /// Set when the answer violates equilibrium (a singular matrix).
    singular: Option<String>,
    shape: Deformation,
}

impl<'w, C: Communicator> ContactProblem<'w, C> {
    fn new(world: &'w C) -> Result<Self, Error> {
        let start = Instant::now();
        let root = world.rank() == 0;
        progress::start(root);
        let settings = Settings::from_options()?;
        crate::linalg::memfit::watch(world)?;
        if root {
            for note in &settings.notes {
                eprintln!("{note}");
            }
        }
        // The warnings among the notes (options without effect, typos)
        // belong in the report too.
        let warnings = settings
            .notes
            .iter()
            .filter_map(|n| n.strip_prefix("warning: ").map(str::to_string))
            .collect();
        Ok(ContactProblem {
            world,
            root,
            settings,
            stages: Stages::register()?,
            events: Events::register()?,
            start,
            times: Times::default(),
            warnings,
            touched: false,
            r_trial: None,
            outputs_reached: false,
            steps: Vec::new(),
            curve_label: String::new(),
        })
    }

    /// The steps of a run. Once the problem is assembled, a failure of the
    /// method ([`Error::is_outcome`]: not converged, a failed linear solve
    /// or factorization, memory in MUMPS; collective, so every rank takes
    /// the same branch) skips the steps left but the check and the outputs,
    /// which report the state as it is (zero displacement and multipliers
    /// when no iteration ran) with `converged: false` and the failure's
    /// message; the run then ends with that error.
    fn run(&mut self, unused: &mut Unused) -> Result<(), Error> {
        let mut local = self.make_and_distribute_mesh()?;
        crate::fem::material::resolve(&mut local, &self.settings)?;
        self.settings.check_reference(local.dim)?;
        if self.settings.reference.is_some() {
            let e_star = crate::fem::material::contact_e_star(self.world, &local, &self.settings);
            self.settings.contact_e_star = e_star;
        }
        let nu = crate::fem::material::local_max_nu(&local, &self.settings);
        let nu = crate::comm::allreduce_max_n(self.world, nu);
        if let Some(w) = crate::fem::material::locking_warning(nu, &local, &self.settings) {
            self.warn(w);
        }
        let (contact, dirichlet, restraint) = self.setup_contact(&local)?;
        let assembled = self.assemble(&local, contact, dirichlet, &restraint);
        let mut problem = assembled.map_err(|e| self.explain_r(e))?;
        let mut failure = problem.lin.failure();
        let mut choice = None;
        if failure.is_none() {
            match self.choose_r(&local, &mut problem, &restraint) {
                Ok(c) => choice = c,
                Err(e) if e.is_outcome() => failure = Some(e),
                Err(e) => return Err(e),
            }
        }
        if failure.is_some() {
            choice = self.unchosen(&problem);
        }
        unused.early(self.root)?;
        let mut solution = None;
        if failure.is_none() {
            let solved = if self.settings.history.is_some() {
                self.solve_history(&local, &mut problem, &restraint)
            } else {
                self.solve(&local, &mut problem, &restraint)
            };
            match solved {
                Ok(s) => solution = Some(s),
                Err(e) if e.is_outcome() => failure = Some(e),
                Err(e) => return Err(e),
            }
        }
        let mut solution = match solution {
            Some(s) => s,
            None => self.unsolved(&problem)?,
        };
        let checked = self.check(&local, &problem, &restraint, &solution)?;
        // The outcome: the first failure, else the iterations' own verdict
        // (a run that did not converge says why), else an answer that
        // violates equilibrium after a converged run (a singular matrix).
        let outcome = failure
            .or_else(|| {
                (!solution.solved.converged).then(|| Error::NotConverged(solution.solved.failure()))
            })
            .or_else(|| checked.singular.clone().map(Error::NotConverged))
            .map(|e| self.explain_r(e));
        if outcome.is_some() {
            solution.solved.converged = false;
        }
        let message = outcome.as_ref().map(|e| e.to_string());
        self.output(
            &local,
            &problem,
            choice.as_ref(),
            &solution,
            &checked,
            message,
        )?;
        outcome.map_or(Ok(()), Err)
    }

    /// `e` with a note naming r when `-ubr_r` gave an r far outside the
    /// range the program would choose ([`R_FAR`] from the trial r0), for
    /// the failures such an r causes (a singular or ill-conditioned
    /// matrix, an iteration that does not converge).
    fn explain_r(&self, e: Error) -> Error {
        let (Some(r), Some(r0)) = (self.settings.ubr.r, self.r_trial) else {
            return e;
        };
        let far = r > R_FAR * r0 || r < r0 / R_FAR;
        let named = matches!(
            e,
            Error::NotConverged(_) | Error::LinearSolver(_) | Error::IllPosed(_)
        );
        // The iterations name an r far from r0 themselves.
        let said = e.to_string().contains("trial r0");
        if !far || !named || said || self.settings.algorithm != Algorithm::Ubr {
            return e;
        }
        e.with_note(&format!(
            "r = {r:e} (-ubr_r) is {:.0e} times the trial r0 = {r0:.3e} the program starts from, far outside the range it would choose (it stays within a few times r0); use -ubr_r auto (the default)",
            r / r0
        ))
    }

    /// The r choice to report when it did not run or failed: r as it is,
    /// no spectral estimate.
    fn unchosen(&self, problem: &Problem) -> Option<penalty::Choice> {
        (self.settings.algorithm == Algorithm::Ubr).then(|| {
            let auto = self.settings.ubr.r.is_none();
            penalty::Choice {
                r: problem.r(),
                source: if auto {
                    penalty::Source::Auto
                } else {
                    penalty::Source::Option
                },
                r0: self.r_trial.filter(|_| auto).unwrap_or(problem.r()),
                estimate: f64::NAN,
                sigma_min: f64::NAN,
                sigma_max: f64::NAN,
                steps: 0,
                refactorized: false,
                friction_held: false,
            }
        })
    }

    /// The solution to report when the iterations did not run or failed:
    /// zero displacement and multipliers, no iteration, every measure of
    /// the iterations unknown (NaN: null in the report).
    fn unsolved(&self, problem: &Problem) -> Result<Solution, Error> {
        let s = &self.settings;
        let name = match (s.algorithm, s.friction) {
            (Algorithm::SnesVi, _) => Method::SnesVi,
            (Algorithm::Ssn, _) => Method::SsnC,
            (Algorithm::Ubr, Friction::None) => Method::UbrC,
            (Algorithm::Ubr, Friction::Tresca) => Method::UbrTf,
            (Algorithm::Ubr, Friction::Coulomb) => Method::CfFp,
        };
        let nan = f64::NAN;
        let last = UbrOutcome {
            criterion: nan,
            residual: nan,
            dual: nan,
            tension: nan,
            p: nan,
            k: nan,
            error_estimate: nan,
            ..UbrOutcome::default()
        };
        Ok(Solution {
            state: UbrState::new(problem)?,
            solved: Solved {
                name,
                iterations: 0,
                fixed_point_iterations: 0,
                frictionless_iterations: 0,
                converged: false,
                last,
                fp_change: None,
                bound: Vec::new(),
                error_estimate: None,
                failure: None,
                unsolved: true,
            },
        })
    }

    /// Prints a warning once (rank 0) and keeps it for the report.
    fn warn(&mut self, message: String) {
        // (The steps of a load history check each answer: once is enough.)
        if self.warnings.contains(&message) {
            return;
        }
        if self.root {
            eprintln!("warning: {message}");
        }
        self.warnings.push(message);
    }

    /// A generated mesh on several ranks, made by every rank (the
    /// generators are deterministic: every rank builds the same mesh, or
    /// meets the same error, so errors stay collective), each keeping its
    /// own part: split by RCB, the block's box alone
    /// ([`mesh::block3d_parts::own_part`]) or the whole mesh cut by
    /// [`distribute::own_part_rcb`]; split by METIS, rank 0's parts
    /// broadcast and each rank's built from its own copy
    /// ([`distribute::own_part_metis`]). None otherwise.
    fn generated_part(&mut self) -> Result<Option<LocalMesh>, Error> {
        let (stages, source) = (&self.stages, &self.settings.mesh);
        let partitioner = self.settings.partition;
        let size = self.world.size() as usize;
        let crate::options::MeshSource::Generate { name, h, q1 } = source else {
            return Ok(None);
        };
        if size == 1 {
            return Ok(None);
        }
        let rank = self.world.rank() as usize;
        let t = Instant::now();
        if partitioner == Partitioner::Rcb && name == "block3d" {
            // The block's parts are boxes of the grid: each rank makes its
            // own and nothing else.
            let _guard = stages.mesh.push()?;
            if let Some(local) = mesh::block3d_parts::own_part(*h, *q1, size, rank)? {
                self.times.mesh = t.elapsed().as_secs_f64();
                return Ok(Some(local));
            }
        }
        // Without waiting for rank 0 to split and send every part (0.6 s of
        // a 4.0 s run on 16 ranks, 582k nodes, RCB).
        let mesh = {
            let _guard = stages.mesh.push()?;
            mesh::load(source)?
        };
        self.times.mesh = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let _guard = stages.partition.push()?;
        progress::phase(false, || {
            format!("partitioning {} nodes over {size} ranks", mesh.num_nodes())
        });
        let local = match partitioner {
            Partitioner::Rcb => distribute::own_part_rcb(&mesh, size, rank),
            Partitioner::Metis => distribute::own_part_metis(self.world, &mesh)?,
            Partitioner::PtScotch => mesh::ptscotch::own_part(self.world, &mesh)?,
        };
        drop(mesh);
        self.times.partition = t.elapsed().as_secs_f64();
        Ok(Some(local))
    }

    /// Mesh and Partition stages: rank 0 reads or generates the mesh and
    /// splits it (`-partition`: RCB or METIS); each rank receives its part.
    /// A generated mesh is instead made by every rank ([`App::generated_part`]).
    fn make_and_distribute_mesh(&mut self) -> Result<LocalMesh, Error> {
        if let Some(local) = self.generated_part()? {
            return Ok(local);
        }
        let (stages, source) = (&self.stages, &self.settings.mesh);
        let partitioner = self.settings.partition;
        let size = self.world.size() as usize;
        let mut t_mesh = 0.0;
        // The Partition stage and time hold rank 0's partition, the parts'
        // sending and each rank's numbering of its own part.
        let t_all = Instant::now();
        let partition_stage = stages.partition.push()?;
        let load = || {
            let (t, _guard) = (Instant::now(), stages.mesh.push()?);
            let mesh = mesh::load(source);
            t_mesh = t.elapsed().as_secs_f64();
            if let Ok(mesh) = &mesh {
                progress::phase(false, || {
                    format!("partitioning {} nodes over {size} ranks", mesh.num_nodes())
                });
            }
            mesh
        };
        let local = match partitioner {
            Partitioner::PtScotch => mesh::ptscotch::distribute(self.world, load)?,
            Partitioner::Rcb => distribute::distribute(self.world, load, |mesh| {
                Ok(distribute::partition_rcb(&mesh.coords, mesh.dim, size))
            })?,
            Partitioner::Metis => distribute::distribute(self.world, load, |mesh| {
                distribute::partition_nodes(&distribute::NodeGraph::new(mesh), size)
            })?,
        };
        drop(partition_stage);
        let t_partition = t_all.elapsed().as_secs_f64() - t_mesh;
        (self.times.mesh, self.times.partition) = (t_mesh, t_partition);
        if self.root && mesh::gmsh::periodic_skipped() {
            // (Rank 0 read the file and writes the report.)
            self.warn("the mesh file has a $Periodic section, which is ignored: this program ties no periodic boundaries, so the boundaries Gmsh matched move independently (free unless an option holds them)".into());
        }
        Ok(local)
    }

    /// The contact candidates, and the check that every rigid motion is
    /// held (by Dirichlet data, contact along n, or friction): an ill-posed
    /// scene is named now, not met as a zero pivot.
    /// Returns the candidates, the owned Dirichlet dofs and values
    /// ([`crate::fem::dirichlet_dofs`], computed once here), and what holds
    /// the bodies.
    fn setup_contact(&mut self, local: &LocalMesh) -> Result<ContactSetup, Error> {
        let Some(contact) = &self.settings.contact else {
            return bad(
                "option -contact_surface is required (a contact problem needs a candidate surface; -contact_pair SLAVE,MASTER for two elastic bodies)",
            );
        };
        let s = &self.settings;
        let dirichlet = crate::fem::dirichlet_dofs(local, &s.dirichlet)?;
        let mut cs = ContactSet::build(self.world, local, contact)?;
        cs.add_pairs(self.world, local, contact)?;
        let surfaces: Vec<&str> = contact.surfaces.iter().map(String::as_str).collect();
        interior::refuse_inside(self.world, local, "-contact_surface", &surfaces)?;
        let sides: Vec<&str> = contact
            .pairs
            .iter()
            .flat_map(|(s, m)| [s.as_str(), m.as_str()])
            .collect();
        interior::refuse_inside(self.world, local, "-contact_pair", &sides)?;
        cs.align_normals(local, &dirichlet, contact);
        let names = contact.surface_names();
        let dropped = cs.drop_prescribed(self.world, local, &dirichlet, &s.dirichlet, &names)?;
        let pairs = contact.pairs.clone();
        cs.settle(self.world)?;
        if allreduce_count(self.world, cs.len()) == 0 && contact.surfaces.is_empty() {
            return bad("option -contact_pair: no slave node faces its master surface (a slave node is a candidate where master segments cover at least half of its support)");
        }
        if allreduce_count(self.world, cs.len()) == 0 {
            return bad(format!(
                "option -contact_surface: surface '{}' has no candidate node facing the obstacle along the contact direction",
                contact.surface_names()
            ));
        }
        let friction = s.friction != Friction::None;
        let restraint = wellposed::check(self.world, local, &dirichlet, &cs, friction, &pairs)?;
        let mut warnings: Vec<String> = std::mem::take(&mut cs.reoriented);
        warnings.extend(dropped);
        warnings.extend(checks::setup_warnings(
            self.world, local, s, &dirichlet, &cs,
        )?);
        for w in warnings {
            self.warn(w);
        }
        let touches = touching::touching(self.world, local, &restraint.bodies, None);
        let touches = touching::unpaired(self.world, local, &restraint.bodies, &pairs, touches);
        if let Some(w) = touching::warning(&restraint.bodies, &touches, false) {
            self.touched = true;
            self.warn(w);
        }
        Ok((cs, dirichlet, restraint))
    }

    /// Assembly and Factorization stages: K + r B^T W B at the trial r
    /// (K alone for the comparators), the Dirichlet elimination and the
    /// loads; the loads judged against what holds the bodies before the
    /// one factorization.
    fn assemble(
        &mut self,
        local: &LocalMesh,
        cs: ContactSet,
        dirichlet: Vec<(usize, f64)>,
        restraint: &Restraint,
    ) -> Result<Problem, Error> {
        let (world, s) = (self.world, &self.settings);
        let d = local.dim;
        let ssn = s.algorithm != Algorithm::Ubr;
        if ssn && !s.ssn_initial_shift.is_empty() && s.ssn_initial_shift.len() != d {
            return bad(format!(
                "option -ssn_initial_shift: {} components given, the mesh is {d}D",
                s.ssn_initial_shift.len()
            ));
        }
        let friction = s.friction != Friction::None;
        let terms = if ssn {
            ContactTerms::None
        } else {
            ContactTerms::Ubr {
                tangential: friction,
            }
        };
        // r: the user's, or a trial r0 refined after the factorization
        // (auto); the trial is kept to judge the user's r. One modulus for
        // the whole scene: the stiffest body's.
        let m = s.stiffest(d);
        let modulus = penalty::p_wave_modulus(m.young, m.nu, d, s.plane_stress);
        let trial = penalty::trial(world, local, &cs, modulus);
        self.r_trial = Some(trial);
        let s = &self.settings;
        let r0 = s.ubr.r.unwrap_or(trial);
        progress::phase(false, || {
            format!(
                "assembling and factorizing ({} unknowns)",
                local.global_nodes * d
            )
        });
        let assembled = Problem::assemble(world, local, s, cs, dirichlet, terms, r0, &self.stages)?;
        self.judge_loads(local, restraint, &assembled)?;
        if assembled.matrix_mallocs != 0.0 {
            return Err(Error::Internal(format!(
                "{} mallocs during matrix assembly: preallocation is wrong",
                assembled.matrix_mallocs
            )));
        }
        let mut problem = Problem::factorize(world, local, s, assembled, &self.stages)?;
        for w in std::mem::take(&mut problem.lin.warnings) {
            self.warn(w);
        }
        self.times.assembly = problem.time_assembly;
        self.times.factorization = problem.time_factorization;
        Ok(problem)
    }

    /// Can the contact (frictionless, within Coulomb's cone, or within a
    /// Tresca bound given before the solve) balance the loads on the
    /// motions no Dirichlet condition holds? A history: the loads its
    /// steps apply (not the whole load, which it may never apply).
    fn judge_loads(
        &self,
        local: &LocalMesh,
        restraint: &Restraint,
        assembled: &Assembled,
    ) -> Result<(), Error> {
        let (world, s) = (self.world, &self.settings);
        let cs = &assembled.contact;
        let whole;
        let history = s.history.as_ref().zip(assembled.load_parts());
        let (parts, steps) = match &history {
            Some((h, (parts, rest))) => (parts.clone(), history::steps_to_check(h, *rest, true)),
            None => {
                whole = assembled.load.read(|f| f.to_vec())?;
                let step = wellposed::LoadStep {
                    label: None,
                    coefs: vec![1.0],
                };
                (vec![&whole[..]], vec![step])
            }
        };
        // The checks: the friction law's (frictionless, or Coulomb's cone;
        // a Tresca bound below), and where a frictionless solve makes the
        // Tresca bound of a body only friction holds, that solve's.
        let judged = wellposed::Judged {
            world,
            mesh: local,
            restraint,
            cs,
            parts: &parts,
            steps: &steps,
        };
        let bound = wellposed::frictionless_bound_refusal(restraint, s);
        let mut checks = match s.friction {
            Friction::None => vec![(None, false)],
            Friction::Coulomb => vec![(Some(s.friction_coefficient), false)],
            Friction::Tresca => vec![],
        };
        if bound.is_some() {
            checks.push((None, true));
        }
        for (coulomb, for_bound) in checks {
            // A failure of the bound's check is named as the bound's.
            let refusal = bound.as_deref().filter(|_| for_bound);
            wellposed::check_steps(&judged, coulomb, refusal)?;
        }
        // A Tresca bound known before the solve: its total against the
        // tangential load.
        let tresca = match (s.friction, s.tresca_bound) {
            (Friction::Tresca, Some(TrescaBound::Value(v))) => {
                Some((vec![v; cs.len()], "raise -tresca_bound"))
            }
            (Friction::Tresca, Some(TrescaBound::Hertz)) => Some((
                outcome::hertz_bound(
                    world,
                    local,
                    cs,
                    s.reference.as_ref().expect("checked with the options"),
                    s.friction_coefficient,
                    s.e_star(local.dim),
                ),
                "raise -friction_coefficient",
            )),
            _ => None,
        };
        if let Some((bound, raise)) = tresca {
            // Every step: the bound holds a load up to a size.
            let every = history.map(|(h, (_, rest))| history::steps_to_check(h, rest, false));
            let steps = every.as_deref().unwrap_or(&steps);
            let judged = wellposed::Judged { steps, ..judged };
            wellposed::check_tresca(&judged, &bound, raise)?;
        }
        Ok(())
    }

    /// RChoice stage: r from the spectrum of the contact compliance (auto),
    /// or the user's, checked.
    fn choose_r(
        &mut self,
        local: &LocalMesh,
        problem: &mut Problem,
        restraint: &Restraint,
    ) -> Result<Option<penalty::Choice>, Error> {
        if self.settings.algorithm != Algorithm::Ubr {
            return Ok(None);
        }
        let t = Instant::now();
        let _guard = self.stages.r_choice.push()?;
        let auto = self.settings.ubr.r.is_none();
        progress::phase(false, || "choosing r".into());
        let monitor = self.settings.ubr.monitor;
        let choice = penalty::choose(self.world, problem, restraint, local, auto, monitor);
        if choice.is_ok() {
            if let Some(r0) = outcome::r_far(self.world, local, &self.settings, problem) {
                let r = problem.r();
                self.warn(format!(
                    "-ubr_r {r:.3e} is {:.1e} times the trial r0 = {r0:.3e} from which -ubr_r auto chooses (within a factor of about 30 of it): UBR converges slowly or not at all that far from it",
                    r / r0
                ));
            }
        }
        self.times.r_choice = t.elapsed().as_secs_f64();
        Ok(Some(choice?))
    }

    /// Iterations stage: UBR-C, UBR-TF, CF-FP or a comparator.
    fn solve(
        &mut self,
        local: &LocalMesh,
        problem: &mut Problem,
        restraint: &Restraint,
    ) -> Result<Solution, Error> {
        let _guard = self.stages.iterations.push()?;
        let t = Instant::now();
        progress::phase(false, || "iterating".into());
        let solved = outcome::solve(
            self.world,
            local,
            &self.settings,
            problem,
            restraint,
            &self.events,
        );
        self.times.iterations = t.elapsed().as_secs_f64();
        for w in std::mem::take(&mut problem.lin.warnings) {
            self.warn(w);
        }
        let (state, solved) = solved?;
        Ok(Solution { state, solved })
    }

    /// The checks of the answer: the optimality conditions, the forces and
    /// reactions, the warnings a result may call for.
    fn check(
        &mut self,
        local: &LocalMesh,
        problem: &Problem,
        restraint: &Restraint,
        sol: &Solution,
    ) -> Result<Checked, Error> {
        let (world, s) = (self.world, &self.settings);
        progress::phase(false, || "checking the answer".into());
        let bound = checks::friction_bound(s, &sol.state, &sol.solved.bound);
        let pairs = s
            .contact
            .as_ref()
            .map(|c| c.pairs.clone())
            .unwrap_or_default();
        let u_local = checks::local_displacement(local, &problem.physical(&sol.state.u)?)?;
        let forces = checks::forces(world, local, s, problem, &sol.state, &u_local)?;
        let diag = checks::diagnostics(world, problem, &sol.state, &bound)?.with_forces(&forces);
        let singular = checks::singular(problem, &diag, sol.solved.name, sol.solved.iterations);
        let rows = report::contact_rows(local, problem, &sol.state, &sol.solved.bound);
        let rows = report::gather_rows(world, &rows);
        let shape = checks::deformation(world, local, &u_local);
        for w in checks::result_warnings(world, local, s, &problem.contact, &sol.state, &shape) {
            self.warn(w);
        }
        if !self.touched {
            let touches = touching::touching(world, local, &restraint.bodies, Some(&u_local));
            let touches = touching::unpaired(world, local, &restraint.bodies, &pairs, touches);
            if let Some(w) = touching::warning(&restraint.bodies, &touches, true) {
                self.warn(w);
            }
        }
        Ok(Checked {
            diag,
            forces,
            u_local,
            rows,
            singular,
            shape,
        })
    }

    /// Output stage: the summary and rank 0's files, the ParaView files.
    /// `failure`: the message the run ends with when it fails (in the
    /// report).
    fn output(
        &mut self,
        local: &LocalMesh,
        problem: &Problem,
        choice: Option<&penalty::Choice>,
        sol: &Solution,
        checked: &Checked,
        failure: Option<String>,
    ) -> Result<(), Error> {
        self.outputs_reached = true;
        let world = self.world;
        let _guard = self.stages.output.push()?;
        progress::phase(false, || "writing the outputs".into());
        let hwm = report::peak_memory_mb();
        let memory = [
            hwm,
            allreduce_max(world, hwm),
            allreduce_sum(world, [hwm])[0],
        ];
        self.times.total = self.start.elapsed().as_secs_f64();
        let mut written = Ok(());
        progress::finish();
        if self.root {
            let d = local.dim;
            let hertz = self.settings.reference.as_ref().map(|r| {
                let e_star = self.settings.e_star(d);
                report::compare_hertz(&checked.rows, d, &problem.contact.direction, e_star, r)
            });
            // (Not on a failed run: its message says what stopped it.)
            let said = hertz.as_ref().filter(|_| failure.is_none());
            for w in said
                .into_iter()
                .flat_map(|h| [h.resolution_warning(), h.force_warning(), h.shape_warning()])
                .flatten()
            {
                self.warn(w);
            }
            let s = &self.settings;
            let results = Results {
                settings: s,
                local,
                ranks: world.size() as usize,
                candidates: checked.rows.len(),
                problem,
                choice,
                solved: &sol.solved,
                state: &sol.state,
                diag: &checked.diag,
                forces: &checked.forces,
                shape: &checked.shape,
                rows: &checked.rows,
                totals: Totals::of(&checked.rows, d),
                hertz,
                times: self.times.clone(),
                memory,
                warnings: &self.warnings,
                failure,
            };
            report::summary::print(&results);
            written = files::write_root_files(&results);
            if let Some(h) = &s.history {
                let groups: Vec<String> = h.groups.iter().map(|g| g.name()).collect();
                let table = report::history::write_files(
                    s.history_output.as_deref(),
                    s.plot_history_curve.as_deref(),
                    &groups,
                    d,
                    &self.curve_label,
                    &self.steps,
                );
                written = written.and(table);
                if let Some(vtk) = &s.vtk {
                    let path = report::history::pvd_path(vtk);
                    let text = report::history::pvd(vtk, self.steps.len());
                    let pvd = report::write_atomic(std::path::Path::new(&path), text.as_bytes())
                        .map_err(|e| Error::output("-vtk", &path, e));
                    written = written.and(pvd);
                }
            }
        }
        let s = &self.settings;
        if let Some(path) = &s.vtk {
            let rows = report::broadcast_rows(world, &checked.rows);
            let master = master_traction(world, local, s, problem, &sol.state)?;
            let vtk = files::write_vtk(
                world,
                path,
                (s, local),
                &checked.u_local,
                &rows,
                master.as_deref(),
            );
            written = written.and(vtk);
        }
        files::collective(world, written)
    }
}

/// With contact pairs: their traction on the master nodes, by node tag
/// (the VTU field `master_traction`).
fn master_traction<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    s: &Settings,
    problem: &Problem,
    state: &crate::solver::surface::UbrState,
) -> Result<Option<Vec<(u64, f64)>>, Error> {
    let Some(t) = &problem.transform else {
        return Ok(None);
    };
    let masters: Vec<&str> = s
        .contact
        .as_ref()
        .map(|c| c.pairs.iter().map(|p| p.1.as_str()).collect())
        .unwrap_or_default();
    let f = checks::slave_forces(local, problem, state);
    t.master_traction(world, local, &f, &masters).map(Some)
}
