//! Near-null spaces of matrices (`MatNullSpace`).

use super::{check, ensure_running, running, sys, Vector};
use crate::error::Error;

/// A (near-)null space, e.g. the rigid-body modes built from coordinates.
///
/// Invariant: `raw` is a live MatNullSpace of which this value owns one
/// reference.
pub struct NullSpace {
    pub(super) raw: sys::MatNullSpace,
}

impl Drop for NullSpace {
    fn drop(&mut self) {
        if running() {
            // SAFETY: our reference to a live null space (the invariant),
            // given up once, while PETSc runs.
            unsafe { sys::MatNullSpaceDestroy(&mut self.raw) };
        }
    }
}

impl NullSpace {
    /// Rigid-body modes from a coordinate vector whose block size is the dimension.
    pub fn rigid_body(coords: &Vector) -> Result<NullSpace, Error> {
        ensure_running()?;
        let mut raw: sys::MatNullSpace = std::ptr::null_mut();
        // SAFETY: `coords` is live; PETSc writes a new null space into `raw`.
        check(unsafe { sys::MatNullSpaceCreateRigidBody(coords.raw, &mut raw) })?;
        Ok(NullSpace { raw })
    }
}
