//! One chart cycle (`runtime.md` §4).
//!
//! A [`ChartRt`] holds what a chart remembers between cycles besides memory: the operating
//! state, per step the active flag, elapsed time T, confirmation latch and error flag, the
//! running and the suspended sequencer, the action-control memories and the queued commands.
//! [`cycle`] runs the six steps of §4.3 in order; a sequencer abort (a state change, a
//! displacement) is executed where it is decided. Chart code sees the flags, the state and
//! the steps of its own chart through [`ChartEnv`]; tests see every chart through [`Charts`].

use crate::eval::{self, Env};
use crate::machine::{Fault, Machine};
use crate::program::{
    Chart, ChartTrans, ChartTransKind, Command, OpState, Place, Profile, Program, Qualifier,
    SfcFlag, Statement, StepIdx, StepMember, Switching,
};
use crate::trace::{ChartFired, ChartRecord, CommandRecord};
use crate::value::Value;

/// The run-time state of one chart (§4.1).
#[derive(Debug, Clone)]
pub struct ChartRt {
    pub state: OpState,
    chart: u32,
    name: String,
    seqs: Vec<SeqRt>,
    running: Option<Running>,
    suspended: Option<usize>,
    /// The state a sequencer was started in, when it completed since the last implicit
    /// transitions (§4.3 step 3).
    completed: Option<OpState>,
    actions: Vec<ActionMem>,
    /// Per action, its associations `(sequencer, step, index in the step's qualifiers)` in
    /// text order (§4.6).
    assoc: Vec<Vec<(usize, usize, usize)>>,
    queue: Vec<Command>,
    /// IEC charts: the initial step is (re)activated at the next cycle (the first cycle, after
    /// a restart or a `reset`).
    iec_pending: bool,
}

#[derive(Debug, Clone, Copy)]
struct Running {
    seq: usize,
    started_in: OpState,
    /// Started in this cycle: its start step is handed over in §4.5 step 3.
    pending_start: bool,
}

#[derive(Debug, Clone, Default)]
struct SeqRt {
    name: String,
    steps: Vec<StepRt>,
    /// Phases the end step ran since it became active (1 init, 2 run).
    end_phases: u8,
    /// Completed or aborted in this cycle: no candidate before the next (§4.4).
    finished_now: bool,
}

#[derive(Debug, Clone, Default)]
struct StepRt {
    name: String,
    active: bool,
    /// Elapsed time in ms; kept after the step leaves until it is activated again.
    t: i64,
    latch: bool,
    error: bool,
}

#[derive(Debug, Clone, Copy, Default)]
struct Ton {
    prev_in: bool,
    et: i64,
}

impl Ton {
    /// TON(in, t) of §4.6.
    fn eval(&mut self, input: bool, t: i64, dt: i64) -> bool {
        self.et = if self.prev_in {
            (self.et + dt).min(t)
        } else {
            0
        };
        self.prev_in = input;
        input && self.et >= t
    }
}

#[derive(Debug, Clone, Copy, Default)]
struct ActionMem {
    s: bool,
    p_prev: bool,
    l: Ton,
    d: Ton,
    sd_rs: bool,
    sd: Ton,
    ds: Ton,
    ds_rs: bool,
    sl_rs: bool,
    sl: Ton,
    /// IEC: P1/P0 edge memories, the two timers of DL, and Q at the previous evaluation (for
    /// the final scan of an action body).
    p1_prev: bool,
    p0_prev: bool,
    dl_d: Ton,
    dl_l: Ton,
    q_prev: bool,
}

impl ChartRt {
    pub fn new(program: &Program, chart: u32) -> ChartRt {
        let ch = program.charts.get(chart as usize);
        let seqs = ch.map_or_else(Vec::new, |ch| {
            ch.sequencers
                .iter()
                .map(|s| SeqRt {
                    name: s.name.clone(),
                    steps: s
                        .steps
                        .iter()
                        .map(|st| StepRt {
                            name: st.name.clone(),
                            ..StepRt::default()
                        })
                        .collect(),
                    ..SeqRt::default()
                })
                .collect()
        });
        let n_actions = ch.map_or(0, |c| c.actions.len());
        let mut assoc = vec![Vec::new(); n_actions];
        if let Some(ch) = ch {
            for (qi, seq) in ch.sequencers.iter().enumerate() {
                for (si, step) in seq.steps.iter().enumerate() {
                    for (ai, a) in step.qualifiers.iter().enumerate() {
                        if let Some(list) = assoc.get_mut(a.action as usize) {
                            list.push((qi, si, ai));
                        }
                    }
                }
            }
        }
        ChartRt {
            state: OpState::Ready,
            chart,
            name: ch.map_or_else(String::new, |c| c.name.clone()),
            seqs,
            running: None,
            suspended: None,
            completed: None,
            actions: vec![ActionMem::default(); n_actions],
            assoc,
            queue: Vec::new(),
            iec_pending: true,
        }
    }

    /// The chart's index in [`Program::charts`].
    pub fn chart(&self) -> u32 {
        self.chart
    }

    /// The running sequencer, if any.
    pub fn running(&self) -> Option<u32> {
        self.running.map(|r| r.seq as u32)
    }

    /// The suspended sequencer, if any (§4.2).
    pub fn suspended(&self) -> Option<u32> {
        self.suspended.map(|s| s as u32)
    }

    /// Whether a step is active (a step of the suspended sequencer stays active).
    pub fn is_active(&self, sequencer: u32, step: StepIdx) -> bool {
        self.step_rt(sequencer, step).is_some_and(|s| s.active)
    }

    fn step_rt(&self, sequencer: u32, step: StepIdx) -> Option<&StepRt> {
        self.seqs
            .get(sequencer as usize)
            .and_then(|q| q.steps.get(step as usize))
    }

    /// Queues a command for the next cycle (§4.3 step 2).
    pub fn queue(&mut self, command: Command) {
        self.queue.push(command);
    }

    /// `confirm`: sets the latch; the step must be active, else a fault (§1.4).
    pub fn confirm(&mut self, sequencer: u32, step: StepIdx) -> Result<(), Fault> {
        let chart = self.name.clone();
        match self
            .seqs
            .get_mut(sequencer as usize)
            .map(|q| (q.name.clone(), q.steps.get_mut(step as usize)))
        {
            Some((_, Some(s))) if s.active => {
                s.latch = true;
                Ok(())
            }
            Some((seq, Some(s))) => Err(Fault::new(format!(
                "confirm of the inactive step {chart}.{seq}.{}",
                s.name
            ))),
            _ => Err(Fault::new(format!("confirm of an unknown step of {chart}"))),
        }
    }

    /// `restart cold|warm` (§2.8): Ready; variables initial (cold) or kept (warm) — the
    /// machine resets the cells on a cold restart. Every step is inactive, no sequencer runs
    /// or is suspended, flags, latches and action memories are cleared; queued commands stay
    /// for the next cycle.
    pub fn restart(&mut self) {
        self.iec_pending = true;
        self.state = OpState::Ready;
        self.running = None;
        self.suspended = None;
        self.completed = None;
        for q in &mut self.seqs {
            q.end_phases = 0;
            q.finished_now = false;
            for s in &mut q.steps {
                s.active = false;
                s.t = 0;
                s.latch = false;
                s.error = false;
            }
        }
        for a in &mut self.actions {
            *a = ActionMem::default();
        }
    }
}

/// The flag of §4.2 that reflects an operating state.
pub fn flag_of(state: OpState) -> SfcFlag {
    match state {
        OpState::Ready => SfcFlag::Idle,
        OpState::Starting => SfcFlag::Starting,
        OpState::Active => SfcFlag::Run,
        OpState::Completing => SfcFlag::Completing,
        OpState::ErrorCompleting | OpState::Error => SfcFlag::Error,
        OpState::Completed => SfcFlag::Completed,
        OpState::Holding => SfcFlag::Holding,
        OpState::Held | OpState::HeldError => SfcFlag::Held,
        OpState::Resuming | OpState::ResumingError => SfcFlag::Resuming,
        OpState::Aborting => SfcFlag::Aborting,
        OpState::Aborted => SfcFlag::Aborted,
        OpState::Stopping => SfcFlag::Stopping,
        OpState::Stopped => SfcFlag::Stopped,
    }
}

/// The state a command leads to from `state`, `None` when the command is rejected (§4.2).
pub fn command_target(state: OpState, command: Command) -> Option<OpState> {
    use OpState as S;
    match command {
        Command::Start => {
            matches!(state, S::Ready | S::Completed | S::Aborted).then_some(S::Starting)
        }
        Command::Hold => {
            matches!(state, S::Starting | S::Active | S::Resuming).then_some(S::Holding)
        }
        Command::Resume => match state {
            S::Held => Some(S::Resuming),
            S::HeldError => Some(S::ResumingError),
            _ => None,
        },
        Command::Complete => (state == S::Active).then_some(S::Completing),
        Command::Abort => (!matches!(state, S::Ready | S::Aborting | S::Aborted | S::Stopped))
            .then_some(S::Aborting),
        Command::Stop => (!matches!(
            state,
            S::Ready | S::Stopping | S::Stopped | S::Aborting | S::Aborted
        ))
        .then_some(S::Stopping),
        Command::Reset => {
            matches!(state, S::Completed | S::Aborted | S::Stopped).then_some(S::Ready)
        }
        Command::Error => match state {
            S::Starting | S::Active | S::Holding | S::Held | S::Resuming => Some(S::Error),
            S::Completing => Some(S::ErrorCompleting),
            _ => None,
        },
    }
}

/// The successor of a transitional state (§4.2), `None` for a stable one.
pub fn successor(state: OpState) -> Option<OpState> {
    use OpState as S;
    Some(match state {
        S::Starting | S::Resuming | S::ResumingError => S::Active,
        S::Completing | S::ErrorCompleting => S::Completed,
        S::Holding => S::Held,
        S::Error => S::HeldError,
        S::Aborting => S::Aborted,
        S::Stopping => S::Stopped,
        _ => return None,
    })
}

/// A step's value for a path `Chart.[Seq.]Step[.X]`, `.T`, `.error` (§5.3).
pub fn step_value(rt: &ChartRt, sequencer: u32, step: StepIdx, member: StepMember) -> Value {
    let s = rt.step_rt(sequencer, step);
    match member {
        StepMember::Active => Value::Bool(s.is_some_and(|s| s.active)),
        StepMember::Error => Value::Bool(s.is_some_and(|s| s.error)),
        StepMember::Time => Value::Time(
            s.map_or(0, |s| s.t)
                .clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32,
        ),
    }
}

/// What the code of one chart sees: its own flags, state and steps; the steps of other
/// charts read inactive and their state Ready.
pub struct ChartEnv<'a>(pub &'a ChartRt);

impl Env for ChartEnv<'_> {
    fn sfc_flag(&self, flag: SfcFlag) -> bool {
        flag_of(self.0.state) == flag
    }
    fn chart_state(&self, chart: u32) -> u8 {
        if chart == self.0.chart {
            self.0.state as u8
        } else {
            OpState::Ready as u8
        }
    }
    fn step(&self, chart: u32, sequencer: u32, step: StepIdx, member: StepMember) -> Value {
        if chart == self.0.chart {
            step_value(self.0, sequencer, step, member)
        } else {
            eval::NoCharts.step(chart, sequencer, step, member)
        }
    }
}

/// What a test sees: every chart's state and steps (no `SFC.` flag outside a chart).
pub struct Charts<'a>(pub &'a [ChartRt]);

impl Charts<'_> {
    fn find(&self, chart: u32) -> Option<&ChartRt> {
        match self.0.get(chart as usize) {
            Some(rt) if rt.chart == chart => Some(rt),
            _ => self.0.iter().find(|rt| rt.chart == chart),
        }
    }
}

impl Env for Charts<'_> {
    fn sfc_flag(&self, _: SfcFlag) -> bool {
        false
    }
    fn chart_state(&self, chart: u32) -> u8 {
        self.find(chart)
            .map_or(OpState::Ready as u8, |rt| rt.state as u8)
    }
    fn step(&self, chart: u32, sequencer: u32, step: StepIdx, member: StepMember) -> Value {
        match self.find(chart) {
            Some(rt) => step_value(rt, sequencer, step, member),
            None => eval::NoCharts.step(chart, sequencer, step, member),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    Init,
    Run,
    Term,
}

impl Phase {
    fn name(self) -> &'static str {
        match self {
            Phase::Init => "init",
            Phase::Run => "run",
            Phase::Term => "term",
        }
    }
}

/// A duration in ms from a TIME (or S5TIME, or integer) value.
fn time_ms(v: &Value) -> i64 {
    match v {
        Value::Time(ms) => i64::from(*ms),
        Value::S5Time(b) => eval::s5time_ms(*b),
        Value::Dint(x) => i64::from(*x),
        Value::Int(x) => i64::from(*x),
        Value::Dword(x) => i64::from(*x),
        Value::Word(x) => i64::from(*x),
        _ => 0,
    }
}

struct Ctx<'a, 'r> {
    m: &'a mut Machine,
    program: &'a Program,
    ch: &'a Chart,
    dt: i64,
    rec: Option<&'r mut ChartRecord>,
}

impl<'a> Ctx<'a, '_> {
    fn eval(&mut self, rt: &ChartRt, e: &crate::program::Expr) -> Result<Value, Fault> {
        eval::eval(e, self.m, self.program, &ChartEnv(rt))
    }

    fn eval_bool(&mut self, rt: &ChartRt, e: &crate::program::Expr) -> Result<bool, Fault> {
        Ok(eval::truth(&self.eval(rt, e)?))
    }

    /// Runs statements in order. Recurses into `IF`/`CASE` bodies: the depth is bounded by the
    /// parser's nesting limit (HG0012), which the lowering inherits.
    fn exec(&mut self, rt: &ChartRt, stmts: &[Statement]) -> Result<(), Fault> {
        for stmt in stmts {
            let origin = match stmt {
                Statement::Assign(s) => s.origin,
                Statement::If { origin, .. } | Statement::Case { origin, .. } => *origin,
                Statement::Call(c) => c.origin,
            };
            self.exec_one(rt, stmt).map_err(|mut f| {
                if f.origin == crate::program::Origin::NONE {
                    f.origin = origin;
                }
                f
            })?;
        }
        Ok(())
    }

    fn exec_one(&mut self, rt: &ChartRt, stmt: &Statement) -> Result<(), Fault> {
        match stmt {
            Statement::Assign(stmt) => {
                let v = self.eval(rt, &stmt.value)?;
                self.m.write_value(&stmt.target, &eval::convert(v, stmt.ty))
            }
            Statement::If { arms, else_, .. } => {
                for (cond, body) in arms {
                    if self.eval_bool(rt, cond)? {
                        return self.exec(rt, body);
                    }
                }
                self.exec(rt, else_)
            }
            Statement::Case {
                selector,
                arms,
                else_,
                ..
            } => {
                let v = self.eval(rt, selector)?;
                let k = eval::integer_of(&v);
                for (labels, body) in arms {
                    if k.is_some_and(|k| labels.iter().any(|&(lo, hi)| lo <= k && k <= hi)) {
                        return self.exec(rt, body);
                    }
                }
                self.exec(rt, else_)
            }
            Statement::Call(call) => {
                let ch: &'a Chart = self.ch;
                let Some(fb) = ch.fbs.get(call.fb as usize) else {
                    return Err(Fault::new(format!("no function block {}", call.fb)));
                };
                for (member, e) in &call.inputs {
                    let v = self.eval(rt, e)?;
                    let Some(cell) = fb.cell(*member) else {
                        continue;
                    };
                    let v = eval::convert(v, member.ty());
                    self.m.write_value(&Place::Cell(cell), &v)?;
                }
                crate::fb::call(self.m, fb)?;
                for (member, target, ty) in &call.outputs {
                    let Some(cell) = fb.cell(*member) else {
                        continue;
                    };
                    let v = self.m.read_value(&Place::Cell(cell), member.ty())?;
                    self.m.write_value(target, &eval::convert(v, *ty))?;
                }
                Ok(())
            }
        }
    }

    fn phase(&mut self, rt: &ChartRt, seq: usize, step: usize, phase: Phase) -> Result<(), Fault> {
        let ch: &'a Chart = self.ch;
        let Some(st) = ch.sequencers.get(seq).and_then(|q| q.steps.get(step)) else {
            return Ok(());
        };
        if let Some(rec) = self.rec.as_deref_mut() {
            rec.phases.push(format!(
                "{}.{} {}",
                self.ch.sequencers[seq].name,
                st.name,
                phase.name()
            ));
        }
        let stmts = match phase {
            Phase::Init => &st.init,
            Phase::Run => &st.run,
            Phase::Term => &st.term,
        };
        self.exec(rt, stmts)
    }

    fn fired(
        &mut self,
        seq: usize,
        kind: &'static str,
        name: Option<&str>,
        from: &[usize],
        to: &[usize],
    ) {
        if let Some(rec) = self.rec.as_deref_mut() {
            let steps = &self.ch.sequencers[seq].steps;
            let names = |list: &[usize]| {
                list.iter()
                    .filter_map(|&i| steps.get(i).map(|s| s.name.clone()))
                    .collect()
            };
            rec.fired.push(ChartFired {
                sequencer: self.ch.sequencers[seq].name.clone(),
                kind,
                name: name.map(str::to_owned),
                from: names(from),
                to: names(to),
            });
        }
    }

    /// Makes a step active with T := 0 and runs its first phase (§4.5 step 3).
    fn activate(&mut self, rt: &mut ChartRt, seq: usize, step: usize) -> Result<(), Fault> {
        let Some(def) = self.ch.sequencers.get(seq).and_then(|q| q.steps.get(step)) else {
            return Ok(());
        };
        let end = self.ch.sequencers[seq].steps.len() - 1;
        if let Some(s) = rt.seqs[seq].steps.get_mut(step) {
            s.active = true;
            s.t = 0;
            s.error = false;
            s.latch = false;
        }
        let phase = if step == end {
            rt.seqs[seq].end_phases = 1;
            Phase::Init
        } else if def.init.is_empty() {
            Phase::Run
        } else {
            Phase::Init
        };
        self.phase(rt, seq, step, phase)
    }

    fn deactivate_all(rt: &mut ChartRt, seq: usize) {
        let q = &mut rt.seqs[seq];
        q.end_phases = 0;
        for s in &mut q.steps {
            s.active = false;
            s.latch = false;
        }
    }

    /// Abort (§4.5): `term` of each active step but the end step, then the end step's phases
    /// not yet run; the sequencer is finished, not completed.
    fn abort(&mut self, rt: &mut ChartRt, seq: usize) -> Result<(), Fault> {
        let n = rt.seqs[seq].steps.len();
        if n == 0 {
            return Ok(());
        }
        let end = n - 1;
        let from: Vec<usize> = (0..n).filter(|&i| rt.seqs[seq].steps[i].active).collect();
        self.fired(seq, "abort", None, &from, &[]);
        for &i in &from {
            if i != end {
                self.phase(rt, seq, i, Phase::Term)?;
            }
        }
        let end_active = rt.seqs[seq].steps[end].active;
        let done = if end_active {
            rt.seqs[seq].end_phases
        } else {
            0
        };
        for (k, p) in [Phase::Init, Phase::Run, Phase::Term]
            .into_iter()
            .enumerate()
        {
            if k >= usize::from(done) {
                self.phase(rt, seq, end, p)?;
            }
        }
        Self::deactivate_all(rt, seq);
        rt.seqs[seq].finished_now = true;
        Ok(())
    }

    /// A change of the operating state and what it does to the sequencers (§4.2).
    fn change_state(&mut self, rt: &mut ChartRt, new: OpState) -> Result<(), Fault> {
        let old = rt.state;
        rt.state = new;
        if old == OpState::Active && new == OpState::Holding {
            if let Some(r) = rt.running.take() {
                rt.suspended = Some(r.seq);
            }
            return Ok(());
        }
        if let Some(r) = rt.running.take() {
            self.abort(rt, r.seq)?;
        }
        if let Some(s) = rt.suspended {
            if matches!(new, OpState::Holding | OpState::Held | OpState::Resuming) {
                // stays suspended
            } else if old == OpState::Resuming && new == OpState::Active {
                rt.suspended = None;
                rt.running = Some(Running {
                    seq: s,
                    started_in: OpState::Active,
                    pending_start: false,
                });
            } else {
                rt.suspended = None;
                Self::deactivate_all(rt, s);
                rt.seqs[s].finished_now = true;
            }
        }
        Ok(())
    }

    /// Whether the start condition of a sequencer holds (entries ANDed, empty = FALSE).
    fn start_holds(&mut self, rt: &ChartRt, seq: usize) -> Result<bool, Fault> {
        let ch: &'a Chart = self.ch;
        let start = &ch.sequencers[seq].start;
        if start.is_empty() {
            return Ok(false);
        }
        for e in start {
            if !self.eval_bool(rt, e)? {
                return Ok(false);
            }
        }
        Ok(true)
    }

    fn any_start_holds(&mut self, rt: &ChartRt) -> Result<bool, Fault> {
        for seq in 0..self.ch.sequencers.len() {
            if rt.suspended != Some(seq) && self.start_holds(rt, seq)? {
                return Ok(true);
            }
        }
        Ok(false)
    }

    fn mode(&self) -> Switching {
        match self.ch.switching {
            Switching::B | Switching::TAndB | Switching::TOrB if self.ch.mode_auto => Switching::T,
            m => m,
        }
    }

    /// S.T ≥ min, or the mode lets a confirmation override the minimum (§4.5 step 2).
    fn past_min(&mut self, rt: &ChartRt, seq: usize, step: usize) -> Result<bool, Fault> {
        let ch: &'a Chart = self.ch;
        let Some(min) = &ch.sequencers[seq].steps[step].min else {
            return Ok(true);
        };
        let s = &rt.seqs[seq].steps[step];
        if s.latch && matches!(self.mode(), Switching::B | Switching::TOrB) {
            return Ok(true);
        }
        let t = s.t;
        let min = time_ms(&self.eval(rt, min)?);
        Ok(t >= min)
    }

    fn condition(&mut self, rt: &ChartRt, tr: &ChartTrans) -> Result<bool, Fault> {
        for e in &tr.conditions {
            if !self.eval_bool(rt, e)? {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// The switching condition of a transition (§4.5 "Switching").
    fn switches(&mut self, rt: &ChartRt, seq: usize, tr: &ChartTrans) -> Result<bool, Fault> {
        let steps = &rt.seqs[seq].steps;
        let confirmed = tr
            .from
            .iter()
            .any(|&f| steps.get(f as usize).is_some_and(|s| s.latch));
        Ok(match self.mode() {
            Switching::T => self.condition(rt, tr)?,
            Switching::B => confirmed,
            Switching::TAndB => confirmed && self.condition(rt, tr)?,
            Switching::TOrB => confirmed || self.condition(rt, tr)?,
            Switching::Step => {
                let defs = &self.ch.sequencers[seq].steps;
                let asks = tr
                    .from
                    .iter()
                    .any(|&f| defs.get(f as usize).is_some_and(|s| s.confirm));
                if asks {
                    confirmed && self.condition(rt, tr)?
                } else {
                    self.condition(rt, tr)?
                }
            }
        })
    }

    /// §4.5: processing of the running sequencer.
    fn process(&mut self, rt: &mut ChartRt, r: Running) -> Result<(), Fault> {
        let seq = r.seq;
        let ch: &'a Chart = self.ch;
        let def = &ch.sequencers[seq];
        let n = def.steps.len();
        self.exec(rt, &def.pre)?;
        // 2. decide
        let was_active: Vec<bool> = rt.seqs[seq].steps.iter().map(|s| s.active).collect();
        let mut leaving = vec![false; n];
        let mut fired: Vec<usize> = Vec::new();
        let end = n.saturating_sub(1);
        for si in 0..n {
            if !was_active[si] || si == end || leaving[si] || !self.past_min(rt, seq, si)? {
                continue;
            }
            for &ti in &def.steps[si].candidates {
                let Some(tr) = def.transitions.get(ti as usize) else {
                    continue;
                };
                if tr.from.is_empty() {
                    continue;
                }
                let mut ok = true;
                for &f in &tr.from {
                    let f = f as usize;
                    if f >= n || !was_active[f] || leaving[f] {
                        ok = false;
                        break;
                    }
                    if f != si && !self.past_min(rt, seq, f)? {
                        ok = false;
                        break;
                    }
                }
                if ok && self.switches(rt, seq, tr)? {
                    for &f in &tr.from {
                        leaving[f as usize] = true;
                    }
                    fired.push(ti as usize);
                    break;
                }
            }
        }
        // 3. hand over
        let mut entered = vec![false; n];
        if r.pending_start && n > 0 {
            if let Some(run) = rt.running.as_mut() {
                run.pending_start = false;
            }
            self.fired(seq, "start", None, &[], &[0]);
            entered[0] = true;
            self.activate(rt, seq, 0)?;
        }
        for ti in fired {
            let tr = &def.transitions[ti];
            let mut from: Vec<usize> = tr.from.iter().map(|&f| f as usize).collect();
            from.sort_unstable();
            from.dedup();
            let to: Vec<usize> = tr
                .to
                .iter()
                .map(|&t| t as usize)
                .filter(|&t| t < n)
                .collect();
            let kind = match tr.kind {
                ChartTransKind::Trans => "trans",
                ChartTransKind::Jump => "jump",
                ChartTransKind::Loop => "loop",
            };
            self.fired(seq, kind, tr.name.as_deref(), &from, &to);
            for &f in &from {
                self.phase(rt, seq, f, Phase::Term)?;
                let s = &mut rt.seqs[seq].steps[f];
                s.active = false;
                s.latch = false;
                if f == end {
                    rt.seqs[seq].end_phases = 0;
                }
            }
            for &t in &to {
                entered[t] = true;
                self.activate(rt, seq, t)?;
            }
        }
        // 4. run (the end step: run in its second cycle, term in its third)
        let mut completed = false;
        for si in 0..n {
            if !was_active[si] || leaving[si] || entered[si] || !rt.seqs[seq].steps[si].active {
                continue;
            }
            if si == end {
                if rt.seqs[seq].end_phases <= 1 {
                    rt.seqs[seq].end_phases = 2;
                    self.phase(rt, seq, si, Phase::Run)?;
                } else {
                    self.phase(rt, seq, si, Phase::Term)?;
                    completed = true;
                }
            } else {
                self.phase(rt, seq, si, Phase::Run)?;
            }
        }
        if completed {
            Self::deactivate_all(rt, seq);
            rt.seqs[seq].finished_now = true;
            rt.running = None;
            rt.completed = Some(r.started_in);
        }
        self.exec(rt, &def.post)
    }

    /// §4.6: action control; every action is written once, FALSE included. IEC charts
    /// (`docs/iec.md` §6, §7): an association counts while its step is active (there is no
    /// running sequencer); `P1`, `P0`, `DL` join the qualifiers; an action with a body runs
    /// it while active and once more when it stops (the final scan).
    fn actions(&mut self, rt: &mut ChartRt) -> Result<(), Fault> {
        const QS: [Qualifier; 12] = [
            Qualifier::N,
            Qualifier::S,
            Qualifier::R,
            Qualifier::P,
            Qualifier::L,
            Qualifier::D,
            Qualifier::Sd,
            Qualifier::Ds,
            Qualifier::Sl,
            Qualifier::P1,
            Qualifier::P0,
            Qualifier::Dl,
        ];
        let qi = |q: Qualifier| QS.iter().position(|x| *x == q).unwrap_or(0);
        let running = rt.running.map(|r| r.seq);
        let ch: &'a Chart = self.ch;
        let iec = ch.profile == Profile::Iec;
        for (ai, action) in ch.actions.iter().enumerate() {
            let mut input = [false; 12];
            // the action's one time t (§4.6, as IEC's action control block has one T): that
            // of the first timed association in text order whose step is active, else of the
            // first timed association
            let mut timed: Option<(&crate::program::Expr, bool)> = None;
            for &(seq, step, k) in rt.assoc.get(ai).map_or(&[][..], |v| &v[..]) {
                let Some(a) = ch.sequencers[seq].steps[step].qualifiers.get(k) else {
                    continue;
                };
                let active = (iec || running == Some(seq)) && rt.seqs[seq].steps[step].active;
                input[qi(a.qualifier)] |= active;
                if let Some(e) = &a.time {
                    match timed {
                        None => timed = Some((e, active)),
                        Some((_, false)) if active => timed = Some((e, true)),
                        _ => {}
                    }
                }
            }
            let t = match timed {
                Some((e, _)) => time_ms(&self.eval(rt, e)?).max(0),
                None => 0,
            };
            let dt = self.dt;
            let [
                i_n,
                i_s,
                i_r,
                i_p,
                i_l,
                i_d,
                i_sd,
                i_ds,
                i_sl,
                i_p1,
                i_p0,
                i_dl,
            ] = input;
            let (t_l, t_d, t_sd, t_ds, t_sl) = (t, t, t, t, t);
            let mem = &mut rt.actions[ai];
            mem.s = !i_r && (i_s || mem.s);
            let l_ton = mem.l.eval(i_l, t_l, dt);
            let l = i_l && !l_ton;
            // every timer is evaluated every cycle (no short circuit): its memory of the
            // previous input must follow
            let d = mem.d.eval(i_d, t_d, dt);
            let p = i_p && !mem.p_prev;
            mem.p_prev = i_p;
            mem.sd_rs = !i_r && (i_sd || mem.sd_rs);
            let sd = mem.sd.eval(mem.sd_rs, t_sd, dt);
            let ds_ton = mem.ds.eval(i_ds, t_ds, dt);
            mem.ds_rs = !i_r && (ds_ton || mem.ds_rs);
            mem.sl_rs = !i_r && (i_sl || mem.sl_rs);
            let sl_ton = mem.sl.eval(mem.sl_rs, t_sl, dt);
            let sl = mem.sl_rs && !sl_ton;
            // DL: TON(I_DL, t) ∧ ¬TON(I_DL, 2·t)
            let dl_on = mem.dl_d.eval(i_dl, t, dt);
            let dl_off = mem.dl_l.eval(i_dl, t.saturating_mul(2), dt);
            let dl = i_dl && dl_on && !dl_off;
            let p1 = i_p1 && !mem.p1_prev;
            mem.p1_prev = i_p1;
            let p0 = !i_p0 && mem.p0_prev;
            mem.p0_prev = i_p0;
            let q = i_n || mem.s || l || d || p || sd || mem.ds_rs || sl || dl;
            // A: Q or one of the pulses of P1/P0 (which have no final scan of their own)
            let x = q || p1 || p0;
            let final_scan = mem.q_prev && !q;
            mem.q_prev = q;
            self.m.write_value(&action.place, &Value::Bool(x))?;
            if let Some(rec) = self.rec.as_deref_mut() {
                rec.actions
                    .insert(action.name.clone(), serde_json::Value::Bool(x));
            }
            if let Some(body) = &action.body
                && (x || final_scan)
            {
                self.exec(rt, body)?;
            }
        }
        Ok(())
    }

    /// IEC: makes a step active with T := 0 and runs its `init` (`docs/iec.md` §7).
    fn activate_iec(&mut self, rt: &mut ChartRt, seq: usize, step: usize) -> Result<(), Fault> {
        if let Some(s) = rt.seqs[seq].steps.get_mut(step) {
            s.active = true;
            s.t = 0;
            s.error = false;
            s.latch = false;
        }
        self.phase(rt, seq, step, Phase::Init)
    }

    /// IEC: evolution of one sequencer (`docs/iec.md` §7 step 4): every enabled transition
    /// whose condition holds fires, decided against memory as it is now; per step the first
    /// candidate (its normal successor — `alt` branches left to right — then its jumps and
    /// loops) wins; steps entered in this cycle are not decided.
    fn evolve_iec(
        &mut self,
        rt: &mut ChartRt,
        seq: usize,
        entered: &mut [bool],
    ) -> Result<(), Fault> {
        let ch: &'a Chart = self.ch;
        let def = &ch.sequencers[seq];
        let n = def.steps.len();
        let was_active: Vec<bool> = rt.seqs[seq].steps.iter().map(|s| s.active).collect();
        let mut leaving = vec![false; n];
        let mut fired: Vec<usize> = Vec::new();
        for si in 0..n {
            if !was_active[si] || leaving[si] || entered[si] || !self.past_min(rt, seq, si)? {
                continue;
            }
            for &ti in &def.steps[si].candidates {
                let Some(tr) = def.transitions.get(ti as usize) else {
                    continue;
                };
                if tr.from.is_empty() {
                    continue;
                }
                let mut ok = true;
                for &f in &tr.from {
                    let f = f as usize;
                    if f >= n || !was_active[f] || leaving[f] || entered[f] {
                        ok = false;
                        break;
                    }
                    if f != si && !self.past_min(rt, seq, f)? {
                        ok = false;
                        break;
                    }
                }
                if ok && self.condition(rt, tr)? {
                    for &f in &tr.from {
                        leaving[f as usize] = true;
                    }
                    fired.push(ti as usize);
                    break;
                }
            }
        }
        for ti in fired {
            let tr = &def.transitions[ti];
            let mut from: Vec<usize> = tr.from.iter().map(|&f| f as usize).collect();
            from.sort_unstable();
            from.dedup();
            let to: Vec<usize> = tr
                .to
                .iter()
                .map(|&t| t as usize)
                .filter(|&t| t < n)
                .collect();
            let kind = match tr.kind {
                ChartTransKind::Trans => "trans",
                ChartTransKind::Jump => "jump",
                ChartTransKind::Loop => "loop",
            };
            self.fired(seq, kind, tr.name.as_deref(), &from, &to);
            for &f in &from {
                self.phase(rt, seq, f, Phase::Term)?;
                rt.seqs[seq].steps[f].active = false;
            }
            for &t in &to {
                entered[t] = true;
                self.activate_iec(rt, seq, t)?;
            }
        }
        Ok(())
    }
}

/// One cycle of an IEC chart (`docs/iec.md` §7).
fn cycle_iec(ctx: &mut Ctx<'_, '_>, rt: &mut ChartRt) -> Result<(), Fault> {
    let ch = ctx.ch;
    // 1. time
    if !rt.iec_pending {
        for q in &mut rt.seqs {
            for s in &mut q.steps {
                if s.active {
                    s.t += ctx.dt;
                }
            }
        }
    }
    // commands: only `reset`
    for c in std::mem::take(&mut rt.queue) {
        let accepted = c == Command::Reset;
        if let Some(rec) = ctx.rec.as_deref_mut() {
            rec.commands.push(CommandRecord {
                command: c.name().to_owned(),
                accepted,
            });
        }
        if accepted {
            rt.iec_pending = true;
            for a in &mut rt.actions {
                *a = ActionMem::default();
            }
        }
    }
    rt.state = OpState::Active;
    // 2. the initial step
    let mut entered: Vec<Vec<bool>> = rt.seqs.iter().map(|q| vec![false; q.steps.len()]).collect();
    if std::mem::replace(&mut rt.iec_pending, false) {
        for (seq, entered) in entered.iter_mut().enumerate() {
            Ctx::deactivate_all(rt, seq);
            if entered.is_empty() {
                continue;
            }
            ctx.fired(seq, "start", None, &[], &[0]);
            entered[0] = true;
            ctx.activate_iec(rt, seq, 0)?;
        }
    }
    // 3. pre, 4. evolution, 5. run
    for (seq, entered) in entered.iter_mut().enumerate() {
        ctx.exec(rt, &ch.sequencers[seq].pre)?;
        ctx.evolve_iec(rt, seq, entered)?;
        for si in 0..rt.seqs[seq].steps.len() {
            if rt.seqs[seq].steps[si].active {
                ctx.phase(rt, seq, si, Phase::Run)?;
            }
        }
    }
    // 6. action control
    ctx.actions(rt)?;
    // 7. post
    for seq in &ch.sequencers {
        ctx.exec(rt, &seq.post)?;
    }
    Ok(())
}

/// One chart cycle (§4.3). `first` is the first cycle of the test or after a restart;
/// `cycle_ms` is Δ (step times and action timers advance by it).
pub fn cycle(
    m: &mut Machine,
    program: &Program,
    chart: u32,
    rt: &mut ChartRt,
    first: bool,
    cycle_ms: u32,
    record: Option<&mut ChartRecord>,
) -> Result<(), Fault> {
    let Some(ch) = program.charts.get(chart as usize) else {
        return Ok(());
    };
    let mut ctx = Ctx {
        m,
        program,
        ch,
        dt: i64::from(cycle_ms),
        rec: record,
    };
    if let Some(rec) = ctx.rec.as_deref_mut() {
        *rec = ChartRecord {
            chart: ch.name.clone(),
            ..ChartRecord::default()
        };
    }
    if ch.profile == Profile::Iec {
        let result = cycle_iec(&mut ctx, rt);
        record_state(&mut ctx, rt);
        return result;
    }
    for q in &mut rt.seqs {
        q.finished_now = false;
    }
    // 1. time (and the step errors of `run time_monitoring`)
    if let Some(r) = rt.running.filter(|r| !r.pending_start) {
        for si in 0..rt.seqs[r.seq].steps.len() {
            if !rt.seqs[r.seq].steps[si].active {
                continue;
            }
            rt.seqs[r.seq].steps[si].t += ctx.dt;
            if let (true, Some(max)) = (ch.time_monitoring, &ch.sequencers[r.seq].steps[si].max) {
                let max = time_ms(&ctx.eval(rt, max)?);
                let s = &mut rt.seqs[r.seq].steps[si];
                if s.t > max {
                    s.error = true;
                }
            }
        }
    }
    // 2. commands
    let mut commands = std::mem::take(&mut rt.queue);
    if first && ch.autostart {
        commands.insert(0, Command::Start);
    }
    for c in commands {
        let target = command_target(rt.state, c);
        if let Some(rec) = ctx.rec.as_deref_mut() {
            rec.commands.push(CommandRecord {
                command: c.name().to_owned(),
                accepted: target.is_some(),
            });
        }
        if let Some(new) = target {
            ctx.change_state(rt, new)?;
            if c == Command::Reset {
                for q in &mut rt.seqs {
                    for s in &mut q.steps {
                        s.error = false;
                        s.latch = false;
                    }
                }
                for a in &mut rt.actions {
                    *a = ActionMem::default();
                }
            }
        }
    }
    // 3. implicit transitions, each source state at most once
    let mut used = [false; 17];
    loop {
        let s = rt.state;
        if used[s as usize] {
            break;
        }
        let next = match s {
            OpState::Active => {
                (rt.completed == Some(OpState::Active)).then_some(OpState::Completing)
            }
            OpState::Completed => ch.cyclic.then_some(OpState::Starting),
            _ => match successor(s) {
                Some(succ) => {
                    let done = rt.completed == Some(s)
                        || (rt.running.is_none() && !ctx.any_start_holds(rt)?);
                    done.then_some(succ)
                }
                None => None,
            },
        };
        let Some(next) = next else { break };
        used[s as usize] = true;
        if let Some(rec) = ctx.rec.as_deref_mut() {
            rec.implicit.push(format!("{}->{}", s.name(), next.name()));
        }
        ctx.change_state(rt, next)?;
    }
    rt.completed = None;
    // 4. selection
    let mut best: Option<usize> = None;
    for (i, q) in ch.sequencers.iter().enumerate() {
        if rt.suspended == Some(i) || rt.seqs[i].finished_now {
            continue;
        }
        if ctx.start_holds(rt, i)? && best.is_none_or(|b| q.prio < ch.sequencers[b].prio) {
            best = Some(i);
        }
    }
    if let Some(c) = best {
        let start = match rt.running {
            None => true,
            Some(r) if r.seq != c && ch.sequencers[c].prio < ch.sequencers[r.seq].prio => {
                rt.running = None;
                ctx.abort(rt, r.seq)?;
                true
            }
            Some(_) => false,
        };
        if start {
            Ctx::deactivate_all(rt, c);
            rt.running = Some(Running {
                seq: c,
                started_in: rt.state,
                pending_start: true,
            });
        }
    }
    // 5. processing
    if let Some(r) = rt.running {
        ctx.process(rt, r)?;
    }
    // 6. action control
    ctx.actions(rt)?;
    record_state(&mut ctx, rt);
    Ok(())
}

/// The state part of a chart's record: operating state, running and suspended sequencer,
/// active steps.
fn record_state(ctx: &mut Ctx<'_, '_>, rt: &ChartRt) {
    if let Some(rec) = ctx.rec.as_deref_mut() {
        rec.state = rt.state.name().to_owned();
        // an IEC chart's sequencer always runs
        rec.running = if ctx.ch.profile == Profile::Iec {
            rt.seqs.first().map(|q| q.name.clone())
        } else {
            rt.running.map(|r| rt.seqs[r.seq].name.clone())
        };
        rec.suspended = rt.suspended.map(|s| rt.seqs[s].name.clone());
        rec.active = rt
            .seqs
            .iter()
            .flat_map(|q| {
                q.steps
                    .iter()
                    .filter(|s| s.active)
                    .map(move |s| format!("{}.{}", q.name, s.name))
            })
            .collect();
    }
}
