//! One chart cycle (`runtime.md` §4).

use crate::machine::{Fault, Machine};
use crate::program::{Command, OpState, Program, StepIdx};
use crate::trace::ChartRecord;

/// The run-time state of one chart (§4.1).
#[derive(Debug, Clone)]
pub struct ChartRt {
    pub state: OpState,
    // The rest is private to the chart engine.
}

impl ChartRt {
    pub fn new(program: &Program, chart: u32) -> ChartRt {
        let _ = (program, chart);
        todo!("chart: §4.1")
    }

    /// Queues a command for the next cycle (§4.3 step 2).
    pub fn queue(&mut self, command: Command) {
        let _ = command;
        todo!()
    }

    /// `confirm`: sets the latch; the step must be active, else a fault (§1.4).
    pub fn confirm(&mut self, sequencer: u32, step: StepIdx) -> Result<(), Fault> {
        let _ = (sequencer, step);
        todo!()
    }

    /// `restart cold|warm` (§2.8): Ready; variables initial (cold) or kept (warm) — the
    /// machine resets the cells on a cold restart.
    pub fn restart(&mut self) {
        todo!()
    }
}

/// One chart cycle (§4.3). `first` is the first cycle of the test or after a restart.
pub fn cycle(
    m: &mut Machine,
    program: &Program,
    chart: u32,
    rt: &mut ChartRt,
    first: bool,
    record: Option<&mut ChartRecord>,
) -> Result<(), Fault> {
    let _ = (m, program, chart, rt, first, record);
    todo!("chart: §4.3")
}
