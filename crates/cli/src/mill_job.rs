//! `oficina mill --job job.toml -o part.nc [--per-tool]`: prints what the job made and
//! writes its program(s), preview and stock images.

use crate::mill::{estimate_profile, print_judged, Args};
use crate::progress::with_bar;
use anyhow::{Context, Result};
use oficina_app::{mill_job_upto, JobOptions};
use oficina_sim::render_png;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// `part.nc` → `part.T2.nc` for tool 2's program.
fn per_tool_name(output: &Path, tool: u32) -> PathBuf {
    let stem = output
        .file_stem()
        .map_or("program".into(), |s| s.to_string_lossy().to_string());
    let ext = output
        .extension()
        .map_or(String::new(), |e| format!(".{}", e.to_string_lossy()));
    output.with_file_name(format!("{stem}.T{tool}{ext}"))
}

pub(crate) fn run(job: &Path, args: &Args) -> Result<ExitCode> {
    let opts = JobOptions {
        post: args.out.params(),
        per_tool: args.per_tool,
    };
    let profile = estimate_profile(&args.profile);
    let (result, bar) = with_bar(|fb| mill_job_upto(job, &opts, &profile, args.upto, fb));
    let r = result?;
    bar.finish_and_clear();
    for w in &r.warnings {
        eprintln!("oficina: warning: {w}");
    }
    for l in &r.imported {
        println!("imported: {l}");
    }
    for s in &r.shapes {
        println!("shape:    {s}");
    }
    println!(
        "job:      {} operations, {} tool load{} in this order:",
        r.ops.len(),
        r.tool_loads,
        if r.tool_loads == 1 { "" } else { "s" }
    );
    for o in &r.ops {
        println!(
            "  T{} {:<10} {} on #{}: {} moves, {:.3} mm deep, {:.0} mm/min at {:.0} rpm ({})",
            o.tool_number,
            o.tool,
            o.name,
            o.shapes
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(" #"),
            o.moves,
            o.depth,
            o.feeds.feed,
            o.feeds.rpm,
            o.feeds.source
        );
    }
    let preview = args
        .preview
        .clone()
        .unwrap_or_else(|| args.output.with_extension("svg"));
    std::fs::write(&preview, &r.preview_svg)
        .with_context(|| format!("{}: cannot write the preview", preview.display()))?;
    let mut gouged = false;
    for p in &r.programs {
        let out = match p.tool {
            Some(t) => per_tool_name(&args.output, t),
            None => args.output.clone(),
        };
        std::fs::write(&out, &p.judged.program)
            .with_context(|| format!("{}: cannot write the program", out.display()))?;
        println!("{}:", out.display());
        if let Some(stock) = &p.judged.stock {
            let png = out.with_extension("stock.png");
            render_png(stock, &png).map_err(anyhow::Error::msg)?;
            println!("  stock:    {}", png.display());
        }
        print_judged(&p.judged);
        gouged |= p.judged.gouged();
    }
    println!("  preview:  {}", preview.display());
    Ok(if gouged {
        ExitCode::from(2)
    } else {
        ExitCode::SUCCESS
    })
}
