//! `-reference hertz` and its options: the force, the radius (or two
//! bodies' radii), the centre and a cylinder's axis (a line contact in
//! 3D); their sizes checked against the mesh once it is read.

use super::declared::*;
use super::numbers::joined;
use super::{shown, HertzReference, Settings};
use crate::error::{bad, Error};

pub(super) fn reference() -> Result<Option<HertzReference>, Error> {
    if REFERENCE.word_or_required()?.is_none() {
        return Ok(None);
    }
    let Some(force) = REFERENCE_FORCE.real()? else {
        return bad("option -reference_force is required with -reference hertz");
    };
    let Some(radii) = REFERENCE_RADIUS.vector()? else {
        return bad("option -reference_radius is required with -reference hertz");
    };
    if radii.len() > 2 {
        return bad(format!(
            "option -reference_radius: {} values given; it takes R (a body on a plane, or the two surfaces' effective radius) or R1,R2 (two curved surfaces: 1/R = 1/R1 + 1/R2, a concave one negative)",
            radii.len()
        ));
    }
    if force <= 0.0 {
        return bad("option -reference_force must be positive");
    }
    // Two surfaces' curvatures add, a concave one's negative (Johnson,
    // Contact Mechanics, 4.2: a pin in a hole, a ball in a socket).
    let curvature: f64 = radii.iter().map(|r| 1.0 / r).sum();
    if radii.len() == 1 && radii[0] <= 0.0 {
        return bad("option -reference_radius must be positive (two values R1,R2 for a convex and a concave surface, the concave one negative)");
    }
    if radii.iter().any(|&r| r == 0.0 || !r.is_finite()) || curvature <= 0.0 {
        return bad(format!(
            "option -reference_radius {}: the surfaces do not curve toward each other (1/R1 + 1/R2 = {} is not positive); a concave surface's radius is negative and must be larger in size than the convex one's",
            joined(&radii),
            shown(curvature)
        ));
    }
    let radius = 1.0 / curvature;
    let axis = match REFERENCE_AXIS.vector()? {
        None => None,
        Some(a) if a.len() != 3 => {
            return bad(format!(
                "option -reference_axis: {} components given; it is the axis of a cylinder lying on its side in 3D (x,y,z)",
                a.len()
            ))
        }
        Some(a) => {
            let norm = a.iter().map(|v| v * v).sum::<f64>().sqrt();
            if !(norm > 0.0 && norm.is_finite()) {
                return bad("option -reference_axis: the zero vector has no direction");
            }
            Some(a.iter().map(|v| v / norm).collect())
        }
    };
    Ok(Some(HertzReference {
        force,
        radius,
        center: REFERENCE_CENTER.vector()?,
        axis,
    }))
}

impl Settings {
    /// The reference's options that the mesh's dimension sizes:
    /// `-reference_center` (one component per dimension) and
    /// `-reference_axis` (3D, across `-contact_direction`). The same on
    /// every rank.
    pub fn check_reference(&self, dim: usize) -> Result<(), Error> {
        if let Some(c) = self.contact_center.as_ref().filter(|c| c.len() != dim) {
            return bad(format!(
                "option -reference_center: {} components given, the mesh is {dim}D",
                c.len()
            ));
        }
        let Some(axis) = self.reference.as_ref().and_then(|r| r.axis.as_ref()) else {
            return Ok(());
        };
        if dim != 3 {
            return bad("option -reference_axis: the mesh is 2D, where Hertz's formula is the cylinder's already (-reference_force per unit thickness); the axis is for a cylinder on its side in 3D");
        }
        let reference = self.reference.as_ref().expect("an axis is a reference's");
        let direction = self.contact.as_ref().map(|c| &c.direction);
        if let Some(n) = direction.filter(|n| n.len() == 3) {
            if reference.line(n).is_none() {
                return bad(format!(
                    "option -reference_axis {}: it lies within 25 degrees of -contact_direction {}; the axis of a cylinder on its side runs across the contact direction",
                    joined(axis),
                    joined(n)
                ));
            }
        }
        Ok(())
    }
}
