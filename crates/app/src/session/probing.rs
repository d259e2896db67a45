//! Probing, tool changes and levelled jobs on grbl firmware, as the workbench drives them:
//! the routines and the transform are `oficina_grbl`'s, this only reaches the device.
//!
//! A probing routine (a touch, a height map) lasts seconds to minutes. It runs on the
//! device's own thread ([`oficina_grbl::GrblDevice::start_routine`]), as a job does: the
//! session hands back a [`Probing`] to wait on *without* the session, so whoever holds the
//! session between two calls (the server's pump) keeps draining status while the probe
//! moves, and Hold / Stop reach the routine as they reach a job.

use super::{state_name, JobView, Session};
use crate::level::{level_options, probe_map, LevelTuning, ProbeRequest};
use crate::{Error, JobRequest};
use oficina_grbl::{
    level_stream, run_corner, run_tool_setter, run_z_plate, Corner, GrblDevice, HeightMap,
    LevelReport, ProbeResult, Routine, SetterResult, ToolChange, ToolSetter, ZPlate,
};
use oficina_machine::State;
use serde::Serialize;

/// A routine under way on the firmware's thread (a probing routine, a homing cycle).
pub struct Probing<T>(pub(crate) Routine<T>);

impl<T> Probing<T> {
    /// Waits for its end (hold the session meanwhile and status stops flowing: don't).
    pub fn wait(self) -> Result<T, Error> {
        self.0.wait().map_err(Error)
    }
}

/// What a probing routine measured and set, for the page.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ProbingResult {
    /// A touch plate or a corner: the contacts (machine mm) and the offset set.
    Offset {
        /// The routine: `z_plate` or `corner`.
        routine: &'static str,
        /// Machine positions of the measured touches.
        contacts: Vec<[f64; 3]>,
        /// The coordinate system set, `G54` … `G59`.
        wcs: String,
        /// Its offset as the firmware holds it afterwards, machine mm.
        offset: [f64; 3],
    },
    /// The tool length setter.
    Setter {
        /// Machine position of the touch.
        contact: [f64; 3],
        /// Its machine Z (the reference for later tools).
        measured_z: f64,
        /// The tool length offset applied with G43.1, when a reference was given.
        tool_offset: Option<f64>,
    },
}

impl ProbingResult {
    fn offset(routine: &'static str, r: ProbeResult) -> ProbingResult {
        ProbingResult::Offset {
            routine,
            contacts: r.contacts,
            wcs: format!("G{}", 53 + r.wcs),
            offset: r.offset,
        }
    }

    fn setter(r: SetterResult) -> ProbingResult {
        ProbingResult::Setter {
            contact: r.contact,
            measured_z: r.measured_z,
            tool_offset: r.tool_offset,
        }
    }
}

impl Session {
    /// The grbl device, idle, or why `what` cannot run.
    fn idle_grbl(&mut self, what: &str) -> Result<&mut GrblDevice, Error> {
        let state = self.machine.status().state;
        let Some(dev) = self
            .machine
            .as_any_mut()
            .and_then(|m| m.downcast_mut::<GrblDevice>())
        else {
            return Err(Error(format!(
                "{what} runs on grbl firmware (connect grbl:/dev/… or tcp://…): the virtual machine has no probe input"
            )));
        };
        if state != State::Idle {
            return Err(Error(format!(
                "{what} starts from idle, not while {}",
                state_name(&state)
            )));
        }
        Ok(dev)
    }

    /// Touches the plate under the tool; the stock's top becomes the chosen system's Z0.
    pub fn probe_z_plate(&mut self, p: ZPlate) -> Result<Probing<ProbingResult>, Error> {
        let dev = self.idle_grbl("the touch plate")?;
        let r = dev
            .start_routine(move |link| {
                run_z_plate(link, &p)
                    .map(|r| ProbingResult::offset("z_plate", r))
                    .map_err(|e| e.to_string())
            })
            .map_err(Error::from_display)?;
        Ok(Probing(r))
    }

    /// Touches the top and the −X, −Y sides; the stock's front-left top corner becomes X0 Y0 Z0.
    pub fn probe_corner(&mut self, p: Corner) -> Result<Probing<ProbingResult>, Error> {
        let dev = self.idle_grbl("the corner probe")?;
        let r = dev
            .start_routine(move |link| {
                run_corner(link, &p)
                    .map(|r| ProbingResult::offset("corner", r))
                    .map_err(|e| e.to_string())
            })
            .map_err(Error::from_display)?;
        Ok(Probing(r))
    }

    /// Touches the tool length setter; with a reference, applies the tool length offset.
    pub fn probe_setter(&mut self, p: ToolSetter) -> Result<Probing<ProbingResult>, Error> {
        let dev = self.idle_grbl("the tool length setter")?;
        let r = dev
            .start_routine(move |link| {
                run_tool_setter(link, &p)
                    .map(ProbingResult::setter)
                    .map_err(|e| e.to_string())
            })
            .map_err(Error::from_display)?;
        Ok(Probing(r))
    }

    /// Probes a height map over `program`'s feed moves (or `req.area`), in the work
    /// coordinates in force.
    pub fn probe_height_map(
        &mut self,
        program: String,
        req: ProbeRequest,
    ) -> Result<Probing<HeightMap>, Error> {
        // What cannot be probed or levelled is refused before anything moves.
        crate::level::probe_grid(Some(&program), &req)?;
        let dev = self.idle_grbl("probing a height map")?;
        let r = dev
            .start_routine(move |link| {
                probe_map(link, Some(&program), &req, &mut |_, _, _, _, _| {}).map_err(|e| e.0)
            })
            .map_err(Error::from_display)?;
        Ok(Probing(r))
    }

    /// How the firmware's sender handles `M6` in the next job (the virtual machine changes
    /// tools from its tool table: refused there).
    pub fn set_tool_change(&mut self, tc: ToolChange) -> Result<(), Error> {
        tc.validate().map_err(Error)?;
        let Some(dev) = self
            .machine
            .as_any_mut()
            .and_then(|m| m.downcast_mut::<GrblDevice>())
        else {
            return Err(Error(
                "the tool-change policy is for grbl firmware: the virtual machine changes tools from its tool table".into(),
            ));
        };
        dev.settings.tool_change = tc;
        Ok(())
    }

    /// The firmware's tool-change policy (`None` on the virtual machine).
    pub fn tool_change_policy(&mut self) -> Option<ToolChange> {
        self.machine
            .as_any_mut()
            .and_then(|m| m.downcast_mut::<GrblDevice>())
            .map(|d| d.settings.tool_change.clone())
    }

    /// Starts `req`'s program levelled with `map` on grbl firmware: its lines keep their
    /// source line numbers, so progress names the program's own lines, and its `M6` stops
    /// as a plain job's do under the firmware's tool-change policy.
    pub fn start_levelled(
        &mut self,
        req: JobRequest,
        map: &HeightMap,
    ) -> Result<LevelReport, Error> {
        let lines = req.text.lines().count();
        if req.from_line.is_some_and(|l| l == 0 || l as usize > lines) {
            return Err(Error(format!(
                "resume from line {}: the program has lines 1 … {lines}",
                req.from_line.unwrap_or(0)
            )));
        }
        // M6 goes to the sender's tool-change policy, as in a plain job (the transform
        // refuses the policies under which the map would not hold).
        let tool_change = self.tool_change_policy();
        let opts = oficina_grbl::LevelOptions {
            tool_change,
            ..level_options(map, &LevelTuning::default())
        };
        let (program, report) =
            level_stream(&format!("{}.levelled", req.name), &req.text, map, &opts)
                .map_err(Error)?;
        let dev = self.idle_grbl("a levelled job")?;
        dev.start_program(program, req.from_line)
            .map_err(Error::from_display)?;
        self.job = Some(JobView {
            name: req.name,
            lines,
            from_line: req.from_line,
            speed: Some(1.0),
            completed: None,
        });
        Ok(report)
    }
}
