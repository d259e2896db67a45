//! grbl's `$` system commands (system.c's `system_execute_line`): settings, reports, check
//! mode, unlock, homing, sleep, startup lines and jogging, with grbl's rules on which need an
//! idle machine; FluidNC's named settings first when the emulator is FluidNC.

use super::*;

impl Core {
    pub(super) fn system_command(&mut self, cmd: &str, raw: &str) {
        // system.c: `$$` is refused only in a cycle or hold (it takes too long to print);
        // `$G`, `$C`, `$X`, `$J=` have their own rules; everything else needs IDLE or ALARM.
        let idle_like = matches!(self.state, GrblState::Idle | GrblState::Alarm);
        let in_cycle = matches!(
            self.state,
            GrblState::Run | GrblState::Hold(_) | GrblState::Door(_)
        );
        if self.config.flavor == Flavor::FluidNc {
            // FluidNC reads a `$` line as typed (case, `/` and all), not cleaned like G-code.
            let typed = raw.trim().strip_prefix('$').unwrap_or(cmd);
            match fluidnc::command(typed, &mut self.fluid, &self.settings, idle_like, in_cycle) {
                fluidnc::Outcome::Say(lines) => {
                    for l in lines {
                        self.say(&l);
                    }
                    return self.say("ok");
                }
                fluidnc::Outcome::Error(e) => return self.reply_error(e),
                fluidnc::Outcome::SetNumbered(n, v) => {
                    let numbered = format!("{n}={}", v.trim());
                    return self.system_command(&numbered, &format!("${numbered}"));
                }
                fluidnc::Outcome::NotFluid => {}
            }
        }
        let own_rules = matches!(cmd, "" | "$" | "G" | "C" | "X") || cmd.starts_with("J=");
        if !own_rules && !idle_like {
            return self.reply_error(8);
        }
        match cmd {
            "" => {
                self.say("[HLP:$$ $# $G $I $N $x=val $Nx=line $J=line $SLP $C $X $H ~ ! ? ctrl-x]")
            }
            "$" => {
                if in_cycle {
                    return self.reply_error(8);
                }
                let lines: Vec<String> = self
                    .settings
                    .iter()
                    .map(|(n, v)| format!("${n}={}", format_setting(*n, *v)))
                    .collect();
                for l in lines {
                    self.say(&l);
                }
            }
            "#" => {
                let f = |p: [f64; 3]| format!("{:.3},{:.3},{:.3}", p[0], p[1], p[2]);
                for i in 0..6 {
                    let l = format!("[G{}:{}]", 54 + i, f(self.interp.wcs_offsets[i]));
                    self.say(&l);
                }
                let lines = [
                    format!("[G28:{}]", f(self.interp.g28)),
                    format!("[G30:{}]", f(self.interp.g30)),
                    format!("[G92:{}]", f(self.interp.g92)),
                    format!("[TLO:{:.3}]", self.interp.tool_length),
                    format!(
                        "[PRB:{}:{}]",
                        f(self.probe_position),
                        u8::from(self.probe_succeeded)
                    ),
                ];
                for l in lines {
                    self.say(&l);
                }
            }
            "G" => {
                let l = format!("[GC:{}]", self.interp.parser_state());
                self.say(&l);
            }
            "I" => {
                let c = &self.config;
                for l in c
                    .flavor
                    .build_info(&c.version, c.planner_blocks, c.rx_buffer)
                {
                    self.say(&l);
                }
            }
            "N" => {
                let lines: Vec<String> = self
                    .startup_lines
                    .iter()
                    .enumerate()
                    .map(|(i, l)| format!("$N{i}={l}"))
                    .collect();
                for l in lines {
                    self.say(&l);
                }
            }
            "C" => {
                if self.check_mode {
                    self.msg("Disabled");
                    self.say("ok");
                    self.soft_reset();
                    return;
                }
                if self.state != GrblState::Idle {
                    return self.reply_error(8);
                }
                self.check_mode = true;
                self.state = GrblState::Check;
                self.msg("Enabled");
            }
            "X" => {
                if self.state == GrblState::Alarm {
                    self.state = GrblState::Idle;
                    self.msg("Caution: Unlocked");
                }
            }
            "H" => {
                if self.setting(22) == 0.0 {
                    return self.reply_error(5);
                }
                if !idle_like {
                    return self.reply_error(8);
                }
                // Answered when the cycle ends (homing.rs).
                return self.start_homing();
            }
            "SLP" => {
                self.state = GrblState::Sleep;
                self.msg("Sleeping");
            }
            "RST=$" | "RST=#" | "RST=*" => {
                if cmd != "RST=#" {
                    self.settings = SETTINGS.iter().map(|s| (s.number, s.default)).collect();
                    self.motion = new_motion(&self.settings, self.mpos);
                }
                if cmd != "RST=$" {
                    self.interp.wcs_offsets = [[0.0; 3]; 6];
                    self.interp.g28 = [0.0; 3];
                    self.interp.g30 = [0.0; 3];
                }
            }
            _ => {
                if let Some(body) = cmd.strip_prefix("J=") {
                    return self.jog(body);
                }
                if let Some(rest) = cmd.strip_prefix('N') {
                    return self.store_startup_line(rest, raw);
                }
                let Some((n, v)) = cmd.split_once('=') else {
                    return self.reply_error(3);
                };
                let (Ok(n), Ok(v)) = (n.parse::<u16>(), v.parse::<f64>()) else {
                    return self.reply_error(3);
                };
                let a_setting = self.has_a() && matches!(n, 103 | 113 | 123 | 133);
                if oficina_grbl::setting_info(n).is_none() && !a_setting {
                    return self.reply_error(3);
                }
                if !idle_like {
                    return self.reply_error(8);
                }
                if v < 0.0 {
                    return self.reply_error(4);
                }
                if n == 0 && v < 3.0 {
                    return self.reply_error(6);
                }
                if n == 20 && v != 0.0 && self.setting(22) == 0.0 {
                    return self.reply_error(10);
                }
                self.settings.insert(n, v);
                // Idle, so the buffer is empty: the machine changes under no block.
                self.motion = new_motion(&self.settings, self.mpos);
                if n == 12 {
                    self.interp.arc_tolerance = v;
                }
            }
        }
        self.say("ok");
    }

    fn store_startup_line(&mut self, rest: &str, raw: &str) {
        let Some((i, _)) = rest.split_once('=') else {
            return self.reply_error(3);
        };
        let Ok(i) = i.parse::<usize>() else {
            return self.reply_error(3);
        };
        if i > 1 {
            return self.reply_error(3);
        }
        // Keep the user's text after '=' (cleaned), validated on a scratch parser.
        let text = raw.split_once('=').map(|x| x.1).unwrap_or("");
        let Ok(clean) = oficina_grbl::clean_line(text) else {
            return self.reply_error(14);
        };
        let mut scratch = self.interp.clone();
        if !clean.is_empty() {
            if let Err(e) = scratch.execute(&clean) {
                return self.reply_error(e);
            }
        }
        self.startup_lines[i] = clean;
        self.say("ok");
    }

    fn jog(&mut self, body: &str) {
        if !matches!(self.state, GrblState::Idle | GrblState::Jog) {
            return self.reply_error(8);
        }
        match self.interp.jog(body) {
            Err(e) => self.reply_error(e),
            Ok(effect) => {
                if self.beyond_soft_limits(&effect.segments) {
                    self.interp.pos = self.motion.tail();
                    return self.reply_error(15);
                }
                self.jogging = true;
                self.pending = Some(Pending {
                    sync: false,
                    dwell: 0.0,
                    segments: effect.segments.into(),
                    flow: Flow::Continue,
                    probe: None,
                    reply: "ok".into(),
                    line: None,
                });
                self.advance_pending();
            }
        }
    }
}
