//! Item 9 and 10 at library level: the seed's prototype job (size 34 → 40, 2 % shrinkage)
//! on the shipped digitised contour; every program read back by the interpreter, accepted by
//! rs274, and simulated with zero gouge.

use oficina_cam::ops::{sole_job, Part, SoleJob, GOUGE_TOL};
use oficina_cam::Tool;
use oficina_geom::{offset_areas, to_ring, Area, Point};
use oficina_post::{program_text, read_back, PostDialect, PostOptions};
use oficina_sim::{check_mill, Design};
use std::collections::HashMap;

fn sample_points() -> Vec<Point> {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../samples/sole/size34.csv"
    ))
    .unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| {
            let mut it = l.split(',');
            let x = it.next()?.trim().parse().ok()?;
            let y = it.next()?.trim().parse().ok()?;
            Some(Point::new(x, y))
        })
        .collect()
}

#[test]
fn size_34_to_40_insert_and_cavity_for_both_feet() {
    let pts = sample_points();
    assert!(pts.len() > 20);
    let r = sole_job(&pts, &SoleJob::seed(34.0, 40.0)).unwrap();
    eprintln!(
        "factors {:?}, fit {} blocks {} dev {:.3}, fallback {:?}",
        r.factors, r.fit.method, r.fit.blocks, r.fit.max_deviation, r.fallback
    );
    assert_eq!(r.programs.len(), 4);
    let opts = PostOptions {
        dialect: PostDialect::LinuxCnc,
        allow_m6: false,
        title: "sole".into(),
        settings: vec![],
    };
    for p in &r.programs {
        let text = program_text(&p.toolpath, &opts).unwrap();
        let canon = read_back(&text, &opts).unwrap();
        let area = Area::from_paths(std::slice::from_ref(&p.contour));
        let (d, inside) = match p.part {
            Part::Insert => (-GOUGE_TOL, false),
            Part::Cavity => (GOUGE_TOL, true),
        };
        let rings = offset_areas(&area, d, 0.001)
            .unwrap()
            .iter()
            .flat_map(|a| {
                a.paths()
                    .map(|q| to_ring(&q.flatten(1e-4)))
                    .collect::<Vec<_>>()
            })
            .collect();
        let tools: HashMap<u32, Tool> = p
            .toolpath
            .operations
            .iter()
            .map(|o| (o.tool_number, o.tool.clone()))
            .collect();
        let design = Design {
            rings,
            cut_inside: inside,
            top: 0.0,
            floor: -p.depth,
        };
        let last = &p.toolpath.operations.last().unwrap().tool;
        let check = check_mill(&canon, &tools, &design, 0.5, 20.0, 40.0, last).unwrap();
        eprintln!(
            "{}: {} lines, gouge {:.4} at {:?}, scallop mean {:.4}",
            p.name(),
            text.lines().count(),
            check.report.max_gouge,
            check.report.gouge_at,
            check.report.scallop_mean
        );
        let uncut = check
            .stock
            .z
            .iter()
            .zip(&check.design.z)
            .filter(|(s, d)| **s > **d + 0.01)
            .count();
        let lowered = check.design.z.iter().filter(|d| **d < -1.0).count();
        eprintln!(
            "  uncut pixels {uncut} of {} ({} in the design's cut region), leftover mean {:.4}",
            check.design.z.len(),
            lowered,
            check.report.leftover_mean
        );
        if let Ok(dir) = std::env::var("OFICINA_SOLE_PNG") {
            oficina_sim::render_png(
                &check.stock,
                &std::path::Path::new(&dir).join(format!("{}.png", p.name())),
            )
            .unwrap();
        }
        assert!(check.report.max_gouge < 1e-3, "{}", p.name());
        if p.part == Part::Cavity {
            // Only wall pixels (the grid against exact arcs) may stand above the floor.
            assert!(
                uncut * 1000 < lowered,
                "{}: {uncut} of {lowered} uncut",
                p.name()
            );
        }
    }
}
