//! `-report FILE.json`: one schema, a `#[derive(Serialize)]` struct written
//! by serde_json (and read back by the tests). Keys are docs/DESIGN.md's; a
//! number that is not finite is `null`, and so is an error without a
//! reference.

use super::Results;
use crate::solver::penalty;
use crate::solver::stopping::StopRule;
use serde::Serialize;
use std::collections::BTreeMap;

#[derive(Serialize)]
pub struct Report {
    pub dimension: usize,
    pub nodes: usize,
    pub elements: usize,
    pub contact_nodes: usize,
    pub contact_active: usize,
    /// How the gaps and normals were found: "fixed" or "closest".
    pub contact_normal: &'static str,
    pub stick_nodes: usize,
    pub slip_nodes: usize,
    pub ranks: usize,
    /// How the mesh was split over the ranks: "metis", "rcb" or "ptscotch" ("none" on one rank).
    pub partition: &'static str,
    pub algorithm: String,
    pub paper_algorithm: &'static str,
    pub friction: &'static str,
    pub friction_coefficient: f64,
    pub mesh: String,
    pub linear_solver: String,
    #[serde(rename = "E")]
    pub young: f64,
    pub nu: f64,
    pub r: f64,
    pub rho: f64,
    pub r_source: &'static str,
    pub r_trial: Option<f64>,
    pub r_estimate: Option<f64>,
    pub r_estimate_solves: usize,
    pub time_r_choice: f64,
    pub stop: &'static str,
    pub lambda_rtol: f64,
    pub lambda_error_estimate: Option<f64>,
    pub linear_solves: usize,
    pub anderson_memory: usize,
    pub condensed_unknowns: usize,
    pub rtol: f64,
    pub residual_tol: f64,
    pub iterations: usize,
    pub fixed_point_iterations: usize,
    pub frictionless_iterations: usize,
    pub converged: bool,
    /// The message the run ended with when it failed (null when it converged).
    pub failure: Option<String>,
    pub criterion: f64,
    pub constraint_residual: f64,
    pub dual_residual: f64,
    pub fixed_point_change: Option<f64>,
    /// `sum w lambda_n`, and `sum w lambda_t` (global components).
    pub contact_force: f64,
    pub tangential_force: Vec<f64>,
    /// `sum w lambda_n` over each group of `-contact_surface` (one entry per
    /// group; a node where two groups meet counts in the first named).
    pub contact_force_groups: BTreeMap<String, f64>,
    /// The force the obstacle exerts on the body, `-sum w (lambda_n n + lambda_t)`.
    pub contact_force_vector: Vec<f64>,
    /// Each obstacle (`-obstacles`; one named "obstacle" without): its
    /// force on the body and its nodes in contact.
    pub obstacles: Vec<ObstacleForce>,
    /// The applied loads (tractions, pressures, body force), summed.
    pub load: Vec<f64>,
    /// The reaction force of each Dirichlet group.
    pub reactions: BTreeMap<String, Vec<f64>>,
    pub time_mesh: f64,
    pub time_partition: f64,
    pub time_assembly: f64,
    pub time_factorization: f64,
    pub time_iterations: f64,
    pub time_total: f64,
    pub pressure_error_l2: Option<f64>,
    pub pressure_error_rel: Option<f64>,
    pub peak_pressure_hertz: Option<f64>,
    pub contact_half_width_hertz: Option<f64>,
    /// Hertz's E* and R (with `-reference hertz`).
    pub hertz_e_star: Option<f64>,
    pub hertz_radius: Option<f64>,
    pub peak_pressure: f64,
    /// The contact half-width in 2D, its radius in 3D (with `-reference hertz`).
    pub contact_half_width: Option<f64>,
    pub equilibrium_residual: f64,
    pub equilibrium_residual_rel: f64,
    pub equilibrium_scale: f64,
    pub min_lambda_n: f64,
    /// min lambda_n relative to max(max |lambda_n|, largest load or
    /// reaction / contact area) (0 when nonnegative).
    pub min_lambda_n_rel: f64,
    pub max_penetration: f64,
    /// max (u_n - g)^+ relative to the largest displacement or initial penetration.
    pub max_penetration_rel: f64,
    pub max_abs_gap: f64,
    pub complementarity: f64,
    /// |complementarity| relative to max(sum w |lambda_n|, largest load or
    /// reaction) x the largest displacement or initial penetration.
    pub complementarity_rel: f64,
    /// Friction checks, at the nodes in contact.
    pub max_friction_excess: f64,
    pub max_friction_excess_rel: f64,
    pub max_bound: f64,
    pub max_slip: f64,
    pub max_stick_slip: f64,
    pub max_stick_slip_rel: f64,
    pub min_slip_alignment: f64,
    /// The largest principal strain, and the cells inverted in x + u.
    pub max_strain: f64,
    pub inverted_elements: usize,
    pub matrix_mallocs: f64,
    pub peak_memory_rank0_mb: f64,
    pub peak_memory_max_mb: f64,
    pub peak_memory_total_mb: f64,
    pub inner_iterations: Vec<usize>,
    /// The warnings of the run (also on stderr), one line each.
    pub warnings: Vec<String>,
}

/// One obstacle's share of the contact force (the report's `obstacles`).
#[derive(Serialize)]
pub struct ObstacleForce {
    pub name: String,
    pub force: Vec<f64>,
    pub contact_nodes: usize,
}

impl Report {
    pub fn new(m: &Results) -> Report {
        let (s, p, res, d) = (m.settings, m.problem, m.solved, m.diag);
        let auto = m.choice.filter(|c| c.source == penalty::Source::Auto);
        Report {
            dimension: m.local.dim,
            nodes: m.local.global_nodes,
            elements: m.local.global_cells,
            contact_nodes: m.candidates,
            contact_active: m.totals.in_contact,
            contact_normal: s.contact.as_ref().map_or("fixed", |c| c.normal.as_str()),
            stick_nodes: m.totals.stick,
            slip_nodes: m.totals.slip,
            ranks: m.ranks,
            partition: s.partition.name(m.ranks),
            algorithm: s.algorithm.to_string(),
            paper_algorithm: res.name.as_str(),
            friction: s.friction.name(),
            friction_coefficient: s.friction_coefficient,
            mesh: super::mesh_label(&s.mesh),
            linear_solver: p.lin.description.clone(),
            young: s.young,
            nu: s.nu,
            r: if res.is_comparator() { s.ssn_r } else { p.r() },
            rho: s.ubr.rho.unwrap_or(p.r()),
            r_source: if auto.is_some() { "auto" } else { "option" },
            r_trial: auto.map(|c| c.r0),
            r_estimate: m.choice.map(|c| c.estimate).filter(|x| x.is_finite()),
            r_estimate_solves: m.choice.map_or(0, |c| c.steps),
            time_r_choice: m.times.r_choice,
            stop: if s.ubr.stop == StopRule::Paper {
                "paper"
            } else {
                "accuracy"
            },
            lambda_rtol: s.ubr.lambda_rtol,
            lambda_error_estimate: res.error_estimate,
            linear_solves: p.lin.solves,
            anderson_memory: s.ubr.anderson,
            condensed_unknowns: p.lin.condensed_unknowns(),
            rtol: s.ubr.rtol,
            residual_tol: s.ubr.residual_tol,
            iterations: res.iterations,
            fixed_point_iterations: res.fixed_point_iterations,
            frictionless_iterations: res.frictionless_iterations,
            converged: res.converged,
            failure: m.failure.clone(),
            criterion: res.last.criterion,
            constraint_residual: res.last.residual,
            dual_residual: res.last.dual,
            fixed_point_change: res.fp_change,
            contact_force: m.totals.force,
            tangential_force: m.totals.tangential_force.clone(),
            contact_force_groups: m.group_forces().into_iter().collect(),
            contact_force_vector: m.forces.contact.clone(),
            obstacles: m
                .forces
                .obstacles
                .iter()
                .map(|(name, force, n)| ObstacleForce {
                    name: name.clone(),
                    force: force.clone(),
                    contact_nodes: *n,
                })
                .collect(),
            load: m.forces.load.clone(),
            reactions: m.forces.reactions.iter().cloned().collect(),
            time_mesh: m.times.mesh,
            time_partition: m.times.partition,
            time_assembly: m.times.assembly,
            time_factorization: m.times.factorization,
            time_iterations: m.times.iterations,
            time_total: m.times.total,
            pressure_error_l2: m.hertz.as_ref().map(|h| h.error_l2),
            pressure_error_rel: m.hertz.as_ref().map(|h| h.error_rel),
            peak_pressure_hertz: m.hertz.as_ref().map(|h| h.peak_hertz),
            contact_half_width_hertz: m.hertz.as_ref().map(|h| h.half_width_hertz),
            hertz_e_star: m.hertz.as_ref().map(|h| h.e_star),
            hertz_radius: m.hertz.as_ref().map(|h| h.radius),
            peak_pressure: m.totals.peak_pressure,
            contact_half_width: m.hertz.as_ref().map(|h| h.half_width),
            equilibrium_residual: d.equilibrium_abs,
            equilibrium_residual_rel: d.equilibrium_rel,
            equilibrium_scale: d.load_norm,
            min_lambda_n: d.min_lambda,
            min_lambda_n_rel: d.min_lambda_rel(),
            max_penetration: d.max_penetration,
            max_penetration_rel: d.penetration_rel(),
            max_abs_gap: d.max_abs_gap,
            complementarity: d.complementarity,
            complementarity_rel: d.complementarity_rel(),
            max_friction_excess: d.max_friction_excess,
            max_friction_excess_rel: d.friction_excess_rel(),
            max_bound: d.max_bound,
            max_slip: d.max_slip,
            max_stick_slip: d.max_stick_slip,
            max_stick_slip_rel: d.stick_slip_rel(),
            min_slip_alignment: d.min_slip_alignment,
            max_strain: m.shape.max_strain,
            inverted_elements: m.shape.inverted,
            matrix_mallocs: p.matrix_mallocs,
            peak_memory_rank0_mb: m.memory[0],
            peak_memory_max_mb: m.memory[1],
            peak_memory_total_mb: m.memory[2],
            inner_iterations: m.state.inner_iterations.clone(),
            warnings: m.warnings.to_vec(),
        }
    }

    /// The report as pretty-printed JSON.
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("a report serializes");
        s.push('\n');
        s
    }
}
