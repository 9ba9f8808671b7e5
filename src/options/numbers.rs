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

/// `x` to nine decimals, without trailing zeros ("0.5", "0", "-0.98").
fn nine_digits(x: f64) -> String {
    let s = format!("{x:.9}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    match s {
        "-0" | "" => "0".to_string(),
        s => s.to_string(),
    }
}

/// "a,b,c" as a user types it.
pub(super) fn joined(v: &[f64]) -> String {
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
        // A direction typed unnormalised, (0.2,0,-1): the unit vector along
        // it to paste (not taken silently: the other number may be a typo).
        let along = if norm > 0.0 && norm.is_finite() {
            let u: Vec<String> = v.iter().map(|x| nine_digits(x / norm)).collect();
            format!("; the unit vector along it is {}", u.join(","))
        } else {
            String::new()
        };
        return bad(format!(
            "option {name}: ({}) is not a unit vector (norm {}){along}",
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_direction_off_unit_length_is_refused_with_the_unit_vector_along_it() {
        let mut notes = Vec::new();
        let e = unit("-contact_direction", vec![0.2, 0.0, -1.0], &mut notes)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("(0.2,0,-1) is not a unit vector")
                && e.contains("the unit vector along it is 0.196116135,0,-0.980580676"),
            "{e}"
        );
        // A zero vector has no direction to offer.
        let e = unit("-contact_direction", vec![0.0, 0.0], &mut notes)
            .unwrap_err()
            .to_string();
        assert!(e.contains("norm 0)") && !e.contains("along it"), "{e}");
        // Within the tolerance: normalised with a note.
        let v = unit("-contact_direction", vec![0.6, -0.8004], &mut notes).unwrap();
        assert!((v[0] - 0.6 / 0.6f64.hypot(0.8004)).abs() < 1e-15 && notes.len() == 1);
    }
}
