//! One group call (`runtime.md` §2).

use crate::machine::{Fault, Machine};
use crate::program::Program;
use crate::trace::InstanceRecord;

/// What a group remembers between calls besides memory: whether it is fresh (§2.2 step 3).
#[derive(Debug, Clone)]
pub struct GroupRt {
    pub fresh: bool,
}

impl GroupRt {
    pub fn new() -> GroupRt {
        GroupRt { fresh: true }
    }
}

impl Default for GroupRt {
    fn default() -> Self {
        GroupRt::new()
    }
}

/// One call of the group's FC (§2.2). `init_sd` is the FC input (§2.2 step 2). With `record`,
/// one [`InstanceRecord`] per instance is appended.
pub fn call(
    m: &mut Machine,
    program: &Program,
    group: u32,
    rt: &mut GroupRt,
    init_sd: bool,
    record: Option<&mut Vec<InstanceRecord>>,
) -> Result<(), Fault> {
    let _ = (m, program, group, rt, init_sd, record);
    todo!("group: §2")
}
