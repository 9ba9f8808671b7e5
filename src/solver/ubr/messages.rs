//! Why a UBR run stopped without converging, in words.

use super::{UbrControl, UbrOutcome};
use crate::solver::stopping::{Accuracy, Progress, StopRule, STALL_ITS};

/// Words on an r far from the trial r0.
pub(super) fn r_far_words(r: f64, r0: f64) -> String {
    format!(
        "r = {r:.3e} (-ubr_r) is {:.1e} times the trial r0 = {r0:.3e} from which -ubr_r auto chooses (within a factor of about 30 of it): far outside the range where UBR converges in a reasonable number of iterations; use -ubr_r auto, or an r near r0",
        r / r0
    )
}

/// Whether a failure's message names an r far from the trial r0
/// ([`r_far_words`]).
pub fn names_far_r(message: &str) -> bool {
    message.contains("(-ubr_r) is") && message.contains("times the trial r0")
}

/// What a stalled run's cause depends on besides its numbers.
pub(super) struct StallScene {
    /// Every contact node slipping explains a stall: friction acts and some
    /// rigid motion is free of Dirichlet conditions (the body can slide or
    /// roll).
    pub slides: bool,
    /// The solves are an iterative solver's.
    pub inexact: bool,
    /// Of its last `STALL_ITS` solves, those it ended before their first
    /// iteration (its tolerances met at the start).
    pub idle: usize,
}

impl StallScene {
    /// `inner`: the inner iterations of every solve so far.
    pub(super) fn new(slides: bool, inexact: bool, inner: &[usize]) -> StallScene {
        let recent = &inner[inner.len().saturating_sub(STALL_ITS)..];
        let idle = recent.iter().filter(|&&i| i == 0).count();
        StallScene {
            slides,
            inexact,
            idle,
        }
    }
}

/// The message of a run stopped because it made no progress: what it
/// stalled at, and the likely cause.
pub(super) fn stalled(
    name: &str,
    ctl: &UbrControl,
    out: &UbrOutcome,
    r: f64,
    acc: &Accuracy,
    progress: &Progress,
    scene: StallScene,
) -> String {
    let StallScene {
        slides,
        inexact,
        idle,
    } = scene;
    let its = out.iterations;
    let target = if ctl.stop == StopRule::Paper {
        format!(
            "relative change (4.16) {:.3e} (target -ubr_rtol {:.1e})",
            out.criterion, ctl.rtol
        )
    } else {
        format!(
            "error estimate of lambda {:.3e} (target -ubr_lambda_rtol {:.1e} / 4)",
            acc.estimate, ctl.lambda_rtol
        )
    };
    // The other iteration than the one that stalled.
    let other = if ctl.anderson > 0 {
        "-ubr_anderson 0 (the paper's plain iteration)"
    } else {
        "the default Anderson acceleration (-ubr_anderson 10)"
    };
    let cause = if inexact && 3 * idle >= progress.since {
        // -ksp_atol 100 on the Hertz scene: 0 and 1 inner iterations in
        // turn, and the words blamed the contact set's cycling.
        format!("the iterative solver ended {idle} of the last {} solves before their first iteration: its tolerances (-ksp_atol, -ksp_rtol) are met where they start, so the displacement hardly follows the contact stresses; lower -ksp_atol below the residuals of the model's units, or leave the tolerances to the program", progress.since)
    } else if slides && out.contact > 0 && out.stick == 0 {
        format!(
            "every one of the {} contact nodes slips: the bound s cannot hold the loads, their tangential part or their moment, and the body slides or rolls (with Coulomb friction: friction cannot hold the loads with the pressures this body develops; lower the tangential load or raise -friction_coefficient)",
            out.contact
        )
    } else if let Some(r0) = ctl.r_far {
        r_far_words(r, r0)
    } else if out.contact == 0 {
        format!("no node touches the obstacle at the last iterations although the loads push the body along a motion that only the contact holds: the iterates do not reach a contact state that holds them (no contact reached); check the obstacle's position and the loads, or try {other}")
    } else if progress.changes >= progress.since / 10 {
        format!(
            "contact statuses changed {} times in those iterations: the contact set cycles between states, as when the contact zone is a few nodes or a point smaller than a cell; refine the mesh where the body touches, or loosen -ubr_lambda_rtol",
            progress.changes
        )
    } else if inexact {
        format!(
            "{} nodes touch the obstacle and the contact set has settled, yet the residual stays flat: the iterative solver's solves (their tolerance and round-off) set a floor above the target; loosen -ubr_lambda_rtol, or use the direct solver (the default: MUMPS, condensed on the contact unknowns)",
            out.contact
        )
    } else {
        format!(
            "{} nodes touch the obstacle and the contact set has settled, yet the residual stays flat at r = {r:.3e}; try {other} or another r",
            out.contact
        )
    };
    format!(
        "{name} stalled: its best residual has not fallen by 3% in the last {} iterations (best {:.3e}), stopped after {its} of -ubr_max_it {}; {target}; {cause}",
        progress.since, progress.best, ctl.max_it
    )
}

/// The message of a run of the accuracy test stopped at round-off: the
/// target is below what double precision resolves on this problem.
pub(super) fn roundoff(
    name: &str,
    ctl: &UbrControl,
    out: &UbrOutcome,
    acc: &Accuracy,
    progress: &Progress,
) -> String {
    format!(
        "{name} reached round-off: its residual has stayed at {:.3e} (below 1e-12, where double precision ends) for the last {} iterations, stopped after {}; error estimate of lambda {:.3e} (residual x amplification {:.3e}, the smallest of the run {:.3e}) against the target -ubr_lambda_rtol {:.1e} / 4, which is below what double precision resolves on this problem; ask for a looser -ubr_lambda_rtol",
        progress.best, progress.since, out.iterations, out.error_estimate, out.k, acc.smallest, ctl.lambda_rtol
    )
}

/// The message of a run stopped by the iteration cap: the failing test,
/// its value and target, and what to try.
pub(super) fn failure(
    name: &str,
    ctl: &UbrControl,
    out: &UbrOutcome,
    r: f64,
    acc: &Accuracy,
) -> String {
    let its = out.iterations;
    if its == 0 {
        return format!(
            "{name} ran no iteration (-ubr_max_it {}): the answer is its start (no contact stress); give -ubr_max_it at least 1 (default 10000)",
            ctl.max_it
        );
    }
    if ctl.stop == StopRule::Paper {
        return format!(
            "{name} stopped after {its} iterations (-ubr_max_it): relative change (4.16) {:.3e} (target -ubr_rtol {:.1e}), constraint residual {:.3e} (target -ubr_residual_tol {:.1e}); try more iterations, -ubr_anderson 10, or the default stopping test (-ubr_stop accuracy)",
            out.criterion, ctl.rtol, out.residual, ctl.residual_tol
        );
    }
    if acc.statuses_unsettled() {
        return format!(
            "{name} stopped after {its} iterations (-ubr_max_it): the error estimate {:.3e} meets its target ({:.1e}) but contact statuses still change every iteration (a node switching between open and contact, or stick and slip); try -ubr_max_it larger or a finer mesh near the edge of the contact zone",
            out.error_estimate,
            0.25 * ctl.lambda_rtol
        );
    }
    format!(
        "{name} stopped after {its} iterations (-ubr_max_it): the error estimate of lambda is {:.3e} (residual {:.3e} x amplification {:.3e}), the target -ubr_lambda_rtol {:.1e} / 4; r = {r:.6e}; try -ubr_max_it larger, a looser -ubr_lambda_rtol, or another r (-ubr_r auto chooses it){}",
        out.error_estimate,
        out.p,
        out.k,
        ctl.lambda_rtol,
        if ctl.anderson == 0 {
            "; the default Anderson acceleration (-ubr_anderson 10) takes far fewer iterations"
        } else {
            ""
        }
    )
}
