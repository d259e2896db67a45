//! The production sheet (seed §4.5, "planilha de apoio à produção", which the seed left
//! unimplemented): stitches, colour changes and threads, stitches and thread per colour,
//! jumps, trims, design size, minimum hoop, sewing time from the head-speed model and the
//! time for n pieces.

use crate::hoop::{smallest_hoop, Hoop, HoopError};
use crate::plan::{Counts, StitchPlan};
use crate::table::{run, HeadSpeed, Pauses, RunReport, Table};
use std::fmt::Write;

/// One thread's line on the sheet.
#[derive(Clone, Debug, PartialEq)]
pub struct ThreadLine {
    /// Its colour, `#rrggbb`.
    pub hex: String,
    /// Its name or catalogue code as the file or design gives it; empty when none.
    pub name: String,
    /// Stitches sewn with it.
    pub stitches: usize,
    /// Along the sewn stitches, m.
    pub length_m: f64,
}

/// The production sheet of a design: counts, threads, hoop, and run times.
#[derive(Clone, Debug, PartialEq)]
pub struct Sheet {
    /// The design's name.
    pub name: String,
    /// Stitch, jump, trim, stop and colour-change counts.
    pub counts: Counts,
    /// Threads in sewing order.
    pub threads: Vec<ThreadLine>,
    /// Width and height of the design, mm.
    pub size: [f64; 2],
    /// The hoop asked for (checked) or the smallest that fits; or why the design leaves it.
    pub hoop: Result<Hoop, HoopError>,
    /// The run on the table.
    pub run: RunReport,
    /// The fixed head speed the run used, if one.
    pub fixed_ppm: Option<f64>,
    /// The table's name.
    pub table: String,
    /// How many pieces the time is given for.
    pub pieces: u32,
}

/// The sheet of `plan`: the hoop is `hoop` when given (checked), else the smallest that fits.
pub fn sheet(
    plan: &StitchPlan,
    hoop: Option<Hoop>,
    table: &Table,
    speed: HeadSpeed,
    pauses: Pauses,
    pieces: u32,
) -> Result<Sheet, String> {
    let counts = plan.counts();
    let threads = plan
        .blocks
        .iter()
        .zip(&counts.per_block)
        .map(|(b, &(n, len))| ThreadLine {
            hex: b.thread.hex(),
            name: b.thread.name.clone(),
            stitches: n,
            length_m: len / 1000.0,
        })
        .collect();
    let size = plan
        .bounds()
        .map_or([0.0, 0.0], |b| [b[2] - b[0], b[3] - b[1]]);
    let hoop = match hoop {
        Some(h) => h.check(plan).map(|()| h),
        None => smallest_hoop(plan),
    };
    Ok(Sheet {
        name: plan.name.clone(),
        counts,
        threads,
        size,
        hoop,
        run: run(plan, table, speed, pauses)?,
        fixed_ppm: match speed {
            HeadSpeed::Fixed(p) => Some(p),
            HeadSpeed::Table => None,
        },
        table: table.name.clone(),
        pieces,
    })
}

/// `1 h 02 min 05 s`, `3 min 20 s`.
pub fn duration(s: f64) -> String {
    let s = s.max(0.0).round() as u64;
    let (h, m, s) = (s / 3600, s / 60 % 60, s % 60);
    if h > 0 {
        format!("{h} h {m:02} min {s:02} s")
    } else {
        format!("{m} min {s:02} s")
    }
}

impl Sheet {
    /// The sheet as plain text.
    pub fn text(&self) -> String {
        let mut t = String::new();
        let c = &self.counts;
        let _ = writeln!(t, "Production sheet: {}", self.name);
        let _ = writeln!(
            t,
            "Design size      {:.1} x {:.1} mm",
            self.size[0], self.size[1]
        );
        let _ = match &self.hoop {
            Ok(h) => writeln!(t, "Hoop             {h}"),
            Err(e) => writeln!(t, "Hoop             NONE: {e}"),
        };
        let _ = writeln!(t, "Stitches         {}", c.stitches);
        let _ = writeln!(
            t,
            "Colours          {} ({} colour changes)",
            self.threads.len(),
            c.color_changes
        );
        let _ = writeln!(
            t,
            "Jumps            {} ({:.1} mm of travel)",
            c.jumps, c.jump_length
        );
        let _ = writeln!(t, "Trims            {}", c.trims);
        let _ = writeln!(t, "Stops            {}", c.stops);
        let _ = writeln!(t, "Threads:");
        for (i, th) in self.threads.iter().enumerate() {
            let _ = writeln!(
                t,
                "  {:>2}. {}  {:>7} stitches  {:>7.2} m{}",
                i + 1,
                th.hex,
                th.stitches,
                th.length_m,
                if th.name.is_empty() {
                    String::new()
                } else {
                    format!("  {}", th.name)
                }
            );
        }
        let r = &self.run;
        match self.fixed_ppm {
            Some(p) => {
                let _ = writeln!(t, "Head speed       fixed {p} stitches/min");
            }
            None => {
                let _ = writeln!(
                    t,
                    "Head speed       seed's table by longest stitch per section:"
                );
                for (code, n, ppm) in &r.by_code {
                    let _ = writeln!(t, "  code {code:>2} ({ppm:>4} ppm) {n:>7} stitches");
                }
            }
        }
        let _ = writeln!(t, "Sewing time      {}", duration(r.sewing_seconds));
        let _ = writeln!(t, "Jumps (needle up)  {}", duration(r.jump_seconds));
        let _ = writeln!(t, "Trims, changes, stops  {}", duration(r.pause_seconds));
        let _ = writeln!(t, "Total per piece  {}", duration(r.total_seconds));
        if self.pieces > 1 {
            let _ = writeln!(
                t,
                "Total for {} pieces {}",
                self.pieces,
                duration(r.total_seconds * self.pieces as f64)
            );
        }
        let _ = writeln!(
            t,
            "Table {}:  {} stitch(es) the table cannot finish with the needle up",
            self.table,
            r.faults.len()
        );
        if r.too_long > 0 {
            let _ = writeln!(t, "WARNING: {} stitch(es) longer than 12.4 mm", r.too_long);
        }
        t
    }

    /// The sheet as an HTML page (the printable A4 page without a render).
    pub fn html(&self) -> String {
        self.html_page(None)
    }

    /// The sheet as an HTML page that prints on one A4 sheet: the render of the design
    /// (a PNG, embedded) beside size, hoop, counts and times, then the colour sequence with
    /// each thread's swatch, name or code, stitches and length.
    pub fn html_page(&self, render_png: Option<&[u8]>) -> String {
        let esc = |s: &str| {
            s.replace('&', "&amp;")
                .replace('<', "&lt;")
                .replace('>', "&gt;")
                .replace('"', "&quot;")
        };
        let mut h = String::from(concat!(
            "<!doctype html><meta charset=\"utf-8\"><title>Production sheet</title>\n<style>",
            "@page{size:A4;margin:12mm}",
            "body{font-family:sans-serif;font-size:10pt;max-width:186mm;margin:auto}",
            "h1{font-size:15pt;margin:0 0 3mm}h2{font-size:11pt;margin:4mm 0 1mm}",
            "td,th{padding:1px 6px;text-align:left;vertical-align:top}",
            ".num{text-align:right}",
            ".sw{display:inline-block;width:1.2em;height:1em;border:1px solid #000;",
            "vertical-align:middle;-webkit-print-color-adjust:exact;print-color-adjust:exact}",
            ".render{display:block;max-width:100%;max-height:150mm;margin:0 auto 2mm;",
            "border:1px solid #bbb}",
            "table.threads{border-collapse:collapse;width:100%}",
            "table.threads tr{border-bottom:1px solid #ddd;break-inside:avoid}",
            "</style>\n"
        ));
        let _ = writeln!(h, "<h1>Production sheet: {}</h1>", esc(&self.name));
        if let Some(png) = render_png {
            let _ = writeln!(
                h,
                "<img class=render alt=\"the design as sewn\" src=\"data:image/png;base64,{}\">",
                base64(png)
            );
        }
        h += "<table>\n";
        for line in self.text().lines().skip(1) {
            if line.starts_with("  ") || line.starts_with("Threads:") {
                continue;
            }
            let (k, v) = line.split_at(line.find("  ").unwrap_or(line.len()));
            let _ = writeln!(
                h,
                "<tr><th>{}</th><td>{}</td></tr>",
                esc(k.trim()),
                esc(v.trim())
            );
        }
        h += "</table>\n<h2>Colour sequence</h2>\n<table class=threads><tr><th>#</th><th>colour</th><th>thread</th><th class=num>stitches</th><th class=num>thread (m)</th></tr>\n";
        for (i, th) in self.threads.iter().enumerate() {
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td><span class=sw style=\"background:{}\"></span> {}</td><td>{}</td><td class=num>{}</td><td class=num>{:.2}</td></tr>",
                i + 1,
                th.hex,
                th.hex,
                if th.name.is_empty() { "—".to_string() } else { esc(&th.name) },
                th.stitches,
                th.length_m
            );
        }
        h += "</table>\n";
        h
    }
}

/// Standard base64 with padding (for the page's embedded render).
fn base64(b: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(b.len().div_ceil(3) * 4);
    for c in b.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            if k <= c.len() {
                s.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    #[test]
    fn base64_pads_as_the_standard_does() {
        assert_eq!(super::base64(b"Man"), "TWFu");
        assert_eq!(super::base64(b"Ma"), "TWE=");
        assert_eq!(super::base64(b"M"), "TQ==");
        assert_eq!(super::base64(&[0xff, 0xfe, 0xfd, 0x00]), "//79AA==");
    }
}
