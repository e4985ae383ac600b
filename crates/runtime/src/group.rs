//! One group call (`runtime.md` §2).
//!
//! A call zeroes the FC's registers, copies `INIT_SD` into every instance, resets the internal
//! messages of a fresh group and runs one turn per instance in run order. A turn follows the
//! table of §2.3 step by step; eligibility is §2.4, the change §2.5, the times §2.6. Every
//! predefined variable is read and written through the instance's binding, so a wired
//! predefined variable (an actual) is honoured like any other formal (§2.1).
//!
//! Without a trace record a turn allocates nothing: part labels are only built when recording.

use crate::machine::{Fault, Machine};
use crate::program::{
    Block, Graph, GraphId, Group, GroupOptions, Instance, Operand, Place, Predef, Program, State,
    Target, TimeValue, Trans,
};
use crate::stl;
use crate::trace::{Blocked, Fired, InstanceRecord};

/// Δ when nobody says otherwise (`runtime.md` §5.2: `cycle` defaults to T#10MS).
pub const DEFAULT_CYCLE_MS: u32 = 10;

/// What a group remembers between calls besides memory: whether it is fresh (§2.2 step 3), the
/// cycle time Δ its times count down by (§2.6), and a state-number lookup built on first use.
#[derive(Debug, Clone)]
pub struct GroupRt {
    /// The next call is the first of the test or the first after `restart cold` (§2.8).
    pub fresh: bool,
    /// Δ in ms, subtracted from WT_/ST_CurrValue by every turn's time update (§2.6).
    /// `None`: the program's test's Δ (`Test::cycle_ms`), [`DEFAULT_CYCLE_MS`] without a test.
    pub cycle_ms: Option<u32>,
    /// Per graph id: state number → index in [`Graph::states`] + 1 (0: no such state). Only
    /// the graphs this group instantiates are filled; built by the first call.
    index: Vec<Vec<u32>>,
    /// The group the lookup was built for.
    built_for: Option<u32>,
}

impl GroupRt {
    /// A fresh group; Δ is the program's (its test's `cycle`, else [`DEFAULT_CYCLE_MS`]).
    pub fn new() -> GroupRt {
        GroupRt {
            fresh: true,
            cycle_ms: None,
            index: Vec::new(),
            built_for: None,
        }
    }

    /// A fresh group with an explicit Δ.
    pub fn with_cycle_ms(cycle_ms: u32) -> GroupRt {
        GroupRt {
            cycle_ms: Some(cycle_ms),
            ..GroupRt::new()
        }
    }

    /// `restart cold|warm` as far as the group's run-time state goes (§2.8): a cold restart
    /// makes it fresh again (initial entry, internal messages reset); a warm one keeps
    /// everything, the startup transition fires through `INIT_SD` = 1 (the runner's input).
    /// Memory is the machine's business ([`Machine::restart_cold`]).
    pub fn restart(&mut self, cold: bool) {
        if cold {
            self.fresh = true;
        }
    }

    fn build_index(&mut self, program: &Program, id: u32, group: &Group) {
        self.index = vec![Vec::new(); program.graphs.len()];
        for inst in &group.instances {
            let Some(graph) = program.graphs.get(inst.graph as usize) else {
                continue;
            };
            let table = &mut self.index[inst.graph as usize];
            if !table.is_empty() || graph.states.is_empty() {
                continue;
            }
            let max = graph.states.iter().map(|s| s.number).max().unwrap_or(0);
            table.resize(max as usize + 1, 0);
            for (i, st) in graph.states.iter().enumerate() {
                // The first state with a number wins (duplicates are an analysis error).
                let slot = &mut table[st.number as usize];
                if *slot == 0 {
                    *slot = i as u32 + 1;
                }
            }
        }
        self.built_for = Some(id);
    }
}

impl Default for GroupRt {
    fn default() -> Self {
        GroupRt::new()
    }
}

/// One call of the group's FC (§2.2). `init_sd` is the FC input (§2.2 step 2). With `record`,
/// one [`InstanceRecord`] per instance is appended (also for the instance whose turn faulted,
/// with the parts up to the fault).
pub fn call(
    m: &mut Machine,
    program: &Program,
    group: u32,
    rt: &mut GroupRt,
    init_sd: bool,
    mut record: Option<&mut Vec<InstanceRecord>>,
) -> Result<(), Fault> {
    let g = program
        .groups
        .get(group as usize)
        .ok_or_else(|| Fault::new(format!("no group {group} in the program")))?;
    if rt.built_for != Some(group) {
        rt.build_index(program, group, g);
    }
    // Step 1.
    m.begin_group_call();
    // Step 2.
    for inst in &g.instances {
        m.write(pv(inst, Predef::InitSd)?, u32::from(init_sd))?;
    }
    // Step 3.
    let fresh = rt.fresh;
    if fresh {
        for msg in &g.internal_messages {
            m.write(&Place::Cell(msg.cell), 0)?;
        }
    }
    rt.fresh = false;
    // Step 4.
    let ctx = Ctx {
        options: g.options,
        fresh,
        dt: rt.cycle_ms.unwrap_or_else(|| {
            program
                .test
                .as_ref()
                .map_or(DEFAULT_CYCLE_MS, |t| t.cycle_ms)
        }),
    };
    for inst in &g.instances {
        let graph = program.graphs.get(inst.graph as usize).ok_or_else(|| {
            Fault::new(format!(
                "instance {} names no graph ({})",
                inst.name, inst.graph
            ))
        })?;
        let table = rt
            .index
            .get(inst.graph as usize)
            .map_or(&[][..], |t| &t[..]);
        let rec = match record.as_deref_mut() {
            Some(list) => {
                list.push(InstanceRecord {
                    group: g.name.clone(),
                    instance: inst.name.clone(),
                    ..InstanceRecord::default()
                });
                list.last_mut()
            }
            None => None,
        };
        let mut turn = Turn {
            m,
            b: &inst.binding,
            graph,
            table,
            ctx: &ctx,
            rec,
        };
        turn.run(inst.graph)?;
    }
    Ok(())
}

/// The place of a predefined variable of an instance; a binding too short to hold the
/// predefined variables is a lowering bug, reported as a fault rather than a panic.
fn pv(inst: &Instance, p: Predef) -> Result<&Place, Fault> {
    inst.binding.get(p.var() as usize).ok_or_else(|| {
        Fault::new(format!(
            "instance {} has no binding for {}",
            inst.name,
            p.name()
        ))
    })
}

struct Ctx {
    options: GroupOptions,
    fresh: bool,
    dt: u32,
}

/// A firing decided by steps 3/4: the transition, its resolved target, its trace kind.
struct Firing<'g> {
    t: &'g Trans,
    to: u16,
    kind: &'static str,
}

struct Turn<'a, 'g> {
    m: &'a mut Machine,
    b: &'g [Place],
    graph: &'g Graph,
    table: &'a [u32],
    ctx: &'a Ctx,
    rec: Option<&'a mut InstanceRecord>,
}

impl<'g> Turn<'_, 'g> {
    #[inline(always)]
    fn p(&self, p: Predef) -> &'g Place {
        // `run` checked the binding's length first.
        &self.b[p.var() as usize]
    }

    #[inline(always)]
    fn get(&mut self, p: Predef) -> Result<u32, Fault> {
        let place = self.p(p);
        self.m.read(place)
    }

    #[inline(always)]
    fn bit(&mut self, p: Predef) -> Result<bool, Fault> {
        Ok(self.get(p)? & 1 != 0)
    }

    #[inline(always)]
    fn set(&mut self, p: Predef, bits: u32) -> Result<(), Fault> {
        let place = self.p(p);
        self.m.write(place, bits)
    }

    fn state(&self, n: u16) -> Option<&'g State> {
        let i = *self.table.get(n as usize)?;
        self.graph.states.get(i.checked_sub(1)? as usize)
    }

    /// Runs the blocks of one part; when recording and the part has a statement, notes it.
    #[inline(always)]
    fn part(
        &mut self,
        blocks: &'g [Block],
        rlo0: bool,
        label: impl FnOnce() -> String,
    ) -> Result<(), Fault> {
        if let Some(rec) = self.rec.as_deref_mut()
            && blocks.iter().any(|blk| !blk.code.is_empty())
        {
            rec.parts.push(label());
        }
        for blk in blocks {
            if !blk.code.is_empty() {
                stl::run_block(self.m, self.b, blk, rlo0)?;
            }
        }
        Ok(())
    }

    /// One instance turn (§2.3).
    fn run(&mut self, graph_id: GraphId) -> Result<(), Fault> {
        if self.b.len() < Predef::ALL.len() {
            return Err(Fault::new(format!(
                "an instance of graph {graph_id} binds {} variables, fewer than the predefined ones",
                self.b.len()
            )));
        }
        let graph = self.graph;
        let s = self.get(Predef::CurrentState)? as u16;
        if self.rec.is_some() {
            // Filled in again at the end; these stay when the turn faults.
            let previous = self.get(Predef::PreviousState)? as u16;
            if let Some(rec) = self.rec.as_deref_mut() {
                rec.state = s;
                rec.previous = previous;
            }
        }
        // Step 0.
        self.set(Predef::StateChange, 0)?;
        if !self.ctx.fresh {
            self.update_time(
                Predef::WtValid,
                Predef::WtStop,
                Predef::WtCurrValue,
                Predef::WtExpired,
            )?;
            self.update_time(
                Predef::StValid,
                Predef::StStop,
                Predef::StCurrValue,
                Predef::StExpired,
            )?;
        }
        // Step 1.
        self.part(&graph.permanent_pre, false, || "permanent C-".to_owned())?;
        let mut current = s;
        if self.ctx.fresh {
            // Step 2: the initial entry (no `!`, no RLO-0 pass, no `X`).
            let d = graph.initial.unwrap_or(0);
            if let Some(rec) = self.rec.as_deref_mut() {
                rec.fired = Some(Fired {
                    kind: "initial",
                    from: None,
                    to: d,
                    prio: None,
                });
            }
            self.enter(s, d, ChangeKind::Initial)?;
            self.entered(d)?;
            current = d;
        } else {
            // Step 3.
            let mut firing = None;
            let mut blocked = false;
            for (i, t) in graph.any.iter().enumerate() {
                if let Some(to) = self.eligible(t)? {
                    if self.ctx.options.any_once && to == s {
                        blocked = true;
                        if let Some(rec) = self.rec.as_deref_mut() {
                            rec.blocked_by = Some(Blocked { prio: t.prio });
                        }
                    } else {
                        let kind = if graph.startup == Some(i) {
                            "startup"
                        } else {
                            "any"
                        };
                        firing = Some(Firing { t, to, kind });
                    }
                    break;
                }
            }
            // Step 4.
            if firing.is_none()
                && let Some(st) = self.state(s)
            {
                self.part(&st.pre, false, || format!("state {s} C-"))?;
                if !blocked {
                    for t in &st.transitions {
                        if let Some(to) = self.eligible(t)? {
                            let kind = match t.to {
                                Target::Return => "return",
                                Target::State(_) => "normal",
                            };
                            firing = Some(Firing { t, to, kind });
                            break;
                        }
                    }
                }
            }
            // Steps 5–7.
            if let Some(f) = firing {
                self.change(s, &f)?;
                self.entered(f.to)?;
                current = f.to;
            }
        }
        // Step 8.
        if let Some(st) = self.state(current) {
            self.part(&st.cyclic, false, || format!("state {current} C"))?;
        }
        // Step 9.
        self.part(&graph.permanent_post, false, || "permanent C".to_owned())?;
        if self.rec.is_some() {
            let state = self.get(Predef::CurrentState)? as u16;
            let previous = self.get(Predef::PreviousState)? as u16;
            let change = self.bit(Predef::StateChange)?;
            if let Some(rec) = self.rec.as_deref_mut() {
                rec.state = state;
                rec.previous = previous;
                rec.state_change = change;
            }
        }
        Ok(())
    }

    /// §2.6 update of one time: count down by Δ while valid and not stopped; at 0 expired.
    #[inline(always)]
    fn update_time(
        &mut self,
        valid: Predef,
        stop: Predef,
        curr: Predef,
        expired: Predef,
    ) -> Result<(), Fault> {
        if !self.bit(valid)? || self.bit(stop)? {
            return Ok(());
        }
        let v = self.get(curr)?.saturating_sub(self.ctx.dt);
        self.set(curr, v)?;
        if v == 0 {
            self.set(valid, 0)?;
            self.set(expired, 1)?;
        }
        Ok(())
    }

    /// §2.4: `Some(resolved target)` when `t` is eligible. Checks stop at the first failure,
    /// so later condition blocks do not run.
    #[inline(always)]
    fn eligible(&mut self, t: &'g Trans) -> Result<Option<u16>, Fault> {
        if t.auto && !self.bit(Predef::AutomaticMode)? {
            return Ok(None);
        }
        if t.manual && !self.bit(Predef::ManualMode)? {
            return Ok(None);
        }
        // "No wait time" is what the load of §2.6 left: WT_Valid = 0 (after an expiry
        // WT_Expired = 1 as well, so the check reads WT_Valid = 0 or WT_Expired = 1).
        if t.waits && self.bit(Predef::WtValid)? && !self.bit(Predef::WtExpired)? {
            return Ok(None);
        }
        let to = match t.to {
            Target::State(n) => n,
            Target::Return => {
                let prev = self.get(Predef::PreviousState)? as u16;
                if self.state(prev).is_none() {
                    return Ok(None);
                }
                prev
            }
        };
        for blk in &t.conditions {
            if !blk.code.is_empty() && !stl::run_block(self.m, self.b, blk, false)? {
                return Ok(None);
            }
        }
        Ok(Some(to))
    }

    /// §2.5 for a firing transition: `!`, the RLO-0 pass, `X`, then step 4.
    fn change(&mut self, s: u16, f: &Firing<'g>) -> Result<(), Fault> {
        if let Some(rec) = self.rec.as_deref_mut() {
            rec.fired = Some(Fired {
                kind: f.kind,
                from: f.t.from,
                to: f.to,
                prio: Some(f.t.prio),
            });
        }
        let to = f.to;
        let from = f.t.from;
        self.part(&f.t.actions, false, || match from {
            Some(a) => format!("trans {a}->{to} !"),
            None => format!("trans any->{to} !"),
        })?;
        if let Some(st) = self.state(s) {
            if self.ctx.options.cyclic_rlo0 {
                self.part(&st.cyclic, true, || format!("state {s} C0"))?;
            }
            self.part(&st.exit, false, || format!("state {s} X"))?;
        }
        let kind = if f.kind == "startup" {
            ChangeKind::Startup
        } else {
            ChangeKind::Normal
        };
        self.enter(s, to, kind)
    }

    /// §2.5 step 4: the predefined variables of the change into `d`, and the times of `d`.
    fn enter(&mut self, s: u16, d: u16, kind: ChangeKind) -> Result<(), Fault> {
        match kind {
            ChangeKind::Initial => {
                self.set(Predef::StExpiredPrev, 0)?;
                self.set(Predef::PreviousState, 0)?;
            }
            ChangeKind::Startup => self.set(Predef::PreviousState, u32::from(s))?,
            ChangeKind::Normal => {
                let expired = self.get(Predef::StExpired)? & 1;
                self.set(Predef::StExpiredPrev, expired)?;
                self.set(Predef::PreviousState, u32::from(s))?;
            }
        }
        self.set(Predef::CurrentState, u32::from(d))?;
        self.set(Predef::StateChange, 1)?;
        let st = self.state(d);
        self.set(
            Predef::UsrMsgSend,
            u32::from(st.is_some_and(|st| st.reports)),
        )?;
        self.load_time(
            st.and_then(|st| st.wait.as_ref()),
            Predef::WtValid,
            Predef::WtExpired,
            Predef::WtCurrValue,
        )?;
        self.load_time(
            st.and_then(|st| st.supervise.as_ref()),
            Predef::StValid,
            Predef::StExpired,
            Predef::StCurrValue,
        )
    }

    /// §2.5 steps 6–7 for the new state `d`: `E`, then `C-` with `precyclic_on_entry`.
    fn entered(&mut self, d: u16) -> Result<(), Fault> {
        if let Some(st) = self.state(d) {
            self.part(&st.entry, false, || format!("state {d} E"))?;
            if self.ctx.options.precyclic_on_entry {
                self.part(&st.pre, false, || format!("state {d} C-"))?;
            }
        }
        Ok(())
    }

    /// §2.6 load: v > 0 starts the time, otherwise the state has none.
    fn load_time(
        &mut self,
        value: Option<&'g TimeValue>,
        valid: Predef,
        expired: Predef,
        curr: Predef,
    ) -> Result<(), Fault> {
        let v: i64 = match value {
            None => 0,
            Some(TimeValue::Const(ms)) => *ms,
            Some(TimeValue::Operand(op)) => match op {
                // A TIME is a signed DINT of milliseconds.
                Operand::Imm(bits) => i64::from(*bits as i32),
                Operand::Var(i) => match self.b.get(*i as usize) {
                    Some(place) => i64::from(self.m.read(place)? as i32),
                    None => 0,
                },
                Operand::Place(place) => i64::from(self.m.read(place)? as i32),
                Operand::None | Operand::Call(_) => 0,
            },
        };
        if v > 0 {
            self.set(valid, 1)?;
            self.set(expired, 0)?;
            self.set(curr, v.min(i64::from(u32::MAX)) as u32)
        } else {
            self.set(valid, 0)?;
            self.set(expired, 0)?;
            self.set(curr, 0)
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum ChangeKind {
    /// The initial entry of a fresh group: PreviousState and ST_ExpiredPrev := 0.
    Initial,
    /// The startup transition: ST_ExpiredPrev unchanged.
    Startup,
    Normal,
}
