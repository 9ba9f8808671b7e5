//! The direct back-end on MUMPS itself (`-pc_type cholesky|lu
//! -pc_factor_mat_solver_type mumps`, the default): what PETSc 3.18's
//! wrapper cannot do, a METIS nested-dissection ordering (Debian's MUMPS has
//! no METIS; PETSc refuses a user ordering) and the Schur complement on the
//! contact unknowns on any number of ranks (PETSc: one rank only).
//!
//! - Input: each rank's rows of the assembled `K_r` (its lower triangle),
//!   distributed assembled format (ICNTL(18) = 3), SYM = 1.
//! - Ordering: METIS_NodeND on the nodal graph (the mesh's, gathered on the
//!   host), each node's dofs together, the contact unknowns last; given as
//!   PERM_IN (ICNTL(7) = 1, sequential analysis ICNTL(28) = 1). In 3D
//!   always; in 2D only where it pays for its own (sequential) time, judged
//!   from the flops MUMPS' AMD ordering predicts
//!   ([`super::ordering::METIS_PAYS_2D`]).
//! - Schur complement (when condensing): on the contact unknowns (candidate
//!   by candidate, rank by rank), centralized on the host (ICNTL(19) = 1),
//!   factorized there by LAPACK; or, from 2 ranks on in 3D and 4 in 2D
//!   (`-ubr_schur_distributed`), on MUMPS' 1 x P grid (ICNTL(19) = 3),
//!   factorized and solved there by ScaLAPACK (`linalg/grid.rs`). A full solve is then a condensation
//!   (ICNTL(26) = 1), a dense solve with S, an expansion (ICNTL(26) = 2).
//!   A condensed UBR solve gathers the m contact values of the right-hand
//!   side on the host, solves with S there and scatters the result back.
//! - Full solves hand MUMPS each rank's rows of the right-hand sides and
//!   send its distributed solution to the rows' owners (ICNTL(20) = 10,
//!   ICNTL(21) = 1; `linalg/distsol.rs`); `-ubr_mumps_rhs centralized`
//!   gathers them on the host and scatters the solutions from there
//!   (ICNTL(20) = ICNTL(21) = 0).
//!
//! The usual `-mat_mumps_icntl_N` / `-mat_mumps_cntl_N` options are passed
//! on, except those this back-end sets: 5, 18 (input format), 19, 26 (Schur),
//! 20, 21 (right-hand sides and solutions), and 28 with METIS (28 = 2:
//! MUMPS' own parallel analysis, [`super::ordering::mumps_parallel`]);
//! `-mat_mumps_icntl_7 1` asks for METIS, `-mat_mumps_icntl_7 K` with K
//! other than 1 for MUMPS' own ordering K (with a Schur complement MUMPS
//! replaces it by AMD: a warning says so).

use super::distsol::DistSolve;
use super::grid::GridSchur;
pub use super::schur::SchurLayout;
use super::schur::{first_factors, host_schur, schur_factor, schur_memory, SCHUR_BLOCK};
use crate::comm::{allreduce_max, allreduce_sum, Layout};
use crate::contact::surface::Surface;
use crate::dense::{sym_upper_mv, SpdFactor};
use crate::error::Error;
use crate::fem::Adjacency;
use crate::mesh::distribute::LocalMesh;
use crate::mumps::{Mumps, OWNED_ICNTL};
use crate::petsc::{options, LogEvent, Matrix};
use mpi::traits::*;

/// The contact part: the Schur complement on the host.
struct SchurPart {
    m: usize,
    /// Whether MUMPS returns it distributed (gathered on the host after
    /// each factorization) or centralized.
    distributed: bool,
    layout: Layout,
    /// Host: the factor of S at the assembled r (S itself, unfactored, is
    /// read where MUMPS returned it, [`host_schur`]: products and shifts),
    /// and of S at the current r when it differs (`shifted_on`; its array
    /// is kept for the next change of r).
    s: Option<SpdFactor>,
    /// Distributed: S's factors on every rank instead (S itself stays in
    /// MUMPS' array); `s` and `shifted` are then empty.
    grid: Option<GridSchur>,
    shifted: Option<SpdFactor>,
    shifted_on: bool,
    /// Host: the gathered right-hand side and the solution of a Schur
    /// solve (m each), kept between the iterations' solves.
    rhs: Vec<f64>,
    sol: Vec<f64>,
}

/// MUMPS on the assembled matrix, with or without the Schur complement.
pub struct Direct {
    mumps: Mumps,
    /// `-log_view` events: MUMPS' numeric factorization and solves, and the
    /// dense Schur solves on the host.
    ev_factor: LogEvent,
    ev_solve: LogEvent,
    ev_schur: LogEvent,
    /// Numeric factorizations so far.
    pub factorizations: usize,
    dofs: Layout,
    schur: Option<SchurPart>,
    /// Flops of the factorization (RINFOG(3)) and the ordering used.
    pub flops: f64,
    pub ordering: String,
    /// An ordering asked for that MUMPS replaced, for the run's warnings.
    pub ordering_warning: Option<String>,
    /// Host: the gathered right-hand sides of a full solve, kept between
    /// solves (centralized right-hand sides only).
    all: Vec<f64>,
    /// Distributed right-hand sides and solutions (the default;
    /// None after [`Direct::centralize_rhs`]).
    dist: Option<DistSolve>,
    /// Which of this rank's lower-triangle entries MUMPS has
    /// ([`lower_triplets`]).
    kept: Vec<bool>,
    /// The number of columns of the last MUMPS solve when it was the
    /// condensation of the base right-hand side ([`Direct::solve_contact_part`]),
    /// whose forward elimination MUMPS keeps for an expansion
    /// ([`Direct::expand`]); 0 after any other solve or a refactorization.
    reduced: usize,
    /// Why the factorization failed ([`Direct::failed`]): every solve
    /// returns it.
    failure: Option<Error>,
    /// The condensation declined after the analysis ([`Plan::decline_below`]):
    /// the Schur block's order m and the predicted flops of the sparse
    /// factorization with it (RINFOG(1)); nothing factorized.
    declined: Option<(usize, f64)>,
}

/// A failure found on the host only (`failed` is read there), made
/// collective: every rank returns an error of the same kind (the host's
/// own, with its message; the others' one of that kind, whose message
/// nobody prints: only rank 0 prints a collective error), none waits in a
/// later collective call.
pub(super) fn host_verdict<C: Communicator>(world: &C, failed: Option<Error>) -> Result<(), Error> {
    // The kind, as the exit status of the error (0: none failed).
    let mut status = failed.as_ref().map_or(0, |e| e.exit_code());
    world.process_at_rank(0).broadcast_into(&mut status);
    match (status, failed) {
        (0, _) => Ok(()),
        (_, Some(e)) => Err(e),
        (s, None) if s == crate::error::EXIT_OUT_OF_MEMORY => {
            Err(Error::OutOfMemory("on rank 0".into()))
        }
        (3, None) => Err(Error::LinearSolver("on rank 0".into())),
        (_, None) => Err(Error::Internal("on rank 0".into())),
    }
}

/// [`host_verdict`] of a dense failure of the host (`failed`): the
/// linear-solver error `what`.
fn host_failed<C: Communicator>(world: &C, failed: bool, what: &str) -> Result<(), Error> {
    host_verdict(world, failed.then(|| Error::LinearSolver(what.into())))
}

/// The user's MUMPS options (`-mat_mumps_icntl_N`, `-mat_mumps_cntl_N`),
/// but those this back-end sets.
fn user_options(mumps: &mut Mumps) -> Result<(), Error> {
    // The user's MUMPS options, but those this back-end sets.
    for i in 1..=60usize {
        if OWNED_ICNTL.contains(&i) {
            continue;
        }
        if let Some(v) = options::get_string(&format!("-mat_mumps_icntl_{i}"))? {
            let v: i32 = v.trim().parse().map_err(|_| {
                Error::BadInput(format!(
                    "option -mat_mumps_icntl_{i}: '{v}' is not an integer"
                ))
            })?;
            mumps.set_icntl(i, v);
        }
    }
    for i in 1..=15usize {
        if let Some(v) = options::get_string(&format!("-mat_mumps_cntl_{i}"))? {
            let v: f64 = v.trim().parse().map_err(|_| {
                Error::BadInput(format!("option -mat_mumps_cntl_{i}: '{v}' is not a number"))
            })?;
            mumps.set_cntl(i, v);
        }
    }
    Ok(())
}

/// The contact nodes (global numbers) of every rank, in the Schur order:
/// rank by rank, candidate by candidate, on the host (empty elsewhere); and
/// their number, on every rank.
fn contact_nodes<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    surface: &Surface,
) -> (Vec<usize>, usize) {
    let mine: Vec<f64> = surface
        .cs
        .node
        .iter()
        .map(|&v| mesh.node_global[v] as f64)
        .collect();
    let layout = Layout::new(world, mine.len());
    let nodes = layout
        .gather(world, &mine)
        .iter()
        .map(|&x| x as usize)
        .collect();
    (nodes, layout.total())
}

/// How [`Direct::new`] factorizes: with the Schur complement on the
/// contact unknowns or not (and where it lies), and whether MUMPS' analysis
/// splits large fronts into chains (`-ubr_mumps_split`).
#[derive(Clone, Copy, Debug)]
pub struct Plan {
    pub schur: Option<SchurLayout>,
    pub split_fronts: bool,
    /// With the Schur complement: decline it where the analysis predicts
    /// fewer sparse factorization flops (RINFOG(1)) than this times m^3
    /// ([`super::CONDENSE_DENSE_SHARE`]).
    pub decline_below: Option<f64>,
}

/// Asks MUMPS for the Schur complement on the `m` unknowns `listvar`
/// (1-based; given on the host, empty elsewhere), distributed over the ranks
/// or on the host. The error of the inner result: the host's Schur block
/// does not fit in memory (every rank told).
fn prepare_schur<C: Communicator>(
    world: &C,
    mumps: &mut Mumps,
    m: usize,
    listvar: Vec<i32>,
    distributed: bool,
) -> Result<Result<(), Error>, Error> {
    if distributed {
        mumps.set_distributed_schur(m, listvar, world.size() as usize, SCHUR_BLOCK);
        // MUMPS underestimates the work space of a small distributed
        // root, and a larger ICNTL(14) after the analysis does not
        // help (block3d_739, Coulomb, 4 ranks: INFOG(1) = -9 at the
        // default 20 and at 640 set after it; 60 before it works).
        if options::get_string("-mat_mumps_icntl_14")?.is_none() {
            mumps.set_icntl(14, 60);
        }
        return Ok(Ok(()));
    }
    let failed = mumps
        .set_schur(m, listvar)
        .err()
        .map(|bytes| schur_memory(m, bytes));
    Ok(host_verdict(world, failed))
}

impl Direct {
    /// Analyses and factorizes `a` (the assembled `K_r`), with the Schur
    /// complement on the contact unknowns when `plan.schur` is given.
    /// `comps`: the components of each candidate in the Schur complement
    /// (the normal axis alone when frictionless along an axis); `adjacency`:
    /// the nodal graph METIS orders; `plan.schur`: with the Schur complement
    /// on the contact unknowns (condensed), built on the host or, on several
    /// ranks, distributed by MUMPS and gathered on the host after each
    /// factorization; `plan.split_fronts`: MUMPS' pre-splitting of large
    /// fronts ([`Mumps::split_fronts`]).
    pub fn new<C: Communicator>(
        world: &C,
        a: &Matrix,
        mesh: &LocalMesh,
        adjacency: &Adjacency,
        surface: &Surface,
        plan: Plan,
        comps: &[usize],
    ) -> Result<Direct, Error> {
        let schur = plan.schur;
        let condense = schur.is_some();
        let d = mesh.dim;
        let n = mesh.global_nodes * d;
        let ev_init = LogEvent::register("MUMPSInit")?.begin();
        let ((irn, jcn, val), kept) = super::lower_triplets(a, d)?;
        let mut mumps = Mumps::new(crate::petsc::comm_world(), world.rank(), true)?;
        drop(ev_init);
        mumps.set_matrix(n, irn, jcn, val);
        user_options(&mut mumps)?;
        let (contact_global, candidates) = contact_nodes(world, mesh, surface);
        let m = candidates * comps.len();
        let dof_layout = Layout::new(world, mesh.owned_count * d);
        let distributed = schur == Some(SchurLayout::Distributed) && world.size() > 1;
        let prepared = if condense {
            let listvar: Vec<i32> = contact_global
                .iter()
                .flat_map(|&g| comps.iter().map(move |&c| (g * d + c + 1) as i32))
                .collect();
            prepare_schur(world, &mut mumps, m, listvar, distributed)?
        } else {
            Ok(())
        };
        if plan.split_fronts {
            mumps.split_fronts();
        }
        let schur_nodes: &[usize] = if condense { &contact_global } else { &[] };
        // The analysis may fail as the factorization may (memory): kept too.
        let analysis = prepared.and_then(|()| match mumps.icntl(28) {
            2 => super::ordering::mumps_parallel(&mut mumps, condense),
            _ => super::ordering::choose(world, &mut mumps, mesh, adjacency, schur_nodes, comps),
        });
        // The dense Schur block would outweigh the sparse work it saves
        // (RINFOG(1), the same on every rank): declined, nothing more done.
        let declined = match (&analysis, plan.decline_below) {
            (Ok(_), Some(share)) if condense => {
                let flops = mumps.rinfog(1);
                (flops < share * (m as f64).powi(3)).then_some((m, flops))
            }
            _ => None,
        };
        // A distributed Schur complement: each rank's part, sized now.
        let analysis = analysis.and_then(|ordering| {
            if condense && distributed && declined.is_none() {
                let failed = mumps.size_distributed_schur().err();
                let worst = allreduce_max(world, failed.unwrap_or(0) as f64);
                if worst > 0.0 {
                    return Err(schur_memory(m, worst as usize));
                }
            }
            Ok(ordering)
        });
        let (ordering, analysed) = match analysis {
            Ok(ordering) if plan.split_fronts && mumps.fronts_split() > 0 => {
                let n = mumps.fronts_split();
                let fronts = if n == 1 { "front" } else { "fronts" };
                (
                    format!("{ordering}; {n} large {fronts} split in chains"),
                    Ok(()),
                )
            }
            Ok(ordering) => (ordering, Ok(())),
            Err(e) => ("not analysed".to_string(), Err(e)),
        };
        let ordering_warning = super::ordering::replaced_ordering(&mumps, analysed.is_ok())?;
        let ev_factor = LogEvent::register("MUMPSFactorNum")?;
        let ev_solve = LogEvent::register("MUMPSSolve")?;
        let ev_schur = LogEvent::register("SchurSolve")?;
        let mut direct = Direct {
            mumps,
            ev_factor,
            ev_solve,
            ev_schur,
            factorizations: 1,
            dofs: dof_layout,
            schur: None,
            flops: 0.0,
            ordering,
            ordering_warning,
            all: Vec::new(),
            dist: Some(DistSolve::new(world, mesh.owned_count * d)),
            kept,
            reduced: 0,
            failure: None,
            declined,
        };
        if let Err(e) = analysed {
            return Direct::failed(direct, e);
        }
        if declined.is_some() {
            return Ok(direct);
        }
        let factorized = super::memfit::fits(world, &direct.mumps).and_then(|()| {
            let _e = direct.ev_factor.begin();
            direct.mumps.factorize()
        });
        direct.flops = direct.mumps.rinfog(3);
        if let Err(e) = factorized {
            return Direct::failed(direct, e);
        }
        if condense {
            let local = surface.cs.len() * comps.len();
            if let Err(e) = direct.first_schur(world, m, distributed, local) {
                return Direct::failed(direct, e);
            }
        }
        Ok(direct)
    }

    /// The Schur complement of the first factorization, of order `m`
    /// (`local` of its unknowns on this rank), factorized.
    fn first_schur<C: Communicator>(
        &mut self,
        world: &C,
        m: usize,
        distributed: bool,
        local: usize,
    ) -> Result<(), Error> {
        let _e = LogEvent::register("SchurFactor")?.begin();
        let (s, grid) = first_factors(world, &self.mumps, m, distributed)?;
        let host = if world.rank() == 0 { m } else { 0 };
        self.schur = Some(SchurPart {
            m,
            distributed,
            layout: Layout::new(world, local),
            s,
            grid,
            shifted: None,
            shifted_on: false,
            rhs: vec![0.0; host],
            sol: vec![0.0; host],
        });
        Ok(())
    }

    /// Full solves gather the right-hand sides on the host and scatter the
    /// solutions from there (`-ubr_mumps_rhs centralized`), instead of
    /// MUMPS' distributed right-hand sides and solutions.
    pub fn centralize_rhs(&mut self) {
        self.dist = None;
    }

    /// An analysis or factorization that failed in a way the run reports
    /// as its outcome (a failed linear solve, exit status 3, or memory, 4:
    /// collective errors) is kept, not returned: the problem is still set
    /// up, every later solve returns it ([`Direct::failure`]), and the run
    /// writes its outputs before it ends with it. Any other error is
    /// returned.
    fn failed(mut direct: Direct, e: Error) -> Result<Direct, Error> {
        if !matches!(e, Error::LinearSolver(_) | Error::OutOfMemory(_)) {
            return Err(e);
        }
        direct.schur = None;
        direct.failure = Some(e);
        Ok(direct)
    }

    /// The condensation declined after the analysis: the Schur block's
    /// order and the sparse factorization's predicted flops with it
    /// (nothing factorized: the caller builds the plain back-end).
    pub fn declined(&self) -> Option<(usize, f64)> {
        self.declined
    }

    /// The failure of the factorization, if it failed (the same on every rank).
    pub fn failure(&self) -> Option<&Error> {
        self.failure.as_ref()
    }

    /// `Err` with the failure of the factorization, if it failed.
    fn usable(&self) -> Result<(), Error> {
        self.failure.clone().map_or(Ok(()), Err)
    }

    pub fn is_condensed(&self) -> bool {
        self.schur.is_some()
    }

    /// The pivots MUMPS replaced as tiny in the factorization (INFOG(25);
    /// 0 after a failed one). With the Schur block MUMPS replaces pivots
    /// below an absolute threshold, whatever CNTL(3..5) and ICNTL(24) say:
    /// at E = 1e-20 (loads alike) it replaced 505 on block3d_739 and the
    /// Schur complement came out wrong (the compliance 0.417 instead of
    /// 0.609, times 1/E); the full factorization replaced none.
    pub fn tiny_pivots(&self) -> i32 {
        match self.failure {
            Some(_) => 0,
            None => self.mumps.infog(25),
        }
    }

    /// Whether MUMPS returns the Schur complement distributed.
    pub fn schur_distributed(&self) -> bool {
        self.schur.as_ref().is_some_and(|s| s.distributed)
    }

    /// Schur complement order (0 without).
    pub fn schur_size(&self) -> usize {
        self.schur.as_ref().map_or(0, |s| s.m)
    }

    /// The `k` columns of `cols` (this rank's rows of each, column-major)
    /// gathered on the host, column by column in rank order, into the
    /// buffer kept between solves (to be put back in `self.all`).
    fn gather_columns<C: Communicator>(&mut self, world: &C, cols: &[f64], k: usize) -> Vec<f64> {
        let (local, n) = (cols.len() / k.max(1), self.dofs.total());
        let host = world.rank() == 0;
        let mut all = std::mem::take(&mut self.all);
        if host {
            all.resize(n * k, 0.0);
        }
        for j in 0..k {
            let dst = if host {
                &mut all[j * n..(j + 1) * n]
            } else {
                &mut [][..]
            };
            self.dofs
                .gather_into(world, &cols[j * local..(j + 1) * local], dst);
        }
        all
    }

    /// The inverse of [`Direct::gather_columns`]: the `k` host columns of
    /// `all` scattered into `cols` (this rank's rows of each,
    /// column-major); the buffer goes back to `self.all`.
    fn scatter_columns<C: Communicator>(
        &mut self,
        world: &C,
        all: Vec<f64>,
        k: usize,
        cols: &mut [f64],
    ) {
        let (local, n) = (cols.len() / k.max(1), self.dofs.total());
        let host = world.rank() == 0;
        for j in 0..k {
            let part = if host {
                &all[j * n..(j + 1) * n]
            } else {
                &[][..]
            };
            self.dofs
                .scatter(world, part, &mut cols[j * local..(j + 1) * local]);
        }
        self.all = all;
    }

    /// Solves `K_r X = B` for `k` right-hand sides: this rank's rows of each
    /// column, column-major (`local * k`), overwritten by the solutions.
    pub fn solve_full<C: Communicator>(
        &mut self,
        world: &C,
        cols: &mut [f64],
        k: usize,
    ) -> Result<(), Error> {
        self.usable()?;
        let _e = self.ev_solve.begin();
        let host = world.rank() == 0;
        self.reduced = 0;
        let Some(m) = self.schur.as_ref().map(|sp| sp.m) else {
            return self.mumps_solve(world, cols, k, 0);
        };
        self.mumps_solve(world, cols, k, 1)?;
        // The dense solves on the host; their failure is made collective
        // before the next MUMPS call.
        let sp = self.schur.as_mut().expect("condensed");
        if let Some(g) = sp.grid.as_mut() {
            g.solve_reduced(self.mumps.redrhs_mut(), k)?;
            return self.mumps_expand(world, cols, k);
        }
        let mut status = 0.0f64;
        if host {
            let s = sp.s.as_ref().expect("the host has S");
            let red = self.mumps.redrhs_mut();
            for j in 0..k {
                if s.solve(&red[j * m..(j + 1) * m], &mut sp.sol).is_err() {
                    status = 1.0;
                }
                red[j * m..(j + 1) * m].copy_from_slice(&sp.sol);
            }
        }
        host_failed(world, status != 0.0, "the dense Schur solve failed")?;
        self.mumps_expand(world, cols, k)
    }

    /// One MUMPS solve of the `k` columns of `cols` (this rank's rows of
    /// each, column-major): the whole solve without Schur complement
    /// (`schur_phase` 0, the solutions into `cols`) or the condensation (1,
    /// the reduced right-hand sides on the host, `cols` unchanged), with
    /// distributed right-hand sides and solutions or through the host.
    fn mumps_solve<C: Communicator>(
        &mut self,
        world: &C,
        cols: &mut [f64],
        k: usize,
        schur_phase: i32,
    ) -> Result<(), Error> {
        if let Some(dist) = self.dist.as_mut() {
            return dist.solve(world, &mut self.mumps, cols, k, schur_phase);
        }
        let mut all = self.gather_columns(world, cols, k);
        let r = self.mumps.solve(&mut all, k, schur_phase);
        if r.is_ok() && schur_phase == 0 {
            self.scatter_columns(world, all, k, cols);
        } else {
            self.all = all;
        }
        r
    }

    /// The expansion (ICNTL(26) = 2) of the last condensation from the
    /// Schur solutions in MUMPS' REDRHS: `k` whole solutions into `cols`.
    fn mumps_expand<C: Communicator>(
        &mut self,
        world: &C,
        cols: &mut [f64],
        k: usize,
    ) -> Result<(), Error> {
        if let Some(dist) = self.dist.as_mut() {
            return dist.expand(world, &mut self.mumps, cols, k);
        }
        let mut all = std::mem::take(&mut self.all);
        if world.rank() == 0 {
            all.resize(self.dofs.total() * k, 0.0);
        }
        if let Err(e) = self.mumps.solve(&mut all, k, 2) {
            self.all = all;
            return Err(e);
        }
        self.scatter_columns(world, all, k, cols);
        Ok(())
    }

    /// The Schur components of the solution of `K_r u = b` (b: this rank's
    /// rows), this rank's part (candidate by candidate) into `x`: the
    /// condensation (forward elimination, ICNTL(26) = 1) and a dense solve
    /// with S at the assembled r, without the expansion (the backward pass
    /// over the factors, half a full solve's time) that only the other
    /// unknowns need. `b` is condensed as `keep` identical columns: MUMPS
    /// keeps their forward elimination, and [`Direct::expand`] then gives the
    /// whole solutions for any `keep` right-hand sides that differ from `b`
    /// on the Schur unknowns alone, from their values there, with the
    /// backward pass only.
    pub fn solve_contact_part<C: Communicator>(
        &mut self,
        world: &C,
        b: &[f64],
        x: &mut [f64],
        keep: usize,
    ) -> Result<(), Error> {
        self.usable()?;
        let _e = self.ev_solve.begin();
        let host = world.rank() == 0;
        let keep = keep.max(1);
        let mut cols = b.repeat(keep);
        self.reduced = 0;
        self.mumps_solve(world, &mut cols, keep, 1)?;
        self.reduced = keep;
        let sp = self.schur.as_mut().expect("condensed");
        if let Some(g) = sp.grid.as_mut() {
            let red = self.mumps.redrhs_mut();
            g.solve_reduced(red, 1)?;
            sp.layout.scatter(world, &red[..red.len().min(sp.m)], x);
            return Ok(());
        }
        let failed = host && {
            let s = sp.s.as_ref().expect("the host has S");
            s.solve(&self.mumps.redrhs_mut()[..sp.m], &mut sp.sol)
                .is_err()
        };
        host_failed(world, failed, "the dense Schur solve failed")?;
        sp.layout.scatter(world, &sp.sol, x);
        Ok(())
    }

    /// The whole solutions of `K_r X = B` whose values on the Schur unknowns
    /// are the `k` columns of `xs` (this rank's part of each, candidate by
    /// candidate), where the columns of B equal the base right-hand side of
    /// the last [`Direct::solve_contact_part`] off the Schur unknowns: the
    /// expansion (ICNTL(26) = 2) from the forward elimination MUMPS kept.
    /// Into `cols` (this rank's rows of each, column-major); `Ok(false)`,
    /// nothing done, unless the last MUMPS solve was that condensation with
    /// `k` columns (the expansion then uses it up).
    pub fn expand<C: Communicator>(
        &mut self,
        world: &C,
        xs: &[f64],
        k: usize,
        cols: &mut [f64],
    ) -> Result<bool, Error> {
        self.usable()?;
        if k == 0 || self.reduced != k {
            return Ok(false);
        }
        self.reduced = 0;
        let _e = self.ev_solve.begin();
        let host = world.rank() == 0;
        let sp = self.schur.as_mut().expect("condensed");
        let part = xs.len() / k;
        let m = sp.m;
        for j in 0..k {
            sp.layout
                .gather_into(world, &xs[j * part..(j + 1) * part], &mut sp.rhs);
            if host {
                self.mumps.redrhs_mut()[j * m..(j + 1) * m].copy_from_slice(&sp.rhs);
            }
        }
        self.mumps_expand(world, cols, k)?;
        Ok(true)
    }

    /// `x = S_r^{-1} c` on the contact unknowns (this rank's part of each),
    /// with S at the current r.
    pub fn solve_schur<C: Communicator>(
        &mut self,
        world: &C,
        c: &[f64],
        x: &mut [f64],
    ) -> Result<(), Error> {
        self.usable()?;
        let _e = self.ev_schur.begin();
        let sp = self.schur.as_mut().expect("condensed");
        if let Some(g) = sp.grid.as_mut() {
            return g.solve(world, &sp.layout, c, x, true);
        }
        sp.layout.gather_into(world, c, &mut sp.rhs);
        let failed = world.rank() == 0 && {
            let s = if sp.shifted_on {
                sp.shifted.as_ref()
            } else {
                sp.s.as_ref()
            }
            .expect("the host has S");
            s.solve(&sp.rhs, &mut sp.sol).is_err()
        };
        host_failed(world, failed, "the dense Schur solve failed")?;
        sp.layout.scatter(world, &sp.sol, x);
        Ok(())
    }

    /// `S_a y` for this rank's part `y` of a contact vector, gathered and
    /// scattered back (S at the assembled r).
    pub fn apply_schur<C: Communicator>(&self, world: &C, y: &[f64], out: &mut [f64]) {
        let sp = self.schur.as_ref().expect("condensed");
        if let Some(g) = &sp.grid {
            g.apply(world, &sp.layout, self.mumps.schur_local(), y, out);
            return;
        }
        let all = sp.layout.gather(world, y);
        let mut prod = Vec::new();
        if world.rank() == 0 {
            prod = vec![0.0; sp.m];
            sym_upper_mv(sp.m, host_schur(&self.mumps), &all, &mut prod);
        }
        sp.layout.scatter(world, &prod, out);
    }

    /// S at `S_a + delta M`, M the contact blocks `blocks` (this rank's
    /// candidates, `d x d` each (d: the Schur components per candidate),
    /// row-major; Dirichlet rows and columns zero).
    pub fn shift_schur<C: Communicator>(
        &mut self,
        world: &C,
        delta: f64,
        blocks: &[f64],
        d: usize,
    ) -> Result<(), Error> {
        self.usable()?;
        let sp = self.schur.as_mut().expect("condensed");
        let layout = Layout::new(world, blocks.len());
        if let Some(g) = sp.grid.as_mut() {
            let all = layout.all_gather(world, blocks);
            return g.shift(world, self.mumps.schur_local(), delta, &all, d);
        }
        let all = layout.gather(world, blocks);
        let mut status = 0.0f64;
        if world.rank() == 0 {
            let m = sp.m;
            // Into the array of the previous shifted factor, if any: a copy
            // of S_a, the blocks added to its upper triangle, factorized.
            let mut f = sp.shifted.take().unwrap_or_default();
            let ok = f
                .refactor_with(m, host_schur(&self.mumps), |s| {
                    for (i, b) in all.chunks(d * d).enumerate() {
                        for a in 0..d {
                            for c in a..d {
                                let (row, col) = (i * d + a, i * d + c);
                                s[col * m + row] += delta * b[a * d + c];
                            }
                        }
                    }
                })
                .is_ok();
            sp.shifted = Some(f);
            sp.shifted_on = ok;
            if !ok {
                status = 1.0;
            }
        }
        host_failed(
            world,
            status != 0.0,
            "the factorization of the shifted Schur complement failed",
        )?;
        Ok(())
    }

    /// Refactorizes after the values of `a` changed (same pattern; the
    /// entries left out of MUMPS' input still zero).
    pub fn refactorize<C: Communicator>(&mut self, world: &C, a: &Matrix) -> Result<(), Error> {
        let vals = self.mumps.values_mut();
        let (mut k, mut j, mut lost) = (0, 0, false);
        let kept = &self.kept;
        a.for_each_owned_row(|row, cols, v| {
            for (&c, &x) in cols.iter().zip(v) {
                if c as usize <= row {
                    if kept[k] {
                        vals[j] = x;
                        j += 1;
                    } else if x != 0.0 {
                        lost = true;
                    }
                    k += 1;
                }
            }
        })?;
        // Collective: every rank returns, none waits in MUMPS.
        let [lost] = allreduce_sum(world, [if lost { 1.0 } else { 0.0 }]);
        if lost > 0.0 {
            return Err(Error::Internal(
                "an entry left out of MUMPS' input is no longer zero".into(),
            ));
        }
        self.usable()?;
        self.reduced = 0;
        let factorized = {
            let _e = self.ev_factor.begin();
            self.mumps.factorize()
        };
        self.factorizations += 1;
        let verdict = factorized.and_then(|()| match self.schur.as_mut() {
            Some(sp) => {
                if let Some(g) = sp.grid.as_mut() {
                    return g.refactor(world, self.mumps.schur_local());
                }
                // The old factor goes first (the host holds one S at a time).
                sp.s = None;
                let (s, failed) = schur_factor(world, host_schur(&self.mumps), sp.m);
                (sp.s, sp.shifted_on) = (s, false);
                host_verdict(world, failed)
            }
            None => Ok(()),
        });
        if let Err(e) = verdict {
            // No factorization to solve with any more.
            if matches!(e, Error::LinearSolver(_) | Error::OutOfMemory(_)) {
                self.schur = None;
                self.failure = Some(e.clone());
            }
            return Err(e);
        }
        Ok(())
    }
}
