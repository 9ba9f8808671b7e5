//! The `-log_view` stages (one per phase of a run) and events (the steps of
//! the UBR loop), registered once.

use super::{check, sys};
use crate::error::Error;
use std::ffi::CString;

/// `-log_view` stages, one per phase.
pub struct Stages {
    pub mesh: LogStage,
    pub partition: LogStage,
    pub assembly: LogStage,
    pub factorization: LogStage,
    pub iterations: LogStage,
    /// The automatic choice of r (-ubr_r auto).
    pub r_choice: LogStage,
    pub output: LogStage,
}

/// `-log_view` events of the UBR loop.
pub struct Events {
    pub rhs: LogEvent,
    pub solve: LogEvent,
    pub projection: LogEvent,
}

impl Stages {
    pub fn register() -> Result<Stages, Error> {
        Ok(Stages {
            mesh: LogStage::register("Mesh")?,
            partition: LogStage::register("Partition")?,
            assembly: LogStage::register("Assembly")?,
            factorization: LogStage::register("Factorization")?,
            iterations: LogStage::register("Iterations")?,
            r_choice: LogStage::register("RChoice")?,
            output: LogStage::register("Output")?,
        })
    }
}

impl Events {
    pub fn register() -> Result<Events, Error> {
        Ok(Events {
            rhs: LogEvent::register("UBRRhs")?,
            solve: LogEvent::register("UBRSolve")?,
            projection: LogEvent::register("UBRProjection")?,
        })
    }
}

/// A `-log_view` stage. `push` returns a guard that pops it.
#[derive(Clone, Copy)]
pub struct LogStage(sys::PetscLogStage);

impl LogStage {
    pub fn register(name: &str) -> Result<LogStage, Error> {
        let n = CString::new(name).unwrap();
        let mut s: sys::PetscLogStage = 0;
        // SAFETY: a C string, which PETSc copies; it writes the stage's
        // number into `s`.
        check(unsafe { sys::PetscLogStageRegister(n.as_ptr(), &mut s) })?;
        Ok(LogStage(s))
    }
    pub fn push(self) -> Result<StageGuard, Error> {
        // SAFETY: a stage registered by `register` (the field is private).
        check(unsafe { sys::PetscLogStagePush(self.0) })?;
        Ok(StageGuard)
    }
}

/// Pops the stage pushed by [`LogStage::push`] when dropped.
pub struct StageGuard;
impl Drop for StageGuard {
    fn drop(&mut self) {
        if super::running() {
            // SAFETY: pops the stage this guard's push pushed (guards are
            // dropped in the reverse order of their pushes), while PETSc
            // runs. Its error code has nowhere to go from a drop.
            unsafe { sys::PetscLogStagePop() };
        }
    }
}

/// A `-log_view` event.
#[derive(Clone, Copy)]
pub struct LogEvent(sys::PetscLogEvent);

impl LogEvent {
    pub fn register(name: &str) -> Result<LogEvent, Error> {
        let n = CString::new(name).unwrap();
        let mut classid: sys::PetscClassId = 0;
        let mut e: sys::PetscLogEvent = 0;
        // SAFETY: a static C string, which PETSc copies; it writes the class
        // id into `classid`.
        check(unsafe { sys::PetscClassIdRegister(c"UBR".as_ptr(), &mut classid) })?;
        // SAFETY: a C string, which PETSc copies, and the class registered
        // above; it writes the event's number into `e`.
        check(unsafe { sys::PetscLogEventRegister(n.as_ptr(), classid, &mut e) })?;
        Ok(LogEvent(e))
    }
    pub fn begin(self) -> EventGuard {
        // SAFETY: an event registered by `register` (the field is private).
        // (Logging only: its error code is not the run's.)
        unsafe { sys::ubr_log_event_begin(self.0) };
        EventGuard(self.0)
    }
}

/// Ends the event begun by [`LogEvent::begin`] when dropped.
pub struct EventGuard(sys::PetscLogEvent);
impl Drop for EventGuard {
    fn drop(&mut self) {
        if super::running() {
            // SAFETY: ends the event this guard's begin began, while PETSc
            // runs.
            unsafe { sys::ubr_log_event_end(self.0) };
        }
    }
}
