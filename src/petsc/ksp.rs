//! PETSc's solvers: the Krylov solver with its preconditioner ([`Ksp`])
//! and the nonlinear solver of the SNES VI comparator ([`Snes`]).

use super::{check, comm_world, ensure_running, running, string_from, sys};
use super::{DenseColumns, Matrix, Vector};
use crate::error::Error;
use std::ffi::{c_char, c_void};

/// A Krylov solver (`KSP`) with its preconditioner.
///
/// Invariant: `raw` is a live KSP of which this value owns one reference.
pub struct Ksp {
    raw: sys::KSP,
}

impl Drop for Ksp {
    fn drop(&mut self) {
        if running() {
            // SAFETY: our reference to a live KSP (the invariant), given up
            // once, while PETSc runs.
            unsafe { sys::KSPDestroy(&mut self.raw) };
        }
    }
}

fn petsc_bool(yes: bool) -> sys::PetscBool {
    if yes {
        sys::PETSC_TRUE
    } else {
        sys::PETSC_FALSE
    }
}

impl Ksp {
    pub fn new(comm: sys::MPI_Comm) -> Result<Ksp, Error> {
        ensure_running()?;
        let mut raw: sys::KSP = std::ptr::null_mut();
        // SAFETY: `comm` is live (the module's contract); PETSc writes a new
        // KSP into `raw`.
        check(unsafe { sys::KSPCreate(comm, &mut raw) })?;
        Ok(Ksp { raw })
    }

    pub fn set_operators(&self, a: &Matrix) -> Result<(), Error> {
        self.set_operators_split(a, a)
    }

    /// The operator `a` (products) and the matrix `p` the preconditioner is
    /// built from.
    pub fn set_operators_split(&self, a: &Matrix, p: &Matrix) -> Result<(), Error> {
        // SAFETY: the three are live; the KSP takes references to both
        // matrices.
        check(unsafe { sys::KSPSetOperators(self.raw, a.raw, p.raw) })
    }

    /// Reads `-ksp_*` and `-pc_*`: the user's choice wins over the defaults
    /// set before this call.
    pub fn set_from_options(&self) -> Result<(), Error> {
        // SAFETY: self.raw is live (the invariant).
        check(unsafe { sys::KSPSetFromOptions(self.raw) })
    }

    pub fn set_up(&self) -> Result<(), Error> {
        // SAFETY: self.raw is live.
        check(unsafe { sys::KSPSetUp(self.raw) })
    }

    pub fn set_initial_guess_nonzero(&self, yes: bool) -> Result<(), Error> {
        // SAFETY: self.raw is live.
        check(unsafe { sys::KSPSetInitialGuessNonzero(self.raw, petsc_bool(yes)) })
    }

    pub fn set_rtol(&self, rtol: f64) -> Result<(), Error> {
        let default = sys::PETSC_DEFAULT as f64;
        // SAFETY: self.raw is live.
        check(unsafe {
            sys::KSPSetTolerances(self.raw, rtol, default, default, sys::PETSC_DEFAULT)
        })
    }

    /// Solves `A x = b`; a solve that PETSc reports as diverged (a failed
    /// factorization, a breakdown, too many iterations) is an error.
    pub fn solve(&self, b: &Vector, x: &Vector) -> Result<usize, Error> {
        // SAFETY: the three are live (PETSc checks the layouts).
        check(unsafe { sys::KSPSolve(self.raw, b.raw, x.raw) })?;
        let mut reason: sys::KSPConvergedReason = 0;
        let mut its: sys::PetscInt = 0;
        // SAFETY: self.raw is live; PETSc writes one enum.
        check(unsafe { sys::KSPGetConvergedReason(self.raw, &mut reason) })?;
        // SAFETY: self.raw is live; PETSc writes one integer.
        check(unsafe { sys::KSPGetIterationNumber(self.raw, &mut its) })?;
        if (reason as i32) < 0 {
            return Err(self.failure(reason, its));
        }
        Ok(its as usize)
    }

    /// The error of a solve that diverged with `reason` after `its`
    /// iterations. (The calls that only name it are not checked: a failure
    /// leaves the number.)
    fn failure(&self, reason: sys::KSPConvergedReason, its: sys::PetscInt) -> Error {
        let mut name: *const c_char = std::ptr::null();
        // SAFETY: self.raw is live; PETSc writes the address of a static C
        // string (or leaves null).
        unsafe { sys::KSPGetConvergedReasonString(self.raw, &mut name) };
        let name = if name.is_null() {
            format!("{reason}")
        } else {
            // SAFETY: one of PETSc's static C strings.
            unsafe { string_from(name) }
        };
        let mut detail = String::new();
        if name.contains("PC_FAILED") {
            let mut pc: sys::PC = std::ptr::null_mut();
            let mut why: sys::PCFailedReason = 0;
            // SAFETY: self.raw is live; PETSc writes its PC (borrowed, not a
            // new reference) into `pc`.
            unsafe { sys::KSPGetPC(self.raw, &mut pc) };
            // SAFETY: the KSP's live PC (PETSc refuses a null one); PETSc
            // writes one enum.
            unsafe { sys::PCGetFailedReasonRank(pc, &mut why) };
            let why = why as i32;
            detail = format!(
                " (preconditioner failure reason {why}: {})",
                pc_failed_reason(why)
            );
            if let Some((said, memory)) = mumps_infog(pc) {
                detail.push_str(&said);
                if memory {
                    return Error::OutOfMemory(format!(
                        "the factorization of the linear solve failed: {name}{detail}"
                    ));
                }
            }
        }
        Error::LinearSolver(format!(
            "linear solve failed after {its} iterations: {name}{detail}"
        ))
    }
}

/// PETSc's `PCFailedReason` in words (its names, e.g. SUBPC_ERROR, say
/// little to a user): a bare "preconditioner failure reason 6" was all a
/// GAMG run with `-mg_levels_pc_type sor` said of the zero pivots its SOR
/// sweeps met on a coarse level.
fn pc_failed_reason(why: i32) -> &'static str {
    match why {
        -1 => "its set-up failed",
        1 => "a structurally zero pivot in a factorization",
        2 => "a zero pivot in a factorization or an SOR sweep",
        3 => "a factorization ran out of memory",
        4 => "a factorization failed",
        5 => "the right-hand side is not consistent with a singular operator",
        6 => "a preconditioner inside it failed, such as a multigrid level's smoother or a block's solver (PETSc's -info names the row of a zero pivot)",
        _ => "a failure this program does not know",
    }
}

/// What MUMPS said (INFOG(1), INFOG(2) and their meaning) when `pc` is a
/// factorization by MUMPS (PETSc's interface, `-ubr_mumps_direct 0`): its
/// own failures otherwise end as a bare "preconditioner failure reason".
/// The calls are not checked: a failure leaves None. The flag: a failure
/// for memory (INFOG(1) = -5, -7, -13, -19: exit 4, as with MUMPS driven by
/// the program).
fn mumps_infog(pc: sys::PC) -> Option<(String, bool)> {
    let mut kind: sys::PCType = std::ptr::null();
    // SAFETY: the KSP's live PC; PETSc writes the address of its type name.
    unsafe { sys::PCGetType(pc, &mut kind) };
    // SAFETY: null or one of PETSc's C strings.
    let kind = unsafe { string_from(kind) };
    if kind != "cholesky" && kind != "lu" {
        return None;
    }
    let mut f: sys::Mat = std::ptr::null_mut();
    // SAFETY: a factorization PC; PETSc writes its factored matrix
    // (borrowed) or leaves null.
    unsafe { sys::PCFactorGetMatrix(pc, &mut f) };
    if f.is_null() {
        return None;
    }
    let mut package: sys::MatSolverType = std::ptr::null();
    // SAFETY: a live factored matrix; PETSc writes its package's name.
    unsafe { sys::MatFactorGetSolverType(f, &mut package) };
    // SAFETY: null or one of PETSc's C strings.
    if unsafe { string_from(package) } != "mumps" {
        return None;
    }
    let (mut code, mut info2): (sys::PetscInt, sys::PetscInt) = (0, 0);
    // SAFETY: a MUMPS factor; PETSc writes one integer each.
    unsafe { sys::MatMumpsGetInfog(f, 1, &mut code) };
    // SAFETY: as above.
    unsafe { sys::MatMumpsGetInfog(f, 2, &mut info2) };
    // PetscInt is i64 in a PETSc built with 64-bit indices.
    #[allow(clippy::unnecessary_cast)]
    let (code, info2) = (code as i32, info2 as i32);
    (code < 0).then(|| {
        let said = format!(
            "; MUMPS: INFOG(1) = {code}, {}",
            crate::mumps::meaning(code, info2)
        );
        (said, matches!(code, -5 | -7 | -13 | -19))
    })
}

impl Ksp {
    /// Keep the preconditioner when the operator's values change (the
    /// algebraic multigrid of `K + r B^T W B` serves another r as well).
    pub fn set_reuse_preconditioner(&self, yes: bool) -> Result<(), Error> {
        // SAFETY: self.raw is live.
        check(unsafe { sys::KSPSetReusePreconditioner(self.raw, petsc_bool(yes)) })
    }

    /// Solves `A X = B` for all columns at once (`KSPMatSolve`; a direct
    /// factorization solves them in one pass over its factors).
    pub fn mat_solve(&self, b: &DenseColumns, x: &DenseColumns) -> Result<(), Error> {
        // SAFETY: the three are live (PETSc checks the sizes).
        check(unsafe { sys::KSPMatSolve(self.raw, b.raw, x.raw) })
    }

    pub fn pc_type(&self) -> Result<String, Error> {
        let mut pc: sys::PC = std::ptr::null_mut();
        let mut t: sys::PCType = std::ptr::null();
        // SAFETY: self.raw is live; PETSc writes its PC (borrowed) into `pc`.
        check(unsafe { sys::KSPGetPC(self.raw, &mut pc) })?;
        // SAFETY: the KSP's live PC; PETSc writes the address of its type's
        // name (a C string it keeps) or null.
        check(unsafe { sys::PCGetType(pc, &mut t) })?;
        // SAFETY: null or a C string of PETSc's, alive with the PC.
        Ok(unsafe { string_from(t) })
    }

    pub fn ksp_type(&self) -> Result<String, Error> {
        let mut t: sys::KSPType = std::ptr::null();
        // SAFETY: self.raw is live; PETSc writes the address of its type's
        // name (a C string it keeps) or null.
        check(unsafe { sys::KSPGetType(self.raw, &mut t) })?;
        // SAFETY: null or a C string of PETSc's, alive with the KSP.
        Ok(unsafe { string_from(t) })
    }
}

/// The data the SNES callbacks of a linear residual `F(x) = A x - b` need:
/// a reference of its own to each, so that they live as long as the SNES.
struct LinearResidual {
    a: Matrix,
    b: Vector,
}

/// `F(x) = A x - b`, SNES's function.
///
/// # Safety
/// `ctx` points to the [`LinearResidual`] of the [`Snes`] that registered
/// it, and `x`, `f` are live vectors laid out like `b`, as PETSc's SNES
/// passes them.
// SAFETY: only PETSc's SNES calls it, as the function registered by
// Snes::new_vi, with the arguments of the contract above.
unsafe extern "C" fn linear_residual(
    _snes: sys::SNES,
    x: sys::Vec,
    f: sys::Vec,
    ctx: *mut c_void,
) -> sys::PetscErrorCode {
    // SAFETY: the boxed context of the Snes being solved, alive while its
    // SNES is (the contract).
    let c = unsafe { &*(ctx as *const LinearResidual) };
    // SAFETY: the context holds its own references to A and b; x and f are
    // live (the contract).
    let e = unsafe { sys::MatMult(c.a.raw, x, f) };
    if e != 0 {
        return e;
    }
    // SAFETY: as above.
    unsafe { sys::VecAXPY(f, -1.0, c.b.raw) }
}

/// SNES's Jacobian: that of a linear residual is its (already assembled)
/// matrix, so there is nothing to do (and nothing is read).
extern "C" fn constant_jacobian(
    _snes: sys::SNES,
    _x: sys::Vec,
    _j: sys::Mat,
    _p: sys::Mat,
    _ctx: *mut c_void,
) -> sys::PetscErrorCode {
    0
}

/// A PETSc nonlinear solver (`SNES`) on the linear residual `A x - b` with
/// variable bounds (SNES VI), for the SNES VI comparator.
///
/// Invariant: `raw` is a live SNES of ours whose function's context is
/// `ctx`, which it outlives by nothing (destroyed first, in `drop`).
pub struct Snes {
    raw: sys::SNES,
    ctx: Box<LinearResidual>,
}

impl Drop for Snes {
    fn drop(&mut self) {
        if running() {
            // SAFETY: our live SNES (the invariant), destroyed once, while
            // PETSc runs, before its context (a field, dropped after this).
            unsafe { sys::SNESDestroy(&mut self.raw) };
        }
    }
}

/// A new reference to the matrix and the vector of `A x - b`.
fn linear_residual_of(a: &Matrix, b: &Vector) -> Result<LinearResidual, Error> {
    // SAFETY: a.raw is live; one more reference to it, which the Matrix
    // made next gives up when dropped.
    check(unsafe { sys::PetscObjectReference(a.raw as sys::PetscObject) })?;
    let a = Matrix { raw: a.raw };
    // SAFETY: b.raw is live; as above.
    check(unsafe { sys::PetscObjectReference(b.raw as sys::PetscObject) })?;
    let b = Vector { raw: b.raw };
    Ok(LinearResidual { a, b })
}

impl Snes {
    /// `vinewtonrsls` (unless `-snes_type` says otherwise) on `F(x) = A x - b`,
    /// with `lower <= x <= upper`; every SNES option applies.
    pub fn new_vi(a: &Matrix, b: &Vector, lower: &Vector, upper: &Vector) -> Result<Snes, Error> {
        ensure_running()?;
        let ctx = Box::new(linear_residual_of(a, b)?);
        let mut raw: sys::SNES = std::ptr::null_mut();
        // SAFETY: PETSc writes a new SNES on the world communicator.
        check(unsafe { sys::SNESCreate(comm_world(), &mut raw) })?;
        let s = Snes { raw, ctx };
        let vi = sys::SNESVINEWTONRSLS.as_ptr() as *const c_char;
        // SAFETY: s.raw is live; the type's name is a static C string.
        check(unsafe { sys::SNESSetType(s.raw, vi) })?;
        let f = b.duplicate()?;
        let ctx = &*s.ctx as *const LinearResidual as *mut c_void;
        // SAFETY: s.raw and f.raw are live (the SNES takes a reference to
        // f); `ctx` is the boxed context, which does not move and outlives
        // the SNES (the invariant), as linear_residual requires.
        check(unsafe { sys::SNESSetFunction(s.raw, f.raw, Some(linear_residual), ctx) })?;
        // SAFETY: s.raw and a.raw are live (the SNES takes references);
        // constant_jacobian reads nothing.
        check(unsafe {
            sys::SNESSetJacobian(
                s.raw,
                a.raw,
                a.raw,
                Some(constant_jacobian),
                std::ptr::null_mut(),
            )
        })?;
        // SAFETY: the three are live (the SNES takes references).
        check(unsafe { sys::SNESVISetVariableBounds(s.raw, lower.raw, upper.raw) })?;
        // SAFETY: s.raw is live.
        check(unsafe { sys::SNESSetFromOptions(s.raw) })?;
        Ok(s)
    }

    /// Solves from the initial guess in `x`; returns (Newton iterations,
    /// linear iterations, why it did not converge: None where it did). The
    /// last iterate stays in `x` either way.
    pub fn solve(&self, x: &Vector) -> Result<(usize, usize, Option<String>), Error> {
        let mut its: sys::PetscInt = 0;
        let mut lits: sys::PetscInt = 0;
        let mut reason: sys::SNESConvergedReason = 0;
        // SAFETY: both are live (no right-hand side: the null vector).
        check(unsafe { sys::SNESSolve(self.raw, std::ptr::null_mut(), x.raw) })?;
        // SAFETY: self.raw is live; PETSc writes one integer.
        check(unsafe { sys::SNESGetIterationNumber(self.raw, &mut its) })?;
        // SAFETY: self.raw is live; PETSc writes one integer.
        check(unsafe { sys::SNESGetLinearSolveIterations(self.raw, &mut lits) })?;
        // SAFETY: self.raw is live; PETSc writes one enum.
        check(unsafe { sys::SNESGetConvergedReason(self.raw, &mut reason) })?;
        if (reason as i32) <= 0 {
            let mut name: *const c_char = std::ptr::null();
            // SAFETY: self.raw is live; PETSc writes the address of a static
            // C string (or leaves null). Not checked: a failure leaves the
            // number.
            unsafe { sys::SNESGetConvergedReasonString(self.raw, &mut name) };
            let name = if name.is_null() {
                format!("{}", reason as i32)
            } else {
                // SAFETY: one of PETSc's static C strings.
                unsafe { string_from(name) }
            };
            let why = format!("SNES VI did not converge after {its} Newton iterations: {name}");
            return Ok((its as usize, lits as usize, Some(why)));
        }
        Ok((its as usize, lits as usize, None))
    }
}
