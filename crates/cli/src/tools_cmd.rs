//! `oficina tools feeds`: the feeds-and-speeds calculator on the tool library.

use anyhow::Result;
use clap::Args as ClapArgs;
use oficina_app::{tool_feeds, FeedsQuery};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(ClapArgs, Debug)]
pub(crate) struct FeedsArgs {
    /// Tool library (TOML [[tool]] tables).
    #[arg(long, requires = "tool")]
    pub library: Option<PathBuf>,
    /// The library's tool number.
    #[arg(long, requires = "library")]
    pub tool: Option<u32>,
    /// Material: the library's chip load for it.
    #[arg(long)]
    pub material: Option<String>,
    /// Diameter, mm (overrides the library's).
    #[arg(long)]
    pub diameter: Option<f64>,
    /// Cutting edges (overrides the library's).
    #[arg(long)]
    pub flutes: Option<u32>,
    /// Spindle speed, rev/min (overrides the library's).
    #[arg(long)]
    pub rpm: Option<f64>,
    /// Chip load, mm per tooth (overrides the library's for the material).
    #[arg(long)]
    pub chip_load: Option<f64>,
}

pub(crate) fn feeds(a: FeedsArgs) -> Result<ExitCode> {
    let q = FeedsQuery {
        library: a.library.zip(a.tool),
        material: a.material,
        diameter: a.diameter,
        flutes: a.flutes,
        rpm: a.rpm,
        chip_load: a.chip_load,
    };
    let r = tool_feeds(&q).map_err(|e| anyhow::anyhow!(e.0))?;
    println!(
        "tool:          {} (Ø{} mm, {} flutes)",
        r.tool, r.diameter, r.flutes
    );
    println!("spindle:       {:.0} rpm", r.rpm);
    println!("chip load:     {} mm/tooth", r.chip_load);
    println!(
        "feed:          {:.0} mm/min (chip load × flutes × rpm)",
        r.feed
    );
    println!("plunge feed:   {:.0} mm/min (a third)", r.feed / 3.0);
    println!("cutting speed: {:.0} m/min (π × D × rpm)", r.surface_speed);
    Ok(ExitCode::SUCCESS)
}
