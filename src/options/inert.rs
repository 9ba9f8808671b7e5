//! Options that have no effect in this scene: given, read or not, but
//! ignored by what the scene runs (`-friction_coefficient` on a
//! frictionless contact, the UBR settings under a comparator, a tolerance
//! of the other stopping test, ...). Each is named once on stderr, when the
//! options are read, with what it would need:
//! `warning: option -friction_coefficient has no effect: the contact is frictionless (-friction none); friction needs -friction tresca or coulomb`.
//! The exit status is unchanged. (An option nothing reads at all, a typo
//! included, is named by [`super::unused`].)

use super::declared::*;
use super::{Algorithm, Friction, Settings, StopRule, TrescaBound};

/// (option, why it has no effect) for every option that `given` says the
/// user gave and that has none in the scene of `s`, each once.
/// `solver_read`: the options PETSc's linear solver reads (KSP, PC);
/// `ranks`: the run's rank count.
pub fn inert(
    s: &Settings,
    solver_read: &[String],
    ranks: usize,
    given: &mut dyn FnMut(&str) -> bool,
) -> Vec<(String, String)> {
    let mut r = Rules {
        out: Vec::new(),
        given,
    };
    algorithm_rules(&mut r, s);
    friction_rules(&mut r, s);
    ubr_rules(&mut r, s, solver_read);
    if s.algorithm == Algorithm::Ubr && s.linear.mumps_direct() {
        layout_rules(&mut r, s, ranks);
    }
    scene_rules(&mut r, s);
    r.out
}

/// The options found so far, and whether the user gave an option.
struct Rules<'g> {
    out: Vec<(String, String)>,
    given: &'g mut dyn FnMut(&str) -> bool,
}

impl Rules<'_> {
    /// Each of `names` the user gave has no effect, for `why` (once).
    fn rule(&mut self, names: &[&str], why: &str) {
        for &n in names {
            if !self.out.iter().any(|(o, _)| o == n) && (self.given)(n) {
                self.out.push((n.to_string(), why.to_string()));
            }
        }
    }
}

/// The options of the other algorithms.
fn algorithm_rules(r: &mut Rules, s: &Settings) {
    let algorithm = s.algorithm;
    // The comparators run none of the UBR settings (SSN-C prints its
    // iterations with -ubr_monitor).
    if algorithm != Algorithm::Ubr {
        let ubr: Vec<&'static str> = ALL
            .iter()
            .map(|o| o.name())
            .filter(|n| n.starts_with("-ubr_"))
            .filter(|n| !(algorithm == Algorithm::Ssn && *n == UBR_MONITOR.name))
            .collect();
        r.rule(
            &ubr,
            &format!("-contact_algorithm {algorithm} runs no UBR iteration (the -ubr_* options are UBR's)"),
        );
    }
    if algorithm != Algorithm::Ssn {
        r.rule(
            &[SSN_R.name, SSN_MAX_IT.name],
            &format!(
                "it is SSN-C's (-contact_algorithm ssn), and -contact_algorithm is {algorithm}"
            ),
        );
    }
    if algorithm == Algorithm::Ubr {
        r.rule(
            &[SSN_INITIAL_SHIFT.name],
            "it is the comparators' initial guess (-contact_algorithm ssn or snesvi), and -contact_algorithm is ubr",
        );
    }
}

/// The options of friction that the scene's friction law does not use.
fn friction_rules(r: &mut Rules, s: &Settings) {
    // Friction.
    match s.friction {
        Friction::None => {
            r.rule(
                &[FRICTION_COEFFICIENT.name, TRESCA_BOUND.name],
                "the contact is frictionless (-friction none); friction needs -friction tresca or coulomb",
            );
            r.rule(
                &[UBR_FP_RTOL.name, UBR_FP_MAX_IT.name, UBR_FP_ANDERSON.name],
                "it is a setting of CF-FP's fixed point, which runs with -friction coulomb only; the contact is frictionless",
            );
        }
        Friction::Tresca => {
            if let Some(TrescaBound::Value(v)) = s.tresca_bound {
                r.rule(
                    &[FRICTION_COEFFICIENT.name],
                    &format!("-tresca_bound {v} gives the Tresca bound itself (nu_f scales the bounds hertz and frictionless only)"),
                );
            }
            r.rule(
                &[UBR_FP_RTOL.name, UBR_FP_MAX_IT.name, UBR_FP_ANDERSON.name],
                "it is a setting of CF-FP's fixed point, which runs with -friction coulomb only, and -friction is tresca",
            );
        }
        Friction::Coulomb => {}
    }
}

/// UBR's: the two stopping tests take different tolerances; the linear
/// solver's.
fn ubr_rules(r: &mut Rules, s: &Settings, solver_read: &[String]) {
    let algorithm = s.algorithm;
    // The two stopping tests take different tolerances.
    if algorithm == Algorithm::Ubr {
        match s.ubr.stop {
            StopRule::Accuracy => r.rule(
                &[
                    UBR_RTOL.name,
                    UBR_RESIDUAL_TOL.name,
                    UBR_DUAL_RTOL.name,
                    UBR_FP_RTOL.name,
                ],
                "it is a tolerance of the paper's stopping test (-ubr_stop paper), and -ubr_stop is accuracy (the default: -ubr_lambda_rtol sets its tolerance)",
            ),
            StopRule::Paper => r.rule(
                &[UBR_LAMBDA_RTOL.name],
                "it is the tolerance of the accuracy stopping test (-ubr_stop accuracy), and -ubr_stop is paper (-ubr_rtol and -ubr_residual_tol set its tolerances)",
            ),
        }
        // The linear solver.
        if s.linear.mumps_direct() {
            // The program drives MUMPS itself: no PETSc solver is made.
            let petsc: Vec<&str> = solver_read
                .iter()
                .map(String::as_str)
                .filter(|n| !["-ksp_type", "-pc_type", "-pc_factor_mat_solver_type"].contains(n))
                .collect();
            r.rule(
                &petsc,
                "it is an option of PETSc's linear solvers, and the solver here is MUMPS driven by ubr-petsc (the default), which reads -mat_mumps_icntl_N and -mat_mumps_cntl_N only (-ubr_mumps_direct 0 goes through PETSc's solver)",
            );
        }
        if !s.linear.default_direct() {
            r.rule(
                &[
                    UBR_MUMPS_DIRECT.name,
                    UBR_CONDENSE_MAX.name,
                    UBR_SCHUR_DISTRIBUTED.name,
                    UBR_MUMPS_RHS.name,
                    UBR_MUMPS_SPLIT.name,
                ],
                "it applies to the default direct solver (a MUMPS factorization, -ksp_type preonly), and the PETSc options choose another",
            );
        } else if !s.ubr.mumps_direct {
            r.rule(
                &[UBR_CONDENSE_MAX.name, UBR_SCHUR_DISTRIBUTED.name],
                "the condensation needs MUMPS driven by the program (-ubr_mumps_direct 1), and -ubr_mumps_direct is 0",
            );
            r.rule(
                &[UBR_MUMPS_RHS.name, UBR_MUMPS_SPLIT.name],
                "it applies to MUMPS driven by the program (-ubr_mumps_direct 1), and -ubr_mumps_direct is 0",
            );
        }
        if !s.linear.iterative() {
            r.rule(
                &[UBR_SBAIJ.name, UBR_INNER_RTOL_FACTOR.name],
                "it applies to iterative solvers (a -ksp_type other than preonly), and the linear solver is a direct one",
            );
        }
    }
}

/// Where the condensed solve's Schur complement lies (MUMPS driven by the
/// program): nowhere without condensation, on the one rank of a one-rank
/// run.
fn layout_rules(r: &mut Rules, s: &Settings, ranks: usize) {
    if s.ubr.condense_max == Some(0) {
        r.rule(
            &[UBR_SCHUR_DISTRIBUTED.name],
            "it places the Schur complement of the condensed solves, and -ubr_condense_max 0 condenses nothing",
        );
    }
    // The program analyses sequentially (ICNTL(28) = 1) unless MUMPS' own
    // parallel analysis is asked for; ICNTL(29) picks its ordering tool.
    let icntl28 = crate::petsc::options::peek("-mat_mumps_icntl_28")
        .ok()
        .flatten();
    if icntl28.as_deref().map(str::trim) != Some("2") {
        r.rule(
            &["-mat_mumps_icntl_29"],
            "it chooses the ordering of MUMPS' parallel analysis, which runs with -mat_mumps_icntl_28 2 only (ubr-petsc orders and analyses otherwise)",
        );
    }
    if ranks == 1 {
        r.rule(
            &[UBR_SCHUR_DISTRIBUTED.name],
            "it chooses where the Schur complement lies on several ranks, and the run has one rank, which holds it",
        );
    }
}

/// The Hertz reference, the contact centre, the mesh.
fn scene_rules(r: &mut Rules, s: &Settings) {
    // The Hertz reference and the contact centre.
    if s.reference.is_none() {
        r.rule(
            &[
                REFERENCE_FORCE.name,
                REFERENCE_RADIUS.name,
                REFERENCE_AXIS.name,
            ],
            "it describes the Hertz reference, and -reference hertz is not given",
        );
        if s.plot_contact.is_none() {
            r.rule(
                &[REFERENCE_CENTER.name],
                "it centres the Hertz comparison (-reference hertz) and -plot_contact, and neither is given",
            );
        }
    }
    // The mesh.
    if matches!(s.mesh, super::MeshSource::File(_)) {
        r.rule(
            &[MESH_H.name],
            "it is the element size of -mesh_generate, and the mesh is read from -mesh",
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::options::LinearBackend;

    #[test]
    fn solver_kinds() {
        let d = LinearBackend::of(None, None, None, true);
        assert!(d.default_direct() && d.mumps_direct() && !d.iterative());
        let p = LinearBackend::of(None, None, None, false);
        assert!(p.default_direct() && !p.mumps_direct());
        let g = LinearBackend::of(Some("gamg"), None, None, true);
        assert!(!g.default_direct() && !g.mumps_direct() && g.iterative());
        let u = LinearBackend::of(Some("lu"), None, Some("superlu_dist"), true);
        assert!(!u.default_direct() && !u.mumps_direct() && !u.iterative());
        let c = LinearBackend::of(Some("cholesky"), Some("cg"), None, true);
        assert!(!c.default_direct() && !c.mumps_direct() && c.iterative());
    }
}
