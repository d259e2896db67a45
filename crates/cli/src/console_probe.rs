//! The console's `/probe` commands: a touch plate (`/probe z`), an outside corner
//! (`/probe corner`) and a tool length setter (`/probe setter`), read like command-line
//! options and run by `oficina-grbl`'s routines over the console's link.

use clap::Parser;
use oficina_grbl::{Approach, Corner, ProbeResult, Sender, ToolSetter, ZPlate};

/// `/probe …`, typed in the console.
#[derive(Parser, Debug)]
#[command(name = "/probe", disable_version_flag = true)]
struct ProbeCommand {
    #[command(subcommand)]
    what: What,
}

#[derive(clap::Subcommand, Debug)]
enum What {
    /// A touch plate on the stock, under the tool: the stock's top becomes Z0.
    Z {
        /// Plate thickness, mm.
        #[arg(long, allow_hyphen_values = true)]
        plate: f64,
        /// Coordinate system to set: 1 = G54 … 6 = G59.
        #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
        wcs: u8,
        #[command(flatten)]
        approach: ApproachArgs,
    },
    /// The front-left corner: the top, then the −X and −Y sides; the corner becomes
    /// X0 Y0 Z0. Start above the top, within --reach of both sides.
    Corner {
        /// Diameter of the tool or probe tip, mm.
        #[arg(long, allow_hyphen_values = true)]
        tool: f64,
        /// Thickness of a plate the top is touched on, mm (0: the stock's top).
        #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
        plate: f64,
        /// From the faces touched to the corner, X,Y mm (a corner plate's lips).
        #[arg(long, default_value = "0,0", allow_hyphen_values = true)]
        offset: String,
        /// How far out to move before going down beside each side, mm.
        #[arg(long, default_value_t = 15.0, allow_hyphen_values = true)]
        reach: f64,
        /// How far below the top the sides are touched, mm.
        #[arg(long, default_value_t = 3.0, allow_hyphen_values = true)]
        depth: f64,
        /// Coordinate system to set: 1 = G54 … 6 = G59.
        #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
        wcs: u8,
        #[command(flatten)]
        approach: ApproachArgs,
    },
    /// The tool length setter: gives the machine Z of the touch; with --reference (the
    /// reference tool's), applies the difference as the tool length offset (G43.1).
    Setter {
        /// Machine X,Y of the setter (go there at --safe-z first); default: where the tool is.
        #[arg(long, allow_hyphen_values = true)]
        at: Option<String>,
        /// Machine Z to travel at when going to the setter.
        #[arg(long, default_value_t = -5.0, allow_hyphen_values = true)]
        safe_z: f64,
        /// Machine Z the reference tool touched at.
        #[arg(long, allow_hyphen_values = true)]
        reference: Option<f64>,
        #[command(flatten)]
        approach: ApproachArgs,
    },
}

#[derive(clap::Args, Debug)]
struct ApproachArgs {
    /// Feed of the search, mm/min.
    #[arg(long, default_value_t = 100.0, allow_hyphen_values = true)]
    feed: f64,
    /// Feed of the measured touch, mm/min.
    #[arg(long, default_value_t = 25.0, allow_hyphen_values = true)]
    slow: f64,
    /// Longest search, mm.
    #[arg(long, default_value_t = 30.0, allow_hyphen_values = true)]
    travel: f64,
    /// Back-off between the search and the touch, and at the end, mm.
    #[arg(long, default_value_t = 2.0, allow_hyphen_values = true)]
    retract: f64,
}

impl ApproachArgs {
    fn approach(&self) -> Approach {
        Approach {
            travel: self.travel,
            feed: self.feed,
            slow_feed: self.slow,
            retract: self.retract,
        }
    }
}

/// Runs a `/probe …` line on the firmware; what was measured and set, or why not, as text
/// for the operator.
pub(crate) fn run(sender: &mut Sender, line: &str) -> Result<String, String> {
    let cmd = ProbeCommand::try_parse_from(line.split_whitespace())
        .map_err(|e| e.render().to_string())?;
    let failed = |e: oficina_grbl::ProbeError| format!("probe failed: {e}");
    match cmd.what {
        What::Z {
            plate,
            wcs,
            approach,
        } => {
            let p = ZPlate {
                thickness: plate,
                wcs,
                approach: approach.approach(),
            };
            let r = oficina_grbl::run_z_plate(sender, &p).map_err(failed)?;
            Ok(format!(
                "probe z: touched the plate at machine Z {:.3}; {} (the stock's top is Z0)",
                r.contacts[0][2],
                offset(&r, "Z")
            ))
        }
        What::Corner {
            tool,
            plate,
            offset: side,
            reach,
            depth,
            wcs,
            approach,
        } => {
            let p = Corner {
                thickness: plate,
                side_offset: pair("--offset", &side)?,
                tool_diameter: tool,
                reach,
                depth,
                wcs,
                approach: approach.approach(),
            };
            let r = oficina_grbl::run_corner(sender, &p).map_err(failed)?;
            Ok(format!(
                "probe corner: top at machine Z {:.3}, X side at X {:.3}, Y side at Y {:.3}; {} (the corner is X0 Y0 Z0)",
                r.contacts[0][2],
                r.contacts[1][0],
                r.contacts[2][1],
                offset(&r, "XYZ")
            ))
        }
        What::Setter {
            at,
            safe_z,
            reference,
            approach,
        } => {
            let p = ToolSetter {
                at: at.as_deref().map(|s| pair("--at", s)).transpose()?,
                safe_z,
                reference,
                approach: approach.approach(),
            };
            let r = oficina_grbl::run_tool_setter(sender, &p).map_err(failed)?;
            Ok(match r.tool_offset {
                Some(tlo) => format!(
                    "probe setter: touched at machine Z {:.3}; tool length offset G43.1 Z{tlo:.3} applied",
                    r.measured_z
                ),
                None => format!(
                    "probe setter: touched at machine Z {:.3} (after a tool change: /probe setter --reference {:.3})",
                    r.measured_z, r.measured_z
                ),
            })
        }
    }
}

/// `G54 offset Z = -60.000` for the axes named.
fn offset(r: &ProbeResult, axes: &str) -> String {
    let set: Vec<String> = axes
        .chars()
        .map(|a| {
            let i = (a as u8 - b'X') as usize;
            format!("{a} = {:.3}", r.offset[i])
        })
        .collect();
    format!("G{} offset {}", 53 + r.wcs, set.join(", "))
}

/// `X,Y` as two numbers.
fn pair(option: &str, s: &str) -> Result<[f64; 2], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("{option} {s}: expected two numbers X,Y"))?;
    <[f64; 2]>::try_from(v).map_err(|_| format!("{option} {s}: expected two numbers X,Y"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probe_lines_parse_and_bad_ones_say_why() {
        let c = ProbeCommand::try_parse_from("/probe z --plate 19.5 --feed 200".split_whitespace())
            .unwrap();
        assert!(
            matches!(c.what, What::Z { plate, approach: ApproachArgs { feed, .. }, .. } if plate == 19.5 && feed == 200.0)
        );
        assert!(ProbeCommand::try_parse_from("/probe z".split_whitespace()).is_err());
        let e = ProbeCommand::try_parse_from("/probe z --plate x".split_whitespace()).unwrap_err();
        assert!(e.render().to_string().contains("--plate"), "{e}");
        let c = ProbeCommand::try_parse_from(
            "/probe setter --at -20,-30 --reference -80.5".split_whitespace(),
        )
        .unwrap();
        assert!(matches!(c.what, What::Setter { reference: Some(r), .. } if r == -80.5));
        assert_eq!(pair("--at", "-20,-30"), Ok([-20.0, -30.0]));
        assert!(pair("--at", "1,2,3").is_err());
    }
}
