//! The tool-change flags of `run` and `console` (grbl has no tool changer: the sender
//! handles `M6`), and the operator's side of a change.

use crate::machine_profile::parse_xyz;
use oficina_grbl::{setter_at, ToolChange, ToolPolicy};

#[derive(clap::Args, Debug, Clone)]
pub(crate) struct ToolChangeArgs {
    /// What the sender does at M6 on grbl firmware: pause (stop there for a manual change,
    /// go on at resume), park (move to --park first), remeasure (pause, then measure the
    /// new tool on --tool-setter and apply G43.1), ignore (drop M6 and T), firmware (send M6
    /// as written: grblHAL/FluidNC with a tool changer).
    #[arg(long, default_value = "pause", value_name = "POLICY")]
    pub tool_change: ToolPolicy,
    /// Park position for tool changes, machine X,Y,Z mm (G53 G0 Z, then X Y).
    #[arg(long, value_parser = parse_xyz, value_name = "X,Y,Z")]
    pub park: Option<[f64; 3]>,
    /// Tool length setter for --tool-change remeasure: machine X,Y over it and the machine Z
    /// to travel at and start probing from (50 mm travel, 200 then 25 mm/min).
    #[arg(long, value_parser = parse_xyz, value_name = "X,Y,ZSTART")]
    pub tool_setter: Option<[f64; 3]>,
    /// remeasure: measure the tool in the spindle when the job starts (the reference), not
    /// at the first M6.
    #[arg(long)]
    pub measure_at_start: bool,
}

impl ToolChangeArgs {
    /// The sender's settings, checked.
    pub(crate) fn settings(&self) -> anyhow::Result<ToolChange> {
        let tc = ToolChange {
            policy: self.tool_change,
            park: self.park,
            setter: self.tool_setter.map(|[x, y, z]| setter_at(x, y, z)),
            measure_at_start: self.measure_at_start,
        };
        tc.validate().map_err(anyhow::Error::msg)?;
        Ok(tc)
    }
}
