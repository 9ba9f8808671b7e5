//! The `-log_view` stages (one per phase of a run) and events (the steps of
//! the UBR loop), registered once.

use super::{LogEvent, LogStage};
use crate::error::Error;

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
