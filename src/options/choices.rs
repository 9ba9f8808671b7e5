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
    /// A rigid cylinder (`-obstacle cylinder`): a point `center` of its
    /// axis, the unit `axis` (3D; empty in 2D, where it is the disc, the
    /// ball) and its radius.
    Cylinder {
        center: Vec<f64>,
        axis: Vec<f64>,
        radius: f64,
    },
    /// A rigid surface from a file (`-obstacle mesh`): Gmsh line (2D) or
    /// triangle (3D) elements, or STL, closed and outward oriented (a
    /// part read reversed where that puts the body inside the obstacle); a
    /// physical group of it, and the search distance beyond which a node
    /// is no candidate (None: every node of the contact surface).
    Mesh {
        file: String,
        group: Option<String>,
        search: Option<f64>,
    },
}

/// One of several obstacles (`-obstacles`): its name, the obstacle, its
/// fixed contact direction (toward it; empty with closest normals and none
/// given) and how its candidates' gaps and normals are found.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedObstacle {
    pub name: String,
    pub obstacle: Obstacle,
    pub direction: Vec<f64>,
    pub normal: NormalMode,
}

/// How each candidate's gap and normal are found (`-contact_normal`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NormalMode {
    /// The paper's fixed `-contact_direction` for every candidate.
    Fixed,
    /// From each candidate's closest point on the obstacle.
    Closest,
}

impl NormalMode {
    /// The option value, as the report writes it.
    pub fn as_str(self) -> &'static str {
        match self {
            NormalMode::Fixed => "fixed",
            NormalMode::Closest => "closest",
        }
    }
}

/// Which stopping test (`-ubr_stop`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StopRule {
    /// The error estimate of lambda below `-ubr_lambda_rtol`.
    Accuracy,
    /// The paper's (4.16)/(5.6), with `-ubr_rtol` and `-ubr_residual_tol`.
    Paper,
}

/// Which contact algorithm runs (`-contact_algorithm`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Algorithm {
    /// The paper's Uzawa block relaxation (UBR-C, UBR-TF, CF-FP).
    Ubr,
    /// The SSN-C comparator.
    Ssn,
    /// PETSc's SNES VI comparator.
    SnesVi,
}

impl Algorithm {
    /// The option value (`ubr`, `ssn`, `snesvi`); `None` for another word.
    pub fn parse(word: &str) -> Option<Algorithm> {
        match word {
            "ubr" => Some(Algorithm::Ubr),
            "ssn" => Some(Algorithm::Ssn),
            "snesvi" => Some(Algorithm::SnesVi),
            _ => None,
        }
    }

    /// The option value, as the user writes it.
    pub fn as_str(self) -> &'static str {
        match self {
            Algorithm::Ubr => "ubr",
            Algorithm::Ssn => "ssn",
            Algorithm::SnesVi => "snesvi",
        }
    }
}

impl std::fmt::Display for Algorithm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The linear back-end, decided once from `-pc_type`, `-ksp_type`,
/// `-pc_factor_mat_solver_type` and `-ubr_mumps_direct` (PETSc's defaults
/// of [`crate::linalg::linear_solver`] filled in).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LinearBackend {
    /// A factorization (`-pc_type cholesky|lu`, Cholesky when not given)
    /// by `package` (MUMPS by default) under the Krylov method `ksp`
    /// (preonly by default). `mumps_direct`: UBR drives MUMPS itself (the
    /// default: preonly, MUMPS, `-ubr_mumps_direct 1`); the comparators
    /// still go through PETSc's KSP.
    Factorization {
        ksp: String,
        package: String,
        mumps_direct: bool,
    },
    /// Any other preconditioner `pc` under the Krylov method `ksp` (CG by
    /// default).
    Preconditioned { pc: String, ksp: String },
}

impl LinearBackend {
    /// From `-pc_type`, `-ksp_type`, `-pc_factor_mat_solver_type` as given,
    /// and `-ubr_mumps_direct`.
    pub fn of(
        pc: Option<&str>,
        ksp: Option<&str>,
        package: Option<&str>,
        mumps_direct: bool,
    ) -> LinearBackend {
        match pc {
            None | Some("cholesky") | Some("lu") => {
                let ksp = ksp.unwrap_or("preonly").to_string();
                let package = package.unwrap_or("mumps").to_string();
                let mumps_direct = mumps_direct && ksp == "preonly" && package == "mumps";
                LinearBackend::Factorization {
                    ksp,
                    package,
                    mumps_direct,
                }
            }
            Some(pc) => LinearBackend::Preconditioned {
                pc: pc.to_string(),
                ksp: ksp.unwrap_or("cg").to_string(),
            },
        }
    }

    /// The default direct solver (a MUMPS factorization with `-ksp_type
    /// preonly`), which the program may drive itself.
    pub fn default_direct(&self) -> bool {
        matches!(self, LinearBackend::Factorization { ksp, package, .. } if ksp == "preonly" && package == "mumps")
    }

    /// UBR calls MUMPS directly (the default direct solver and
    /// `-ubr_mumps_direct 1`).
    pub fn mumps_direct(&self) -> bool {
        matches!(
            self,
            LinearBackend::Factorization {
                mumps_direct: true,
                ..
            }
        )
    }

    /// A Krylov method (`-ksp_type` other than preonly).
    pub fn iterative(&self) -> bool {
        match self {
            LinearBackend::Factorization { ksp, .. }
            | LinearBackend::Preconditioned { ksp, .. } => ksp != "preonly",
        }
    }
}
