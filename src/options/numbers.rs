//! The numbers of the options: a user's value in a message, positive
//! values and unit vectors.

use crate::error::{bad, Error};

/// A contact direction within this distance of unit length is normalised;
/// others are refused.
pub(super) const UNIT_TOLERANCE: f64 = 1e-3;

/// A number of the user's in a message, as typed: plain digits from 1e-4
/// to 1e15, an exponent beyond (Rust's plain digits of -1e-300 ran to
/// 300 characters).
pub(crate) fn shown(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&x.abs()) {
        x.to_string()
    } else {
        format!("{x:e}")
    }
}

/// "a,b,c" as a user types it.
fn joined(v: &[f64]) -> String {
    v.iter().map(|&x| shown(x)).collect::<Vec<_>>().join(",")
}

pub(super) fn positive(name: &str, v: f64) -> Result<f64, Error> {
    if v <= 0.0 {
        return bad(format!("option {name}: {} is not positive", shown(v)));
    }
    Ok(v)
}

/// `v` as a unit vector: normalised, silently within 1e-6 of unit length
/// (the digits of a typed unit vector), with a note up to
/// [`UNIT_TOLERANCE`], else bad input. Always normalised: a normal off unit
/// length by the 5e-13 of twelve typed digits left a normal part of that
/// size in every tangential displacement, a floor of 1.5e-12 under the
/// accuracy test's residual (incline2d_coulomb: not converged at
/// -ubr_lambda_rtol 1e-10).
pub(super) fn unit(
    name: &str,
    mut v: Vec<f64>,
    notes: &mut Vec<String>,
) -> Result<Vec<f64>, Error> {
    // Scaled, so that tiny components do not square to zero.
    let big = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let norm = if big > 0.0 && big.is_finite() {
        big * v.iter().map(|x| (x / big) * (x / big)).sum::<f64>().sqrt()
    } else {
        big
    };
    if (norm - 1.0).abs() > UNIT_TOLERANCE {
        return bad(format!(
            "option {name}: ({}) is not a unit vector (norm {})",
            joined(&v),
            shown(norm)
        ));
    }
    let given = joined(&v);
    v.iter_mut().for_each(|x| *x /= norm);
    if (norm - 1.0).abs() > 1e-6 {
        notes.push(format!(
            "note: {name} {given} (norm {}) normalised to ({})",
            shown(norm),
            v.iter()
                .map(|x| format!("{x:.12}"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    Ok(v)
}
