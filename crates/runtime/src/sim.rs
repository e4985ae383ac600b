//! A simulation: a machine, the groups' and charts' run-time state, the clock; one machine
//! cycle at a time (`runtime.md` §1.3, §2.8).
//!
//! Cycle k (1-based) runs at virtual time t_k = k·Δ: the clock reads t_k from the start of
//! cycle k until cycle k + 1 starts, so test statements between cycles k and k + 1 see t_k
//! (and 0 before the first cycle). One cycle executes the run list in order: a group is one
//! call of its FC (`group::call`), a chart one chart cycle (`chart::cycle`). The first cycle
//! of the test and the first after each `restart` pass INIT_SD = 1 to the groups and
//! `first = true` to the charts.

use crate::chart::{self, ChartRt, Charts};
use crate::group::{self, GroupRt};
use crate::machine::{Fault, Machine};
use crate::program::{Command, Program, RunEntry, StepIdx};
use crate::trace::{ChartRecord, CycleRecord};

/// The most cycles one test may run (§1.4); one more is a runtime fault.
pub const MAX_CYCLES: u64 = 10_000_000;

/// A running simulation of a program.
pub struct Sim<'p> {
    pub program: &'p Program,
    pub machine: Machine,
    /// One per [`Program::groups`] entry.
    pub groups: Vec<GroupRt>,
    /// One per [`Program::charts`] entry.
    pub charts: Vec<ChartRt>,
    /// Δ in ms.
    pub cycle_ms: u32,
    /// The run list.
    pub run: Vec<RunEntry>,
    /// Cycles started so far: the number of the last cycle (0 before the first).
    pub cycle: u64,
    /// The next cycle is the first after startup (test start or a restart).
    first: bool,
}

impl<'p> Sim<'p> {
    /// A simulation at test start (§2.8): the test's Δ and run list, or for a program without
    /// a test Δ = 10 ms and every group, then every chart.
    pub fn new(program: &'p Program) -> Sim<'p> {
        let (cycle_ms, run) = match &program.test {
            Some(test) => (test.cycle_ms.max(1), test.run.clone()),
            None => (
                10,
                (0..program.groups.len() as u32)
                    .map(RunEntry::Group)
                    .chain((0..program.charts.len() as u32).map(RunEntry::Chart))
                    .collect(),
            ),
        };
        Sim {
            program,
            machine: Machine::new(program),
            groups: program
                .groups
                .iter()
                .map(|_| GroupRt::with_cycle_ms(cycle_ms))
                .collect(),
            charts: (0..program.charts.len() as u32)
                .map(|chart| ChartRt::new(program, chart))
                .collect(),
            cycle_ms,
            run,
            cycle: 0,
            first: true,
        }
    }

    /// Virtual time t_k of cycle `k`, ms.
    pub fn time_of(&self, cycle: u64) -> u64 {
        cycle.saturating_mul(u64::from(self.cycle_ms))
    }

    /// What the clock reads now (t of the last cycle started, 0 before the first).
    pub fn now_ms(&self) -> u64 {
        self.time_of(self.cycle)
    }

    /// Whether the next cycle is the first after startup (INIT_SD = 1).
    pub fn next_is_first(&self) -> bool {
        self.first
    }

    /// Runs one machine cycle. With `record`, its `cycle`, `time_ms`, `init_sd`, `instances`
    /// and `charts` are filled in (also when a fault stops the cycle half-way: what ran so far).
    /// More than [`MAX_CYCLES`] cycles is a fault; that cycle is not started.
    pub fn step(&mut self, mut record: Option<&mut CycleRecord>) -> Result<(), Fault> {
        if self.cycle >= MAX_CYCLES {
            return Err(Fault::new(format!(
                "more than {MAX_CYCLES} cycles in one test"
            )));
        }
        self.cycle += 1;
        let first = std::mem::replace(&mut self.first, false);
        self.machine.now_ms = self.time_of(self.cycle);
        if let Some(record) = record.as_deref_mut() {
            record.cycle = self.cycle;
            record.time_ms = self.machine.now_ms;
            record.init_sd = first;
        }
        for index in 0..self.run.len() {
            match self.run[index] {
                RunEntry::Group(g) => {
                    let Some(rt) = self.groups.get_mut(g as usize) else {
                        continue;
                    };
                    let instances = record.as_deref_mut().map(|r| &mut r.instances);
                    group::call(&mut self.machine, self.program, g, rt, first, instances)?;
                }
                RunEntry::Chart(c) => {
                    let Some(rt) = self.charts.get_mut(c as usize) else {
                        continue;
                    };
                    match record.as_deref_mut() {
                        Some(record) => {
                            record.charts.push(ChartRecord {
                                chart: self
                                    .program
                                    .charts
                                    .get(c as usize)
                                    .map(|chart| chart.name.clone())
                                    .unwrap_or_default(),
                                ..ChartRecord::default()
                            });
                            let chart_record = record.charts.last_mut();
                            chart::cycle(
                                &mut self.machine,
                                self.program,
                                c,
                                rt,
                                first,
                                self.cycle_ms,
                                chart_record,
                            )?;
                        }
                        None => chart::cycle(
                            &mut self.machine,
                            self.program,
                            c,
                            rt,
                            first,
                            self.cycle_ms,
                            None,
                        )?,
                    }
                }
            }
        }
        Ok(())
    }

    /// `restart cold|warm` (§2.8). Cold: memory as at test start except inputs, stub values,
    /// call counters and the clock, every group fresh again; warm: nothing reset. Both: the
    /// next cycle passes INIT_SD = 1, and every chart goes back to Ready (its variables
    /// initial after a cold restart, because the machine resets the cells).
    pub fn restart(&mut self, cold: bool) {
        if cold {
            self.machine.restart_cold(self.program);
        }
        for group in &mut self.groups {
            group.restart(cold);
        }
        for chart in &mut self.charts {
            chart.restart();
        }
        self.first = true;
    }

    /// Queues a command for a chart (applied in its next cycle, §4.3 step 2).
    pub fn command(&mut self, chart: u32, command: Command) {
        if let Some(rt) = self.charts.get_mut(chart as usize) {
            rt.queue(command);
        }
    }

    /// `confirm`: the step must be active, else a fault (§1.4).
    pub fn confirm(&mut self, chart: u32, sequencer: u32, step: StepIdx) -> Result<(), Fault> {
        match self.charts.get_mut(chart as usize) {
            Some(rt) => rt.confirm(sequencer, step),
            None => Err(Fault::new("confirm of a chart that is not run")),
        }
    }

    /// The machine and what a test expression sees besides memory (every chart's state and
    /// steps), borrowed together.
    pub fn split(&mut self) -> (&mut Machine, Charts<'_>) {
        (&mut self.machine, Charts(&self.charts))
    }
}
