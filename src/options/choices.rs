//! The typed values that options parse to, for the floors above (the
//! obstacle of [`crate::contact::obstacle`], the stopping test of
//! [`crate::solver::stopping`]).

/// The rigid obstacle (`-obstacle`).
#[derive(Clone, Debug, PartialEq)]
pub enum Obstacle {
    Plane {
        point: Vec<f64>,
    },
    Ball {
        center: Vec<f64>,
        radius: f64,
    },
    /// The paper's 3D obstacle (section 7.2): the half of the ball facing the
    /// body, standing on its flat face on a rigid floor, the plane through the
    /// centre orthogonal to n. Every node of the contact surface is a
    /// candidate (the paper's Gamma_c is the whole surface).
    HalfBall {
        center: Vec<f64>,
        radius: f64,
    },
}

/// Which stopping test (`-ubr_stop`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StopRule {
    /// The error estimate of lambda below `-ubr_lambda_rtol`.
    Accuracy,
    /// The paper's (4.16)/(5.6), with `-ubr_rtol` and `-ubr_residual_tol`.
    Paper,
}
