//! The summary rank 0 prints at the end of a run: the scene, the algorithm
//! and the r it used, the iterations, the contact, the optimality checks
//! (each relative to a named scale), the forces, and the times.

use super::Results;
use crate::solver::outcome::Method;
use crate::solver::penalty;
use crate::solver::stopping::StopRule;
use crate::solver::ubr::UbrOutcome;

/// "(1.5e0, -2.0e-3)": a vector for the summary.
fn vector(v: &[f64]) -> String {
    let parts: Vec<String> = v.iter().map(|x| format!("{x:.6e}")).collect();
    format!("({})", parts.join(", "))
}

/// A computed value to `digits` significant digits: plain from 0.1 to
/// 1e5 (364.12, 2.7169), scientific outside (2.4330e-3, 1.4490e9).
pub fn significant(x: f64, digits: usize) -> String {
    let digits = digits.max(1);
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    // The exponent after rounding (9.99996 to 5 digits is 10.000).
    let e = format!("{:.*e}", digits - 1, x);
    let exp: i32 = e
        .split_once('e')
        .and_then(|(_, e)| e.parse().ok())
        .unwrap_or(0);
    if (-1..5).contains(&exp) {
        let decimals = (digits as i32 - 1 - exp).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        e
    }
}

/// A value the user gave (E, nu, r): as given, in its shortest form, with
/// an exponent when large or small (2000, 0.3, 2.1e11, 1e-6).
pub fn given(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-3..1e5).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

fn verdict(converged: bool) -> &'static str {
    if converged {
        "converged"
    } else {
        "NOT converged"
    }
}

pub fn print(m: &Results) {
    header(m);
    algorithm(m);
    iterations(m);
    contact(m);
    optimality(m);
    forces(m);
    if let Some(h) = &m.hertz {
        println!(
            "  hertz           pressure error L2 {:.4e}, relative {:.3}%",
            h.error_l2,
            100.0 * h.error_rel
        );
        println!(
            "                  peak pressure {} vs Hertz p0 {}; contact {} {} vs Hertz {}",
            significant(h.peak, 5),
            significant(h.peak_hertz, 5),
            if h.line { "half-width" } else { "radius" },
            significant(h.half_width, 5),
            significant(h.half_width_hertz, 5)
        );
        println!(
            "                  Hertz's E* {}, R {}",
            significant(h.e_star, 5),
            significant(h.radius, 5)
        );
    }
    let t = &m.times;
    println!(
        "  time (s)        mesh {:.3}, partition {:.3}, assembly {:.3}, factorization {:.3}, iterations {:.3}, total {:.3}",
        t.mesh, t.partition, t.assembly, t.factorization, t.iterations, t.total
    );
    println!(
        "  memory (MiB)    peak {:.0} on rank 0, {:.0} on the largest rank, {:.0} in all",
        m.memory[0], m.memory[1], m.memory[2]
    );
}

fn header(m: &Results) {
    let s = m.settings;
    let local = m.local;
    println!(
        "ubr-petsc: Algorithm {} ({}), {} rank{}",
        m.solved.name,
        m.friction_name(),
        m.ranks,
        if m.ranks == 1 { "" } else { "s" }
    );
    println!("  mesh            {}", super::mesh_label(&s.mesh));
    println!(
        "                  {} nodes, {} {}, {} contact candidates",
        local.global_nodes, local.global_cells, local.cell_kinds, m.candidates
    );
    if m.ranks > 1 {
        println!(
            "                  split over {} ranks by {}",
            m.ranks,
            s.partition.words()
        );
    }
    println!(
        "  material        E = {}, nu = {}, {}",
        given(s.young),
        given(s.nu),
        if local.dim == 3 {
            "3D"
        } else if s.plane_stress {
            "plane stress"
        } else {
            "plane strain"
        }
    );
    for b in &s.materials.bodies {
        let own = b.over(s.materials.global);
        println!(
            "                  body {}: E = {}, nu = {}{}",
            b.group,
            given(own.young),
            given(own.nu),
            b.density
                .map_or(String::new(), |rho| format!(", density = {}", given(rho)))
        );
    }
    if let Some(line) = friction_line(s) {
        println!("  friction        {line}");
    }
    println!("  linear solver   {}", m.problem.lin.description);
}

/// The friction law and its data: Coulomb's coefficient, or the Tresca
/// bound s (a constant bound given with `-tresca_bound VALUE` has no
/// coefficient: "nu_f = 0" said nothing of it).
fn friction_line(s: &crate::options::Settings) -> Option<String> {
    use crate::options::{Friction, TrescaBound};
    let nu = given(s.friction_coefficient);
    match (s.friction, s.tresca_bound) {
        (Friction::None, _) => None,
        (Friction::Coulomb, _) => Some(format!("Coulomb, nu_f = {nu}")),
        (Friction::Tresca, Some(TrescaBound::Value(v))) => {
            Some(format!("Tresca, bound s = {} at every candidate", given(v)))
        }
        (Friction::Tresca, Some(TrescaBound::Hertz)) => Some(format!(
            "Tresca, bound s = nu_f times Hertz' pressure, nu_f = {nu}"
        )),
        (Friction::Tresca, _) => Some(format!(
            "Tresca, bound s = nu_f times the pressure of a frictionless solve, nu_f = {nu}"
        )),
    }
}

/// Where r came from, for the summary.
fn r_source(choice: Option<&penalty::Choice>) -> String {
    match choice {
        Some(c) if c.source == penalty::Source::Auto => {
            let moved = if c.r == c.r0 {
                "kept: within 3x of the estimate"
            } else if c.refactorized {
                "refactorized"
            } else {
                "moved without refactorization"
            };
            if c.estimate.is_finite() {
                let held = match c.friction_held {
                    true => format!(
                        ", divided by {}: friction alone holds a rigid motion",
                        penalty::FRICTION_HELD
                    ),
                    false => String::new(),
                };
                format!(
                    "auto: spectral estimate {:.4e} from {} Lanczos solves{held}, trial {:.4e} {moved}",
                    c.estimate, c.steps, c.r0
                )
            } else {
                format!(
                    "auto: trial {:.4e} (too few candidates for an estimate)",
                    c.r0
                )
            }
        }
        _ => "option -ubr_r".to_string(),
    }
}

fn algorithm(m: &Results) {
    let (s, res) = (m.settings, m.solved);
    if res.name == Method::SnesVi {
        println!(
            "  iterations      {} Newton iterations of PETSc's vinewtonrsls ({} linear)",
            res.iterations,
            m.state.inner_iterations.iter().sum::<usize>()
        );
    } else if res.name == Method::SsnC {
        let shift: Vec<String> = s.ssn_initial_shift.iter().map(|&v| given(v)).collect();
        println!(
            "  r (SSN-C)       {} (r/E = {}), initial guess ({})",
            given(s.ssn_r),
            significant(s.ssn_r / s.stiffest(m.local.dim).young, 5),
            if shift.is_empty() {
                "0".to_string()
            } else {
                shift.join(",")
            }
        );
        println!(
            "  iterations      {}, {} (one factorization each)",
            res.iterations,
            if res.converged {
                "converged: the active set repeated"
            } else {
                "NOT converged"
            }
        );
    } else {
        let r = m.problem.r();
        // A stalled Tresca solve of a friction-held body went on at a
        // lower r (a warning says so).
        let lowered = match m.choice {
            Some(c) if c.source == penalty::Source::Auto && r < c.r => {
                format!(", lowered to r / {:.0} after a stall", c.r / r)
            }
            _ => String::new(),
        };
        println!(
            "  r               {:.6e} (r/E = {}; {}{lowered})",
            r,
            // E of the stiffest body (the global E with one material).
            significant(r / s.stiffest(m.local.dim).young, 5),
            r_source(m.choice)
        );
        if let Some(rho) = s.ubr.rho {
            println!("  rho             {} (-ubr_rho)", given(rho));
        }
        if s.ubr.anderson > 0 {
            println!(
                "  Anderson        memory {} (safeguarded type II on z = lambda + r B u): {} of {} evaluations extrapolated, {} rejected{}{}",
                s.ubr.anderson,
                res.last.anderson_steps,
                res.last.iterations,
                res.last.anderson_rejected,
                if res.fixed_point_iterations > 0 {
                    " (the last Tresca solve)"
                } else {
                    ""
                },
                retreat_words(&res.last, res.fixed_point_iterations)
            );
        } else {
            println!("  Anderson        off (-ubr_anderson 0: the paper's plain iteration)");
        }
    }
}

/// Anderson's retreats to the plain iteration (and the plain iteration's
/// restarts from the start), for the Anderson line.
fn retreat_words(last: &UbrOutcome, fixed_point_iterations: usize) -> String {
    let then = match last.plain_restarts {
        0 => "",
        _ => ", and where that drifted or stalled too, from the start",
    };
    let best = format!("the plain iteration from the best of them{then}");
    match (last.anderson_retreats, fixed_point_iterations) {
        (0, _) => String::new(),
        (_, 0) => format!("; its iterates drifted or stalled: {best}"),
        (1, _) => format!("; in one Tresca solve the iterates drifted or stalled: {best}"),
        (n, _) => format!("; in {n} Tresca solves the iterates drifted or stalled: {best}"),
    }
}

fn iterations(m: &Results) {
    let (s, res) = (m.settings, m.solved);
    if res.frictionless_iterations > 0 {
        println!(
            "  frictionless    {} UBR iterations for the bound s = nu_f lambda_c",
            res.frictionless_iterations
        );
    }
    if res.fixed_point_iterations > 0 {
        // The target of the change of s is the paper's test; the accuracy
        // test bounds the error of lambda instead (the next line).
        let target = if s.ubr.stop == StopRule::Paper {
            format!(", target {:.1e}", s.ubr.fp_rtol)
        } else {
            String::new()
        };
        println!(
            "  fixed point     {} iterations, {} Tresca iterations in total, {} (relative change of s {:.3e}{target})",
            res.fixed_point_iterations,
            res.iterations,
            verdict(res.converged),
            res.fp_change.unwrap_or(f64::NAN),
        );
    }
    if !res.is_comparator() {
        if s.ubr.stop == StopRule::Paper {
            println!(
                "  iterations      {}, {} (paper's test, last run: rel. change (4.16) {:.3e}, target {:.1e}; residual {:.3e}, target {:.1e})",
                res.iterations, verdict(res.converged), res.last.criterion, s.ubr.rtol, res.last.residual, s.ubr.residual_tol
            );
        } else {
            let estimate = res
                .error_estimate
                .filter(|e| !e.is_nan())
                .map_or("not estimated".to_string(), |e| format!("{e:.3e}"));
            println!(
                "  iterations      {}, {}: estimated error of lambda {estimate} (relative, max norm; target {:.1e}); the paper's (4.16) {:.3e}",
                res.iterations,
                verdict(res.converged),
                s.ubr.lambda_rtol,
                res.last.criterion
            );
        }
        println!(
            "  linear solves   {} (r choice included)",
            m.problem.lin.solves
        );
    }
    if m.problem.lin.iterative {
        println!(
            "  inner its       {} in total",
            m.state.inner_iterations.iter().sum::<usize>()
        );
    }
    if res.unsolved {
        println!("  answer          none: the run stopped with the error below; what follows is the zero start, not a solution");
    }
}

fn contact(m: &Results) {
    let t = &m.totals;
    if m.problem.tangential {
        println!(
            "  contact         {} nodes in contact ({} stick, {} slip), total contact force {:.10e}",
            t.in_contact, t.stick, t.slip, t.force
        );
        println!(
            "                  tangential force {}",
            vector(&t.tangential_force)
        );
    } else {
        println!(
            "  contact         {} nodes in contact, total contact force {:.10e}",
            t.in_contact, t.force
        );
    }
    if m.forces.obstacles.len() > 1 {
        for (name, force, n) in &m.forces.obstacles {
            // (A contact pair is named SLAVE/MASTER.)
            let what = if name.contains('/') {
                "contact pair"
            } else {
                "obstacle"
            };
            println!(
                "                  {what} {name}: force {}, {n} nodes in contact",
                vector(force)
            );
        }
    }
    let groups = m.group_forces();
    if groups.len() > 1 {
        let parts: Vec<String> = groups
            .iter()
            .map(|(name, f)| format!("{name} {f:.6e}"))
            .collect();
        println!(
            "                  contact force by surface: {}",
            parts.join(", ")
        );
    }
}

/// The optimality conditions, each relative to the scale it names.
fn optimality(m: &Results) {
    let d = m.diag;
    println!(
        "  optimality      equilibrium {:.2e} (residual relative to the larger of the load and the contact forces)",
        d.equilibrium_rel
    );
    println!(
        "                  min lambda_n {:.2e} (relative to the pressure scale {:.3e}), max (u_n - g)^+ {:.2e} (relative to the largest displacement or initial penetration {:.3e}), |complementarity| {:.2e} (relative to the force scale {:.3e} x {})",
        d.min_lambda_rel(),
        d.pressure_scale(),
        d.penetration_rel(),
        d.length(),
        d.complementarity_rel(),
        d.force_scale(),
        if d.max_opening > d.length() {
            format!("the largest opening |g - u_n| {:.3e}", d.max_opening)
        } else {
            "that length".to_string()
        }
    );
    if m.problem.tangential {
        let scale = if d.sliding {
            format!("max slip {:.3e}", d.slip_scale())
        } else {
            format!(
                "the largest displacement {:.3e}, as no node slides",
                d.slip_scale()
            )
        };
        println!(
            "  friction law    at the {} nodes in contact: max (|lambda_t| - s)^+ {:.2e} (relative to max s), slip at stick nodes {:.2e} (relative to {scale}), min cos(u_t, lambda_t) at slip nodes {:.12}",
            m.totals.in_contact,
            d.friction_excess_rel(),
            d.stick_slip_rel(),
            d.min_slip_alignment
        );
    }
}

fn forces(m: &Results) {
    let f = m.forces;
    for (name, r) in &f.reactions {
        println!("  reaction        {name}: {}", vector(r));
    }
    let nonzero = |v: &[f64]| v.iter().any(|x| *x != 0.0);
    if !f.reactions.is_empty() || nonzero(&f.load) {
        let scale = f
            .contact
            .iter()
            .chain(&f.load)
            .chain(f.reactions.iter().flat_map(|(_, r)| r))
            // (A pair's force: loads that balance on their own, a body
            // pressed on itself, leave it the scale.)
            .chain(f.obstacles.iter().flat_map(|(_, v, _)| v))
            .fold(0.0f64, |a, b| a.max(b.abs()));
        let imbalance = f.imbalance().iter().fold(0.0f64, |a, b| a.max(b.abs()));
        println!(
            "  forces          load {}, contact {}; balance {:.1e} (relative to the largest force)",
            vector(&f.load),
            vector(&f.contact),
            if scale > 0.0 { imbalance / scale } else { 0.0 }
        );
    }
}
